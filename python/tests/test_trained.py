"""Trained policies (written by ``yokai train``) as ``yokai.Agent``s."""

import subprocess
import sys

import numpy as np
import pytest

import yokai
from training import BINARY, TINY, train_tiny

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    return train_tiny(tmp_path_factory.mktemp("train"))


def games_of(policy, partner="random", seeds=range(5)):
    """The replays of games of ``policy`` (a name or path) in seat 0 beside ``partner``."""
    return [yokai.play("9c-2p-perfect", [policy, partner], seed=s, agent_seed=s).to_replay() for s in seeds]


def test_a_trained_policy_plays_whole_games(run_dir):
    agent = yokai.Agent(str(run_dir), seed=1)
    assert agent.name == str(run_dir)
    replays = games_of(str(run_dir))
    assert all(yokai.Env.from_replay(r).done for r in replays)
    # Seated with the same seeds it plays the same games. (This barely trained network is
    # near uniform: with the same draws it plays the very games `random` plays.)
    assert games_of(str(run_dir)) == replays


def test_the_run_directory_policy_file_and_checkpoint_play_identical_games(run_dir):
    """The three forms of a trained run hold the same network and END rule."""
    want = games_of(str(run_dir), partner="belief")
    for name in ("policy.ykp", "checkpoint.ykc"):
        assert games_of(str(run_dir / name), partner="belief") == want, name
    np.testing.assert_array_equal(
        yokai.policy_parameters(str(run_dir / "policy.ykp")),
        yokai.policy_parameters(str(run_dir / "checkpoint.ykc")),
    )


def test_another_game_and_broken_files_are_clear_errors(run_dir, tmp_path):
    agent = yokai.Agent(str(run_dir))
    with pytest.raises(yokai.ConfigError, match="was trained on 9c-2p-perfect, not on 9c-3p-perfect"):
        agent.act(yokai.Env("9c-3p-perfect", seed=0))
    broken = tmp_path / "broken.ykp"
    data = (run_dir / "policy.ykp").read_bytes()
    broken.write_bytes(data[: len(data) // 2])
    with pytest.raises(yokai.ConfigError, match="broken.ykp is corrupt"):
        yokai.Agent(str(broken))


@pytest.mark.parametrize(
    "network",
    [
        'encoder = "gatv2"\nhead = "pointer"\ngraph_layers = 2\ngraph_width = 8',
        'encoder = "relation"\nmemory = "trxl"\ntrxl_width = 8\ntrxl_heads = 2\ntrxl_memory = 4',
    ],
    ids=["gatv2", "relation-trxl"],
)
def test_ablation_networks_load_and_play(network, tmp_path):
    """The paper's ablation networks (graph encoders, Transformer-XL memory) load from
    Python like the GRU networks and play whole games."""
    run = train_tiny(tmp_path, TINY.replace('preset = "compact"', 'preset = "compact"\n' + network))
    replays = games_of(str(run), partner="greedy", seeds=range(3))
    assert all(yokai.Env.from_replay(r).done for r in replays)
    assert games_of(str(run / "policy.ykp"), partner="greedy", seeds=range(3)) == replays


def test_an_export_holds_the_networks_weights_and_what_rebuilds_its_inputs(run_dir, tmp_path):
    """``yokai export`` writes SafeTensors that the ecosystem's own reader loads: the same
    numbers as the policy's parameters, and the training config and game as metadata."""
    safetensors_numpy = pytest.importorskip("safetensors.numpy")
    from safetensors import safe_open

    out = tmp_path / "net.safetensors"
    subprocess.run([str(BINARY), "export", str(run_dir), "--out", str(out)], check=True, capture_output=True)
    tensors = safetensors_numpy.load_file(str(out))
    params = yokai.policy_parameters(str(run_dir))
    flat = np.concatenate([t.ravel() for t in tensors.values()])
    # Every parameter once (the file orders tensors by name, the policy by module).
    assert flat.dtype == np.float32 and flat.size == params.size
    assert np.array_equal(np.sort(flat), np.sort(params))
    # burn's linear layout: weight [d_in, d_out]; the GRU's input map reads the embedding.
    assert tensors["memory.input.weight"].shape == (16, 48)
    with safe_open(str(out), "np") as f:
        meta = f.metadata()
    config = tomllib.loads(meta["yokai.train_config"])
    assert config["network"]["hidden"] == 16 and meta["yokai.hidden_size"] == "16"
    assert tomllib.loads(meta["yokai.game"])["cards"] == 9
    # Without --out it lands beside the policy file; a path that is no policy is an error.
    subprocess.run([str(BINARY), "export", str(run_dir)], check=True, capture_output=True)
    assert (run_dir / "policy.safetensors").exists()
    bad = subprocess.run([str(BINARY), "export", str(tmp_path / "nothing")], capture_output=True, text=True)
    assert bad.returncode != 0 and "nothing" in bad.stderr


def test_the_end_rule_of_a_trained_agent_can_be_chosen(run_dir):
    """At a threshold of 0.99 the barely trained network never ends a game early; drawing
    END (its few per cent at every turn) ends some of 40 games. Bad rules are refused."""

    def early_ends(end):
        ended = 0
        for seed in range(40):
            agents = [yokai.Agent(str(run_dir), seed=seed, end=end) for _ in range(2)]
            env = yokai.play("9c-2p-perfect", agents, seed=seed)
            ended += env.outcome["early_end"]
        return ended

    assert early_ends(0.99) == 0
    assert early_ends("draw") > 0
    for bad, error in [(1.0, ValueError), ("sometimes", ValueError), (True, ValueError), ([0.5], TypeError)]:
        with pytest.raises(error, match="end"):
            yokai.Agent(str(run_dir), end=bad)
    with pytest.raises(ValueError, match="not a trained policy"):
        yokai.Agent("greedy", end=0.5)


def test_at_temperature_zero_a_trained_agent_plays_the_same_whatever_its_seed(run_dir):
    """T = 0 takes the most likely legal move: agents seeded differently play the same
    games, move for move; at the trained distribution (T = 1) their draws differ. Bad
    temperatures, and one for a bot, are refused."""

    def games(temperature, agent_seed):
        played = []
        for seed in range(6):
            agents = [yokai.Agent(str(run_dir), end=0.5, temperature=temperature) for _ in range(2)]
            env = yokai.play("9c-2p-perfect", agents, seed=seed, agent_seed=agent_seed)
            played.append(tuple(env.history))
        return played

    assert games(0.0, 0) == games(0.0, 100)
    assert games(1.0, 0) != games(1.0, 100)
    for bad in [-0.5, float("nan"), 1000.0]:
        with pytest.raises(ValueError, match="temperature"):
            yokai.Agent(str(run_dir), temperature=bad)
    with pytest.raises(ValueError, match="not a trained policy"):
        yokai.Agent("greedy", temperature=0.0)

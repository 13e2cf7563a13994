"""``python -m yokai.torch_train`` and ``yokai.TrainEnv``: the Rust trainer's games,
network and levers in PyTorch, and the one weight format both trainers' policies share."""

import json
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import yokai
from training import BINARY, TINY, train_tiny

torch = pytest.importorskip("torch")
pytest.importorskip("safetensors")

from yokai.torch_train import ActorCritic, Shapes, Trainer, load  # noqa: E402
from yokai.torch_train.ppo import _toml  # noqa: E402

# Every layer the PyTorch network has: pointer head with the pooled END input, the colour
# layer (belief loss), the central critic and a hidden layer before the heads (+1HL).
EVERY_LAYER = TINY.replace(
    "hidden = 16",
    'hidden = 16\nhead = "pointer"\npointer_pool = true\ncritic = "central"\nactor_gain = 1.0\nhead_layers = 1',
).replace(
    "total_steps = 128",
    'total_steps = 128\nbelief_aux = 0.5\nend_lookahead = 0.5\nend_lookahead_form = "target"\n'
    "entropy_normalized = true",
)


def _write(text: str) -> str:
    """``text`` in a TOML file of its own (the trainer takes a preset name or a path)."""
    f = tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False)
    f.write(text)
    f.close()
    return f.name


def torch_network_of(config_text: str) -> ActorCritic:
    env = yokai.TrainEnv(_write(config_text), seed=0)
    config = _toml(env.train_config)
    return ActorCritic(config["network"], config["ppo"], Shapes.of(env))


def test_the_torch_network_computes_what_the_rust_network_computes(tmp_path):
    """A Rust-trained network, exported, loaded into the PyTorch network: over whole games
    every step's logits (both seats) and memory equal the Rust network's within float
    rounding. Checks the layers, their names and layouts, and the board read from the
    node features."""
    run = train_tiny(tmp_path, EVERY_LAYER)
    exported = tmp_path / "net.safetensors"
    subprocess.run([str(BINARY), "export", str(run), "--out", str(exported)], check=True, capture_output=True)
    net = load(torch_network_of(EVERY_LAYER), str(exported))
    compared = 0
    for deal in range(3):
        env = yokai.Env("9c-2p-perfect", seed=deal)
        rust_state = [None, None]
        torch_state = [torch.zeros(1, 16), torch.zeros(1, 16)]
        first = True
        while not env.done:
            for seat in range(2):
                logits, rust_state[seat] = yokai.policy_step(str(exported), env, seat, rust_state[seat])
                obs = torch.from_numpy(env.observation(seat, "graph", "float32")).reshape(1, -1)
                keep = torch.tensor([0.0 if first else 1.0])
                with torch.no_grad():
                    torch_state[seat] = net.recur(obs, torch_state[seat], keep)
                    np.testing.assert_allclose(torch_state[seat][0].numpy(), rust_state[seat], atol=1e-5)
                    if logits is not None:
                        mine, _ = net.heads(obs, torch_state[seat])
                        np.testing.assert_allclose(mine[0].numpy(), logits, atol=2e-4, rtol=1e-4)
                        compared += 1
            first = False
            env.step(env.legal_actions()[deal % len(env.legal_actions())])
    assert compared > 40, compared


def test_a_torch_policy_is_a_policy_every_front_end_plays(tmp_path):
    """The trainer's ``policy.safetensors`` loads in Rust (``yokai.Agent``, ``yokai eval``)
    with the same numbers: Rust's logits equal PyTorch's on it, and it plays whole games."""
    out = tmp_path / "run"
    code = subprocess.run(
        [sys.executable, "-m", "yokai.torch_train", _write(EVERY_LAYER), "--out", str(out), "--quiet"],
        capture_output=True, text=True,
    )
    assert code.returncode == 0, code.stderr
    lines = [json.loads(line) for line in (out / "metrics.jsonl").read_text().splitlines()]
    assert [line["update"] for line in lines] == [1, 2]
    assert lines[-1]["env_steps"] == 128
    policy = out / "policy.safetensors"
    net = load(torch_network_of(EVERY_LAYER), str(policy))
    env = yokai.Env("9c-2p-perfect", seed=3)
    env.step(env.legal_actions()[0])
    logits, _ = yokai.policy_step(str(policy), env, env.acting_seat)
    obs = torch.from_numpy(env.observation(env.acting_seat, "graph", "float32")).reshape(1, -1)
    with torch.no_grad():
        mine, _ = net.heads(obs, net.recur(obs, torch.zeros(1, 16), torch.zeros(1)))
    np.testing.assert_allclose(mine[0].numpy(), logits, atol=2e-4, rtol=1e-4)
    game = yokai.play("9c-2p-perfect", [str(policy), "greedy"], seed=1)
    assert game.done
    report = subprocess.run(
        [str(BINARY), "eval", str(policy), "greedy", "--games", "20", "--out", str(tmp_path / "eval")],
        capture_output=True, text=True,
    )
    assert report.returncode == 0, report.stderr
    # Its metrics.jsonl reads as the Rust trainer's: eval draws the run's learning curves.
    assert (tmp_path / "eval" / "learning_return.png").exists()
    # A run that exists is not overwritten without --resume; --resume goes on to the budget.
    again = subprocess.run([sys.executable, "-m", "yokai.torch_train", _write(EVERY_LAYER), "--out", str(out)],
                           capture_output=True, text=True)
    assert again.returncode == 2 and "--resume" in again.stderr
    longer = subprocess.run(
        [sys.executable, "-m", "yokai.torch_train", _write(EVERY_LAYER), "--out", str(out), "--resume", "--quiet",
         "--set", "ppo.total_steps=256"],
        capture_output=True, text=True,
    )
    assert longer.returncode == 0, longer.stderr
    lines = [json.loads(line) for line in (out / "metrics.jsonl").read_text().splitlines()]
    assert [line["update"] for line in lines] == [1, 2, 3, 4]


def test_the_train_env_deals_the_rust_trainers_games_and_maps_other_play_views():
    """Without symmetries a row's view is its seat's observation of the game the Rust
    trainer deals for the seed; under Other-Play the seats of one game see it through
    their own symmetries (so their colour labels differ in some games), and actions chosen
    in a view step the true game legally, for many steps of random play."""
    plain = yokai.TrainEnv("quick", seed=4, set=["ppo.num_envs=6"])
    vec = yokai.VecEnv("9c-2p-perfect", num_envs=6, seed=yokai.derive_seed(4, 0xE5), obs="graph", dtype="float32")
    want = vec.reset()
    view = plain.observe()
    np.testing.assert_array_equal(view["obs"], want["obs"].reshape(view["obs"].shape))
    np.testing.assert_array_equal(view["legal_mask"], want["legal_mask"].reshape(12, -1).astype(np.float32))
    assert view["keep"].tolist() == [0.0] * 12
    op = yokai.TrainEnv("quick-op", seed=4, set=["ppo.num_envs=16"])
    rng = np.random.default_rng(0)
    differing, ended = 0, 0
    for _ in range(300):
        v = op.observe()
        truth = v["truth"].reshape(16, 2, -1)
        differing += int((truth[:, 0] != truth[:, 1]).any(axis=1).sum())
        # The END column: what ending pays, where the acting seat may end.
        acting_rows = np.arange(16) * 2 + v["acting_seat"]
        end_legal = v["legal_mask"][acting_rows, op.end_action] > 0
        assert np.all(v["end_reward"][~end_legal] == 0)
        actions = [rng.choice(np.flatnonzero(m)) for m in v["legal_mask"]]
        step = op.step(np.array(actions))
        ended += int(step["done"].sum())
    assert differing > 100 and ended > 0
    with pytest.raises(yokai.IllegalActionError):
        op.step(np.full(32, op.num_actions + 5))
    with pytest.raises(ValueError, match="shape"):
        op.step(np.zeros(31, dtype=np.int64))


def test_bad_configs_and_fields_it_does_not_train_are_named():
    with pytest.raises(yokai.ConfigError, match="not a preset"):
        yokai.TrainEnv("qiuck")
    with pytest.raises(yokai.ConfigError, match="ppo.lr"):
        yokai.TrainEnv("quick", set=["ppo.lr=fast"])
    with pytest.raises(ValueError, match="obl.level"):
        Trainer("obl-quick")
    with pytest.raises(ValueError, match="network.encoder"):
        Trainer("ippo-9c-2p")


def test_the_torch_trainer_learns_the_main_jobs_preset():
    """The learning test of the PyTorch trainer: ``quick`` (the main job's preset: pointer
    head, pooled END, END term, belief loss, central critic), seed 0, 150 updates (307k
    steps) on the CPU. Its training games' mean R over updates 131-150 must beat the first
    10 updates' by 2 points, and random legal play's R −4.0 by 2.5. Measured 2026-11-25 on the
    2-core development machine: −4.16 → −0.17, 71 s."""
    torch.set_num_threads(1)
    t = Trainer("quick", seed=0)
    rewards = []
    for _ in range(150):
        g = t.step()["games"]
        rewards.append(g["reward"] if g else float("nan"))
    first, last = np.nanmean(rewards[:10]), np.nanmean(rewards[-20:])
    print(f"torch quick: first 10 updates R {first:.2f}, updates 131-150 R {last:.2f}")
    assert last > first + 2.0, (first, last)
    assert last > -4.0 + 2.5, last


@pytest.mark.parametrize("symmetries", ["none", "both"])
def test_the_learner_replays_the_rollout_exactly_with_and_without_other_play(symmetries):
    """The first minibatch, before its step, recomputes the rollout's log-probabilities
    from the states stored at the rollout's start: equal up to float rounding, with and
    without Other-Play's views. A learner that saw other views, states or actions than the
    rollout did (a wrong row order, a lost episode reset, an action in the wrong frame)
    shows here."""
    algorithm = ["algorithm.name=op", f"algorithm.symmetries={symmetries}"] if symmetries != "none" else []
    t = Trainer(_write(EVERY_LAYER), overrides=algorithm + ["ppo.rollout_steps=32"])
    for _ in range(2):
        stats = t.step()
        assert stats["replay_error"] < 1e-4, stats
        assert all(np.isfinite(stats[k]) for k in ("policy_loss", "value_loss", "grad_norm"))


def test_draw_follows_the_probabilities_and_never_draws_an_impossible_action():
    """The rollout's sampler: over 200,000 draws of one row each action's share is within
    0.005 of its probability, the actions of probability 0 (first, middle, last) never
    come, and a generator's seed gives the same draws."""
    from yokai.torch_train.ppo import draw

    probs = torch.tensor([0.0, 0.1, 0.0, 0.25, 0.05, 0.6, 0.0])
    rows = probs.repeat(200_000, 1)
    drawn = draw(rows, torch.Generator().manual_seed(7))
    share = torch.bincount(drawn, minlength=7).double() / len(drawn)
    assert (share[[0, 2, 6]] == 0).all(), share
    np.testing.assert_allclose(share.numpy(), probs.double().numpy(), atol=0.005)
    again = draw(rows[:1000], torch.Generator().manual_seed(7))
    assert torch.equal(again, drawn[:1000])
    # Unnormalised rows (a softmax's rounding) are read as their own total: the same
    # uniforms give the same draws (a draw that ignored the total would not).
    assert torch.equal(draw(rows[:1000] * 3.0, torch.Generator().manual_seed(7)), drawn[:1000])

"""The PyTorch example (python/examples/ppo_torch.py) trains for a few updates on the CPU.

Skipped where PyTorch is not installed (it is not a dependency of the package)."""

import importlib.util
import math
import pathlib
import sys

import pytest

torch = pytest.importorskip("torch")

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "ppo_torch.py"


def load_example():
    spec = importlib.util.spec_from_file_location("ppo_torch", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules["ppo_torch"] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def test_ppo_torch_runs_updates_on_cpu_with_legal_actions(tmp_path):
    example = load_example()
    log_file = tmp_path / "log.jsonl"
    # 8 games x 40 steps: every game ends at least once (a 9c-2p game lasts at most 32 steps),
    # and VecEnv.step raises IllegalActionError if the masked sampler ever picks an illegal
    # action for the acting seat or anything but NOOP for a waiting one.
    argv = ["--num-envs", "8", "--rollout-steps", "40", "--minibatches", "2", "--epochs", "2",
            "--hidden", "32", "--filters", "8", "--max-updates", "2", "--device", "cpu",
            "--threads", "1", "--log", str(log_file), "--tensorboard", str(tmp_path / "tb")]
    log = example.main(argv)
    assert [line["update"] for line in log] == [1, 2]
    assert [line["env_steps"] for line in log] == [8 * 40, 2 * 8 * 40]
    assert log_file.read_text().count("\n") == 2
    for line in log:
        assert line["games"] >= 8
        # R is an integer per game: the update's mean
        # times its number of games is a whole number, and so is the count of early ends.
        assert line["reward"] * line["games"] == pytest.approx(round(line["reward"] * line["games"]), abs=1e-6)
        assert line["early_end"] * line["games"] == pytest.approx(round(line["early_end"] * line["games"]), abs=1e-6)
        assert 0 <= line["early_end"] <= 1
        assert all(math.isfinite(line[k]) for k in ("policy_loss", "value_loss", "entropy"))
        # The masked entropy of a near-uniform initial policy over the legal moves is large.
        assert line["entropy"] > 1.0
    # The same figures in TensorBoard, at the env steps, read back with TensorBoard's reader.
    accumulator = pytest.importorskip("tensorboard.backend.event_processing.event_accumulator")
    acc = accumulator.EventAccumulator(str(tmp_path / "tb"))
    acc.Reload()
    for tag, key in [("games/reward", "reward"), ("train/policy_loss", "policy_loss")]:
        points = acc.Scalars(tag)
        assert [p.step for p in points] == [line["env_steps"] for line in log]
        assert [p.value for p in points] == pytest.approx([line[key] for line in log], rel=1e-6)


def test_ppo_torch_defaults_are_the_paper_preset_of_yokai_train(capsys):
    example = load_example()
    with pytest.raises(SystemExit):
        example.parse_args(["--help"])
    text = capsys.readouterr().out
    assert "--entropy-coef" in text and "--rollout-steps" in text
    # The example and `yokai train ippo-9c-2p` must train the same thing by default: what the
    # shipped preset states is what the example's flags default to.
    try:
        import tomllib
    except ModuleNotFoundError:  # Python < 3.11: the test extra installs tomli
        import tomli as tomllib
    preset = pathlib.Path(__file__).resolve().parents[2] / "configs" / "ippo-9c-2p.toml"
    config = tomllib.loads(preset.read_text())
    args = example.parse_args([])
    assert args.config == config["game"]
    for key, value in config["ppo"].items():
        assert getattr(args, key) == value, key


def test_ppo_torch_resumes_from_its_checkpoint_on_the_full_schedule(tmp_path):
    example = load_example()
    ckpt = str(tmp_path / "run.pt")
    small = ["--num-envs", "4", "--rollout-steps", "8", "--minibatches", "2", "--epochs", "1",
             "--hidden", "16", "--filters", "4", "--device", "cpu", "--threads", "1",
             "--total-steps", str(4 * 8 * 4), "--checkpoint", ckpt]
    first = example.main(small + ["--max-updates", "2"])
    assert [line["update"] for line in first] == [1, 2]
    rest = example.main(small + ["--resume", "true"])
    # The run goes on at update 3 of 4, with the learning rate annealed over all 4.
    assert [line["update"] for line in rest] == [3, 4]
    assert [line["env_steps"] for line in rest] == [3 * 32, 4 * 32]
    assert rest[0]["lr"] == pytest.approx(3e-4 * (1 - 2 / 4))
    saved = torch.load(ckpt)
    assert saved["update"] == 4
    with pytest.raises(SystemExit, match="--checkpoint"):
        example.main(["--resume", "true", "--device", "cpu"])


def test_ppo_torch_asks_for_wandb_by_name_when_it_is_missing(monkeypatch):
    example = load_example()
    monkeypatch.setitem(sys.modules, "wandb", None)  # as if not installed
    with pytest.raises(SystemExit, match="pip install wandb"):
        example.main(["--num-envs", "2", "--rollout-steps", "2", "--max-updates", "1", "--device", "cpu",
                      "--hidden", "8", "--filters", "4", "--wandb-project", "yokai-test"])


def test_ppo_torch_learns_what_its_shaped_return_pays_for(tmp_path):
    """40 updates of 64 games × 32 steps (82k env steps, about 20 s on 2 cores) with a small
    network: the shaping reward pays for every card observed and hint placed, so games that
    go on pay more than an early END, and the policy learns to stop ENDing. Random play
    ENDs early in 64 % of games; measured here: 66 % in the first update, 3–8 % in the last
    five. The test asks for a fall from at least 55 % to at most 20 %."""
    example = load_example()
    argv = ["--num-envs", "64", "--rollout-steps", "32", "--minibatches", "2", "--epochs", "2",
            "--hidden", "64", "--filters", "16", "--lr", "1e-3", "--max-updates", "40",
            "--device", "cpu", "--threads", "2"]
    log = example.main(argv)
    first = sum(line["early_end"] for line in log[:2]) / 2
    last = sum(line["early_end"] for line in log[-5:]) / 5
    assert first >= 0.55, f"the first updates should END as random play does, got {first:.2f}"
    assert last <= 0.20, f"no learning: early END rate {first:.2f} -> {last:.2f}"

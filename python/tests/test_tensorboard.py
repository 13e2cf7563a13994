"""`yokai train` writes TensorBoard event files that TensorBoard's own reader reads, with the
figures of metrics.jsonl at each update's env steps, across a stop and a resume."""

import json

import pytest

from training import TINY, train_tiny

# 256 steps of 8 games x 8 steps: four updates, each logged.
CONFIG = TINY.replace("total_steps = 128", "total_steps = 256") + "[run]\nlog_every = 1\n"


def test_event_files_hold_the_metrics_across_a_resume(tmp_path):
    accumulator = pytest.importorskip("tensorboard.backend.event_processing.event_accumulator")
    train_tiny(tmp_path, CONFIG, "--max-updates", "2")
    run = train_tiny(tmp_path, CONFIG, "--resume")
    files = sorted(run.glob("events.out.tfevents.*"))
    assert len(files) == 2, files  # one per start

    acc = accumulator.EventAccumulator(str(run), size_guidance={accumulator.SCALARS: 0})
    acc.Reload()
    lines = [json.loads(line) for line in (run / "metrics.jsonl").read_text().splitlines()]
    assert [line["update"] for line in lines] == [1, 2, 3, 4]
    tags = acc.Tags()["scalars"]
    for tag, read in [
        ("train/policy_loss", lambda m: m["policy_loss"]),
        ("train/value_loss", lambda m: m["value_loss"]),
        ("train/lr", lambda m: m["lr"]),
    ]:
        assert tag in tags, tags
        points = acc.Scalars(tag)
        assert [p.step for p in points] == [m["env_steps"] for m in lines], tag
        for p, m in zip(points, lines, strict=True):
            assert p.value == pytest.approx(read(m), rel=1e-6, abs=1e-7), tag
    # Games finished in some update: their figures are under games/.
    with_games = [m for m in lines if m["games"]]
    assert with_games, "no game ended in 256 steps"
    rewards = {p.step: p.value for p in acc.Scalars("games/reward")}
    for m in with_games:
        assert rewards[m["env_steps"]] == pytest.approx(m["games"]["reward"], rel=1e-6)

"""The helper scripts that the results pages name as their commands (scripts/)."""

import json
import pathlib
import subprocess
import sys

SCRIPTS = pathlib.Path(__file__).resolve().parents[2] / "scripts"


def run_updates(*args):
    return subprocess.run(
        [sys.executable, str(SCRIPTS / "updates.py"), *map(str, args)],
        capture_output=True,
        text=True,
    )


def write_run(directory, rows):
    directory.mkdir()
    (directory / "metrics.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))


def test_updates_averages_each_field_over_each_inclusive_range(tmp_path):
    run = tmp_path / "seed-0"
    # update u: reward u, value loss 10 u; update 3's rollout finished no game.
    write_run(
        run,
        [
            {"update": u, "value_loss": 10.0 * u, "games": None if u == 3 else {"reward": float(u)}}
            for u in range(1, 7)
        ],
    )
    out = run_updates("--ranges", "1-3,4-6", "--field", "games.reward", "--field", "value_loss", run)
    assert out.returncode == 0, out.stderr
    last = out.stdout.strip().splitlines()[-1]
    # rewards 1, 2 (update 3 has none) -> 1.50; 4, 5, 6 -> 5.00; value loss 20.00, 50.00
    assert last == f"| {run} | 1.50 | 5.00 | 20.00 | 50.00 |"


def test_updates_names_the_run_and_range_without_data(tmp_path):
    run = tmp_path / "seed-0"
    write_run(run, [{"update": 1, "value_loss": 1.0, "games": None}])
    out = run_updates("--ranges", "1-1", "--field", "games.reward", run)
    assert out.returncode != 0
    assert "no `games.reward` in updates 1-1" in out.stderr and str(run) in out.stderr


def test_updates_sums_joined_fields_over_a_range_with_sum(tmp_path):
    run = tmp_path / "seed-0"
    write_run(
        run,
        [{"update": u, "learn_seconds": 1.0 * u, "rollout_seconds": 0.5, "games": None} for u in range(1, 5)],
    )
    out = run_updates("--sum", "--ranges", "1-2,3-4", "--field", "learn_seconds+rollout_seconds", run)
    assert out.returncode == 0, out.stderr
    # (1 + 0.5) + (2 + 0.5) = 4.00; (3 + 0.5) + (4 + 0.5) = 8.00
    assert out.stdout.strip().splitlines()[-1] == f"| {run} | 4.00 | 8.00 |"

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


def run_kernel_times(*args):
    return subprocess.run(
        [sys.executable, str(SCRIPTS / "cubecl-kernel-times.py"), *map(str, args)],
        capture_output=True,
        text=True,
    )


def test_cubecl_kernel_times_sums_by_family_and_lists_a_familys_kernels(tmp_path):
    import lzma

    log = tmp_path / "cubecl.log.xz"
    lines = [
        "[START_KERNEL_COMPILATION]",  # not a launch: skipped
        "| 2ms       | ReduceKernel | TensorArgs_88872be8",
        "| 2ms       | ReduceKernel | TensorArgs_88872be8",
        "| 500µs     | ReduceKernel | TensorArgs_38f8a462",
        "| 1.5ms     | MatmulEntry | TensorArgs | DynamicScalar",
        "| 1000ns    | FullKernel_c9d6915a",
        "| 999µs     | FullKernel_0a1b2c3d",
    ]
    with lzma.open(log, "wt") as f:
        f.write("\n".join(lines) + "\n")
    out = run_kernel_times(log)
    assert out.returncode == 0, out.stderr
    rows = out.stdout.strip().splitlines()
    # 4.5 ms + 1.5 ms + 1 ms = 7 ms in 6 launches; families largest first, hashes cut off.
    assert rows[0] == f"{log}: 0.01 s in 6 launches"
    assert rows[1].split()[-1] == "ReduceKernel" and "3 launches" in rows[1] and "64.3 %" in rows[1]
    assert rows[2].endswith("Matmul TensorArgs") and "1 launches" in rows[2]
    assert rows[3].endswith("FullKernel") and "2 launches" in rows[3] and "14.3 %" in rows[3]
    out = run_kernel_times(log, "--family", "ReduceKernel")
    rows = out.stdout.strip().splitlines()
    # One kernel of the family at a time: the 2-launch one first, its median 2 ms.
    assert "2 launches, median     2000.0 µs" in rows[1] and rows[1].endswith("TensorArgs_88872be8")
    assert rows[2].endswith("TensorArgs_38f8a462")
    out = run_kernel_times(tmp_path / "missing.log")
    assert out.returncode != 0 and "missing.log: cannot be read" in out.stderr

"""The Python benchmark runs and reports both loops."""

import json

from yokai import bench


def test_bench_reports_rust_and_python_rates(capsys):
    bench.main(["--configs", "9c-2p-perfect", "--envs", "64", "--dtypes", "uint8", "--seconds", "0.2", "--json"])
    row = json.loads(capsys.readouterr().out.strip())
    assert row["config"] == "9c-2p-perfect" and row["num_envs"] == 64
    assert row["rust_steps_per_s"] > 0 and row["python_steps_per_s"] > 0
    assert abs(row["python_share"] - row["python_steps_per_s"] / row["rust_steps_per_s"]) < 1e-9

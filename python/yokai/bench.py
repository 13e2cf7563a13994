"""Steps per second of :class:`yokai.VecEnv` from Python: ``python -m yokai.bench``.

For each setting it times two loops over the same environment and sampler:

- ``rust``: random legal actions stepped entirely in Rust (``VecEnv.run_random``), the
  same loop as ``yokai bench``;
- ``python``: a Python loop of ``sample_actions()`` + ``step()``, receiving the NumPy
  views every step, as a Python trainer would;

and prints both in game steps per second (one seat acting, as the paper counts) and the
share of the Rust rate that survives the binding.
"""

from __future__ import annotations

import argparse
import json
import time

from ._core import VecEnv


def _rate(run_one, num_envs: int, seconds: float) -> float:
    """Env steps/s of `run_one()` (one batched step per call) over about `seconds`."""
    warmup_end = time.perf_counter() + min(0.5, seconds / 5)
    while time.perf_counter() < warmup_end:
        run_one()
    calls = 0
    start = time.perf_counter()
    while True:
        for _ in range(8):
            run_one()
        calls += 8
        elapsed = time.perf_counter() - start
        if elapsed >= seconds:
            return calls * num_envs / elapsed


def measure(config: str, num_envs: int, dtype: str, obs: str, seconds: float, threads=None) -> dict:
    env = VecEnv(config, num_envs=num_envs, seed=0, obs=obs, dtype=dtype, threads=threads)
    env.reset()
    counter = [0]

    def rust_step():
        env.run_random(1, counter[0])
        counter[0] += 1

    def python_step():
        env.step(env.sample_actions(counter[0]))
        counter[0] += 1

    rust = _rate(rust_step, num_envs, seconds)
    python = _rate(python_step, num_envs, seconds)
    return {
        "config": config,
        "num_envs": num_envs,
        "dtype": dtype,
        "obs": obs,
        "rust_steps_per_s": rust,
        "python_steps_per_s": python,
        "python_share": python / rust,
    }


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(
        prog="python -m yokai.bench",
        description="Time yokai.VecEnv from Python against the same loop in Rust.",
    )
    parser.add_argument("--configs", nargs="+", default=["9c-2p-perfect", "16c-2p-perfect"])
    parser.add_argument("--envs", nargs="+", type=int, default=[1024])
    parser.add_argument("--dtypes", nargs="+", default=["float32", "uint8"])
    parser.add_argument("--obs", default="image", help="observation encoding (default image)")
    parser.add_argument("--seconds", type=float, default=2.0, help="timed seconds per loop")
    parser.add_argument("--threads", type=int, default=None, help="worker threads (default: all cores)")
    parser.add_argument("--json", action="store_true", help="print JSON lines instead of a table")
    args = parser.parse_args(argv)
    if not args.json:
        print(f"{'config':<16} {'games':>6} {'dtype':<8} {'rust steps/s':>14} {'python steps/s':>15} {'python/rust':>12}")
    for config in args.configs:
        for num_envs in args.envs:
            for dtype in args.dtypes:
                row = measure(config, num_envs, dtype, args.obs, args.seconds, args.threads)
                if args.json:
                    print(json.dumps(row))
                else:
                    print(
                        f"{config:<16} {num_envs:>6} {dtype:<8} {row['rust_steps_per_s']:>14,.0f} "
                        f"{row['python_steps_per_s']:>15,.0f} {row['python_share']:>11.1%}"
                    )


if __name__ == "__main__":
    main()

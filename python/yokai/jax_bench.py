"""Env steps per second of :mod:`yokai.jax` under ``jit``: ``python -m yokai.jax_bench``.

For each number of games it times three loops that play pseudo-random legal actions:

- ``jit``: ``jax.lax.scan`` over ``--steps`` steps of ``jax.vmap(YokaiEnv.step)``, the
  whole scan jitted (compilation excluded), as a JaxMARL training loop runs it;
- ``host``: the same batched engine calls (``PackedGames.step``) from a NumPy loop, with
  no JAX, timing the calls alone: what the engine, the packed state and writing every
  observation in full cost;
- ``vec_env``: ``VecEnv.step`` from a Python loop, the interface that keeps the games in
  Rust.

``round_trip_us`` is what each jitted step costs beyond the engine call: the callback's
hand-over, the copies of the state and observations, and the action choice in JAX.
"""

from __future__ import annotations

import argparse
import json
import platform
import time

import jax
import jax.numpy as jnp
import numpy as np

from . import _core
from .jax import YokaiEnv


def _pick(legal, salt):
    """A pseudo-random legal action per row of ``legal`` ``[..., A]`` from integer hashing
    (the host loop hashes the same way): cheap next to the step, unlike a categorical."""
    a = jnp.arange(legal.shape[-1], dtype=jnp.uint32)
    h = (a * jnp.uint32(2654435761) + salt[..., None] * jnp.uint32(40503)) >> 16
    return jnp.argmax(jnp.where(legal, h.astype(jnp.int32) + 1, 0), axis=-1)


def jit_rate(config: str, num_envs: int, steps: int, repeats: int) -> float:
    env = YokaiEnv(config)

    def step(states, t):
        legal = jax.vmap(env.get_avail_actions)(states)
        salt = (t * jnp.uint32(num_envs) + jnp.arange(num_envs, dtype=jnp.uint32))[:, None]
        acts = {a: _pick(legal[a], salt[:, 0] + i) for i, a in enumerate(env.agents)}
        keys = jnp.zeros((num_envs, 2), jnp.uint32)
        _, states, r, _, _ = jax.vmap(env.step)(keys, states, acts)
        return states, r["__all__"]

    @jax.jit
    def run(states, t0):
        return jax.lax.scan(step, states, t0 + jnp.arange(steps, dtype=jnp.uint32))

    _, states = jax.jit(jax.vmap(env.reset))(jax.random.split(jax.random.PRNGKey(0), num_envs))
    states, r = run(states, jnp.uint32(0))  # compile
    jax.block_until_ready(r)
    start = time.perf_counter()
    for k in range(repeats):
        states, r = run(states, jnp.uint32((k + 1) * steps))
    jax.block_until_ready(r)
    return repeats * steps * num_envs / (time.perf_counter() - start)


def host_rate(config: str, num_envs: int, steps: int, repeats: int) -> float:
    games = _core.PackedGames(config)
    streams = np.arange(num_envs, dtype=np.uint64)
    out = games.reset(streams)
    a = np.arange(games.num_actions, dtype=np.uint32) * np.uint32(2654435761)
    envs = np.arange(num_envs, dtype=np.uint32)
    spent = 0.0
    for t in range(repeats * steps):
        salt = np.uint32(t) * np.uint32(num_envs) + envs
        seats = np.stack([salt + np.uint32(i) for i in range(games.num_players)], axis=1)
        h = ((a + seats[..., None] * np.uint32(40503)) >> 16).astype(np.int32) + 1
        acts = np.where(out["legal_mask"], h, 0).argmax(-1).astype(np.uint32)
        start = time.perf_counter()
        out = games.step(out["state"], streams, out["episode"], acts, True)
        spent += time.perf_counter() - start
    return repeats * steps * num_envs / spent


def vec_env_rate(config: str, num_envs: int, steps: int, repeats: int) -> float:
    env = _core.VecEnv(config, num_envs=num_envs, seed=0)
    env.reset()
    start = time.perf_counter()
    for t in range(repeats * steps):
        env.step(env.sample_actions(t))
    return repeats * steps * num_envs / (time.perf_counter() - start)


def main(argv=None) -> list:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", default="9c-2p-perfect")
    ap.add_argument("--envs", type=int, nargs="+", default=[1024, 4096])
    ap.add_argument("--steps", type=int, default=128, help="steps per jitted scan")
    ap.add_argument("--repeats", type=int, default=3, help="scans timed per setting")
    ap.add_argument("--json", help="write the rows here")
    args = ap.parse_args(argv)
    rows = []
    for n in args.envs:
        row = {"config": args.config, "num_envs": n}
        for name, fn in (("jit", jit_rate), ("host", host_rate), ("vec_env", vec_env_rate)):
            row[name] = fn(args.config, n, args.steps, args.repeats)
        row["round_trip_us"] = 1e6 * n * (1 / row["jit"] - 1 / row["host"])
        rows.append(row)
        print(
            f"{args.config} {n:6d} games: jit {row['jit']:10,.0f}  host {row['host']:10,.0f}  "
            f"VecEnv {row['vec_env']:10,.0f} env steps/s; round trip {row['round_trip_us']:,.0f} µs per step"
        )
    if args.json:
        meta = {"machine": platform.processor() or platform.machine(), "jax": jax.__version__, "rows": rows}
        with open(args.json, "w") as f:
            json.dump(meta, f, indent=2)
    return rows


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Ablation of training levers: each variant of a base config is trained on the same seeds
and budget, then every seed's policy plays self-play games with `yokai eval`. Prints a
Markdown table (SP R per seed, mean ± SE over seeds, wall clock per seed) and writes it to
OUT/ablation.md.

    scripts/ablation.py --base quick --steps 600000 --seeds 0,1,2 --games 1000 \\
        baseline dense:network.head=dense cluster:ppo.cluster_shaping=1.0

A variant is `NAME` (the base as it is) or `NAME:key=value,key=value` with dotted keys of
the training config (docs/training.md); values are TOML values (`1.0`, `true`, `"dense"`
or a bare word, taken as a string). Run it with nothing else on the machine: the wall clock
is part of the table.
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys
import time
import tomllib

ROOT = pathlib.Path(__file__).resolve().parent.parent


def toml_value(text):
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text  # a bare word: a string


def dump_toml(config):
    """The config (top-level scalars and one level of tables of scalars) as TOML."""

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v)
        return repr(v)

    lines = [f"{k} = {value(v)}" for k, v in config.items() if not isinstance(v, dict)]
    for k, table in config.items():
        if isinstance(table, dict):
            lines += ["", f"[{k}]"] + [f"{kk} = {value(vv)}" for kk, vv in table.items()]
    return "\n".join(lines) + "\n"


def variant_config(base, spec):
    name, _, changes = spec.partition(":")
    config = json.loads(json.dumps(base))
    for change in filter(None, changes.split(",")):
        key, eq, text = change.partition("=")
        if not eq or "." not in key:
            sys.exit(f"variant {name!r}: {change!r} is not key.sub=value")
        table, field = key.split(".", 1)
        config.setdefault(table, {})[field] = toml_value(text)
    return name, config


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("variants", nargs="+", help="NAME or NAME:key=value,...")
    ap.add_argument("--base", default="quick", help="a preset in configs/ or a TOML file")
    ap.add_argument("--steps", type=int, required=True, help="environment steps per seed")
    ap.add_argument("--seeds", default="0,1,2")
    ap.add_argument("--games", type=int, default=1000, help="self-play games per seed")
    ap.add_argument("--out", default="runs/ablation")
    ap.add_argument("--yokai", default=str(ROOT / "target/release/yokai"))
    ap.add_argument("--threads", type=int, help="worker threads per training run (default: all)")
    args = ap.parse_args()

    base_path = pathlib.Path(args.base)
    if not base_path.exists():
        base_path = ROOT / "configs" / f"{args.base}.toml"
    base = tomllib.loads(base_path.read_text())
    base.setdefault("ppo", {})["total_steps"] = args.steps
    seeds = [int(s) for s in args.seeds.split(",")]
    out = pathlib.Path(args.out)
    rows = []
    for spec in args.variants:
        name, config = variant_config(base, spec)
        vdir = out / name
        vdir.mkdir(parents=True, exist_ok=True)
        cfg = vdir / f"{name}.toml"
        cfg.write_text(dump_toml(config))
        rewards, seconds = [], []
        for seed in seeds:
            start = time.time()
            subprocess.run(
                [args.yokai, "train", str(cfg), "--seeds", str(seed), "--eval-games", "0",
                 "--out", str(vdir)]
                + (["--threads", str(args.threads)] if args.threads else []),
                check=True, stdout=subprocess.DEVNULL,
            )
            seconds.append(time.time() - start)
            edir = vdir / f"eval-seed-{seed}"
            subprocess.run(
                [args.yokai, "eval", str(vdir / f"seed-{seed}"), "--games", str(args.games),
                 "--out", str(edir)],
                check=True, stdout=subprocess.DEVNULL,
            )
            rewards.append(json.loads((edir / "matrix.json").read_text())[0]["metrics"]["reward"])
            print(f"{name} seed {seed}: SP R {rewards[-1]:.2f} in {seconds[-1]:.0f} s",
                  file=sys.stderr)
        mean = sum(rewards) / len(rewards)
        se = (math.sqrt(sum((r - mean) ** 2 for r in rewards) / (len(rewards) - 1) / len(rewards))
              if len(rewards) > 1 else float("nan"))
        rows.append((spec, rewards, mean, se, sum(seconds) / len(seconds)))
    table = [
        f"base `{base_path.name}`, {args.steps:,} steps, seeds {args.seeds}, "
        f"{args.games:,} self-play games per seed",
        "",
        "| variant | SP R per seed | mean ± SE | s per seed |",
        "|---|---|---|---|",
    ] + [
        f"| `{spec}` | {', '.join(f'{r:.2f}' for r in rewards)} | {mean:.2f} ± {se:.2f} | {secs:.0f} |"
        for spec, rewards, mean, se, secs in rows
    ]
    text = "\n".join(table) + "\n"
    (out / "ablation.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

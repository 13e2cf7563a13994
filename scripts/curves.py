#!/usr/bin/env python3
"""Learning curves of groups of runs side by side, as a Markdown table: at each env-step
point, the mean ± SE over a group's seeds of its training games' R and SEE, each seed's
value the mean over the updates in the window that ends at the point (with --ee also the
share of games ENDed early and their length). Reads the
metrics.jsonl of run directories from `yokai train` and `python -m yokai.torch_train`
alike. Then each group's speed: per seed the mean env steps/s of its updates after the
first 10 (start-up), and their sum (the machine's, for seeds run side by side).

    scripts/curves.py --at 0.5e6,1e6,2e6 --window 2e5 rust=runs/a/seed-0,runs/a/seed-1 torch=runs/t/seed-0,...
"""

import argparse
import json
import pathlib

from stats import mean_se


def series(run: str):
    """(env_steps, R, SEE, EE, LEN) of every update of `run` whose rollout finished a game."""
    out = []
    for line in (pathlib.Path(run) / "metrics.jsonl").read_text().splitlines():
        d = json.loads(line)
        if d.get("games"):
            g = d["games"]
            out.append((d["env_steps"], g["reward"], g["successful_early_end"], g["early_end"], g["length"]))
    return out


def speed(run: str) -> float:
    """Mean env steps/s of `run`'s updates after the first 10."""
    lines = [json.loads(l) for l in (pathlib.Path(run) / "metrics.jsonl").read_text().splitlines()][10:]
    if not lines:
        raise SystemExit(f"{run}: no update after the 10th")
    return sum(d["sps"] for d in lines) / len(lines)


def at(points, step: float, window: float, k: int) -> float:
    inside = [p[k] for p in points if step - window < p[0] <= step]
    if not inside:
        raise SystemExit(f"no update between {step - window:,.0f} and {step:,.0f} env steps")
    return sum(inside) / len(inside)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--at", required=True, help="env-step points, comma-separated (1e6 allowed)")
    p.add_argument("--window", type=float, default=2e5, help="env steps averaged before each point")
    p.add_argument("--ee", action="store_true", help="also the share ENDed early (EE %%) and LEN")
    p.add_argument("groups", nargs="+", help="NAME=RUN[,RUN...]")
    args = p.parse_args()
    points = [float(x) for x in args.at.split(",")]
    groups = [(g.split("=", 1)[0], [series(r) for r in g.split("=", 1)[1].split(",")]) for g in args.groups]
    columns = [(1, 1.0, "R"), (2, 100.0, "SEE %")] + ([(3, 100.0, "EE %"), (4, 1.0, "LEN")] if args.ee else [])
    head = ["env steps"] + [f"{name} {label}" for _, _, label in columns for name, _ in groups]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for step in points:
        cells = []
        for k, scale, _ in columns:
            for _, runs in groups:
                m, se = mean_se([scale * at(r, step, args.window, k) for r in runs])
                cells.append(f"{m:.2f} ± {se:.2f}")
        print(f"| {step:,.0f} | " + " | ".join(cells) + " |")
    print()
    print("| group | env steps/s per seed (updates after the 10th) | together |")
    print("|---|---|---|")
    for g in args.groups:
        name, runs = g.split("=", 1)
        speeds = [speed(r) for r in runs.split(",")]
        print(f"| {name} | {', '.join(f'{x:,.0f}' for x in speeds)} | {sum(speeds):,.0f} |")


if __name__ == "__main__":
    main()

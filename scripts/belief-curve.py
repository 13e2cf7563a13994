#!/usr/bin/env python3
"""How well an OBL level's belief model reads the level below, as it trains: from each
run's `belief.jsonl` (one line per belief update, written by `yokai train` for OBL levels
≥ 2), the model's cross-entropy of the unseen cards' true colours against the first-hand
baseline's, in nats per unseen card, averaged (weighted by slots) over the `--window`
updates that end at each point of `--at`.

    scripts/belief-curve.py --at 300,1000,3000,10000 --window 100 runs/obl/level-2/seed-{0,1,2}

Prints a Markdown table, one row per point: each run's gain (baseline − model, above 0
where the belief reads more than first-hand knowledge), and their mean ± SE over runs.
"""
import argparse
import json
import pathlib
import sys

from stats import mean_se


def fail(message):
    sys.exit(f"belief-curve: {message}")


def read(run):
    path = pathlib.Path(run) / "belief.jsonl"
    try:
        lines = path.read_text().splitlines()
    except FileNotFoundError:
        fail(f"{path}: no such file (only OBL levels ≥ 2 train a belief)")
    rows = []
    for n, line in enumerate(lines, start=1):
        try:
            rows.append(json.loads(line))
        except json.JSONDecodeError as e:
            fail(f"{path}:{n}: not JSON ({e})")
    return path, rows


def gain(path, rows, end, window):
    if end > len(rows):
        fail(f"{path}: {len(rows)} updates, none at {end}")
    part = rows[max(0, end - window) : end]
    slots = sum(r["slots"] for r in part)
    if slots == 0:
        fail(f"{path}: no unseen cards in updates {end - len(part) + 1}-{end}")
    model = sum(r["cross_entropy"] * r["slots"] for r in part) / slots
    baseline = sum(r["first_hand_baseline"] * r["slots"] for r in part) / slots
    return baseline - model


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--at", required=True, help="update counts, comma-separated")
    parser.add_argument("--window", type=int, default=100)
    args = parser.parse_args()
    points = [int(float(x)) for x in args.at.split(",")]
    data = [read(run) for run in args.runs]
    print("| updates | " + " | ".join(args.runs) + " | mean ± SE |")
    print("|---|" + "---|" * (len(args.runs) + 1))
    for end in points:
        gains = [gain(path, rows, end, args.window) for path, rows in data]
        mean, se = mean_se(gains)
        cells = " | ".join(f"{g:.4f}" for g in gains)
        print(f"| {end} | {cells} | {mean:.4f} ± {se:.4f} |")


if __name__ == "__main__":
    main()

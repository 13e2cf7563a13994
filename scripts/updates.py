#!/usr/bin/env python3
"""Per run, the mean of metrics.jsonl fields over ranges of updates, as a Markdown table:
what a run did in its first updates (a restart's jolt) or its last ones, where
`scripts/curves.py` averages groups of seeds over env-step windows. A field is a key of
metrics.jsonl, dotted for the game figures (`games.reward`, `value_loss`), or several
joined by `+` for their sum per update (`learn_seconds+rollout_seconds`); ranges are update
numbers, 1-based and inclusive. `--sum` adds the updates of a range up instead of averaging
them (the seconds a stretch of the run took).

    scripts/updates.py --ranges 1-3,4-10,11-50,101-250 --field games.reward --field value_loss runs/a/seed-0 runs/a/seed-1
"""

import argparse
import json
import pathlib


def value(row: dict, field: str):
    """The field's value in one update's row, None where the row lacks it."""
    total = 0.0
    for name in field.split("+"):
        x = row
        for key in name.split("."):
            x = x.get(key) if isinstance(x, dict) else None
        if x is None:
            return None
        total += x
    return total


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--ranges", required=True, help="update ranges A-B, comma-separated")
    p.add_argument("--field", action="append", required=True, help="metrics field (repeatable)")
    p.add_argument("--sum", action="store_true", help="sum over each range instead of the mean")
    p.add_argument("runs", nargs="+", help="run directories (each with metrics.jsonl)")
    args = p.parse_args()
    ranges = [tuple(int(x) for x in r.split("-")) for r in args.ranges.split(",")]
    head = ["run"] + [f"{f} {a}–{b}" for f in args.field for a, b in ranges]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for run in args.runs:
        rows = [json.loads(l) for l in (pathlib.Path(run) / "metrics.jsonl").read_text().splitlines()]
        cells = []
        for f in args.field:
            for a, b in ranges:
                xs = [value(r, f) for r in rows if a <= r["update"] <= b]
                xs = [x for x in xs if x is not None]
                if not xs:
                    raise SystemExit(f"{run}: no `{f}` in updates {a}-{b}")
                cells.append(f"{sum(xs) if args.sum else sum(xs) / len(xs):.2f}")
        print(f"| {run} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()

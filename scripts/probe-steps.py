#!/usr/bin/env python3
"""The accuracies of a `yokai probe` run weighted by seat states, overall and over bins of
game steps: the linear probe of the memory, the first-hand oracle and, where the network
has one, the belief head, per run, setting and card set (all cards, unopened ones).

    scripts/probe-steps.py runs/probe/probe.csv --bins 0,10,20,30

`yokai probe`'s own table averages each step's accuracy over the steps (every step counts
alike, the late steps of the few long games as much as the first); this one weights each
step by its states (`rows`), as the states a policy meets come, and splits the game into
bins where the information arrives at different times. Each bin's cell gives the oracle,
the belief head and the states in the bin.
"""
import argparse
import csv
import pathlib
import sys


def weighted(rows, key):
    """Mean of `key` over `rows`, each weighted by its states; None without states or
    without the column (a probe of a network with no belief head)."""
    n = sum(int(r["rows"]) for r in rows)
    if n == 0 or any(r.get(key, "") == "" for r in rows):
        return None
    return sum(float(r[key]) * int(r["rows"]) for r in rows) / n


def percent(v):
    return "–" if v is None else f"{100 * v:.1f}"


def table(rows, starts):
    bins = list(zip(starts, starts[1:] + [None]))
    label = lambda lo, hi: f"steps {lo}–{hi - 1}" if hi is not None else f"steps {lo}–"
    out = [
        "| run | setting | cards | states | probe | oracle | belief head | "
        + " | ".join(f"oracle / head, {label(lo, hi)}" for lo, hi in bins)
        + " |",
        "|---|---|---|---|---|---|---|" + "---|" * len(bins),
    ]
    for run, setting in dict.fromkeys((r["run"], r["setting"]) for r in rows):
        for cards in ("all", "unseen"):
            rs = [r for r in rows if (r["run"], r["setting"], r["cards"]) == (run, setting, cards)]
            if not rs:
                continue
            cells = []
            for lo, hi in bins:
                b = [r for r in rs if int(r["step"]) >= lo and (hi is None or int(r["step"]) < hi)]
                states = sum(int(r["rows"]) for r in b)
                cells.append(
                    f"{percent(weighted(b, 'oracle'))} / {percent(weighted(b, 'head'))} ({states})"
                    if b
                    else "–"
                )
            out.append(
                f"| {run} | {setting} | {cards} | {sum(int(r['rows']) for r in rs)} | "
                f"{percent(weighted(rs, 'accuracy'))} | {percent(weighted(rs, 'oracle'))} | "
                f"{percent(weighted(rs, 'head'))} | " + " | ".join(cells) + " |"
            )
    return "\n".join(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", type=pathlib.Path, help="probe.csv written by `yokai probe`")
    parser.add_argument(
        "--bins", default="0,10,20,30", help="first game step of each bin, ascending (default 0,10,20,30)"
    )
    args = parser.parse_args()
    try:
        starts = [int(s) for s in args.bins.split(",")]
    except ValueError:
        sys.exit(f"--bins {args.bins!r}: give whole numbers separated by commas, e.g. 0,10,20,30")
    if starts != sorted(set(starts)) or starts[0] < 0:
        sys.exit(f"--bins {args.bins!r}: the steps must be distinct, ascending and not negative")
    try:
        with open(args.csv, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"probe-steps.py: cannot read {args.csv}: {e.strerror}")
    missing = {"run", "setting", "step", "cards", "accuracy", "oracle", "rows"} - set(rows[0] if rows else {})
    if missing:
        sys.exit(f"probe-steps.py: {args.csv} is not a `yokai probe` probe.csv (no {', '.join(sorted(missing))})")
    print(table(rows, starts))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Cross-play between groups of one saved evaluation: how the seeds of one run (a method, a
chain's level, a seed set) play with the seeds of another. `yokai eval A B -o FOLDER`
plays every pair of every group's seeds; its report gives each group's own self-play and
cross-play, and this script the rest, from `summary.json` and `matrix.json`:

    scripts/cross-groups.py runs/cross/eval
    scripts/cross-groups.py --names "OP 0-2,OP 3-5" runs/cross/eval

Prints, in Markdown, a table of groups × groups: on the diagonal the group's cross-play
(its pairs of distinct seeds), off it the mean R over every pair of one seed of each
group, ± the SE over those pairs (pairs share seeds, so the SE is a rough guide, smaller
than that of independent pairs); and each group's self-play (its seeds with themselves).
"""
import argparse
import pathlib
import sys

import evalfiles
from stats import mean_se


def fail(message):
    sys.exit(f"cross-groups: {message}")


def read_json(path):
    return evalfiles.read_json(path, "cross-groups")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("eval", help="a folder written by `yokai eval ... -o FOLDER`")
    parser.add_argument("--names", help="comma-separated short names, one per group, in order")
    args = parser.parse_args()
    folder = pathlib.Path(args.eval)
    groups = read_json(folder / "summary.json").get("groups", [])
    if len(groups) < 2:
        fail(f"{folder / 'summary.json'}: {len(groups)} group(s); cross-play between groups needs 2")
    names = [g["name"] for g in groups]
    if args.names:
        names = [n.strip() for n in args.names.split(",")]
        if len(names) != len(groups):
            fail(f"--names gives {len(names)} names for {len(groups)} groups")
    reward = {}
    for e in read_json(folder / "matrix.json"):
        r = e["metrics"]["reward"]
        reward[(e["row"], e["col"])] = r
        reward[(e["col"], e["row"])] = r

    def r_of(a, b):
        if (a, b) not in reward:
            fail(f"{folder / 'matrix.json'}: no pair {a} + {b}")
        return reward[(a, b)]

    def cell(ga, gb):
        if ga is gb:
            seeds = ga["seeds"]
            pairs = [(a, b) for i, a in enumerate(seeds) for b in seeds[i + 1:]]
        else:
            pairs = [(a, b) for a in ga["seeds"] for b in gb["seeds"]]
        if not pairs:
            return "–"
        m, se = mean_se([r_of(a, b) for a, b in pairs])
        return f"{m:.2f} ± {se:.2f}"

    print("| group | SP R | " + " | ".join(f"with {n}" for n in names) + " |")
    print("|---|---|" + "---|" * len(names))
    for name, ga in zip(names, groups):
        sp, sp_se = mean_se([r_of(s, s) for s in ga["seeds"]])
        cells = [cell(ga, gb) for gb in groups]
        print(f"| {name} | {sp:.2f} ± {sp_se:.2f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Self-play and cross-play of saved evaluations side by side, and the differences between
them: what a results page quotes when it compares runs (levels of a chain, a lever on and
off). Each EVAL is a folder written by `yokai eval RUN -o FOLDER` (its `summary.json` and
`matrix.json`), optionally named: `NAME=FOLDER`.

    scripts/compare-evals.py "level 1=runs/obl/level-1/eval" "level 2=runs/obl/level-2/eval"
    scripts/compare-evals.py --against first "300=runs/b300/eval" "3000=runs/b3000/eval"

Prints, in Markdown:
- per evaluation: SP R mean ± SE over the seeds, SP R per seed (the matrix's diagonal, in
  the summary's seed order), XP R mean ± SE, XP − SP, SP SEE % and LEN;
- per comparison (each evaluation against the one before it, or against the first with
  `--against first`): the difference of the SP means with SE = sqrt(se_a² + se_b²), and,
  when both hold the same seeds, the paired per-seed differences (seed N of B minus seed N
  of A) with their mean ± SE. Seeds are matched by the `seed-N` in their run names (seeds
  3–5 are not paired with seeds 0–2: other seeds are independent samples); runs named
  without one are paired in order when the counts agree.

Only the first group of each summary is read (`--group` picks another).
"""
import argparse
import math
import pathlib

import evalfiles
from stats import mean_se


def load(spec, group_index):
    name, eq, folder = spec.partition("=")
    if not eq:
        name, folder = spec, spec
    return {"name": name, **evalfiles.read_group(pathlib.Path(folder), group_index, "compare-evals")}


def pairing(a, b):
    """Why A and B cannot be paired seed by seed, or None when they can."""
    if len(a["per_seed"]) != len(b["per_seed"]):
        return "(seed counts differ)"
    if a["seed_numbers"] and b["seed_numbers"] and a["seed_numbers"] != b["seed_numbers"]:
        return "(other seeds: unpaired)"
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("evals", nargs="+", metavar="[NAME=]FOLDER")
    parser.add_argument("--against", choices=["previous", "first"], default="previous")
    parser.add_argument("--group", type=int, default=0)
    args = parser.parse_args()
    runs = [load(spec, args.group) for spec in args.evals]

    print("| evaluation | SP R per seed | SP R | XP R | XP − SP | SP SEE % | SP LEN |")
    print("|---|---|---|---|---|---|---|")
    for r in runs:
        sp, xp = r["sp"], r["xp"]
        seeds = ", ".join(f"{x:.2f}" for x in r["per_seed"])
        if xp and xp.get("entries", 0) > 0:
            xp_cell = f"{xp['reward']['mean']:.2f} ± {xp['reward']['se']:.2f}"
            gap = f"{xp['reward']['mean'] - sp['reward']['mean']:+.2f}"
        else:
            xp_cell, gap = "–", "–"
        print(
            f"| {r['name']} | {seeds} | {sp['reward']['mean']:.2f} ± {sp['reward']['se']:.2f} "
            f"| {xp_cell} | {gap} | {sp['see']['mean']:.1f} | {sp['length']['mean']:.1f} |"
        )

    if len(runs) < 2:
        return
    print()
    print("| comparison | SP difference (SE) | paired per seed | paired mean ± SE |")
    print("|---|---|---|---|")
    for i, b in enumerate(runs[1:], start=1):
        a = runs[0] if args.against == "first" else runs[i - 1]
        sa, sb = a["sp"]["reward"], b["sp"]["reward"]
        diff, se = sb["mean"] - sa["mean"], math.hypot(sa["se"], sb["se"])
        z = f"{diff / se:.1f} SE" if se > 0 else "–"
        why_not = pairing(a, b)
        if why_not is None:
            xs = [y - x for x, y in zip(a["per_seed"], b["per_seed"])]
            m, s = mean_se(xs)
            paired = ", ".join(f"{x:+.2f}" for x in xs)
            paired_mean = f"{m:+.2f} ± {s:.2f}"
        else:
            paired, paired_mean = why_not, "–"
        print(
            f"| {b['name']} − {a['name']} | {diff:+.2f} ({se:.2f}, {z}) | {paired} | {paired_mean} |"
        )


if __name__ == "__main__":
    main()

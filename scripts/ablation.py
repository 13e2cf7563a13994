#!/usr/bin/env python3
"""Ablation of training levers: each variant of a base config is trained on the same seeds
and budget, then evaluated with `yokai eval`. Prints a Markdown table (SP R per seed, mean ±
SE over seeds, wall clock) and writes it to OUT/ablation.md.

    scripts/ablation.py --base quick --steps 600000 --seeds 0,1,2 --games 1000 \\
        baseline dense:network.head=dense cluster:ppo.cluster_shaping=1.0

    scripts/ablation.py --base cpu --together --partners belief,greedy --games 5000 \\
        --out runs/cpu-40M-ablations base no-belief:ppo.belief_aux=0.0

A variant is `NAME` (the base as it is) or `NAME:key=value,key=value` with dotted keys of
the training config (docs/training.md), passed to `yokai train` as `--set key=value` (which
refuses an unknown field or a bad value). Each variant trains into OUT/NAME.

- By default the seeds train one after another (`--threads` each) and each seed plays
  `--games` self-play games alone (OUT/NAME/eval-seed-N).
- `--together` trains a variant's seeds side by side in one `yokai train` call, as the
  issue's targets are measured (3 seeds side by side on the machine), and the wall clock is
  the variant's; the variant is then evaluated as a whole: every pair of its seeds and each
  seed with every `--partners` bot, `--games` per pair (`yokai eval OUT/NAME [PARTNERS]
  --games G -o OUT/NAME/eval`), and the table gains cross-play between seeds. `--partners`
  alone also evaluates as a whole.
- `--resume` reads a variant whose evaluation is already in OUT/NAME (an interrupted
  ablation, or a variant measured before, copied in) instead of training and evaluating
  it again; its wall clock shows as –.

Run it with nothing else on the machine: the wall clock is part of the table.
"""
import argparse
import pathlib
import subprocess
import sys
import time

import evalfiles
from stats import mean_se

ROOT = pathlib.Path(__file__).resolve().parent.parent


def variant_sets(spec):
    """(NAME, ["--set", "key=value", ...]) of a variant `NAME[:key=value,...]`."""
    name, _, changes = spec.partition(":")
    sets = []
    for change in filter(None, changes.split(",")):
        key, eq, _ = change.partition("=")
        if not eq or "." not in key:
            sys.exit(f"variant {name!r}: {change!r} is not key.sub=value")
        sets += ["--set", change]
    return name, sets


def seeds_of_eval(folder, seeds):
    """SP R per seed (in `seeds` order) and the XP summary (mean and SE over the pairs of
    different seeds) of `yokai eval`'s folder for a variant. Seeds are known by the
    `seed-N` in their run names, so an evaluation made where the variant was first trained
    (and then copied or linked into OUT) reads the same."""
    group = evalfiles.read_group(folder, 0, "ablation.py")
    by_seed = dict(zip(group["seed_numbers"] or [], group["per_seed"]))
    missing = [s for s in seeds if s not in by_seed]
    if missing:
        sys.exit(f"ablation.py: {folder}: no self-play of seed(s) {missing}")
    return [by_seed[s] for s in seeds], group["xp"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("variants", nargs="+", help="NAME or NAME:key=value,...")
    ap.add_argument("--base", default="quick", help="a preset name or a TOML file")
    ap.add_argument("--steps", type=int, help="environment steps per seed (default: the base's)")
    ap.add_argument("--seeds", default="0,1,2")
    ap.add_argument("--games", type=int, default=1000, help="games per seed or per pair")
    ap.add_argument("--out", default="runs/ablation")
    ap.add_argument("--yokai", default=str(ROOT / "target/release/yokai"))
    ap.add_argument("--threads", type=int, help="worker threads per training run (default: all)")
    ap.add_argument("--together", action="store_true",
                    help="train a variant's seeds side by side in one call, evaluate them as a whole")
    ap.add_argument("--partners", default="",
                    help="bots each seed also plays with, e.g. belief,greedy (evaluates as a whole)")
    ap.add_argument("--resume", action="store_true",
                    help="read variants whose evaluation is already in OUT instead of running them again")
    args = ap.parse_args()

    variants = [variant_sets(spec) for spec in args.variants]
    seeds = [int(s) for s in args.seeds.split(",")]
    partners = [p for p in args.partners.split(",") if p]
    whole = args.together or bool(partners)
    out = pathlib.Path(args.out)
    common = (["--steps", str(args.steps)] if args.steps else []) + ["--eval-games", "0"] + (
        ["--threads", str(args.threads)] if args.threads else [])

    def train(vdir, sets, seeds_arg):
        start = time.time()
        subprocess.run([args.yokai, "train", args.base, *sets, "--seeds", seeds_arg, *common,
                        "--out", str(vdir)], check=True, stdout=subprocess.DEVNULL)
        return time.time() - start

    def evaluations(vdir):
        """A variant's `yokai eval` calls, as (what is evaluated, the folder it writes): the
        variant as a whole, else each seed alone."""
        if whole:
            return [(vdir, vdir / "eval")]
        return [(vdir / f"seed-{seed}", vdir / f"eval-seed-{seed}") for seed in seeds]

    rows = []
    for (name, sets), spec in zip(variants, args.variants):
        vdir = out / name
        if args.resume and all((e / "matrix.json").exists() for _, e in evaluations(vdir)):
            seconds = None
            print(f"{name}: evaluation found in {vdir}, read as it is", file=sys.stderr)
        else:
            vdir.mkdir(parents=True, exist_ok=True)
            if args.together:
                seconds = train(vdir, sets, args.seeds)
                print(f"{name}: seeds {args.seeds} trained together in {seconds:.0f} s", file=sys.stderr)
            else:
                seconds = sum(train(vdir, sets, str(seed)) for seed in seeds) / len(seeds)
            for evaluated, edir in evaluations(vdir):
                # `-o` and `--out` are one option of `yokai eval`; each call keeps the spelling
                # its test (python/tests/test_scripts.py) pins.
                out_flag = "-o" if whole else "--out"
                subprocess.run([args.yokai, "eval", str(evaluated), *partners, "--games", str(args.games),
                                out_flag, str(edir)], check=True, stdout=subprocess.DEVNULL)
        if whole:
            rewards, xp = seeds_of_eval(evaluations(vdir)[0][1], seeds)
        else:
            rewards, xp = [evalfiles.read_json(e / "matrix.json", "ablation.py")[0]["metrics"]["reward"]
                           for _, e in evaluations(vdir)], None
        print(f"{name}: SP R {', '.join(f'{r:.2f}' for r in rewards)}", file=sys.stderr)
        rows.append((spec, rewards, *mean_se(rewards), xp, seconds))

    steps = f"{args.steps:,} steps" if args.steps else "the base's steps"
    games = f"{args.games:,} games per pair" if whole else f"{args.games:,} self-play games per seed"
    clock = "s for the seeds together" if args.together else "s per seed"
    head = ["variant", "SP R per seed", "mean ± SE"] + (["XP R"] if whole else []) + [clock]
    table = [f"base `{args.base}`, {steps}, seeds {args.seeds}, {games}", "",
             "| " + " | ".join(head) + " |", "|---" * len(head) + "|"]
    for spec, rewards, mean, se, xp, secs in rows:
        cells = [f"`{spec}`", ", ".join(f"{r:.2f}" for r in rewards), f"{mean:.2f} ± {se:.2f}"]
        if whole:
            cells.append(f"{xp['reward']['mean']:.2f} ± {xp['reward']['se']:.2f}" if xp else "–")
        table.append("| " + " | ".join(cells + ["–" if secs is None else f"{secs:.0f}"]) + " |")
    text = "\n".join(table) + "\n"
    (out / "ablation.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

"""The level-to-level differences quoted in docs/results/obl-12M-levels-3-4.md, from the
saved evaluations (level 2: ../obl-12M/lr1e-3-level-2): unpaired (difference of the SP
means, SE = sqrt(se_a² + se_b²)) and paired per seed (SP of seed N at the higher level
minus seed N at the lower, mean ± SE over the seeds); and each level's XP − SP.
Run from the repository root: python3 docs/results/data/obl-12M-levels-3-4/differences.py"""
import json, math, pathlib

D = pathlib.Path(__file__).parent
LEVELS = {
    1: D.parent / "obl-12M" / "lr1e-3-level-1",
    2: D.parent / "obl-12M" / "lr1e-3-level-2",
    3: D / "level-3",
    4: D / "level-4",
}
LEVELS = {k: v for k, v in LEVELS.items() if (v / "summary.json").exists()}


def group(level):
    return json.loads((LEVELS[level] / "summary.json").read_text())["groups"][0]


def per_seed(level):
    m = json.loads((LEVELS[level] / "matrix.json").read_text())
    return [e["metrics"]["reward"] for e in m if e["row"] == e["col"]]


for level in LEVELS:
    g = group(level)
    sp, xp = g["sp"]["reward"], g["xp"]["reward"]
    print(f"level {level}: SP {sp['mean']:.2f} ± {sp['se']:.2f}, XP {xp['mean']:.2f} ± {xp['se']:.2f}, "
          f"XP − SP {xp['mean'] - sp['mean']:+.2f}; per seed SP {', '.join(f'{x:.2f}' for x in per_seed(level))}")
levels = list(LEVELS)
for a, b in zip(levels, levels[1:]):
    sa, sb = group(a)["sp"]["reward"], group(b)["sp"]["reward"]
    diff, se = sb["mean"] - sa["mean"], math.hypot(sa["se"], sb["se"])
    print(f"level {b} − level {a}: {diff:+.2f}, SE of the difference {se:.2f} ({diff / se:.1f} SE)")
    xs = [y - x for x, y in zip(per_seed(a), per_seed(b))]
    n = len(xs)
    mean = sum(xs) / n
    sd = math.sqrt(sum((x - mean) ** 2 for x in xs) / (n - 1))
    print(f"  paired per seed: {', '.join(f'{x:+.2f}' for x in xs)}; {mean:+.2f} ± {sd / math.sqrt(n):.2f}")

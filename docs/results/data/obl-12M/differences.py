"""The differences quoted in docs/results/obl-12M.md, from the saved evaluations:
unpaired (difference of the SP means, SE = sqrt(se_a² + se_b²)) and paired per seed
(SP of seed N in B minus seed N in A, mean ± SE over the seeds).
Run from the repository root: python3 docs/results/data/obl-12M/differences.py"""
import json, math, pathlib

D = pathlib.Path(__file__).parent

def sp(name):
    g = json.loads((D / name / "summary.json").read_text())["groups"][0]["sp"]["reward"]
    return g["mean"], g["se"]

def per_seed(name):
    m = json.loads((D / name / "matrix.json").read_text())
    return [e["metrics"]["reward"] for e in m if e["row"] == e["col"]]

for a, b in [("level-1-lr3e-3", "lr1e-3-level-1"), ("lr1e-3-level-1", "lr1e-3-level-2")]:
    (ma, sa), (mb, sb) = sp(a), sp(b)
    se = math.hypot(sa, sb)
    print(f"{b} − {a}: {mb - ma:+.2f}, SE of the difference {se:.2f} ({(mb - ma) / se:.1f} SE)")
    xs = [y - x for x, y in zip(per_seed(a), per_seed(b))]
    n = len(xs); mean = sum(xs) / n
    sd = math.sqrt(sum((x - mean) ** 2 for x in xs) / (n - 1))
    print(f"  paired per seed: {', '.join(f'{x:+.2f}' for x in xs)}; {mean:+.2f} ± {sd / math.sqrt(n):.2f}")

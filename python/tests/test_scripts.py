"""The helper scripts that the results pages name as their commands (scripts/)."""

import json
import pathlib
import subprocess
import sys

SCRIPTS = pathlib.Path(__file__).resolve().parents[2] / "scripts"


def run_updates(*args):
    return subprocess.run(
        [sys.executable, str(SCRIPTS / "updates.py"), *map(str, args)],
        capture_output=True,
        text=True,
    )


def write_run(directory, rows):
    directory.mkdir()
    (directory / "metrics.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))


def test_updates_averages_each_field_over_each_inclusive_range(tmp_path):
    run = tmp_path / "seed-0"
    # update u: reward u, value loss 10 u; update 3's rollout finished no game.
    write_run(
        run,
        [
            {"update": u, "value_loss": 10.0 * u, "games": None if u == 3 else {"reward": float(u)}}
            for u in range(1, 7)
        ],
    )
    out = run_updates("--ranges", "1-3,4-6", "--field", "games.reward", "--field", "value_loss", run)
    assert out.returncode == 0, out.stderr
    last = out.stdout.strip().splitlines()[-1]
    # rewards 1, 2 (update 3 has none) -> 1.50; 4, 5, 6 -> 5.00; value loss 20.00, 50.00
    assert last == f"| {run} | 1.50 | 5.00 | 20.00 | 50.00 |"


def test_updates_names_the_run_and_range_without_data(tmp_path):
    run = tmp_path / "seed-0"
    write_run(run, [{"update": 1, "value_loss": 1.0, "games": None}])
    out = run_updates("--ranges", "1-1", "--field", "games.reward", run)
    assert out.returncode != 0
    assert "no `games.reward` in updates 1-1" in out.stderr and str(run) in out.stderr


def test_updates_sums_joined_fields_over_a_range_with_sum(tmp_path):
    run = tmp_path / "seed-0"
    write_run(
        run,
        [{"update": u, "learn_seconds": 1.0 * u, "rollout_seconds": 0.5, "games": None} for u in range(1, 5)],
    )
    out = run_updates("--sum", "--ranges", "1-2,3-4", "--field", "learn_seconds+rollout_seconds", run)
    assert out.returncode == 0, out.stderr
    # (1 + 0.5) + (2 + 0.5) = 4.00; (3 + 0.5) + (4 + 0.5) = 8.00
    assert out.stdout.strip().splitlines()[-1] == f"| {run} | 4.00 | 8.00 |"


def run_kernel_times(*args):
    return subprocess.run(
        [sys.executable, str(SCRIPTS / "cubecl-kernel-times.py"), *map(str, args)],
        capture_output=True,
        text=True,
    )


def test_cubecl_kernel_times_sums_by_family_and_lists_a_familys_kernels(tmp_path):
    import lzma

    log = tmp_path / "cubecl.log.xz"
    lines = [
        "[START_KERNEL_COMPILATION]",  # not a launch: skipped
        "| 2ms       | ReduceKernel | TensorArgs_88872be8",
        "| 2ms       | ReduceKernel | TensorArgs_88872be8",
        "| 500µs     | ReduceKernel | TensorArgs_38f8a462",
        "| 1.5ms     | MatmulEntry | TensorArgs | DynamicScalar",
        "| 1000ns    | FullKernel_c9d6915a",
        "| 999µs     | FullKernel_0a1b2c3d",
    ]
    with lzma.open(log, "wt") as f:
        f.write("\n".join(lines) + "\n")
    out = run_kernel_times(log)
    assert out.returncode == 0, out.stderr
    rows = out.stdout.strip().splitlines()
    # 4.5 ms + 1.5 ms + 1 ms = 7 ms in 6 launches; families largest first, hashes cut off.
    assert rows[0] == f"{log}: 0.01 s in 6 launches"
    assert rows[1].split()[-1] == "ReduceKernel" and "3 launches" in rows[1] and "64.3 %" in rows[1]
    assert rows[2].endswith("Matmul TensorArgs") and "1 launches" in rows[2]
    assert rows[3].endswith("FullKernel") and "2 launches" in rows[3] and "14.3 %" in rows[3]
    out = run_kernel_times(log, "--family", "ReduceKernel")
    rows = out.stdout.strip().splitlines()
    # One kernel of the family at a time: the 2-launch one first, its median 2 ms.
    assert "2 launches, median     2000.0 µs" in rows[1] and rows[1].endswith("TensorArgs_88872be8")
    assert rows[2].endswith("TensorArgs_38f8a462")
    out = run_kernel_times(tmp_path / "missing.log")
    assert out.returncode != 0 and "missing.log: cannot be read" in out.stderr


def write_eval(folder, per_seed, sp_se, xp_mean=None, first_seed=0):
    """A `yokai eval -o` folder: one group whose seeds (`seed-N` from `first_seed` on) play
    themselves with `per_seed` R."""
    folder.mkdir()
    seeds = [f"{folder.name}/seed-{first_seed + i}" for i in range(len(per_seed))]
    stat = lambda mean, se=0.0: {"mean": mean, "se": se, "n": len(per_seed)}  # noqa: E731
    sp = {
        "entries": len(per_seed),
        "reward": stat(sum(per_seed) / len(per_seed), sp_se),
        "see": stat(10.0),
        "length": stat(31.0),
    }
    xp = {"entries": 0} if xp_mean is None else {"entries": 3, "reward": stat(xp_mean, 0.05)}
    group = {"name": folder.name, "seeds": seeds, "sp": sp, "xp": xp}
    (folder / "summary.json").write_text(json.dumps({"groups": [group]}))
    # The diagonal in the reverse of the summary's order, and one cross-play entry: the
    # per-seed column must follow the summary's seeds, not the file's order.
    matrix = [{"row": s, "col": s, "metrics": {"reward": r}} for s, r in zip(seeds, per_seed)]
    matrix = matrix[::-1] + [{"row": seeds[0], "col": seeds[1], "metrics": {"reward": -9.0}}]
    (folder / "matrix.json").write_text(json.dumps(matrix))


def run_script(name, *args):
    """Run scripts/NAME with ARGS; the finished process (returncode, stdout, stderr)."""
    return subprocess.run(
        [sys.executable, str(SCRIPTS / name), *map(str, args)],
        capture_output=True,
        text=True,
    )


def run_compare(*args):
    return run_script("compare-evals.py", *args)


def test_compare_evals_pairs_seeds_in_the_summarys_order(tmp_path):
    write_eval(tmp_path / "a", [1.0, 2.0, 3.0], 0.3, xp_mean=1.5)
    write_eval(tmp_path / "b", [1.5, 2.0, 4.0], 0.4)
    write_eval(tmp_path / "c", [2.0, 2.0], 0.0)
    out = run_compare(f"A={tmp_path / 'a'}", f"B={tmp_path / 'b'}", f"C={tmp_path / 'c'}")
    assert out.returncode == 0, out.stderr
    rows = out.stdout.splitlines()
    assert rows[2] == "| A | 1.00, 2.00, 3.00 | 2.00 ± 0.30 | 1.50 ± 0.05 | -0.50 | 10.0 | 31.0 |"
    assert rows[3].startswith("| B | 1.50, 2.00, 4.00 | 2.50 ± 0.40 | – | – |")
    # B − A: +0.50 with SE hypot(0.3, 0.4) = 0.5; paired +0.5, 0, +1 -> mean 0.5, SE 0.29.
    assert "| B − A | +0.50 (0.50, 1.0 SE) | +0.50, +0.00, +1.00 | +0.50 ± 0.29 |" in rows
    assert any(r.startswith("| C − B |") and "(seed counts differ)" in r for r in rows)
    out = run_compare("--against", "first", f"A={tmp_path / 'a'}", f"B={tmp_path / 'b'}", f"C={tmp_path / 'c'}")
    assert any(r.startswith("| C − A |") for r in out.stdout.splitlines())


def test_compare_evals_pairs_only_the_same_seeds(tmp_path):
    # Seeds 3-5 against seeds 0-2: other seeds, so no paired differences, only the means'.
    write_eval(tmp_path / "a", [1.0, 2.0, 3.0], 0.3)
    write_eval(tmp_path / "b", [2.0, 2.0, 5.0], 0.4, first_seed=3)
    write_eval(tmp_path / "c", [3.0, 3.0, 6.0], 0.4, first_seed=3)
    out = run_compare(f"A={tmp_path / 'a'}", f"B={tmp_path / 'b'}", f"C={tmp_path / 'c'}")
    assert out.returncode == 0, out.stderr
    rows = out.stdout.splitlines()
    assert "| B − A | +1.00 (0.50, 2.0 SE) | (other seeds: unpaired) | – |" in rows
    # C and B hold the same seeds (3, 4, 5) in different folders: paired seed by seed.
    assert "| C − B | +1.00 (0.57, 1.8 SE) | +1.00, +1.00, +1.00 | +1.00 ± 0.00 |" in rows


def test_compare_evals_names_a_folder_that_is_not_an_evaluation(tmp_path):
    out = run_compare(tmp_path)
    assert out.returncode != 0 and f"{tmp_path}/summary.json: no such file" in out.stderr
    (tmp_path / "summary.json").write_text("{")
    out = run_compare(tmp_path)
    assert out.returncode != 0 and "summary.json: not JSON" in out.stderr


def write_two_groups(folder):
    """A `yokai eval -o` folder of two groups, A (seeds 0, 1) and B (seeds 3, 4, 5), every
    pair's R given, each pair once in the file (as `yokai eval` writes it)."""
    folder.mkdir()
    a = ["a/seed-0", "a/seed-1"]
    b = ["b/seed-3", "b/seed-4", "b/seed-5"]
    groups = [{"name": "a", "seeds": a}, {"name": "b", "seeds": b}]
    (folder / "summary.json").write_text(json.dumps({"groups": groups}))
    r = {
        ("a/seed-0", "a/seed-0"): 4.0, ("a/seed-1", "a/seed-1"): 5.0, ("a/seed-0", "a/seed-1"): 3.0,
        ("b/seed-3", "b/seed-3"): 2.0, ("b/seed-4", "b/seed-4"): 2.0, ("b/seed-5", "b/seed-5"): 2.0,
        ("b/seed-3", "b/seed-4"): 1.0, ("b/seed-3", "b/seed-5"): 2.0, ("b/seed-4", "b/seed-5"): 3.0,
    }
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            r[(x, y)] = 1.0 + i  # seed 0 scores 1 with every B seed, seed 1 scores 2
    matrix = [{"row": x, "col": y, "metrics": {"reward": v}} for (x, y), v in r.items()]
    (folder / "matrix.json").write_text(json.dumps(matrix))


def test_cross_groups_tables_every_pair_of_groups(tmp_path):
    write_two_groups(tmp_path / "e")
    out = run_script("cross-groups.py", "--names", "A,B", tmp_path / "e")
    assert out.returncode == 0, out.stderr
    rows = out.stdout.splitlines()
    assert rows[0] == "| group | SP R | with A | with B |"
    # A: SP (4 + 5) / 2 = 4.5 ± 0.5; its one pair of distinct seeds 3.0; with B: three 1s and
    # three 2s, 1.5 ± sqrt(0.3 / 6) = 0.22. B: SP 2.0 ± 0; its pairs 1, 2, 3: 2.0 ± 0.58.
    assert rows[2] == "| A | 4.50 ± 0.50 | 3.00 ± 0.00 | 1.50 ± 0.22 |"
    assert rows[3] == "| B | 2.00 ± 0.00 | 1.50 ± 0.22 | 2.00 ± 0.58 |"


def test_cross_groups_names_what_is_missing(tmp_path):
    write_two_groups(tmp_path / "e")
    out = run_script("cross-groups.py", "--names", "A", tmp_path / "e")
    assert out.returncode != 0 and "--names gives 1 names for 2 groups" in out.stderr
    matrix = json.loads((tmp_path / "e" / "matrix.json").read_text())
    kept = [m for m in matrix if (m["row"], m["col"]) != ("a/seed-1", "b/seed-5")]
    (tmp_path / "e" / "matrix.json").write_text(json.dumps(kept))
    out = run_script("cross-groups.py", tmp_path / "e")
    assert out.returncode != 0 and "no pair a/seed-1 + b/seed-5" in out.stderr
    write_eval(tmp_path / "one", [1.0, 2.0], 0.5)
    out = run_script("cross-groups.py", tmp_path / "one")
    assert out.returncode != 0 and "1 group(s); cross-play between groups needs 2" in out.stderr


def run_belief_curve(*args):
    return run_script("belief-curve.py", *args)


def test_belief_curve_weights_each_update_by_its_slots(tmp_path):
    run = tmp_path / "seed-0"
    run.mkdir()
    # Update 1: 1 slot, model 0.9 against baseline 0.7 (gain -0.2); update 2: 3 slots,
    # model 0.6 against 0.7 (gain +0.1). Over both, weighted: (-0.2 + 3 * 0.1) / 4 = 0.025.
    rows = [
        {"update": 1, "cross_entropy": 0.9, "first_hand_baseline": 0.7, "slots": 1},
        {"update": 2, "cross_entropy": 0.6, "first_hand_baseline": 0.7, "slots": 3},
    ]
    (run / "belief.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    out = run_belief_curve("--at", "1,2", "--window", "2", run)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[2].startswith("| 1 | -0.2000 |")
    assert lines[3].startswith("| 2 | 0.0250 |")
    out = run_belief_curve("--at", "3", run)
    assert out.returncode != 0 and "2 updates, none at 3" in out.stderr
    out = run_belief_curve("--at", "1", tmp_path)
    assert out.returncode != 0 and "only OBL levels ≥ 2 train a belief" in out.stderr


STUB_YOKAI = r'''#!/usr/bin/env python3
"""A stand-in for `yokai` that logs its command line and writes what ablation.py reads."""
import json, pathlib, sys
argv = sys.argv[1:]
with open(pathlib.Path(__file__).with_name("calls.log"), "a") as log:
    log.write(json.dumps(argv) + "\n")
if argv[0] == "train":
    out = pathlib.Path(argv[argv.index("--out") + 1])
    for seed in argv[argv.index("--seeds") + 1].split(","):
        (out / f"seed-{seed}").mkdir(parents=True, exist_ok=True)
elif argv[0] == "eval":
    o = argv.index("-o") + 1 if "-o" in argv else argv.index("--out") + 1
    target = pathlib.Path(argv[1])
    seeds = sorted(int(p.name[5:]) for p in target.glob("seed-*")) if target.name[:5] != "seed-" else [int(target.name[5:])]
    label = lambda s: f"{target if target.name[:5] != 'seed-' else target.parent}/seed-{s} (END > 0.6, T = 0.25)"
    partners = [a for a in argv[2:o - 1] if not a.startswith("--") and not a.isdigit()]
    entries = [{"row": label(a), "col": label(b), "metrics": {"reward": 1.0 + a if a == b else 10.0 + a + b}}
               for i, a in enumerate(seeds) for b in seeds[i:]]
    entries += [{"row": label(a), "col": p, "metrics": {"reward": 0.5}} for a in seeds for p in partners]
    pathlib.Path(argv[o]).mkdir(parents=True, exist_ok=True)
    (pathlib.Path(argv[o]) / "matrix.json").write_text(json.dumps(entries))
    # yokai's summary: XP over the pairs of different seeds, mean and SE.
    pairs = [e["metrics"]["reward"] for e in entries if e["col"] not in partners and e["row"] != e["col"]]
    m = sum(pairs) / len(pairs) if pairs else 0.0
    se = (sum((x - m) ** 2 for x in pairs) / (len(pairs) - 1) / len(pairs)) ** 0.5 if len(pairs) > 1 else 0.0
    group = {"seeds": [label(a) for a in seeds], "sp": {},
             "xp": {"entries": len(pairs), "reward": {"mean": m, "se": se}} if pairs else None}
    (pathlib.Path(argv[o]) / "summary.json").write_text(json.dumps({"groups": [group]}))
'''


def run_ablation(tmp_path, *args):
    stub = tmp_path / "yokai"
    stub.write_text(STUB_YOKAI)
    stub.chmod(0o755)
    out = subprocess.run(
        [sys.executable, str(SCRIPTS / "ablation.py"), "--yokai", str(stub), "--out", str(tmp_path / "abl"), *args],
        capture_output=True,
        text=True,
    )
    log = tmp_path / "calls.log"
    calls = [json.loads(l) for l in log.read_text().splitlines()] if log.exists() else []
    return out, calls


def test_ablation_together_trains_each_variant_once_with_its_sets_and_evaluates_it_whole(tmp_path):
    out, calls = run_ablation(
        tmp_path, "--base", "cpu", "--together", "--partners", "belief,greedy", "--games", "5000",
        "base", "no-belief:ppo.belief_aux=0.0,network.pointer_pool=false",
    )
    assert out.returncode == 0, out.stderr
    abl = tmp_path / "abl"
    # The commands data/cpu-40M-ablations/run.sh ran per arm (its seeds were the default 0..3).
    assert calls == [
        ["train", "cpu", "--seeds", "0,1,2", "--eval-games", "0", "--out", f"{abl}/base"],
        ["eval", f"{abl}/base", "belief", "greedy", "--games", "5000", "-o", f"{abl}/base/eval"],
        ["train", "cpu", "--set", "ppo.belief_aux=0.0", "--set", "network.pointer_pool=false",
         "--seeds", "0,1,2", "--eval-games", "0", "--out", f"{abl}/no-belief"],
        ["eval", f"{abl}/no-belief", "belief", "greedy", "--games", "5000", "-o", f"{abl}/no-belief/eval"],
    ]
    rows = [l for l in out.stdout.splitlines() if l.startswith("| `")]
    # SP = 1 + seed (1, 2, 3: mean 2, SE 0.58); XP = 10 + a + b over pairs (11, 12, 13: 12, SE 0.58).
    assert rows[0].startswith("| `base` | 1.00, 2.00, 3.00 | 2.00 ± 0.58 | 12.00 ± 0.58 | ")
    assert "| variant | SP R per seed | mean ± SE | XP R | s for the seeds together |\n|---|---|---|---|---|\n" in out.stdout
    assert (abl / "ablation.md").read_text() + "\n" == out.stdout  # print adds one newline


def test_ablation_by_default_trains_seed_by_seed_and_plays_each_alone(tmp_path):
    out, calls = run_ablation(tmp_path, "--base", "quick", "--steps", "600000", "--seeds", "0,1", "--threads", "1", "x:ppo.lr=1e-3")
    assert out.returncode == 0, out.stderr
    abl = tmp_path / "abl"
    assert [c[0] for c in calls] == ["train", "train", "eval", "eval"]
    assert calls[0] == ["train", "quick", "--set", "ppo.lr=1e-3", "--seeds", "0", "--steps", "600000",
                        "--eval-games", "0", "--threads", "1", "--out", f"{abl}/x"]
    assert calls[2] == ["eval", f"{abl}/x/seed-0", "--games", "1000", "--out", f"{abl}/x/eval-seed-0"]
    assert "| variant | SP R per seed | mean ± SE | s per seed |\n|---|---|---|---|\n" in out.stdout
    assert "| `x:ppo.lr=1e-3` | 1.00, 2.00 | 1.50 ± 0.50 | " in out.stdout


def test_ablation_resume_reads_evaluated_variants_and_runs_only_the_rest(tmp_path):
    import shutil

    first, _ = run_ablation(tmp_path, "--base", "cpu", "--together", "--partners", "belief", "base")
    assert first.returncode == 0, first.stderr
    (tmp_path / "calls.log").unlink()
    # The variant evaluated in its first OUT, copied into another: its matrix still names
    # the first OUT's paths, and is read all the same.
    shutil.copytree(tmp_path / "abl" / "base", tmp_path / "other" / "base")
    out = subprocess.run(
        [sys.executable, str(SCRIPTS / "ablation.py"), "--yokai", str(tmp_path / "yokai"), "--out",
         str(tmp_path / "other"), "--base", "cpu", "--together", "--partners", "belief", "--resume",
         "base", "lr:ppo.lr=1e-3"],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr
    calls = [json.loads(l) for l in (tmp_path / "calls.log").read_text().splitlines()]
    assert [c[:2] for c in calls] == [["train", "cpu"], ["eval", f"{tmp_path}/other/lr"]]
    assert "base: evaluation found in" in out.stderr
    rows = [l for l in out.stdout.splitlines() if l.startswith("| `")]
    assert rows[0] == "| `base` | 1.00, 2.00, 3.00 | 2.00 ± 0.58 | 12.00 ± 0.58 | – |"
    assert rows[1].startswith("| `lr:ppo.lr=1e-3` | 1.00, 2.00, 3.00 | ")


def test_ablation_refuses_a_variant_that_is_not_key_equals_value(tmp_path):
    out, calls = run_ablation(tmp_path, "--steps", "1000", "good", "bad:lr=3")
    assert out.returncode != 0 and calls == []
    assert "variant 'bad': 'lr=3' is not key.sub=value" in out.stderr


def test_ablation_reads_a_real_evaluations_diagonal_and_pairs():
    import importlib.util

    sys.path.insert(0, str(SCRIPTS))  # ablation.py imports its sibling stats.py
    spec = importlib.util.spec_from_file_location("ablation", SCRIPTS / "ablation.py")
    ablation = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ablation)
    data = SCRIPTS.parent / "docs/results/data/cpu-40M-ablations/base"
    sp, xp = ablation.seeds_of_eval(data, [0, 1, 2])
    assert [round(r, 2) for r in sp] == [6.01, 6.04, 5.92]  # docs/results/cpu-40M-ablations.md
    assert round(xp["reward"]["mean"], 2) == 5.73 and xp["reward"]["n"] == 3
    # In the order the seeds are asked for, whatever the summary's order.
    assert [round(r, 2) for r in ablation.seeds_of_eval(data, [2, 0, 1])[0]] == [5.92, 6.01, 6.04]


def write_probe_csv(path, rows, head=True):
    header = "run,setting,step,cards,accuracy,oracle,rows" + (",head" if head else "")
    lines = [header] + [",".join(map(str, r if head else r[:7])) for r in rows]
    path.write_text("\n".join(lines) + "\n")


def test_probe_steps_weights_by_states_and_bins_the_steps(tmp_path):
    # Steps 0 and 1 in the first bin (100 and 300 states), step 5 in the second (50).
    rows = [
        ["a", "self-play", 0, "unseen", 0.2, 0.4, 100, 0.3],
        ["a", "self-play", 1, "unseen", 0.6, 0.8, 300, 0.7],
        ["a", "self-play", 5, "unseen", 0.5, 0.9, 50, 1.0],
    ]
    write_probe_csv(tmp_path / "probe.csv", rows)
    out = run_script("probe-steps.py", tmp_path / "probe.csv", "--bins", "0,5")
    assert out.returncode == 0, out.stderr
    line = next(l for l in out.stdout.splitlines() if l.startswith("| a |"))
    cells = [c.strip() for c in line.strip("|").split("|")]
    # probe (0.2·100 + 0.6·300 + 0.5·50) / 450 = 50.0 %; oracle 325 / 450 = 72.2 %; head
    # 290 / 450 = 64.4 % (unweighted means over the steps would read 53.3, 70.0, 66.7).
    assert cells[2:7] == ["unseen", "450", "50.0", "72.2", "64.4"]
    # First bin: oracle (40 + 240) / 400 = 70.0 %, head (30 + 210) / 400 = 60.0 %.
    assert cells[7:] == ["70.0 / 60.0 (400)", "90.0 / 100.0 (50)"]


def test_probe_steps_shows_no_head_for_a_probe_without_one_and_names_bad_input(tmp_path):
    write_probe_csv(tmp_path / "old.csv", [["a", "self-play", 0, "all", 0.3, 0.3, 10, ""]], head=False)
    out = run_script("probe-steps.py", tmp_path / "old.csv", "--bins", "0")
    assert out.returncode == 0, out.stderr
    assert "| a | self-play | all | 10 | 30.0 | 30.0 | – | 30.0 / – (10) |" in out.stdout
    out = run_script("probe-steps.py", tmp_path / "missing.csv")
    assert out.returncode != 0 and "cannot read" in out.stderr and "missing.csv" in out.stderr
    (tmp_path / "other.csv").write_text("a,b\n1,2\n")
    out = run_script("probe-steps.py", tmp_path / "other.csv")
    assert out.returncode != 0 and "not a `yokai probe` probe.csv" in out.stderr
    out = run_script("probe-steps.py", tmp_path / "old.csv", "--bins", "5,0")
    assert out.returncode != 0 and "ascending" in out.stderr

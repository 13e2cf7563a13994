"""`python -m yokai.sweep` on a local Ray cluster of 2 CPUs: a 3-seed sweep runs to the end,
a seed whose Ray worker is killed mid-run resumes from its checkpoint and ends with the
parameters of an uninterrupted run, a second start skips finished seeds, and the sweep
evaluates its seeds."""

import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import yokai
from test_trained import BINARY, TINY

pytest.importorskip("ray")
from yokai import sweep  # noqa: E402

# Long enough (400 updates of 64 steps) to be killed mid-run; a checkpoint every 5 updates.
SWEEP_TINY = TINY.replace("total_steps = 128", "total_steps = 25_600") + "[run]\ncheckpoint_every = 5\n"


def test_seeds_and_sweep_files_parse(tmp_path):
    assert sweep.parse_seeds("0..3") == (0, 1, 2)
    assert sweep.parse_seeds("4, 7") == (4, 7)
    with pytest.raises(ValueError, match="empty"):
        sweep.parse_seeds("3..3")
    with pytest.raises(ValueError, match="not A..B"):
        sweep.parse_seeds("a..b")
    spec = tmp_path / "paper.toml"
    spec.write_text('seeds = "0..2"\n[[row]]\nconfig = "ippo-9c-2p"\n[[row]]\nconfig = "op-9c-2p"\nseeds = "5"\nout = "x/op"\n')
    args = sweep.main.__globals__["argparse"].Namespace(sweep=str(spec), out="runs", configs=[], seeds=None)
    rows = sweep.rows_from_args(args)
    assert rows == [
        sweep.Row("ippo-9c-2p", (0, 1), pathlib.Path("runs/ippo-9c-2p")),
        sweep.Row("op-9c-2p", (5,), pathlib.Path("x/op")),
    ]
    # --seeds and --set on the command line reach every row.
    args.seeds, args.set = "3", ["ppo.total_steps=64"]
    assert [(r.seeds, r.set) for r in sweep.rows_from_args(args)] == [((3,), ("ppo.total_steps=64",))] * 2
    args.seeds, args.set = None, None
    # The shipped sweep files name shipped presets, with the paper's seeds (Table 5: four).
    root = pathlib.Path(__file__).resolve().parents[2]
    for shipped in (root / "sweeps").glob("*.toml"):
        args.sweep = str(shipped)
        for row in sweep.rows_from_args(args):
            assert (root / "configs" / f"{row.config}.toml").exists(), (shipped, row)
            # CPU-scale tables: 3 seeds side by side on 2 cores.
            paper_seeds = 3 if shipped.stem.endswith("-cpu") else 4 if shipped.name == "table5.toml" else 12
            assert len(row.seeds) == paper_seeds, shipped
    # Table 2: OBL's five levels in one row, each level its own directory.
    args.sweep = str(root / "sweeps" / "table2.toml")
    obl = [r for r in sweep.rows_from_args(args) if r.levels]
    assert [(r.config, r.levels) for r in obl] == [("obl-9c-2p", (1, 2, 3, 4, 5))]
    assert obl[0].runs()[4] == pathlib.Path("runs/table2/obl-9c-2p/level-5")
    assert sweep.table_options(args.sweep) == {"paper_table": 2, "select_entropy": None}
    assert sweep.table_options(str(root / "sweeps" / "he-alpha.toml")) == {"paper_table": 2, "select_entropy": 0.1}
    args.sweep = str(spec)
    for bad, match in [('table = 7\n[[row]]\nconfig = "quick"\n', "Tables 2 to 6"),
                       ('select_entropy = -1\n[[row]]\nconfig = "quick"\n', "tolerance"),
                       ('[[row]]\nconfig = "obl-quick"\nlevels = "0..2"\n', "count from 1"),
                       ('[[row]]\nconfig = "obl-quick"\nlevels = "x"\n', "row 1: levels")]:
        spec.write_text(bad)
        with pytest.raises(ValueError, match=match):
            sweep.rows_from_args(args)
            sweep.table_options(args.sweep)
    spec.write_text('[[row]]\nconfig = "quick"\nseed = "1"\n')
    with pytest.raises(ValueError, match="row 1 needs config"):
        sweep.rows_from_args(args)
    # A grid of a config field: rows of one config with overrides, each in its own directory.
    spec.write_text('out = "g"\n[[row]]\nconfig = "op-9c-2p"\nset = ["ppo.entropy_coef=0.01"]\n'
                    '[[row]]\nconfig = "op-9c-2p"\n[[row]]\nconfig = "op-9c-2p"\nset = ["ppo.lr=1e-3"]\nname = "fast"\n')
    rows = sweep.rows_from_args(args)
    assert [(r.out, r.set) for r in rows] == [
        (pathlib.Path("g/op-9c-2p-entropy_coef-0.01"), ("ppo.entropy_coef=0.01",)),
        (pathlib.Path("g/op-9c-2p"), ()),
        (pathlib.Path("g/fast"), ("ppo.lr=1e-3",)),
    ]
    # A `grid` key: every combination of its fields' values, the first field slowest, after
    # the row's own `set`; named as the hand-written rows above, or after `name`.
    spec.write_text('out = "g"\n[[row]]\nconfig = "op-9c-2p"\nset = ["ppo.epochs=1"]\n'
                    'grid = { "ppo.entropy_coef" = [0.01, 0.03], "network.head" = ["dense", "pointer"] }\n'
                    '[[row]]\nconfig = "quick"\nname = "q"\ngrid = { "ppo.shaping_fraction" = [0.5] }\n')
    rows = sweep.rows_from_args(args)
    assert [(r.out, r.set) for r in rows] == [
        (pathlib.Path(f"g/op-9c-2p-epochs-1-entropy_coef-{a}-head-{h}"),
         ("ppo.epochs=1", f"ppo.entropy_coef={a}", f'network.head="{h}"'))
        for a in ("0.01", "0.03") for h in ("dense", "pointer")
    ] + [(pathlib.Path("g/q-shaping_fraction-0.5"), ("ppo.shaping_fraction=0.5",))]
    # HE's α sweep is written as grids: the same twelve rows as one row per α.
    args.sweep = str(root / "sweeps" / "he-alpha.toml")
    assert [r.out.name for r in sweep.rows_from_args(args)] == [
        f"he-9c-{p}p-entropy_coef-0.0{a}" for p in (3, 4) for a in range(2, 8)]
    args.sweep = str(spec)
    for bad in ['grid = { "ppo.lr" = [] }', 'grid = { "ppo.lr" = 0.1 }', 'grid = {}',
                'grid = { "ppo.lr" = [0.1] }\nout = "x"']:
        spec.write_text(f'[[row]]\nconfig = "quick"\n{bad}\n')
        with pytest.raises(ValueError, match="row 1: .*grid|grid must"):
            sweep.rows_from_args(args)
    spec.write_text('[[row]]\nconfig = "quick"\n[[row]]\nconfig = "quick"\n')
    with pytest.raises(ValueError, match="same directory"):
        sweep.rows_from_args(args)
    spec.write_text('[[row]]\nconfig = "quick"\nset = "ppo.lr=1"\n')
    with pytest.raises(ValueError, match="FIELD=VALUE"):
        sweep.rows_from_args(args)


def test_progress_lines_read_the_runs_files(tmp_path):
    row = sweep.Row("tiny.toml", (0,), tmp_path / "tiny")
    run = tmp_path / "tiny" / "seed-0"
    started = {}
    assert sweep.progress_line(row, 0, started) == "tiny seed 0: waiting"
    run.mkdir(parents=True)
    (run / "config.toml").write_text("[ppo]\ntotal_steps = 1000\n")
    # An update in which no training game ended logs "games": null.
    (run / "metrics.jsonl").write_text(json.dumps({"update": 3, "env_steps": 192, "games": None}) + "\n")
    assert sweep.progress_line(row, 0, started) == "tiny seed 0: update 3, steps 192/1,000"
    with open(run / "metrics.jsonl", "a") as f:
        f.write(json.dumps({"update": 6, "env_steps": 384, "games": {"reward": -2.5}}) + "\n")
    line = sweep.progress_line(row, 0, started)
    assert line.startswith("tiny seed 0: update 6, steps 384/1,000, R -2.50, ETA "), line
    (run / sweep.DONE).write_text("")
    assert sweep.progress_line(row, 0, started) == "tiny seed 0: finished"
    # OBL levels: the line is the first unfinished level's.
    obl = sweep.Row("obl.toml", (0,), tmp_path / "obl", levels=(1, 2))
    (obl.out / "level-1" / "seed-0").mkdir(parents=True)
    (obl.out / "level-1" / "seed-0" / sweep.DONE).write_text("")
    assert sweep.progress_line(obl, 0, started) == "obl seed 0 level 2: waiting"
    (obl.out / "level-2" / "seed-0").mkdir(parents=True)
    (obl.out / "level-2" / "seed-0" / sweep.DONE).write_text("")
    assert sweep.progress_line(obl, 0, started) == "obl seed 0: finished"


def _sweep(config, out, *more, engine="tune"):
    return subprocess.Popen(
        [sys.executable, "-m", "yokai.sweep", str(config), "--seeds", "0..3", "--out", str(out),
         "--num-cpus", "2", "--eval-games", "20", "--yokai", str(BINARY), "--engine", engine, *more],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )


@pytest.mark.parametrize("engine", ["tune", "tasks"])
def test_a_killed_seed_resumes_from_its_checkpoint_and_the_sweep_evaluates(tmp_path, engine):
    """Under either engine (Tune trials with a FailureConfig, or Ray tasks with retries)."""
    if not BINARY.exists():
        pytest.skip("needs the yokai binary: scripts/test.sh builds it before pytest")
    if engine == "tune":
        pytest.importorskip("ray.tune")
    config = tmp_path / "tiny.toml"
    config.write_text(SWEEP_TINY)
    out = tmp_path / "runs"
    proc = _sweep(config, out, engine=engine)
    # Kill seed 1's Ray worker once it has checkpointed at least twice, while it trains.
    run = out / "seed-1"
    deadline = time.time() + 300
    killed_at = None
    while time.time() < deadline and proc.poll() is None:
        metrics = run / "metrics.jsonl"
        if (run / ".sweep-worker").exists() and metrics.exists():
            lines = metrics.read_text().splitlines()
            if len(lines) >= 12 and not (run / sweep.DONE).exists():
                killed_at = len(lines)
                os.kill(int((run / ".sweep-worker").read_text()), signal.SIGKILL)
                break
        time.sleep(0.02)
    assert killed_at is not None, "seed 1 finished before it could be killed"
    # The trainer dies with its worker a moment after the kill and may finish an update (and
    # its checkpoint) in between, so the bound on the resumed checkpoint is the longest log
    # seen until the retry starts: the retry only truncates the log back to that checkpoint.
    while proc.poll() is None and time.time() < deadline:
        killed_at = max(killed_at, len(metrics.read_text().splitlines()))
        attempts = run / sweep.ATTEMPTS
        if attempts.exists() and len(attempts.read_text().splitlines()) >= 2:
            killed_at = max(killed_at, len(metrics.read_text().splitlines()))
            break
        time.sleep(0.02)
    stdout, stderr = proc.communicate(timeout=600)
    assert proc.returncode == 0, stderr
    for seed in range(3):
        assert f"seed {seed}:" in stdout
    # Two attempts: the first killed, the second resumed from a checkpoint (a multiple of
    # 5 updates) taken before the kill, not from the start.
    attempts = (run / sweep.ATTEMPTS).read_text().splitlines()
    # Each line: date, time, "pid N", what happened.
    assert [a.split(" ", 4)[4].split(":")[0] for a in attempts] == [
        "starts", "resumes from its checkpoint", "done"], attempts
    done = re.search(r"400 updates, 25600 env steps \((\d+) now", attempts[-1])
    assert done, attempts
    resumed_from = 400 - int(done.group(1)) // 64
    assert resumed_from % 5 == 0 and 10 <= resumed_from <= min(killed_at, 395), (attempts, killed_at)
    # The resumed seed equals a run of the same seed without a stop.
    whole = tmp_path / "whole"
    subprocess.run([str(BINARY), "train", str(config), "--seeds", "1", "--out", str(whole),
                    "--threads", "1", "--eval-games", "0"], check=True, capture_output=True)
    assert np.array_equal(yokai.policy_parameters(str(run)), yokai.policy_parameters(str(whole / "seed-1")))
    # Evaluated: every seed in self-play and cross-play.
    matrix = json.loads((out / "eval" / "matrix.json").read_text())
    assert len(matrix) == 6  # 3 self-play entries and 3 cross-play pairs
    if engine == "tune":
        # Tune logged every seed's curve as it trained: the last report of seed 1 (its
        # second attempt) is the run's end, and its env steps rise.
        import csv
        trial = next((tmp_path / ".tune").glob("sweep-*/00-runs-seed-1"))
        with open(sorted(trial.glob("**/progress.csv"))[-1]) as f:
            steps = [int(float(r["env_steps"])) for r in csv.DictReader(f) if r.get("env_steps")]
        assert steps and steps[-1] == 25_600 and steps == sorted(steps), steps
    # A second start skips the finished seeds (Tune: restores the finished experiment), and
    # none of them is trained again.
    logs = [(out / f"seed-{s}" / sweep.ATTEMPTS).read_text() for s in range(3)]
    again = _sweep(config, out, engine=engine)
    stdout, stderr = again.communicate(timeout=600)
    assert again.returncode == 0, stderr
    assert stdout.count("finished earlier") == 3, stdout
    assert logs == [(out / f"seed-{s}" / sweep.ATTEMPTS).read_text() for s in range(3)]


def test_a_rows_overrides_reach_the_trainer_and_a_resume_keeps_them(tmp_path):
    """``set`` of a sweep row becomes ``yokai train --set``: the run's saved config holds
    it. A finished seed is skipped on a second call."""
    if not BINARY.exists():
        pytest.skip("needs the yokai binary: scripts/test.sh builds it before pytest")
    config = tmp_path / "tiny.toml"
    config.write_text(TINY)
    out = tmp_path / "grid"

    def train_seed():
        # In a fresh interpreter: train_seed forks (PR_SET_PDEATHSIG), which is unsafe in
        # this one once another test has started JAX's threads.
        code = (f"import json; from yokai import sweep; print(json.dumps(sweep.train_seed("
                f"{str(BINARY)!r}, {str(config)!r}, 0, {str(out)!r}, 1, 'cpu', ('ppo.lr=0.0125',))))")
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
        return json.loads(proc.stdout)

    assert train_seed()["status"] == "trained"
    saved = (out / "seed-0" / "config.toml").read_text()
    assert re.search(r"^lr = 0\.0125$", saved, re.M), saved
    assert train_seed()["status"] == "finished earlier"


# Every preset at a few steps: 2 updates of 8 games × 8 steps, a 16-unit belief trained for
# 2 updates on OBL levels ≥ 2.
TINY_SETS = ["ppo.num_envs=8", "ppo.rollout_steps=8", "ppo.minibatches=2", "ppo.epochs=1",
             "ppo.total_steps=128", "obl.belief_updates=2", "obl.belief_hidden=16"]
SWEEPS = pathlib.Path(__file__).resolve().parents[2] / "sweeps"


@pytest.mark.parametrize("name", sorted(p.name for p in SWEEPS.glob("*.toml")))
def test_every_shipped_sweep_runs_tiny_and_writes_its_table(tmp_path, name):
    """Each table's sweep, cut to 2 seeds and a few steps, trains every row, evaluates it and
    writes one table with a row per method (per OBL level) beside the paper's table. With
    plain Ray tasks, which run the same rows as Tune trials do (the killed-seed test runs both
    engines) and spare Tune's start-up: 30 s against 46 s for table2 (2026-12-02, 2 cores)."""
    if not BINARY.exists():
        pytest.skip("needs the yokai binary: scripts/test.sh builds it before pytest")
    sets = [arg for s in TINY_SETS for arg in ("--set", s)]
    proc = subprocess.run(
        [sys.executable, "-m", "yokai.sweep", "--sweep", str(SWEEPS / name), "--seeds", "0..2",
         "--num-cpus", "2", "--eval-games", "10", "--yokai", str(BINARY), "--engine", "tasks",
         *sets],
        cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    args = sweep.main.__globals__["argparse"].Namespace(sweep=str(SWEEPS / name), out=None, configs=[],
                                                        seeds="0..2", set=TINY_SETS)
    rows = sweep.rows_from_args(args)
    options = sweep.table_options(str(SWEEPS / name))
    table = (tmp_path / rows[0].out.parent / "table.md").read_text()
    assert table.startswith(f"Beside the paper's Table {options['paper_table']}: "), table
    runs = [r for row in rows for r in row.runs()]
    for run in runs:
        # Named by its directory (and the END rule, where the policy decides END).
        assert re.search(rf"\n\| {re.escape(str(run))}( \([^)]*\))? \| 2 \| ", table), (run, table)
        # The tiny overrides reached the trainer.
        assert re.search(r"^total_steps = 128$", (tmp_path / run / "seed-1" / "config.toml").read_text(), re.M)
    ours = [l for l in table.splitlines() if l.startswith("| runs/")]
    assert len(ours) == len(runs), table
    sections = table.count("\n## ")
    assert sections >= 1 and table.count("| paper: ") >= sections, table
    if options["select_entropy"] is not None:
        # HE's α selection, one per game, over the six α of the sweep.
        assert table.count("HE's α selection") == 2, table
        for alpha in ("0.02", "0.07"):
            assert table.count(f"\n| {alpha} | runs/") == 2, table


def test_progress_reports_read_only_whole_new_lines_and_follow_a_cut_back_log(tmp_path):
    """The Tune trial's reports: the newest whole line past the last look (a half-written
    line waits), nothing when nothing is new, and from the start again when a resumed run
    has cut its log back to its checkpoint."""
    log = tmp_path / "metrics.jsonl"
    line = lambda u: json.dumps({"update": u, "env_steps": 64 * u, "games": {"reward": u / 10}}) + "\n"
    got = []
    log.write_text(line(1) + line(2) + line(3)[:10])
    offset = sweep._report_new(tmp_path, 0, got.append)
    assert got == [{"update": 2, "env_steps": 128, "reward": 0.2}]
    assert offset == len(line(1) + line(2))
    log.write_text(line(1) + line(2) + line(3) + line(4))
    offset = sweep._report_new(tmp_path, offset, got.append)
    assert got[-1]["update"] == 4 and offset == log.stat().st_size
    assert sweep._report_new(tmp_path, offset, got.append) == offset and len(got) == 2
    log.write_text(line(1))
    assert sweep._report_new(tmp_path, offset, got.append) == len(line(1))
    assert got[-1]["update"] == 1

"""Multi-seed sweeps on Ray: ``python -m yokai.sweep CONFIG --seeds 0..12 [--address auto]``.

Each seed of each row is one Ray Tune trial (``--engine tune``, the default: see
``yokai.sweep_tune``) or one plain Ray task (``--engine tasks``) with its declared resources
(``--cpus-per-seed``, ``--gpus-per-seed``) that runs ``yokai train CONFIG --seeds N --out
OUT`` into a directory every node sees (a local path by default; on a cluster a shared
file system such as NFS or Lustre: the trainer writes ordinary files). Then the sweep evaluates every row with
``yokai eval`` (self-play and cross-play over all seeds) and, for several rows, writes the
paper's table with ``yokai compare``.

Fault tolerance comes from the trainer's checkpoints, not from Ray's object store:

- a trial or task whose worker dies (node lost, preempted, killed) is retried by Ray
  (``--max-retries``: Tune's ``FailureConfig``, or the task's retries), and a retry passes
  ``--resume`` when the seed has a checkpoint, so it continues from the last one instead of
  starting over (the trainer's resume is exact: the final parameters equal an
  uninterrupted run's);
- the ``yokai`` process dies with its worker (``PR_SET_PDEATHSIG``), so a retry never races
  an orphan writing the same directory;
- a sweep stopped and started again skips seeds marked finished and resumes the others
  (with Tune, by restoring the experiment under ``<out>/.tune``).

Without ``--address`` a local Ray instance is started, so the same command runs on a
laptop. The driver prints one line per seed (update, steps, R, ETA) read from each run's
``metrics.jsonl``; Ray's dashboard shows the tasks where the user runs one.

A sweep file lists several rows (a grid over configs × seeds)::

    # sweeps/table2.toml
    seeds = "0..12"            # default for every row
    table = 2                  # the paper's table printed beside the closing one
    [[row]]
    config = "ippo-9c-2p"
    [[row]]
    config = "obl-9c-2p"
    levels = "1..6"            # OBL levels 1 to 5 in turn, each its own row (out/level-L)
    [[row]]
    config = "op-9c-2p"
    set = ["ppo.entropy_coef=0.03"]   # yokai train --set: a grid of a config field
    out = "runs/op"            # default: <--out>/<config name>[-<field>-<value>...]

A file may also ask for HE's α selection at the end (``select_entropy = 0.1``, see
``yokai compare --select-entropy``). On the command line, ``--seeds`` replaces every row's
seeds and ``--set`` adds an override to every row, so one command runs a whole table at a
CPU budget, or tiny::

    python -m yokai.sweep --sweep sweeps/table2.toml --seeds 0..3 --set ppo.total_steps=2000000

``python -m yokai.sweep --sweep sweeps/table2.toml --address auto --gpus-per-seed 1``
"""

from __future__ import annotations

import argparse
import ctypes
import functools
import json
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass

try:  # Python 3.11+
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - the sweep extra installs tomli there
    import tomli as tomllib

DONE = ".sweep-done"
ATTEMPTS = "sweep.log"
#: Seconds between looks at a training run's progress.
REPORT_EVERY = 1.0
#: How the seeds are run: Ray Tune trials (failure handling, resume, result logs) or plain
#: Ray tasks (Ray core only).
ENGINES = ("tune", "tasks")


@dataclass(frozen=True)
class Row:
    """One row of a sweep: a training config (a preset name or a TOML file) with
    ``FIELD=VALUE`` overrides (``yokai train --set``) over seeds, into ``out`` (one
    ``seed-N`` run per seed)."""

    config: str
    seeds: tuple
    out: pathlib.Path
    set: tuple = ()
    #: Off-Belief Learning levels trained one after another (``yokai train --levels``), each
    #: into ``out/level-L``; empty for every other method.
    levels: tuple = ()

    def runs(self) -> list:
        """The directories of seed runs this row trains and evaluates: ``out``, or one
        ``out/level-L`` per OBL level."""
        return [level_dir(self.out, l) for l in self.levels] if self.levels else [self.out]


def level_dir(out, level: int) -> pathlib.Path:
    """Where ``yokai train --levels`` puts OBL level ``level``'s seeds under ``out``."""
    return pathlib.Path(out) / f"level-{level}"


def parse_seeds(text: str) -> tuple:
    """``0..3`` (0, 1, 2), ``0,4,7`` or ``5``: ``yokai train --seeds``'s own parser."""
    from yokai import _core

    try:
        return tuple(_core.parse_seeds(str(text).strip()))
    except ValueError as e:
        raise ValueError(f"--seeds {e}") from None


def config_name(config: str) -> str:
    return pathlib.Path(config).stem if config.endswith(".toml") else config


def row_name(config: str, overrides) -> str:
    """A row's directory name: the config's, then each override's last key and value
    (``op-9c-2p`` with ``ppo.entropy_coef=0.01``: ``op-9c-2p-entropy_coef-0.01``)."""
    parts = [config_name(config)]
    for o in overrides:
        field, value = o.split("=", 1)
        parts.append(f"{field.strip().split('.')[-1]}-{value.strip().strip(chr(34))}")
    return "-".join(parts)


def find_yokai(given: str | None = None) -> str:
    """The ``yokai`` binary: ``given``, else ``$YOKAI``, else ``yokai`` on PATH, else this
    checkout's ``target/release/yokai``."""
    candidates = [given, os.environ.get("YOKAI"), shutil.which("yokai")]
    candidates.append(str(pathlib.Path(__file__).resolve().parents[2] / "target" / "release" / "yokai"))
    for c in candidates:
        if c and pathlib.Path(c).is_file():
            return str(pathlib.Path(c).resolve())
    raise FileNotFoundError(
        "no yokai binary: build it (cargo build --release -p yokai-cli) or pass --yokai PATH"
    )


def _die_with_parent():  # pragma: no cover - runs in the child between fork and exec
    """Ask the kernel to SIGKILL this process when its parent (the Ray worker) dies."""
    try:
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except OSError:
        pass


def train_seed(yokai: str, config: str, seed: int, out: str, threads: int, device: str = "cpu",
               overrides: tuple = (), levels: tuple = (), report=None) -> dict:
    """Train (or resume, or skip) one seed; the body of a Ray task or Tune trial. Returns a
    summary. With ``levels``, the seed's OBL levels in order (level L reads the same seed's
    level L-1), each resumed or skipped on its own. ``report``, when given, is called with
    each new line of the run's ``metrics.jsonl`` as training goes (Tune's ``report``)."""
    if not levels:
        return _train_run(yokai, config, seed, pathlib.Path(out), threads, device, overrides, [],
                          report=report)
    result = {}
    for level in levels:
        level_report = None if report is None else (lambda m, level=level: report({**m, "level": level}))
        result = _train_run(yokai, config, seed, level_dir(out, level), threads, device,
                            overrides, ["--levels", str(level)], out=pathlib.Path(out), report=level_report)
        result["level"] = level
    return result


def _train_run(yokai: str, config: str, seed: int, runs: pathlib.Path, threads: int, device: str,
               overrides: tuple, extra: list, out: pathlib.Path | None = None, report=None) -> dict:
    """``yokai train`` of one seed into ``runs/seed-N`` (``--out out``, ``runs`` by default),
    handing ``report`` the run's progress (see ``train_seed``)."""
    run = runs / f"seed-{seed}"
    if (run / DONE).exists():
        return {"seed": seed, "status": "finished earlier"}
    resume = (run / "checkpoint.ykc").exists()
    run.mkdir(parents=True, exist_ok=True)
    _note(run, f"pid {os.getpid()} {'resumes from its checkpoint' if resume else 'starts'}")
    (run / ".sweep-worker").write_text(str(os.getpid()))
    cmd = [yokai, "train", config, "--seeds", str(seed), "--out", str(out or runs), "--eval-games", "0",
           "--threads", str(threads), "--device", device, *extra] + (["--resume"] if resume else [])
    if not resume:  # a resumed run keeps its checkpoint's config
        cmd += [arg for o in overrides for arg in ("--set", o)]
    # stderr goes to a file, not a pipe: a pipe nobody reads while the run is polled fills
    # up and stops the trainer.
    with tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, text=True,
                                preexec_fn=_die_with_parent if sys.platform.startswith("linux") else None)
        if report is None:
            proc.wait()
        else:
            offset = 0
            while proc.poll() is None:
                time.sleep(REPORT_EVERY)
                offset = _report_new(run, offset, report)
            _report_new(run, offset, report)
        err.seek(0)
        stderr = err.read()
    if proc.returncode != 0:
        _note(run, f"pid {os.getpid()} failed: exit {proc.returncode}")
        raise RuntimeError(f"yokai train {config} seed {seed} ({run}) exited with {proc.returncode}:\n"
                           f"{stderr[-2000:]}")
    # yokai's summary, "seed N: U updates, S env steps (S' now, in T s: …)", says how many
    # steps this attempt trained, hence where it resumed. (Its progress lines, "seed N:
    # update U/T (P %) | …", come before it.)
    summary = next((l for l in stderr.splitlines()
                    if re.match(rf"seed {seed}: \d+ updates, ", l)), "")
    _note(run, f"pid {os.getpid()} done: {summary}")
    (run / DONE).write_text(summary)
    return {"seed": seed, "status": "resumed" if resume else "trained", "log": stderr.strip()}


def _report_new(run: pathlib.Path, offset: int, report) -> int:
    """Hand ``report`` the update, env steps and training games' R of the newest whole line
    written to the run's ``metrics.jsonl`` past byte ``offset``; returns the offset after
    the last whole line read. Only the new bytes are read: a long run's log grows to
    megabytes, and it is looked at every ``REPORT_EVERY`` seconds."""
    try:
        with open(run / "metrics.jsonl", "rb") as f:
            # A resumed run cuts its log back to its checkpoint: then read from the start.
            if os.fstat(f.fileno()).st_size < offset:
                offset = 0
            f.seek(offset)
            new = f.read()
    except OSError:
        return offset
    # A line without its newline is still being written: leave it for the next look.
    whole = new[: new.rfind(b"\n") + 1]
    lines = whole.splitlines()
    if lines:
        try:
            last = json.loads(lines[-1])
        except ValueError:  # cut back and rewritten between two looks: skip this one
            return offset + len(whole)
        reward = (last.get("games") or {}).get("reward")
        report({"update": int(last["update"]), "env_steps": int(last["env_steps"]),
                **({"reward": float(reward)} if reward is not None else {})})
    return offset + len(whole)


def _note(run: pathlib.Path, text: str):
    """One line of the seed's attempt log (``sweep.log``)."""
    with open(run / ATTEMPTS, "a") as log:
        log.write(f"{time.strftime('%Y-%m-%d %H:%M:%S')} {text}\n")


def evaluate_row(yokai: str, out: str, games: int, threads: int) -> str:
    """``yokai eval`` over every seed of a row (self-play and all cross-play pairs)."""
    eval_dir = str(pathlib.Path(out) / "eval")
    cmd = [yokai, "eval", out, "--games", str(games), "--out", eval_dir, "--threads", str(threads)]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"yokai eval {out} exited with {proc.returncode}:\n{proc.stderr[-2000:]}")
    return eval_dir


def _last_metrics(run: pathlib.Path) -> dict | None:
    try:
        lines = (run / "metrics.jsonl").read_text().strip().splitlines()
        return json.loads(lines[-1]) if lines else None
    except (OSError, ValueError):
        return None


def _total_steps(run: pathlib.Path) -> int | None:
    try:
        return int(tomllib.loads((run / "config.toml").read_text())["ppo"]["total_steps"])
    except Exception:  # noqa: BLE001 - not written yet, or unreadable: no total to show
        return None


def progress_line(row: Row, seed: int, started: dict) -> str:
    """``seed N: update U, steps S/T, R r, ETA`` from the run's own files (of the level it
    is on, for OBL)."""
    # Rows are told apart by their directory: several may share a config.
    name = f"{row.out.name} seed {seed}"
    runs = row.runs()
    level = next((i for i, r in enumerate(runs) if not (r / f"seed-{seed}" / DONE).exists()), None)
    if level is None:
        return f"{name}: finished"
    run = runs[level] / f"seed-{seed}"
    if row.levels:
        name += f" level {row.levels[level]}"
    last = _last_metrics(run)
    if last is None:
        return f"{name}: waiting"
    steps, total = int(last["env_steps"]), _total_steps(run)
    # An update in which no training game finished logs `"games": null`.
    reward = (last.get("games") or {}).get("reward")
    line = f"{name}: update {last['update']}, steps {steps:,}"
    if total:
        line += f"/{total:,}"
    if reward is not None:
        line += f", R {reward:+.2f}"
    first = started.setdefault((run, seed), (time.time(), steps))
    rate = (steps - first[1]) / max(time.time() - first[0], 1e-9)
    if total and rate > 0:
        line += f", ETA {int((total - steps) / rate)} s"
    return line


def run_sweep(rows, address=None, cpus_per_seed=1, gpus_per_seed=0.0, max_retries=3,
              eval_games=1000, yokai=None, num_cpus=None, progress_every=10.0, quiet=False,
              device="cpu", paper_table=2, select_entropy=None, engine="tune"):
    """Train every seed of every row (as Ray Tune trials with ``engine="tune"``, as plain
    Ray tasks with ``"tasks"``), then evaluate each row (each OBL level apart); returns
    ``{"runs": [...], "evals": [...], "table": path or None}``, the table beside the paper's
    Table ``paper_table`` (with HE's α selection at that tolerance when ``select_entropy``
    is given). ``num_cpus`` caps a local Ray instance (tests)."""
    try:
        import ray
    except ImportError:
        raise SystemExit("yokai.sweep needs Ray: pip install './python[sweep]' (or pip install ray)") from None
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(ENGINES)}, not {engine!r}")
    if engine == "tune":
        from yokai import sweep_tune

        sweep_tune.require_tune()

    yokai = find_yokai(yokai)
    if not ray.is_initialized():
        ray.init(address=address, num_cpus=num_cpus if address is None else None,
                 include_dashboard=False, logging_level="WARNING", log_to_driver=False)
    threads = max(1, int(cpus_per_seed))
    seeds = [(row, seed) for row in rows for seed in row.seeds]
    for row in rows:
        row.out.mkdir(parents=True, exist_ok=True)
    started = {}

    def report_progress():
        if not quiet:
            for row, seed in seeds:
                print(progress_line(row, seed, started), file=sys.stderr)

    if engine == "tune":
        trials = [trial_of(rows, i, seed) for i, row in enumerate(rows) for seed in row.seeds]
        finished = [all((run / f"seed-{t['seed']}" / DONE).exists() for run in rows[t["row"]].runs())
                    for t in trials]
        results = sweep_tune.train_with_tune(
            trials, functools.partial(_train_trial, yokai, threads, device),
            storage=rows[0].out.parent / ".tune", cpus=cpus_per_seed, gpus=gpus_per_seed,
            max_failures=max_retries, progress=report_progress, progress_every=progress_every)
        results = [{**r, "status": "finished earlier"} if done else r for r, done in zip(results, finished)]
    else:
        task = ray.remote(num_cpus=cpus_per_seed, num_gpus=gpus_per_seed, max_retries=max_retries,
                          retry_exceptions=True)(train_seed)
        pending = [task.remote(yokai, row.config, seed, str(row.out), threads, device, row.set, row.levels)
                   for row, seed in seeds]
        results = []
        next_report = time.time()
        while pending:
            ready, pending = ray.wait(pending, timeout=1.0)
            for ref in ready:
                results.append(ray.get(ref))  # raises once the retries are spent
            if time.time() >= next_report or not pending:
                report_progress()
                next_report = time.time() + progress_every
    evals = []
    if eval_games > 0:
        evaluate = ray.remote(num_cpus=cpus_per_seed)(evaluate_row)
        evals = ray.get([evaluate.remote(yokai, str(runs), eval_games, max(1, int(cpus_per_seed)))
                         for row in rows for runs in row.runs()])
    table = None
    if len(evals) > 1:
        table = str(rows[0].out.parent / "table.md")
        select = ["--select-entropy", str(select_entropy)] if select_entropy is not None else []
        proc = subprocess.run([yokai, "compare", *evals, "--out", table, "--paper-table", str(paper_table),
                               *select], capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"yokai compare exited with {proc.returncode}:\n{proc.stderr[-2000:]}")
    return {"runs": results, "evals": evals, "table": table}


def trial_of(rows, index: int, seed: int) -> dict:
    """Row ``index``'s seed as a Tune trial: JSON-able, with absolute paths (a trial runs in
    a directory of its own)."""
    row = rows[index]
    config = row.config
    if config.endswith(".toml") and pathlib.Path(config).exists():
        config = str(pathlib.Path(config).resolve())
    return {"row": index, "name": row.out.name, "seed": seed, "config": config,
            "out": str(row.out.resolve()), "set": list(row.set), "levels": list(row.levels)}


def _train_trial(yokai: str, threads: int, device: str, trial: dict, report) -> dict:
    """``train_seed`` of one Tune trial, reporting its progress to Tune."""
    return train_seed(yokai, trial["config"], trial["seed"], trial["out"], threads, device,
                      tuple(trial["set"]), tuple(trial["levels"]), report=report)


def read_sweep(path) -> dict:
    """A sweep file's TOML, its top-level keys checked."""
    spec = tomllib.loads(pathlib.Path(path).read_text())
    unknown = set(spec) - {"seeds", "out", "row", "table", "select_entropy"}
    if unknown:
        raise ValueError(f"{path}: unknown keys {sorted(unknown)} (seeds, out, table, select_entropy, [[row]])")
    tolerance = spec.get("select_entropy")
    if tolerance is not None and not (isinstance(tolerance, (int, float)) and tolerance >= 0):
        raise ValueError(f"{path}: select_entropy is a tolerance in R (>= 0), not {tolerance!r}")
    table = spec.get("table", 2)
    if not (isinstance(table, int) and 2 <= table <= 6):
        raise ValueError(f"{path}: table must be the number of one of the paper's Tables 2 to 6, not {table!r}")
    return spec


def table_options(path) -> dict:
    """What a sweep file asks of its closing table: the paper's table beside it
    (``table``), HE's α selection (``select_entropy``)."""
    spec = read_sweep(path) if path else {}
    return {"paper_table": spec.get("table", 2), "select_entropy": spec.get("select_entropy")}


def rows_from_args(args) -> list:
    """The rows to train: the sweep file's, or one per config. ``--seeds`` given on the
    command line replaces every row's seeds and ``--set`` is added to every row's
    overrides (after its own, so it wins): a whole table at another budget, or tiny."""
    out = pathlib.Path(args.out) if args.out else None
    given_seeds = parse_seeds(args.seeds) if args.seeds is not None else None
    extra = tuple(getattr(args, "set", None) or ())
    if not all("=" in o for o in extra):
        raise ValueError("--set takes FIELD=VALUE")
    if args.sweep:
        spec = read_sweep(args.sweep)
        base = pathlib.Path(spec.get("out", out or "runs"))
        rows = []
        for i, r in enumerate(spec.get("row", [])):
            if "config" not in r or set(r) - {"config", "seeds", "out", "set", "name", "levels", "grid"}:
                raise ValueError(f"{args.sweep}: row {i + 1} needs config (and may have seeds, out, set, name, "
                                 "levels, grid)")
            overrides = r.get("set", [])
            if not (isinstance(overrides, list) and all(isinstance(o, str) and "=" in o for o in overrides)):
                raise ValueError(f"{args.sweep}: row {i + 1}: set must be a list of \"FIELD=VALUE\" strings")
            if "grid" in r:
                if "out" in r:
                    raise ValueError(f"{args.sweep}: row {i + 1}: a grid makes several rows, which cannot share "
                                     "one out; give name (a prefix) instead")
                for more in grid_overrides(r["grid"], f"{args.sweep}: row {i + 1}"):
                    prefix = r.get("name")
                    name = "-".join([prefix, row_name("x", more).removeprefix("x-")]) if prefix else None
                    rows.append(_file_row(spec, r, i, given_seeds, base, tuple(overrides) + more, extra, name,
                                          args.sweep))
                continue
            rows.append(_file_row(spec, r, i, given_seeds, base, tuple(overrides), extra, r.get("name"),
                                  args.sweep))
        outs = [row.out for row in rows]
        if len(set(outs)) != len(outs):
            raise ValueError(f"{args.sweep}: two rows write to the same directory; give them a name or out")
        if not rows:
            raise ValueError(f"{args.sweep}: no [[row]]")
        return rows
    if not args.configs:
        raise ValueError("give one or more configs, or --sweep FILE")
    seeds = given_seeds or parse_seeds("0..3")
    if len(args.configs) == 1 and out is not None:
        return [Row(args.configs[0], seeds, out, extra)]
    base = out or pathlib.Path("runs")
    return [Row(c, seeds, base / config_name(c), extra) for c in args.configs]


def _file_row(spec, r, i, given_seeds, base, overrides, extra, name, path) -> Row:
    """Row ``i`` of a sweep file with its ``overrides`` (its ``set``, and a grid point's)."""
    seeds = given_seeds or parse_seeds(r.get("seeds", spec.get("seeds", "0..3")))
    levels = ()
    if "levels" in r:
        try:
            levels = parse_seeds(str(r["levels"]))
        except ValueError as e:
            raise ValueError(f"{path}: row {i + 1}: levels: {str(e).removeprefix('--seeds ')}") from None
        if 0 in levels:
            raise ValueError(f"{path}: row {i + 1}: OBL levels count from 1")
    name = name or row_name(r["config"], overrides)
    return Row(r["config"], seeds, pathlib.Path(r.get("out", base / name)), overrides + extra, levels)


def grid_overrides(grid, where: str) -> list:
    """A row's ``grid`` (``{"ppo.entropy_coef" = [0.01, 0.03], "ppo.lr" = [1e-3, 3e-3]}``)
    as one tuple of ``FIELD=VALUE`` overrides per point of the grid: every combination of
    the listed values, the first field varying slowest."""
    if not (isinstance(grid, dict) and grid and all(isinstance(v, list) and v for v in grid.values())):
        raise ValueError(f"{where}: grid must map each config field to a non-empty list of values")
    points = [()]
    for field, values in grid.items():
        points = [p + (f"{field}={_toml_value(v)}",) for p in points for v in values]
    return points


def _toml_value(v) -> str:
    """A grid value as ``yokai train --set`` reads it (TOML)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    return str(v)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m yokai.sweep", description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("configs", nargs="*", help="training configs: preset names or TOML files")
    ap.add_argument("--sweep", help="a sweep file of rows (see below)")
    ap.add_argument("--seeds", help="seeds: 0..12, 0,4,7 or 5 (default: the sweep file's, else 0..3); "
                                   "replaces every row's")
    ap.add_argument("--set", action="append", metavar="FIELD=VALUE",
                    help="a config override for every row (yokai train --set), after the row's own: "
                         "e.g. --set ppo.total_steps=2000000 to run a whole table at one budget")
    ap.add_argument("--out", help="run directory of one config, or the parent of one per config "
                                  "(default runs/<config>)")
    ap.add_argument("--address", help="Ray cluster address (auto, ray://host:10001); default: "
                                      "start a local Ray instance")
    ap.add_argument("--cpus-per-seed", type=float, default=1, help="CPUs per seed (default 1)")
    ap.add_argument("--gpus-per-seed", type=float, default=0, help="GPUs per seed (default 0)")
    ap.add_argument("--device", default="cpu", help="where each seed trains: cpu, vulkan or cuda (a yokai "
                                                     "binary built with that feature; see docs/training.md)")
    ap.add_argument("--max-retries", type=int, default=3, help="retries of a failed seed (default 3)")
    ap.add_argument("--engine", choices=ENGINES, default="tune",
                    help="tune: every seed a Ray Tune trial (restarts on failure, the experiment "
                         "restored when started again, results in <out>/.tune); tasks: plain Ray "
                         "tasks, for a Ray without Tune (default tune)")
    ap.add_argument("--eval-games", type=int, default=1000, help="games per pair in the evaluation; 0 skips it")
    ap.add_argument("--num-cpus", type=int, help="CPUs of the local Ray instance (default: all; "
                                                 "ignored with --address)")
    ap.add_argument("--yokai", help="path of the yokai binary on every node (default: $YOKAI, PATH, "
                                    "this checkout's target/release/yokai)")
    ap.epilog = __doc__[__doc__.index("A sweep file"):]
    args = ap.parse_args(argv)
    try:
        rows = rows_from_args(args)
    except (ValueError, OSError) as e:
        ap.error(str(e))
    result = run_sweep(rows, address=args.address, cpus_per_seed=args.cpus_per_seed,
                       gpus_per_seed=args.gpus_per_seed, max_retries=args.max_retries,
                       eval_games=args.eval_games, yokai=args.yokai, num_cpus=args.num_cpus,
                       device=args.device, engine=args.engine, **table_options(args.sweep))
    for r in result["runs"]:
        print(f"seed {r['seed']}: {r['status']}")
    for e in result["evals"]:
        print(f"evaluation: {e}")
    if result["table"]:
        print(f"table: {result['table']}")


if __name__ == "__main__":
    main()

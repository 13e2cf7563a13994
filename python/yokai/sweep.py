"""Multi-seed sweeps on Ray: ``python -m yokai.sweep CONFIG --seeds 0..12 [--address auto]``.

Each seed of each row is one Ray task with its declared resources (``--cpus-per-seed``,
``--gpus-per-seed``) that runs ``yokai train CONFIG --seeds N --out OUT`` into a directory
every node sees (a local path by default; on a cluster a shared file system such as NFS or
Lustre: the trainer writes ordinary files). Then the sweep evaluates every row with
``yokai eval`` (self-play and cross-play over all seeds) and, for several rows, writes the
paper's table with ``yokai compare``.

Fault tolerance comes from the trainer's checkpoints, not from Ray's object store:

- a task whose worker dies (node lost, preempted, killed) is retried by Ray
  (``--max-retries``), and a retry passes ``--resume`` when the seed has a checkpoint, so it
  continues from the last one instead of starting over (the trainer's resume is exact: the
  final parameters equal an uninterrupted run's);
- the ``yokai`` process dies with its worker (``PR_SET_PDEATHSIG``), so a retry never races
  an orphan writing the same directory;
- a sweep stopped and started again skips seeds marked finished and resumes the others.

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
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass

try:  # Python 3.11+
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - the sweep extra installs tomli there
    import tomli as tomllib

DONE = ".sweep-done"
ATTEMPTS = "sweep.log"


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
               overrides: tuple = (), levels: tuple = ()) -> dict:
    """Train (or resume, or skip) one seed; the body of a Ray task. Returns a summary.
    With ``levels``, the seed's OBL levels in order (level L reads the same seed's level
    L-1), each resumed or skipped on its own."""
    if not levels:
        return _train_run(yokai, config, seed, pathlib.Path(out), threads, device, overrides, [])
    result = {}
    for level in levels:
        result = _train_run(yokai, config, seed, level_dir(out, level), threads, device,
                            overrides, ["--levels", str(level)], out=pathlib.Path(out))
        result["level"] = level
    return result


def _train_run(yokai: str, config: str, seed: int, runs: pathlib.Path, threads: int, device: str,
               overrides: tuple, extra: list, out: pathlib.Path | None = None) -> dict:
    """``yokai train`` of one seed into ``runs/seed-N`` (``--out out``, ``runs`` by default)."""
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
    proc = subprocess.run(cmd, capture_output=True, text=True,
                          preexec_fn=_die_with_parent if sys.platform.startswith("linux") else None)
    if proc.returncode != 0:
        _note(run, f"pid {os.getpid()} failed: exit {proc.returncode}")
        raise RuntimeError(f"yokai train {config} seed {seed} ({run}) exited with {proc.returncode}:\n"
                           f"{proc.stderr[-2000:]}")
    # yokai's summary, "seed N: U updates, S env steps (S' now, in T s: …)", says how many
    # steps this attempt trained, hence where it resumed.
    summary = next((l for l in proc.stderr.splitlines() if l.startswith(f"seed {seed}: ")), "")
    _note(run, f"pid {os.getpid()} done: {summary}")
    (run / DONE).write_text(summary)
    return {"seed": seed, "status": "resumed" if resume else "trained", "log": proc.stderr.strip()}


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
              device="cpu", paper_table=2, select_entropy=None):
    """Train every seed of every row as Ray tasks, then evaluate each row (each OBL level
    apart); returns ``{"runs": [...], "evals": [...], "table": path or None}``, the table
    beside the paper's Table ``paper_table`` (with HE's α selection at that tolerance when
    ``select_entropy`` is given). ``num_cpus`` caps a local Ray instance (tests)."""
    try:
        import ray
    except ImportError:
        raise SystemExit("yokai.sweep needs Ray: pip install './python[sweep]' (or pip install ray)") from None

    yokai = find_yokai(yokai)
    if not ray.is_initialized():
        ray.init(address=address, num_cpus=num_cpus if address is None else None,
                 include_dashboard=False, logging_level="WARNING", log_to_driver=False)
    task = ray.remote(num_cpus=cpus_per_seed, num_gpus=gpus_per_seed, max_retries=max_retries,
                      retry_exceptions=True)(train_seed)
    refs = {}
    for row in rows:
        row.out.mkdir(parents=True, exist_ok=True)
        for seed in row.seeds:
            refs[task.remote(yokai, row.config, seed, str(row.out), max(1, int(cpus_per_seed)), device,
                             row.set, row.levels)] = (row, seed)
    started, results, pending = {}, [], list(refs)
    next_report = time.time()
    while pending:
        ready, pending = ray.wait(pending, timeout=1.0)
        for ref in ready:
            results.append(ray.get(ref))  # raises once the retries are spent
        if not quiet and (time.time() >= next_report or not pending):
            for row, seed in refs.values():
                print(progress_line(row, seed, started), file=sys.stderr)
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
            if "config" not in r or set(r) - {"config", "seeds", "out", "set", "name", "levels"}:
                raise ValueError(f"{args.sweep}: row {i + 1} needs config (and may have seeds, out, set, name, levels)")
            overrides = r.get("set", [])
            if not (isinstance(overrides, list) and all(isinstance(o, str) and "=" in o for o in overrides)):
                raise ValueError(f"{args.sweep}: row {i + 1}: set must be a list of \"FIELD=VALUE\" strings")
            seeds = given_seeds or parse_seeds(r.get("seeds", spec.get("seeds", "0..3")))
            levels = ()
            if "levels" in r:
                try:
                    levels = parse_seeds(str(r["levels"]))
                except ValueError as e:
                    raise ValueError(f"{args.sweep}: row {i + 1}: levels: {str(e).removeprefix('--seeds ')}") from None
                if 0 in levels:
                    raise ValueError(f"{args.sweep}: row {i + 1}: OBL levels count from 1")
            name = r.get("name") or row_name(r["config"], overrides)
            rows.append(Row(r["config"], seeds, pathlib.Path(r.get("out", base / name)),
                            tuple(overrides) + extra, levels))
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
                       device=args.device, **table_options(args.sweep))
    for r in result["runs"]:
        print(f"seed {r['seed']}: {r['status']}")
    for e in result["evals"]:
        print(f"evaluation: {e}")
    if result["table"]:
        print(f"table: {result['table']}")


if __name__ == "__main__":
    main()

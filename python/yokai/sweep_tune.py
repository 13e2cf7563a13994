"""The seeds of a sweep as Ray Tune trials: ``python -m yokai.sweep --engine tune`` (the
default when ``ray[tune]`` is installed).

Every (row, seed) is one trial of a ``Tuner`` over a grid (``tune.grid_search``), with the
resources it declares. What Tune brings over plain Ray tasks:

- **failure handling**: a trial whose worker dies or whose trainer fails is restarted up to
  ``--max-retries`` times (``FailureConfig``); the restart resumes from the seed's own
  checkpoint, as a retried task does (``yokai.sweep.train_seed``);
- **resume**: the experiment's state lives under ``<out>/.tune/<name>``; a sweep started
  again with the same trials restores it (``Tuner.restore``), so finished trials are not
  run again and the others go on from their checkpoints;
- **results**: each trial reports the trainer's progress (update, env steps, training games'
  R) as it goes, so Tune's loggers (``progress.csv``, ``result.json``, TensorBoard) and its
  result table (``ResultGrid.get_dataframe()``) hold every seed's curve.

This module knows nothing of rows or of the trainer: ``train_with_tune`` is handed the
trials as JSON-able dicts and the function that trains one.
"""

from __future__ import annotations

import hashlib
import json
import pathlib
import time


def require_tune():
    """``ray.tune``, or an error that says what to install."""
    try:
        from ray import tune
    except ImportError:
        raise SystemExit("the tune engine needs Ray Tune: pip install './python[sweep]' (or "
                         "pip install 'ray[tune]'), or run with --engine tasks") from None
    return tune


def experiment_name(trials: list) -> str:
    """The experiment's directory name: a hash of its trials, so a sweep started again with
    the same trials restores its experiment and one with other trials gets its own."""
    digest = hashlib.sha256(json.dumps(trials, sort_keys=True).encode()).hexdigest()[:12]
    return f"sweep-{digest}"


def train_with_tune(trials: list, train, storage: pathlib.Path, cpus: float, gpus: float,
                    max_failures: int, progress=None, progress_every: float = 10.0) -> list:
    """Run ``train(trial, report)`` for every trial as a Tune trial; returns each trial's
    summary (what ``train`` returned), in the order of ``trials``. ``progress()``, when
    given, is called every ``progress_every`` seconds on the driver, and once at the end
    (the sweep's progress lines). A trial that still fails after ``max_failures`` restarts
    raises ``RuntimeError`` naming it."""
    tune = require_tune()

    class Progress(tune.Callback):
        """Calls ``progress`` on the driver while trials run."""

        def __init__(self):
            self.next = time.time()

        def on_step_begin(self, iteration, trials, **info):
            if time.time() >= self.next:
                progress()
                self.next = time.time() + progress_every

        def on_experiment_end(self, trials, **info):
            progress()

    def trainable(config):
        trial = config["trial"]
        summary = train(trial, tune.report)
        # The last report carries the summary, so the result grid holds it.
        tune.report({"summary": json.dumps(summary)})

    resources = {"cpu": cpus, "gpu": gpus}
    storage = pathlib.Path(storage).resolve()
    name = experiment_name(trials)
    path = storage / name
    runnable = tune.with_resources(trainable, resources)
    if tune.Tuner.can_restore(str(path)):
        tuner = tune.Tuner.restore(str(path), trainable=runnable, resume_unfinished=True,
                                   restart_errored=True)
    else:
        tuner = tune.Tuner(
            runnable,
            param_space={"trial": tune.grid_search(trials)},
            # One process serves trial after trial: a Tune actor's start is most of a tiny
            # trial's time.
            tune_config=tune.TuneConfig(reuse_actors=True,
                                        trial_name_creator=lambda t: _trial_label(t.config["trial"]),
                                        trial_dirname_creator=lambda t: _trial_label(t.config["trial"])),
            run_config=tune.RunConfig(
                name=name, storage_path=str(storage), verbose=0,
                failure_config=tune.FailureConfig(max_failures=max_failures),
                callbacks=[Progress()] if progress else None),
        )
    grid = tuner.fit()
    if grid.errors:
        failed = [_trial_label(r.config["trial"]) for r in grid if r.error]
        raise RuntimeError(f"{len(failed)} trial(s) failed after {max_failures} restarts: "
                           f"{', '.join(failed)}; Tune's logs: {path}\n{grid.errors[0]}")
    summaries = {}
    for result in grid:
        key = json.dumps(result.config["trial"], sort_keys=True)
        summaries[key] = json.loads(result.metrics["summary"])
    return [summaries[json.dumps(t, sort_keys=True)] for t in trials]


def _trial_label(trial: dict) -> str:
    """``03-op-9c-2p-seed-1``: the row's place and directory name, and the seed."""
    return f"{trial['row']:02d}-{trial['name']}-seed-{trial['seed']}"

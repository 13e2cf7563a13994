#!/usr/bin/env python3
"""Each update of a run's metrics.jsonl (from `yokai train` or `python -m yokai.torch_train`)
on one line: env steps/s end to end and the split between rollout and learning. What the
GPU scripts print after each timed run.

    scripts/update-times.py RUN/metrics.jsonl [LABEL]

Exits 1, saying so, when no update finished (the file is missing or empty: `yokai train`
creates it before its first update)."""

import json
import os
import sys

path = sys.argv[1]
label = f"{sys.argv[2]}: " if len(sys.argv) > 2 else ""
lines = open(path).read().splitlines() if os.path.exists(path) else []
if not lines:
    print(f"{label}no update finished")
    sys.exit(1)
for line in lines:
    s = json.loads(line)
    rollout, learning = s["rollout_seconds"], s["learn_seconds"]
    share = 100 * learning / (rollout + learning) if rollout + learning > 0 else float("nan")
    print(f"{label}update {s['update']}: {s['sps']:.0f} env steps/s end to end, "
          f"rollout {rollout:.2f} s, learning {learning:.2f} s ({share:.1f} % of the two)")

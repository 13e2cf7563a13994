#!/usr/bin/env python3
"""Wall clock and speed of a finished sweep, from its seeds' `sweep.log` files.

    python scripts/sweep_times.py runs/table2-cpu

Prints a Markdown table: per row (and OBL level), when its first seed started and its
last finished, the wall clock between them, and each seed's env steps/s as `yokai train`
reported it ("in T s: S SPS"). Rows trained side by side share the machine, so a row's
wall clock is what it took beside the others, not alone.
"""

import pathlib
import re
import sys
from datetime import datetime

STAMP = "%Y-%m-%d %H:%M:%S"


def attempts(log: pathlib.Path):
    """(start, done, sps) of a seed: its first start and its last "done" line."""
    start = done = sps = None
    for line in log.read_text().splitlines():
        when = datetime.strptime(line[:19], STAMP)
        if " starts" in line and start is None:
            start = when
        if " done: " in line:
            done = when
            m = re.search(r": (\d+) SPS\)", line)
            sps = int(m.group(1)) if m else None
    return start, done, sps


def main(root: str):
    root = pathlib.Path(root)
    rows = {}
    for log in sorted(root.glob("**/seed-*/sweep.log")):
        row = log.parent.parent.relative_to(root)
        rows.setdefault(str(row), []).append(attempts(log))
    print("| row | first start | last done | wall clock | env steps/s per seed |")
    print("|---|---|---|---|---|")
    for row, seeds in rows.items():
        starts = [s for s, _, _ in seeds if s]
        dones = [d for _, d, _ in seeds if d]
        if not starts or len(dones) < len(seeds):
            print(f"| {row} | – | – | unfinished | – |")
            continue
        first, last = min(starts), max(dones)
        minutes = (last - first).total_seconds() / 60
        speeds = ", ".join(f"{s:,}" if s else "–" for _, _, s in seeds)
        print(f"| {row} | {first:%H:%M:%S} | {last:%H:%M:%S} | {minutes:.1f} min | {speeds} |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

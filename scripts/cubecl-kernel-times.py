#!/usr/bin/env python3
"""Where a GPU run's time goes, from CubeCL's debug log (CUBECL_DEBUG_LOG, which
scripts/gpu-lib.sh's device_check sets): every kernel launch the log timed, summed.

    scripts/cubecl-kernel-times.py LOG[.xz] [--top N] [--family PREFIX]

Without --family: the time, launch count and mean per kernel family (the kernel's name
with its hash cut off; matrix products by their argument kind), largest first.
With --family PREFIX: the kernels whose name starts with PREFIX one by one (their name up
to 80 characters, hash kept), with median and largest launch: which of a family's kernels
take the time, and how often per gradient step they run.

The log holds the lines `| 12.3µs | KernelName | …`; compile records and other lines are
skipped. The GPU scripts keep the log's last 4 MB, so the figures cover the run's last
tens of thousands of launches, not the whole run."""

import argparse
import collections
import lzma
import re

UNITS = {"ns": 1e-3, "µs": 1.0, "ms": 1e3, "s": 1e6}
LINE = re.compile(r"\|\s*([\d.]+)(ns|µs|ms|s)\s*\|\s*(.*)")


def launches(path):
    """(microseconds, full kernel name) for every timed launch in the log."""
    opener = lzma.open if path.endswith(".xz") else open
    with opener(path, "rt", errors="replace") as f:
        for line in f:
            m = LINE.match(line)
            if m:
                yield float(m.group(1)) * UNITS[m.group(2)], m.group(3).strip()


def family(name):
    parts = [p.strip() for p in name.split("|")]
    head = re.sub(r"_[0-9a-f]{6,}$", "", parts[0])
    return f"Matmul {parts[1]}" if head == "MatmulEntry" and len(parts) > 1 else head


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("log")
    p.add_argument("--top", type=int, default=12)
    p.add_argument("--family", help="list this family's kernels one by one")
    a = p.parse_args()
    times = collections.defaultdict(list)
    try:
        for us, name in launches(a.log):
            if a.family is None:
                times[family(name)].append(us)
            elif name.startswith(a.family):
                times[name[:80]].append(us)
    except (OSError, EOFError, lzma.LZMAError) as e:
        raise SystemExit(f"{a.log}: cannot be read: {e}")
    total = sum(sum(v) for v in times.values())
    count = sum(len(v) for v in times.values())
    if not count:
        raise SystemExit(f"{a.log}: no timed kernel launches")
    print(f"{a.log}: {total / 1e6:.2f} s in {count} launches")
    rows = sorted(times.items(), key=lambda kv: -sum(kv[1]))[: a.top]
    for name, v in rows:
        v = sorted(v)
        print(
            f"{sum(v) / 1e6:8.3f} s {100 * sum(v) / total:5.1f} % {len(v):7d} launches, "
            f"median {v[len(v) // 2]:10.1f} µs, largest {v[-1]:10.1f} µs  {name}"
        )


if __name__ == "__main__":
    main()

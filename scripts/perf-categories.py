#!/usr/bin/env python3
"""Group a perf profile's samples by what the code does, for "where an update's time goes".

    perf record -e cpu-clock -F 2000 -o perf.data target/release/yokai train cpu-fast \\
        --seeds 0 --max-updates 80 --eval-games 0 --threads 2 --out /tmp/prof
    perf report -i perf.data --no-children --sort symbol -g none | scripts/perf-categories.py

Each symbol's share goes to the first category whose pattern it matches (in the order
below), the rest to "other". Prints one line per category, in per cent of all samples.
"""

import re
import sys

CATEGORIES = [
    ("matrix products (gemm kernels)", r"gemm"),
    ("memory copies and fills (memmove, memset, page clearing)", r"memmove|memset|clear_page|copy_2d|memcpy"),
    ("scalar exp / expm1 / tanh (libm)", r"expf|expm1f|tanhf|logf|log1pf"),
    ("element-wise kernels (burn-flex unary/binary/zip, macerator)", r"burn_flex::ops::(unary|binary)|burn_flex::zip|macerator"),
    ("allocator (malloc, free)", r"malloc|_int_free|cfree|unlink_chunk|free@|_int_realloc|realloc"),
    ("autodiff graph bookkeeping (hashing, graph, Arc)", r"hash_one|burn_autodiff|hashbrown|Arc|drop_in_place"),
    ("games and rollout (engine, env, actor)", r"yokai_engine|yokai_vec|yokai_train::(trainer::rollout|actor)"),
    ("kernel scheduling (threads waiting and waking)", r"\[k\]"),
]


def main() -> None:
    totals = {name: 0.0 for name, _ in CATEGORIES}
    other = 0.0
    for line in sys.stdin:
        m = re.match(r"\s+([0-9.]+)%\s+(\[.\])\s+(.*)", line)
        if not m:
            continue
        share, symbol = float(m.group(1)), m.group(2) + " " + m.group(3)
        for name, pattern in CATEGORIES:
            if re.search(pattern, symbol):
                totals[name] += share
                break
        else:
            other += share
    for name, _ in CATEGORIES:
        print(f"{name}: {totals[name]:.1f}")
    print(f"other: {other:.1f}")


if __name__ == "__main__":
    main()

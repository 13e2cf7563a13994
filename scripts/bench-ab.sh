#!/usr/bin/env bash
# Interleaved A/B of two `yokai` binaries: on a shared machine whose speed drifts over
# minutes, running A then B (never all of A, then all of B) is what makes them comparable.
#
#   scripts/bench-ab.sh OLD_YOKAI NEW_YOKAI ROUNDS [yokai bench options…]
#   scripts/bench-ab.sh /tmp/yokai-before target/release/yokai 16 \
#       --envs 2048 --configs 9c-2p-perfect --dtypes u8 --encodings image-chw --seconds 0.3
#
# Prints, for each binary and each bench row, the median and the best of the ROUNDS runs.
# Build the "before" binary from a worktree with its own CARGO_TARGET_DIR.
set -euo pipefail
if [ $# -lt 3 ]; then
    sed -n 2,9p "$0" >&2
    exit 2
fi
old=$1 new=$2 rounds=$3
shift 3
for _ in $(seq "$rounds"); do
    for side in old new; do
        bin=$old
        [ "$side" = new ] && bin=$new
        "$bin" bench --json "$@" 2>/dev/null | sed "s/^/$side /"
    done
done | python3 -c '
import json, statistics, sys
runs = {}
for line in sys.stdin:
    side, row = line.split(" ", 1)
    r = json.loads(row)
    key = (r["config"], r["envs"], r["encoding"], r["dtype"], r["threads"])
    runs.setdefault(key, {}).setdefault(side, []).append(r["steps_per_second"] / 1e6)
for key, sides in runs.items():
    cells = [f"{s}: median {statistics.median(v):.2f} M, best {max(v):.2f} M" for s, v in sorted(sides.items(), reverse=True)]
    print(" ".join(map(str, key)), "|", " | ".join(cells))
'

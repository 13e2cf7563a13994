#!/usr/bin/env bash
# Interleaved A/B of the training speed of two `yokai` binaries (the trainer's counterpart
# of bench-ab.sh): each round trains CONFIG for UPDATES updates with the old binary, then
# with the new one, so that the machine's drift over minutes hits both alike.
#
#   scripts/train-ab.sh OLD_YOKAI NEW_YOKAI ROUNDS CONFIG [UPDATES] [yokai train options…]
#   scripts/train-ab.sh /tmp/yokai-before target/release/yokai 4 cpu 40 --threads 2
#
# Prints, per binary, the median over rounds of each run's mean env steps/s and rollout and
# learning seconds per update, the first 10 updates of every run left out (start-up).
set -euo pipefail
if [ $# -lt 4 ]; then
    sed -n 2,10p "$0" >&2
    exit 2
fi
old=$1 new=$2 rounds=$3 config=$4 updates=${5:-40}
shift $(($# < 5 ? 4 : 5))
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for round in $(seq "$rounds"); do
    for side in old new; do
        bin=$old
        [ "$side" = new ] && bin=$new
        dir="$out/$side-$round"
        "$bin" train "$config" --seeds 0 --max-updates "$updates" --eval-games 0 \
            --out "$dir" "$@" > /dev/null 2>&1
        echo "$side $dir/seed-0/metrics.jsonl"
    done
done | python3 -c '
import json, statistics, sys
runs = {"old": [], "new": []}
for line in sys.stdin:
    side, path = line.split()
    rows = [json.loads(l) for l in open(path)][10:]
    runs[side].append([statistics.mean(r[k] for r in rows)
                       for k in ("sps", "rollout_seconds", "learn_seconds")])
for side, got in runs.items():
    med = [statistics.median(col) for col in zip(*got)]
    print(f"{side}: {med[0]:,.0f} env steps/s (runs {min(g[0] for g in got):,.0f}-"
          f"{max(g[0] for g in got):,.0f}), rollout {med[1]:.4f} s, learning {med[2]:.4f} s per update")
'

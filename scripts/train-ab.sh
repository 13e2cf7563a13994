#!/usr/bin/env bash
# Interleaved comparison of the training speed of two or more `yokai` binaries (the
# trainer's counterpart of bench-ab.sh): each round trains CONFIG for UPDATES updates with
# every binary in turn, so that the machine's drift over minutes hits all of them alike.
#
#   scripts/train-ab.sh YOKAI YOKAI [YOKAI…] ROUNDS CONFIG [UPDATES] [yokai train options…]
#   scripts/train-ab.sh /tmp/yokai-before target/release/yokai 4 cpu 40 --threads 2
#
# An arm may add config overrides of its own, `YOKAI@FIELD=VALUE[,FIELD=VALUE…]`, to compare
# settings on one binary:
#   scripts/train-ab.sh target/release/yokai@network.colours=dealt \
#       target/release/yokai@network.colours=first-seen 5 cpu-op 80 --threads 2
#
# Prints, per binary, the median over rounds of each run's mean env steps/s and rollout and
# learning seconds per update, the first 10 updates of every run left out (start-up).
set -euo pipefail
bins=()
while [ $# -gt 0 ] && ! [[ $1 =~ ^[0-9]+$ ]]; do
    bins+=("$1")
    shift
done
if [ ${#bins[@]} -lt 2 ] || [ $# -lt 2 ]; then
    sed -n 2,15p "$0" >&2
    exit 2
fi
rounds=$1 config=$2 updates=${3:-40}
shift $(($# < 3 ? 2 : 3))
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for round in $(seq "$rounds"); do
    for k in "${!bins[@]}"; do
        dir="$out/$k-$round"
        arm=${bins[$k]} sets=()
        if [[ $arm == *@* ]]; then
            IFS=, read -ra fields <<< "${arm#*@}"
            for f in "${fields[@]}"; do sets+=(--set "$f"); done
        fi
        "${arm%%@*}" train "$config" --seeds 0 --max-updates "$updates" --eval-games 0 \
            --out "$dir" "${sets[@]}" "$@" > /dev/null 2>&1
        echo "$arm $dir/seed-0/metrics.jsonl"
    done
done | python3 -c '
import json, statistics, sys
runs = {}
for line in sys.stdin:
    bin, path = line.rsplit(" ", 1)
    rows = [json.loads(l) for l in open(path.strip())][10:]
    runs.setdefault(bin, []).append([statistics.mean(r[k] for r in rows)
                                     for k in ("sps", "rollout_seconds", "learn_seconds")])
for bin, got in runs.items():
    med = [statistics.median(col) for col in zip(*got)]
    print(f"{bin}: {med[0]:,.0f} env steps/s (runs {min(g[0] for g in got):,.0f}-"
          f"{max(g[0] for g in got):,.0f}), rollout {med[1]:.4f} s, learning {med[2]:.4f} s per update")
'

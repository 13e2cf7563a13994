#!/usr/bin/env bash
# Wall clock of `yokai train` for several seeds with different numbers of seeds trained
# side by side (--jobs), interleaved round by round so that drift of the machine's speed
# hits every setting alike.
#
#   scripts/jobs-ab.sh YOKAI ROUNDS STEPS "JOBS..." [extra yokai train options…]
#   scripts/jobs-ab.sh target/release/yokai 2 200000 "1 2 3" --seeds 0..3 --threads 2
#
# Prints, per --jobs value, each round's seconds, their median, and total env steps/s.
set -euo pipefail
if [ $# -lt 4 ]; then
    sed -n 2,9p "$0" >&2
    exit 2
fi
bin=$1 rounds=$2 steps=$3 jobs=$4
shift 4
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for r in $(seq "$rounds"); do
    for j in $jobs; do
        rm -rf "$out/run"
        start=$(date +%s.%N)
        "$bin" train quick --steps "$steps" --eval-games 0 --jobs "$j" --out "$out/run" "$@" \
            >/dev/null 2>&1
        end=$(date +%s.%N)
        seeds=$(ls -d "$out"/run/seed-* | wc -l)
        echo "$j $(echo "$end - $start" | bc) $seeds"
    done
done | python3 -c '
import statistics, sys
runs = {}
for line in sys.stdin:
    j, secs, seeds = line.split()
    runs.setdefault(int(j), []).append((float(secs), int(seeds)))
steps = int(sys.argv[1])
for j, v in sorted(runs.items()):
    secs = [s for s, _ in v]
    m = statistics.median(secs)
    print(f"--jobs {j}: " + ", ".join(f"{s:.1f}" for s in secs)
          + f" s; median {m:.1f} s = {v[0][1] * steps / m:,.0f} env steps/s in all")
' "$steps"

#!/bin/sh
# Keep one trained and evaluated OBL level of a run in the docs, the way the levels under
# docs/results/data/ are kept:
#   scripts/keep-obl-level.sh OUT LEVEL DATA WEIGHTS
# OUT is the run's folder (with train-LEVEL.log and times.txt, as the run.sh scripts under
# docs/results/data/ write them), LEVEL the level, DATA the folder for the evaluation's
# files (docs/results/data/...), WEIGHTS the folder under docs/results/data/obl-chain-weights
# for every seed's policy.ykp. Example (seeds 0-2 of the route with the symmetries from 4):
#   scripts/keep-obl-level.sh runs/obl-op-from-4-0 4 \
#     docs/results/data/obl-op-from-4/seeds-0-2-level-4 op-from-4-0-level-4
set -eu
if [ $# -ne 4 ]; then
  echo "usage: $0 OUT LEVEL DATA WEIGHTS (see the comment at its top)" >&2
  exit 2
fi
OUT=$1 L=$2 DATA=$3
WEIGHTS=docs/results/data/obl-chain-weights/$4
RUN=$OUT/level-$L
[ -f "$RUN/eval/matrix.csv" ] || { echo "$RUN/eval/matrix.csv: no evaluation of level $L" >&2; exit 1; }
mkdir -p "$DATA"
for f in learning_belief.png learning_return.png learning_see.png matrix.csv matrix.json \
  report.md summary.json xp_heatmap.png; do
  cp "$RUN/eval/$f" "$DATA/"
done
FIRST=$(ls -d "$RUN"/seed-* | head -n 1)
cp "$FIRST/config.toml" "$DATA/$(basename "$FIRST")-config.toml"
grep "^seed [0-9]*: [0-9]* updates" "$OUT/train-$L.log" > "$DATA/train-last-lines.txt"
grep "level $L" "$OUT/times.txt" > "$DATA/times.txt"
for seed in "$RUN"/seed-*; do
  mkdir -p "$WEIGHTS/$(basename "$seed")"
  cp "$seed/policy.ykp" "$WEIGHTS/$(basename "$seed")/"
done
echo "kept level $L of $OUT in $DATA and $WEIGHTS"

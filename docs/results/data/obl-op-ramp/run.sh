#!/bin/sh
# The from-4 route of data/obl-op-from-4-all (seeds 0-2, every level by one rule) with
# Other-Play's symmetries brought in gradually at level 4: `--set obl.symmetries_ramp=0.5`
# grows the share of games dealt with symmetries from 0 to 1 over the level's first half
# (the preset obl-cpu-op's own rule since 2026-12-07; the --set options keep the command as
# it was run). Level 4 starts from data/obl-chain-weights/$START (op-from-4-all-level-3).
# Run from the repository root:
#   LEVELS=4 YOKAI=/work/bin/yokai sh docs/results/data/obl-op-ramp/run.sh
# Level 5 and above (no ramp there: it acts only at the switch level) start from
# $OUT/level-(L-1), or where that is missing from data/obl-chain-weights/$KEPT-level-(L-1).
# The held-out seeds 3-5 run through data/obl-op-ramp-held-out/run.sh, this with other
# SEEDS, OUT, START and KEPT.
export YOKAI=${YOKAI:-yokai} OUT=${OUT:-runs/obl-op-ramp} SEEDS=${SEEDS:-0..3}
START=${START:-op-from-4-all-level-3} KEPT=${KEPT:-op-ramp}
export PRESET=obl-cpu-op
export SET="--set obl.symmetries_from_level=4 --set obl.symmetries_ramp=0.5"
for L in ${LEVELS:-4}; do
  if [ $L -eq 4 ]; then FROM=$START; else FROM=$KEPT-level-$((L - 1)); fi
  LEVEL=$L FROM=$FROM sh scripts/obl-level.sh || exit 1
done

#!/bin/sh
# The route with Other-Play's symmetries from level 4 (`obl-cpu-op --set
# obl.symmetries_from_level=4`) on seeds 0-2, every level by that rule: levels 2-3 with the
# all-seeds belief and no symmetries (obl-cpu-long's rule), from level 4 with them. Level 1
# is data/obl-chain-weights/lr1e-3-level-1 (obl-cpu-long's level 1: the belief of level 0 is
# exact, so belief_of does not act there). Run from the repository root:
#   LEVELS="2 3" YOKAI=/work/bin/yokai sh docs/results/data/obl-op-from-4-all/run.sh
# A level whose level below is not in $OUT starts from
# data/obl-chain-weights/op-from-4-all-level-(L-1) (level 2: lr1e-3-level-1).
export YOKAI=${YOKAI:-yokai} OUT=${OUT:-runs/obl-op-from-4-all} SEEDS=${SEEDS:-0..3}
export PRESET=obl-cpu-op SET="--set obl.symmetries_from_level=4"
for L in ${LEVELS:-2 3}; do
  if [ $L -eq 2 ]; then FROM=lr1e-3-level-1; else FROM=op-from-4-all-level-$((L - 1)); fi
  LEVEL=$L FROM=$FROM sh scripts/obl-level.sh || exit 1
done

#!/bin/sh
# data/obl-op-ramp's route on the held-out seeds 3-5: Other-Play's symmetries brought in
# gradually at level 4 (`--set obl.symmetries_ramp=0.5`: the share of games dealt with
# symmetries grows from 0 to 1 over the level's first half). Level 4 starts from
# data/obl-chain-weights/held-out-level-3, the level 3 the hard switch of data/obl-op-from-4
# started from. Run from the repository root:
#   LEVELS="4 5" YOKAI=/work/bin/yokai sh docs/results/data/obl-op-ramp-held-out/run.sh
# Level 5 and above start from $OUT/level-(L-1), or where that is missing from
# data/obl-chain-weights/op-ramp-held-out-level-(L-1).
OUT=${OUT:-runs/obl-op-ramp-held-out} SEEDS=${SEEDS:-3..6} START=held-out-level-3 \
  KEPT=op-ramp-held-out exec sh docs/results/data/obl-op-ramp/run.sh

#!/bin/sh
# The preset obl-cpu-op with Other-Play's symmetries switched on at level 4 instead of 5
# (`--set obl.symmetries_from_level=4`), seeds 3-5, on top of the held-out chain's level 3
# (data/obl-chain-weights/held-out-level-3). Run from the repository root:
#   LEVEL=4 YOKAI=/work/bin/yokai sh docs/results/data/obl-op-from-4/run.sh
# then LEVEL=5 and LEVEL=6 (run 2026-12-06, level 4 from 16:49, cut and resumed at 17:40);
# a level whose level below is not in $OUT starts from
# data/obl-chain-weights/op-from-4-level-(L-1) (level 4: held-out-level-3), or $FROM. Seeds 0-2
# on their level 3 (the chain the preset's seeds 0-2 levels 5-7 grew from):
#   LEVEL=4 FROM=b10k-level-3 SEEDS=0..3 OUT=runs/obl-op-from-4-0 sh …/run.sh
# Each level is one scripts/obl-level.sh: wall clock by /usr/bin/time in $OUT/times.txt, each
# level evaluated after it (5,000 games per pair). Seeds 0-2's level 4 kept with
#   scripts/keep-obl-level.sh runs/obl-op-from-4-0 4 docs/results/data/obl-op-from-4/seeds-0-2-level-4 op-from-4-0-level-4
export YOKAI=${YOKAI:-yokai} OUT=${OUT:-runs/obl-op-from-4} LEVEL=${LEVEL:-4} SEEDS=${SEEDS:-3..6}
if [ $LEVEL -eq 4 ]; then DEFAULT=held-out-level-3; else DEFAULT=op-from-4-level-$((LEVEL - 1)); fi
export FROM=${FROM:-$DEFAULT}
PRESET=obl-cpu-op SET="--set obl.symmetries_from_level=4" exec sh scripts/obl-level.sh

#!/bin/sh
# OBL with Other-Play: one level of obl-cpu-long with algorithm.symmetries = "both", started
# from a kept level of a chain trained without symmetries. Run from the repository root:
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-op/run.sh
# The defaults: level 5 of seeds 3-5 from data/obl-chain-weights/held-out-level-4 (run
# 2026-12-06, 07:47). Seeds 0-2 from the chain of obl-belief-all-seeds.md:
#   FROM=all-seeds-level-4 SEEDS=0..3 OUT=runs/obl-op-0 sh docs/results/data/obl-op/run.sh
# Each level is one scripts/obl-level.sh (wall clock by /usr/bin/time in $OUT/times.txt, then
# evaluated, 5,000 games per pair). data/obl-op-chain/chain.sh runs this level after level.
export YOKAI=${YOKAI:-yokai} OUT=${OUT:-runs/obl-op} LEVEL=${LEVEL:-5} SEEDS=${SEEDS:-3..6}
export FROM=${FROM:-held-out-level-$((LEVEL - 1))}
PRESET=obl-cpu-long SET="--set algorithm.symmetries=both" exec sh scripts/obl-level.sh

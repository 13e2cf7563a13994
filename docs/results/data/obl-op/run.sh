#!/bin/sh
# OBL with Other-Play: one level of obl-cpu-long with algorithm.symmetries = "both", started
# from a kept level of a chain trained without symmetries. Run from the repository root:
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-op/run.sh
# The defaults: level 5 of seeds 3-5 from data/obl-chain-weights/held-out-level-4 (run
# 2026-12-06, 07:47). Seeds 0-2 from the chain of obl-belief-all-seeds.md:
#   FROM=all-seeds-level-4 SEEDS=0..3 OUT=runs/obl-op-0 sh docs/results/data/obl-op/run.sh
# Each command's wall clock by /usr/bin/time in $OUT/times.txt. data/obl-op-chain/chain.sh
# runs it level after level.
YOKAI=${YOKAI:-yokai}
OUT=${OUT:-runs/obl-op}
L=${LEVEL:-5}
FROM=${FROM:-held-out-level-$((L - 1))}
SEEDS=${SEEDS:-3..6}
mkdir -p $OUT
# The level below from the kept weights, unless the run folder has it (or this is level 1).
[ $L -eq 1 ] || [ -d $OUT/level-$((L - 1)) ] ||
  cp -r docs/results/data/obl-chain-weights/$FROM $OUT/level-$((L - 1))
echo "level $L start $(date -u +%T)" >> $OUT/times.txt
/usr/bin/time -f "level $L: %e s wall, %U s user" -a -o $OUT/times.txt \
  $YOKAI train obl-cpu-long --levels $L --seeds $SEEDS --set algorithm.symmetries=both \
    --eval-games 0 --out $OUT > $OUT/train-$L.log 2>&1 || exit 1
echo "level $L eval start $(date -u +%T)" >> $OUT/times.txt
$YOKAI eval $OUT/level-$L --games 5000 -o $OUT/level-$L/eval > $OUT/eval-$L.log 2>&1
echo "level $L eval end $(date -u +%T)" >> $OUT/times.txt

#!/bin/sh
# Held-out chain: seeds 3-5, the item-3 recipe with the all-seeds belief from level 2.
# Run from the repository root. Levels 1-3 ran on 2026-11-30 as
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-held-out/chain.sh
# Level 4 ran on 2026-12-02 (LEVELS="4", from data/obl-chain-weights/held-out-level-3).
# Level 5 ran on 2026-12-06 (LEVELS="5", from data/obl-chain-weights/held-out-level-4).
# To continue: copy data/obl-chain-weights/held-out-level-5 to runs/obl-held/level-5, then
#   LEVELS="6" sh docs/results/data/obl-held-out/chain.sh
# The same recipe is the preset obl-cpu-long: yokai train obl-cpu-long --levels L --seeds 3..6
YOKAI=${YOKAI:-yokai}
OUT=runs/obl-held
mkdir -p $OUT
for L in ${LEVELS:-1 2 3}; do
  echo "level $L start $(date -u +%T)" >> $OUT/times.txt
  /usr/bin/time -f "level $L: %e s wall, %U s user" -a -o $OUT/times.txt \
    $YOKAI train obl-cpu --levels $L --steps 12000000 --set ppo.lr=1e-3 \
      --set obl.belief_updates=10000 --set obl.belief_of=all-seeds --seeds 3..6 \
      --eval-games 0 --out $OUT > $OUT/train-$L.log 2>&1 || exit 1
  echo "level $L eval start $(date -u +%T)" >> $OUT/times.txt
  $YOKAI eval $OUT/level-$L --games 5000 -o $OUT/level-$L/eval > $OUT/eval-$L.log 2>&1
  echo "level $L eval end $(date -u +%T)" >> $OUT/times.txt
done

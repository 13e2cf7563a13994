#!/bin/sh
# Held-out chain: seeds 3-5, the item-3 recipe with the all-seeds belief from level 2.
cd /work/main
for L in 1 2 3; do
  echo "level $L start $(date -u +%T)" >> runs/obl-held/times.txt
  /usr/bin/time -f "level $L: %e s wall, %U s user" -a -o runs/obl-held/times.txt \
    /work/bin/yokai train obl-cpu --levels $L --steps 12000000 --set ppo.lr=1e-3 \
      --set obl.belief_updates=10000 --set obl.belief_of=all-seeds --seeds 3..6 \
      --eval-games 0 --out runs/obl-held > runs/obl-held/train-$L.log 2>&1 || exit 1
  echo "level $L eval start $(date -u +%T)" >> runs/obl-held/times.txt
  /work/bin/yokai eval runs/obl-held/level-$L --games 5000 -o runs/obl-held/level-$L/eval > runs/obl-held/eval-$L.log 2>&1
  echo "level $L eval end $(date -u +%T)" >> runs/obl-held/times.txt
done

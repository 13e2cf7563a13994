#!/bin/sh
# OBL with Other-Play's symmetries from level 1: `obl-cpu-long` with
# `algorithm.symmetries = "both"` at every level, seeds 0-2. Run from the repository root:
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-op-chain/chain.sh
# Levels 1-2 ran on 2026-12-06 from 12:00 (LEVELS="1 2"; level 2 did not finish in the session). To continue in a later session:
# copy data/obl-chain-weights/op-chain-level-L to runs/obl-op-chain/level-L, then
#   LEVELS="L+1 ..." sh docs/results/data/obl-op-chain/chain.sh
# Wall clock by /usr/bin/time in $OUT/times.txt; each level evaluated after it, 5,000 games.
YOKAI=${YOKAI:-yokai}
OUT=${OUT:-runs/obl-op-chain}
SEEDS=${SEEDS:-0..3}
mkdir -p $OUT
for L in ${LEVELS:-1 2}; do
  echo "level $L start $(date -u +%T)" >> $OUT/times.txt
  /usr/bin/time -f "level $L: %e s wall, %U s user" -a -o $OUT/times.txt \
    $YOKAI train obl-cpu-long --levels $L --seeds $SEEDS --set algorithm.symmetries=both \
      --eval-games 0 --out $OUT > $OUT/train-$L.log 2>&1 || exit 1
  echo "level $L eval start $(date -u +%T)" >> $OUT/times.txt
  $YOKAI eval $OUT/level-$L --games 5000 -o $OUT/level-$L/eval > $OUT/eval-$L.log 2>&1
  echo "level $L eval end $(date -u +%T)" >> $OUT/times.txt
done

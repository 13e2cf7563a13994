#!/bin/sh
# Cross-play between OBL chains trained apart: the preset obl-cpu-op's level 7 on seeds 0-2
# and on seeds 3-5 (two lineages that share nothing from level 1 on), the same chains'
# level 5 without Other-Play's symmetries, and level 6 of the route with the symmetries
# from level 4 (seeds 3-5). Every pair of the 15 policies, 5,000 games per pair, each
# policy's own play rule (T = 0.25, END above 0.6). From the repository root:
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-cross-lineage/run.sh
# then the group x group table:
#   python3 scripts/cross-groups.py --names "OP L7 s0-2,OP L7 s3-5,no-sym L5 s0-2,no-sym L5 s3-5,from-4 L6 s3-5" runs/obl-cross-lineage/eval
YOKAI=${YOKAI:-yokai}
OUT=${OUT:-runs/obl-cross-lineage}
W=docs/results/data/obl-chain-weights
mkdir -p $OUT
echo "eval start $(date -u +%T)" >> $OUT/times.txt
/usr/bin/time -f "eval: %e s wall, %U s user" -a -o $OUT/times.txt \
  $YOKAI eval $W/op-level-7 $W/op-held-out-level-7 $W/all-seeds-level-5 $W/held-out-level-5 \
    $W/op-from-4-level-6 --games 5000 -o $OUT/eval > $OUT/eval.log 2>&1

#!/bin/sh
# Level 4 of the all-seeds chain (seeds 0-2) from fresh weights: the ablation of
# "level L+1 starts from level L's weights". The same level 3 below, the same all-seeds
# belief, 12M steps; no --init-from, so the level trains as a level 1 does (lr 1e-3,
# shaping 1.0 annealed over the first tenth). Run from the repository root:
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-start-ablations/fresh-weights.sh
# The control is all-seeds-level-4 (docs/results/obl-belief-all-seeds.md).
YOKAI=${YOKAI:-yokai}
OUT=runs/obl-fresh
mkdir -p $OUT
[ -d $OUT/level-3 ] || cp -r docs/results/data/obl-chain-weights/b10k-level-3 $OUT/level-3
echo "train start $(date -u +%T)" >> $OUT/times.txt
/usr/bin/time -f "train: %e s wall, %U s user" -a -o $OUT/times.txt \
  $YOKAI train obl-cpu --steps 12000000 --set ppo.lr=1e-3 --set obl.belief_updates=10000 \
    --set obl.belief_of=all-seeds --set obl.level=4 --set obl.previous=$OUT/level-3 \
    --seeds 0..3 --eval-games 0 --out $OUT/level-4-fresh > $OUT/train.log 2>&1 || exit 1
echo "eval start $(date -u +%T)" >> $OUT/times.txt
$YOKAI eval $OUT/level-4-fresh --games 5000 -o $OUT/level-4-fresh/eval > $OUT/eval.log 2>&1
echo "eval end $(date -u +%T)" >> $OUT/times.txt

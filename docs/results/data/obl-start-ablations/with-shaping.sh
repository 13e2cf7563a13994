#!/bin/sh
# Level 4 of the all-seeds chain (seeds 0-2) from level 3's weights, as obl-cpu-long
# trains it, but with the shaping reward of a new run (obl.warm_shaping = 1.0, the value of
# ppo.shaping): the ablation of the warm rule at 12M steps. obl-cpu-long's warm_lr equals its
# ppo.lr (1e-3), so the shaping is the only part of the rule that differs. Run from the
# repository root:
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-start-ablations/with-shaping.sh
# The control is all-seeds-level-4 (docs/results/obl-belief-all-seeds.md).
YOKAI=${YOKAI:-yokai}
OUT=runs/obl-shaped
mkdir -p $OUT
[ -d $OUT/level-3 ] || cp -r docs/results/data/obl-chain-weights/b10k-level-3 $OUT/level-3
echo "train start $(date -u +%T)" >> $OUT/times.txt
/usr/bin/time -f "train: %e s wall, %U s user" -a -o $OUT/times.txt \
  $YOKAI train obl-cpu --levels 4 --steps 12000000 --set ppo.lr=1e-3 \
    --set obl.belief_updates=10000 --set obl.belief_of=all-seeds --set obl.warm_shaping=1.0 \
    --seeds 0..3 --eval-games 0 --out $OUT > $OUT/train.log 2>&1 || exit 1
echo "eval start $(date -u +%T)" >> $OUT/times.txt
$YOKAI eval $OUT/level-4 --games 5000 -o $OUT/level-4/eval > $OUT/eval.log 2>&1
echo "eval end $(date -u +%T)" >> $OUT/times.txt

#!/bin/sh
# Level 4 of the all-seeds chain (seeds 0-2, on b10k-level-3 and its all-seeds belief,
# 12M steps at lr 1e-3) started another way than obl-cpu-long starts it; the control is
# all-seeds-level-4 (docs/results/obl-belief-all-seeds.md). Run from the repository root:
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-start-ablations/run.sh fresh
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-start-ablations/run.sh with-shaping
# fresh:        from fresh weights (no --levels, no --init-from), so the level trains as a
#               level 1 does (lr 1e-3, shaping 1.0 annealed over the first tenth): the
#               ablation of "level L+1 starts from level L's weights".
# with-shaping: from level 3's weights (--levels 4) with the shaping reward of a new run
#               (obl.warm_shaping = 1.0, the value of ppo.shaping): the ablation of the warm
#               rule; obl-cpu-long's warm_lr equals its ppo.lr, so only the shaping differs.
YOKAI=${YOKAI:-yokai}
COMMON="--steps 12000000 --set ppo.lr=1e-3 --set obl.belief_updates=10000 \
  --set obl.belief_of=all-seeds --seeds 0..3 --eval-games 0"
case "$1" in
  fresh)
    OUT=runs/obl-fresh; RUN=$OUT/level-4-fresh
    ARGS="--set obl.level=4 --set obl.previous=$OUT/level-3 --out $RUN" ;;
  with-shaping)
    OUT=runs/obl-shaped; RUN=$OUT/level-4
    ARGS="--levels 4 --set obl.warm_shaping=1.0 --out $OUT" ;;
  *) echo "usage: $0 fresh|with-shaping" >&2; exit 2 ;;
esac
mkdir -p $OUT
[ -d $OUT/level-3 ] || cp -r docs/results/data/obl-chain-weights/b10k-level-3 $OUT/level-3
echo "train start $(date -u +%T)" >> $OUT/times.txt
# shellcheck disable=SC2086 # COMMON and ARGS are word lists
/usr/bin/time -f "train: %e s wall, %U s user" -a -o $OUT/times.txt \
  $YOKAI train obl-cpu $COMMON $ARGS > $OUT/train.log 2>&1 || exit 1
echo "eval start $(date -u +%T)" >> $OUT/times.txt
$YOKAI eval $RUN --games 5000 -o $RUN/eval > $OUT/eval.log 2>&1
echo "eval end $(date -u +%T)" >> $OUT/times.txt

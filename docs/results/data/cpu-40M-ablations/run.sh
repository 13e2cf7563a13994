#!/bin/sh
# The `cpu` preset's levers switched off one at a time at the preset's own budget (40M
# steps, seeds 0-2 side by side), with the preset itself trained first by the same build:
# the ablation rows the issue "Agents at the paper's level on a CPU" asks for at the target
# budget (docs/results/cpu-levers.md has them at 1M steps). Run from the repository root:
#   ARMS="base no-belief no-pool" YOKAI=/work/bin/yokai sh docs/results/data/cpu-40M-ablations/run.sh
# Each arm: `yokai train cpu $SET --eval-games 0 --out $OUT/ARM` timed by /usr/bin/time in
# $OUT/times.txt, then `yokai eval $OUT/ARM belief greedy --games 5000 -o $OUT/ARM/eval`.
# Arms run one after another, so each trains on the whole machine. Besides the levers off
# (no-belief, no-pool, no-end-term, no-entropy-norm, whole-shaping, two-epochs), two arms
# raise the belief loss's weight (belief-1, belief-2).
set -u
YOKAI=${YOKAI:-yokai} OUT=${OUT:-runs/cpu-40M-ablations}
mkdir -p "$OUT"
for ARM in ${ARMS:-base no-belief no-pool}; do
  case $ARM in
    base) SET= ;;
    no-belief) SET="--set ppo.belief_aux=0.0" ;;
    no-pool) SET="--set network.pointer_pool=false" ;;
    no-end-term) SET="--set ppo.end_lookahead=0.0" ;;
    no-entropy-norm) SET="--set ppo.entropy_normalized=false" ;;
    whole-shaping) SET="--set ppo.shaping_fraction=1.0" ;;
    two-epochs) SET="--set ppo.epochs=2" ;;
    belief-1) SET="--set ppo.belief_aux=1.0" ;;
    belief-2) SET="--set ppo.belief_aux=2.0" ;;
    *) echo "unknown arm $ARM" >&2; exit 2 ;;
  esac
  echo "$ARM start $(date -u +%T)" >> "$OUT/times.txt"
  /usr/bin/time -f "$ARM train: %e s wall, %U s user" -a -o "$OUT/times.txt" \
    $YOKAI train cpu $SET --eval-games 0 --out "$OUT/$ARM" > "$OUT/train-$ARM.log" 2>&1 || exit 1
  /usr/bin/time -f "$ARM eval: %e s wall, %U s user" -a -o "$OUT/times.txt" \
    $YOKAI eval "$OUT/$ARM" belief greedy --games 5000 -o "$OUT/$ARM/eval" > "$OUT/eval-$ARM.log" 2>&1 || exit 1
done

#!/bin/sh
# OBL with Other-Play's symmetries from level 1: `obl-cpu-long` with
# `algorithm.symmetries = "both"` at every level, seeds 0-2. Run from the repository root:
#   YOKAI=/work/bin/yokai sh docs/results/data/obl-op-chain/chain.sh
# Levels 1-2 ran on 2026-12-06 from 12:00 (LEVELS="1 2"). To continue in a later session:
# LEVELS="3 4" sh …/chain.sh; a level whose level below is not in $OUT starts from
# data/obl-chain-weights/op-chain-level-(L-1).
# Each level is one data/obl-op/run.sh: wall clock by /usr/bin/time in $OUT/times.txt, each
# level evaluated after it (5,000 games per pair).
export YOKAI=${YOKAI:-yokai} OUT=${OUT:-runs/obl-op-chain} SEEDS=${SEEDS:-0..3}
for L in ${LEVELS:-1 2}; do
  LEVEL=$L FROM=op-chain-level-$((L - 1)) sh docs/results/data/obl-op/run.sh || exit 1
done

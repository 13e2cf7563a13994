#!/bin/sh
# Level 2 (belief 10,000) under five END thresholds, 2,000 games per pair each, each against
# the preset's 0.6. Made with, for T in 0.4 0.5 0.6 0.7 0.8 (niced, beside level 3's training):
#   yokai eval runs/obl-b10k/level-2 --games 2000 --end T -o runs/l2-end/end-T
# Run from the repository root; output in table.txt.
D=docs/results/data/obl-belief-10k/level-2-end-rule
exec python3 scripts/compare-evals.py --against first "END > 0.6=$D/end-0.6" "END > 0.4=$D/end-0.4" \
  "END > 0.5=$D/end-0.5" "END > 0.7=$D/end-0.7" "END > 0.8=$D/end-0.8"

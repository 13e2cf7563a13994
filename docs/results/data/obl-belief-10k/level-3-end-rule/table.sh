#!/bin/sh
# Level 3 (belief 10,000) under three END thresholds, 2,000 games per pair each, each against
# the preset's 0.6. Made with, for T in 0.4 0.5 0.6 (niced, beside level 4's training):
#   yokai eval runs/obl-b10k/level-3 --games 2000 --end T -o runs/l3-end/end-T
# Run from the repository root; output in table.txt.
D=docs/results/data/obl-belief-10k/level-3-end-rule
exec python3 scripts/compare-evals.py --against first "END > 0.6=$D/end-0.6" "END > 0.4=$D/end-0.4" \
  "END > 0.5=$D/end-0.5"

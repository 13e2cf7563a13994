#!/bin/sh
# The differences quoted in docs/results/obl-belief-10k.md, from the saved evaluations:
# level 2 with the belief at 300 updates (../obl-12M) and at 10,000, each against level 1,
# and the two level 2s against each other. Run from the repository root; output in
# differences.txt.
D=docs/results/data
python3 scripts/compare-evals.py --against first "level 1=$D/obl-12M/lr1e-3-level-1" \
  "level 2, belief 300=$D/obl-12M/lr1e-3-level-2" "level 2, belief 10000=$D/obl-belief-10k/level-2"
echo
python3 scripts/compare-evals.py "level 2, belief 300=$D/obl-12M/lr1e-3-level-2" \
  "level 2, belief 10000=$D/obl-belief-10k/level-2" | sed -n '/^| comparison/,$p'
echo
# level 3 (10,000) against level 2 (10,000), level 4 against level 3
python3 scripts/compare-evals.py "level 2, belief 10000=$D/obl-belief-10k/level-2" \
  "level 3, belief 10000=$D/obl-belief-10k/level-3" "level 4, belief 10000=$D/obl-belief-10k/level-4"
echo
python3 scripts/compare-evals.py "level 3, belief 300=$D/obl-12M-levels-3-4/level-3" \
  "level 3, belief 10000=$D/obl-belief-10k/level-3" | sed -n '/^| comparison/,$p'

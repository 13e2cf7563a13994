#!/bin/sh
# The level-to-level differences quoted in docs/results/obl-12M-levels-3-4.md, from the
# saved evaluations (levels 1 and 2: ../obl-12M): each level against the one below,
# unpaired and paired per seed, and each level's XP − SP. Run from the repository root;
# output in differences.txt.
D=docs/results/data
exec python3 scripts/compare-evals.py "level 1=$D/obl-12M/lr1e-3-level-1" \
  "level 2=$D/obl-12M/lr1e-3-level-2" "level 3=$D/obl-12M-levels-3-4/level-3" \
  "level 4=$D/obl-12M-levels-3-4/level-4"

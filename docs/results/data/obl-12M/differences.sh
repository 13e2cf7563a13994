#!/bin/sh
# The differences quoted in docs/results/obl-12M.md, from the saved evaluations: each row
# against the one before it (level 1 at lr 1e-3 against 3e-3; level 2 against level 1),
# unpaired and paired per seed. Run from the repository root; output in differences.txt.
D=docs/results/data/obl-12M
exec python3 scripts/compare-evals.py "level 1, lr 3e-3=$D/level-1-lr3e-3" \
  "level 1, lr 1e-3=$D/lr1e-3-level-1" "level 2, lr 1e-3=$D/lr1e-3-level-2"

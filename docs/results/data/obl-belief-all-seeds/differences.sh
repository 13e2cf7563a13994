#!/bin/sh
# The differences quoted in docs/results/obl-belief-all-seeds.md, from the saved evaluations:
# level 4 with the belief of its own seed's level 3 (obl-belief-10k) and of every seed's,
# each against level 3, then against each other (paired per seed: the same level-3 start).
# Run from the repository root; output in differences.txt.
D=docs/results/data
python3 scripts/compare-evals.py --against first "level 3=$D/obl-belief-10k/level-3" \
  "level 4, own-seed=$D/obl-belief-10k/level-4" "level 4, all-seeds=$D/obl-belief-all-seeds/level-4"
echo
# then each against the one before: all-seeds level 4 against own-seed, level 5 against it
python3 scripts/compare-evals.py "level 4, own-seed=$D/obl-belief-10k/level-4" \
  "level 4, all-seeds=$D/obl-belief-all-seeds/level-4" "level 5, all-seeds=$D/obl-belief-all-seeds/level-5"

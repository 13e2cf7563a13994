#!/bin/sh
# The differences quoted in docs/results/obl-op-chain.md, from the saved evaluations. Run
# from the repository root; output in differences.txt. Level 1 against the same level
# without the symmetries; each later level against level 1 with them, and, where it exists,
# the same level of a chain without them on the same seeds.
D=docs/results/data
C=$D/obl-op-chain
{
python3 scripts/compare-evals.py "level 1 without symmetries=$D/obl-12M/lr1e-3-level-1" \
  "level 1 with Other-Play=$C/level-1"
[ -d $C/level-2 ] && echo && python3 scripts/compare-evals.py --against previous \
  "level 1 with Other-Play=$C/level-1" "level 2 with Other-Play=$C/level-2"
[ -d $C/level-2 ] && echo && python3 scripts/compare-evals.py \
  "level 2 without symmetries (own-seed belief)=$D/obl-belief-10k/level-2" \
  "level 2 with Other-Play=$C/level-2"
} > $C/differences.txt

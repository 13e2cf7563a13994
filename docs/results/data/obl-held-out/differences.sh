#!/bin/sh
# The differences quoted in docs/results/obl-held-out-seeds.md, from the saved evaluations
# of every level kept here. Run from the repository root; output in differences.txt.
D=docs/results/data
H=$D/obl-held-out
LEVELS=$(for L in 1 2 3 4 5 6; do [ -d $H/level-$L ] && echo $L; done)
# the held-out chain, each level against the one below (paired per seed: seed N's lineage)
set --
for L in $LEVELS; do set -- "$@" "level $L=$H/level-$L"; done
python3 scripts/compare-evals.py "$@"
echo
# each level of seeds 3-5 against the same level of seeds 0-2 (other seeds: unpaired).
# Seeds 0-2: level 1 of obl-12M, levels 2-3 with own-seed beliefs (obl-belief-10k), levels
# 4-5 with all-seeds beliefs (obl-belief-all-seeds).
for L in $LEVELS; do
  case $L in
    1) A=$D/obl-12M/lr1e-3-level-1 ;;
    2|3) A=$D/obl-belief-10k/level-$L ;;
    *) A=$D/obl-belief-all-seeds/level-$L ;;
  esac
  python3 scripts/compare-evals.py "level $L, seeds 0-2=$A" "level $L, seeds 3-5=$H/level-$L"
  echo
done

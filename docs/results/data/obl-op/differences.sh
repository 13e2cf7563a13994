#!/bin/sh
# The differences quoted in docs/results/obl-other-play.md, from the saved evaluations. Run
# from the repository root; output in differences.txt.
D=docs/results/data
O=$D/obl-op
{
python3 scripts/compare-evals.py --against first "seeds 3-5, level 4=$D/obl-held-out/level-4" \
  "level 5 without symmetries=$D/obl-held-out/level-5" "level 5 with Other-Play=$O/held-out-level-5"
echo
[ -d $O/level-5 ] && python3 scripts/compare-evals.py --against first \
  "seeds 0-2, level 4=$D/obl-belief-all-seeds/level-4" \
  "level 5 without symmetries=$D/obl-belief-all-seeds/level-5" "level 5 with Other-Play=$O/level-5"
} > $O/differences.txt

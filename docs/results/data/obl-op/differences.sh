#!/bin/sh
# The differences quoted in docs/results/obl-other-play.md, from the saved evaluations. Run
# from the repository root; output in differences.txt. Each seed set: levels 4 (no
# symmetries), 5 without, 5 to 7 with Other-Play, against level 4; then each level with
# Other-Play against the level it was trained on.
D=docs/results/data
O=$D/obl-op
compare() { # NAME-OF-SET LEVEL-4 LEVEL-5 OP-LEVEL-5 OP-LEVEL-6 OP-LEVEL-7
  six=; [ -d "$5" ] && six="level 6 with Other-Play=$5"
  seven=; [ -d "$6" ] && seven="level 7 with Other-Play=$6"
  python3 scripts/compare-evals.py --against first "$1, level 4=$2" \
    "level 5 without symmetries=$3" "level 5 with Other-Play=$4" ${six:+"$six"} \
    ${seven:+"$seven"}
  echo
  [ -d "$5" ] && python3 scripts/compare-evals.py --against previous \
    "$1, level 5 with Other-Play=$4" "level 6 with Other-Play=$5" ${seven:+"$seven"} && echo
}
{
compare "seeds 3-5" $D/obl-held-out/level-4 $D/obl-held-out/level-5 $O/held-out-level-5 \
  $O/held-out-level-6 $O/held-out-level-7
[ -d $O/level-5 ] && compare "seeds 0-2" $D/obl-belief-all-seeds/level-4 \
  $D/obl-belief-all-seeds/level-5 $O/level-5 $O/level-6 $O/level-7
} > $O/differences.txt

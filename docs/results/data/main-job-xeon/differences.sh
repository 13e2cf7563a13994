#!/bin/sh
# The differences quoted in docs/results/main-job-xeon.md, from the saved evaluations.
# Run from the repository root; output in differences.txt. The 2026-11-25 run kept a
# matrix.json only for its 1,000-game evaluation, so the paired builds compare at 1,000.
D=docs/results/data
M=$D/main-job-xeon
python3 scripts/compare-evals.py --against first \
  "97b9f87 (2026-11-25)=$D/play-temperature/main-job" \
  "4f019de=$M/build-4f019de/eval-1000" \
  "09f65b8=$M/seeds-0-2/eval-1000"
echo
python3 scripts/compare-evals.py "4f019de=$M/build-4f019de/eval-1000" "09f65b8=$M/seeds-0-2/eval-1000"
echo
python3 scripts/compare-evals.py "seeds 0-2, 5,000 games=$M/seeds-0-2/eval-5000" "seeds 3-5, 5,000 games=$M/seeds-3-5/eval-5000"

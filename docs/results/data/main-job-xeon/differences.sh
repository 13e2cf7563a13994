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
echo
# The search continued (second session of 2026-12-02): the 97b9f87 build again, on this
# Xeon, and the two golden-file commits between it and 4f019de, each against 97b9f87.
python3 scripts/compare-evals.py --against first \
  "97b9f87 on the Xeon=$M/build-97b9f87/eval-1000" \
  "abdce51=$M/build-abdce51/eval-1000" \
  "f207b25=$M/build-f207b25/eval-1000" \
  "4f019de=$M/build-4f019de/eval-1000" \
  "09f65b8=$M/seeds-0-2/eval-1000"
echo
# More steps at today's build (01a7087; training code as 09f65b8): `quick` with --steps.
python3 scripts/compare-evals.py --against first \
  "5M (the preset), seeds 0-2=$M/seeds-0-2/eval-5000" \
  "6.5M, seeds 0-2=$M/steps-6.5M/eval-5000" \
  "7M, seeds 0-2=$M/steps-7M/eval-5000"
echo
python3 scripts/compare-evals.py --against first \
  "5M (the preset), seeds 3-5=$M/seeds-3-5/eval-5000" \
  "7M, seeds 3-5=$M/steps-7M-seeds-3-5/eval-5000"

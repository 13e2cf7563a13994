#!/usr/bin/env bash
# One device call: does `yokai train --device cuda` (built without CubeCL's autotune) finish
# updates of the paper network at the paper's batch, and how fast? Issue 15's first GPU
# figure, asked for since docs/results/gpu-h200-2.md (where the autotuned build compiled
# for 275 s and finished no update).
#
#   scripts/gpu-paper-speed.sh BINARY OUT [SECONDS]
#
#   BINARY   yokai built with `--features cuda`, stripped; `.xz` is unpacked first
#   OUT      what comes back: call.log, cubecl.log (its last 4 MB), metrics-CONFIG.jsonl
#   SECONDS  wall-clock budget of the whole script (default 520, inside a 600 s call)
#
# Steps: ippo-9c-2p (1,024 games x 128 steps, 4 epochs x 4 minibatches), 5 updates, with
# the kernels CubeCL has compiled and the GPU's use sampled every 30 s, stopped at 60 % of
# the budget; then, in what is left, ippo-16c-2p for 3 updates. The first update of each
# includes compiling its kernels; the later ones are the speed.
set -uo pipefail
bin=${1:?usage: gpu-paper-speed.sh BINARY OUT [SECONDS]}
out=${2:?usage: gpu-paper-speed.sh BINARY OUT [SECONDS]}
budget=${3:-520}
here=$(cd "$(dirname "$0")" && pwd)
. "$here/gpu-lib.sh"
call_start "$out" call.log
bin=$(unpacked "$bin") || exit 1
echo "== $(date -u +%FT%TZ) $($bin --version 2>&1); budget $budget s; $(nproc) cores"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm --format=csv,noheader
lscpu | grep -m1 'Model name'
cuda_env

first=$((budget * 6 / 10))
echo "== ippo-9c-2p on cuda, 5 updates, at most $first s"
device_check "$bin" cuda "$out" "$first" ippo-9c-2p 5
cp /tmp/gpu-check/seed-0/metrics.jsonl "$out/metrics-ippo-9c-2p.jsonl" 2> /dev/null
mv "$out/cubecl.log" "$out/cubecl-ippo-9c-2p.log" 2> /dev/null

rest=$(($(left) - 20))
if [ "$rest" -gt 60 ]; then
    echo "== ippo-16c-2p on cuda, 3 updates, at most $rest s"
    device_check "$bin" cuda "$out" "$rest" ippo-16c-2p 3
    cp /tmp/gpu-check/seed-0/metrics.jsonl "$out/metrics-ippo-16c-2p.jsonl" 2> /dev/null
    mv "$out/cubecl.log" "$out/cubecl-ippo-16c-2p.log" 2> /dev/null
fi
xz -T0 -f "$out"/cubecl-*.log 2> /dev/null
echo "== done in $(($(date +%s) - start)) s"

#!/usr/bin/env bash
# One call's worth of the GPU work of issue 15 (docs/training.md, "Training on a GPU"), for a
# machine with an NVIDIA GPU and no Rust toolchain: the binary is built elsewhere and carried.
#
#   scripts/gpu-session.sh BINARY OUT [SECONDS] [DEVICE] [RUN_TAR]
#
#   BINARY   yokai built with `--features cuda` (or vulkan), stripped; `.xz` is unpacked first
#   OUT      folder for what comes back: session.log, cubecl.log, bench.txt, the run's metrics and a
#            tar of the run to resume from next time (at most 8 files, none in subfolders)
#   SECONDS  wall-clock budget for the whole script (default 540, inside a 600 s call)
#   DEVICE   cuda (default), vulkan or cpu (cpu: a dry run of this script on any machine)
#   RUN_TAR  a tar written by an earlier call (OUT/run-ippo-9c-2p.tar): training resumes it
#   (TRAIN_CONFIG names another preset to train, BENCH=0 skips the timing of step 3)
#
# Steps: find the CUDA headers and NVRTC if CUDA_PATH / LD_LIBRARY_PATH do not say; check the
# device with 2 updates of `quick`; time 3 updates of ippo-9c-2p and ippo-16c-2p at the paper's
# batch (scripts/gpu-bench.sh); then train ippo-9c-2p in chunks of --max-updates with --resume
# until the budget is nearly spent, so the run goes on across calls.
#
# A dry run on a CPU-only machine: TRAIN_CONFIG=quick BENCH=0 scripts/gpu-session.sh \
#   target/release/yokai out/dry 120 cpu
set -uo pipefail
bin=${1:?usage: gpu-session.sh BINARY OUT [SECONDS] [DEVICE] [RUN_TAR]}
out=${2:?usage: gpu-session.sh BINARY OUT [SECONDS] [DEVICE] [RUN_TAR]}
budget=${3:-540}
device=${4:-cuda}
run_tar=${5:-}
config=${TRAIN_CONFIG:-ippo-9c-2p}
here=$(cd "$(dirname "$0")" && pwd)
. "$here/gpu-lib.sh"
call_start "$out" session.log
bin=$(unpacked "$bin") || exit 1
echo "== $(date -u +%FT%TZ) $($bin --version 2>&1) on $device; budget ${budget} s"
command -v nvidia-smi > /dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
nproc

[ "$device" = cuda ] && cuda_env

echo "== device check: 2 updates of quick on $device"
device_check "$bin" "$device" "$out" 120 || { echo "the device does not train: stopping here"; exit 1; }

if [ "${BENCH:-1}" != 0 ]; then
    echo "== the paper's batch: 3 updates each of ippo-9c-2p and ippo-16c-2p ($(left) s left)"
    "$here/gpu-bench.sh" "$bin" /tmp/gpu-bench 3 "$device" | tee "$out/bench.txt"
fi

run=/tmp/gpu-run/$config
rm -rf /tmp/gpu-run && mkdir -p /tmp/gpu-run
resume=()
if [ -n "$run_tar" ] && [ -f "$run_tar" ]; then
    tar -xf "$run_tar" -C /tmp/gpu-run && resume=(--resume)
    echo "== resuming $(tail -1 "$run/seed-0/metrics.jsonl" | python3 -c 'import json,sys; s=json.load(sys.stdin); print("update", s["update"], "at", s["env_steps"], "env steps")')"
fi
chunk=5
while :; do
    t0=$(date +%s)
    # Stop while there is time to tar the run: a chunk that cannot finish is not started.
    [ "$(left)" -gt 60 ] || break
    echo "== training $config on $device: $chunk more updates ($(left) s left)"
    timeout $(($(left) - 30)) "$bin" train "$config" --device "$device" --seeds 0 --max-updates "$chunk" \
        --eval-games 0 --out "$run" "${resume[@]}" 2>&1 | quiet
    status=${PIPESTATUS[0]}
    [ "$status" = 0 ] || { echo "training stopped with status $status"; break; }
    resume=(--resume)
    took=$(($(date +%s) - t0))
    # The next chunk fills about a third of what is left, from this chunk's pace.
    chunk=$(( ($(left) / 3) * chunk / (took > 0 ? took : 1) ))
    [ "$chunk" -ge 1 ] || break
done
if [ -f "$run/seed-0/metrics.jsonl" ]; then
    cp "$run/seed-0/metrics.jsonl" "$out/metrics-$config.jsonl"
    tar -cf "$out/run-$config.tar" -C /tmp/gpu-run "$config"
    tail -1 "$run/seed-0/metrics.jsonl"
fi
echo "== done in $(($(date +%s) - start)) s"

#!/usr/bin/env bash
# End-to-end training speed of the paper network on a GPU (issue 15, docs/training.md):
# a few PPO updates at the paper's batch (1,024 games x 128 steps, 4 epochs x 4
# minibatches) for 9c-2p and 16c-2p, then each update's split between rollout and
# learning from the run's metrics.jsonl.
#
#   scripts/gpu-bench.sh [YOKAI_BINARY] [OUT_DIR] [UPDATES] [DEVICE]
#
# BENCH_TIMEOUT (seconds, default 280) stops each config's run: the updates that finished
# inside it are still reported.
#
# The binary must be built with the GPU feature:
#   cargo build --release -p yokai-cli --features vulkan
set -uo pipefail
bin=${1:-target/release/yokai}
out=${2:-out/gpu-bench}
updates=${3:-3}
device=${4:-vulkan}
limit=${BENCH_TIMEOUT:-280}
. "$(dirname "$0")/gpu-lib.sh"
mkdir -p "$out"
for config in ippo-9c-2p ippo-16c-2p; do
    rm -rf "${out:?}/$config"
    echo "== $config on $device: $updates updates"
    timeout "$limit" "$bin" train "$config" --device "$device" --seeds 0 --max-updates "$updates" \
        --eval-games 0 --out "$out/$config" 2>&1 | quiet
    echo "exit status ${PIPESTATUS[0]} (124: stopped after $limit s)"
    "$gpu_scripts/update-times.py" "$out/$config/seed-0/metrics.jsonl"
done

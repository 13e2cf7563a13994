#!/usr/bin/env bash
# One device call's worth of issue 37's GPU work (docs/results/gpu-h200.md), for a machine
# with an NVIDIA GPU, PyTorch and no Rust toolchain: the `yokai` binary (built with
# `--features cuda`) and the `yokai` wheel (abi3) are built elsewhere and carried.
#
#   scripts/gpu-call.sh BINARY WHEEL OUT [SECONDS]
#
#   BINARY   yokai built with `--features cuda`, stripped; `.xz` is unpacked first
#   WHEEL    the yokai-learning-environment wheel (abi3), installed with --no-deps
#   OUT      what comes back (8 files, the device tool's most; no subfolders): call.log,
#            cubecl.log, bench.txt, torch-speed.txt, eval-report.md, eval-matrix.json,
#            eval-summary.json, runs.tar (the trained runs, to resume)
#   SECONDS  wall-clock budget of the whole script (default 560, inside a 600 s call)
#
# Phases, each stopped by its own time limit so that a slow or broken one leaves time to
# the next:
#   1. `yokai train quick --device cuda`, 2 updates within 150 s: does burn's CUDA runtime
#      train at all, and how many kernels it compiles on the way (`device_check` in
#      gpu-lib.sh);
#   2. if it does, `scripts/gpu-bench.sh` (2 updates each of ippo-9c-2p and ippo-16c-2p at
#      the paper's batch, 1,024 games x 128 steps, 4 epochs x 4 minibatches);
#   3. the PyTorch trainer's speed on the GPU with the `cpu` preset's network and levers:
#      at the paper's batch, and at the GPU batches phase 4 may use;
#   4. `cpu` levers on the GPU (TORCH_SET below), seeds 0-2 side by side, until 100 s are
#      left; resumed from RUNS_TAR when given;
#   5. `yokai eval` of the three runs (5,000 games per pair, the preset's play rule).
#
# TORCH_SET: the overrides of phase 4 (default: 256 games x 32 steps, 16 minibatches: the
# `cpu` preset's minibatch of 16 games and its gradient steps per env step, on 4x the games).
# RUNS_TAR: runs.tar from an earlier call, resumed. A dry run on a CPU-only machine:
#   DEVICE=cpu scripts/gpu-call.sh target/release/yokai target/wheel/*.whl out/dry 240
set -uo pipefail
bin=${1:?usage: gpu-call.sh BINARY WHEEL OUT [SECONDS]}
wheel=${2:?usage: gpu-call.sh BINARY WHEEL OUT [SECONDS]}
out=${3:?usage: gpu-call.sh BINARY WHEEL OUT [SECONDS]}
budget=${4:-560}
device=${DEVICE:-cuda}
torch_set=${TORCH_SET:-ppo.num_envs=256 ppo.rollout_steps=32 ppo.minibatches=16}
here=$(cd "$(dirname "$0")" && pwd)
. "$here/gpu-lib.sh"
call_start "$out" call.log
bin=$(unpacked "$bin") || exit 1
python3 -m pip install -q --no-index --no-deps --no-compile --target /tmp/site "$wheel" || exit 1
export PYTHONPATH=/tmp/site${PYTHONPATH:+:$PYTHONPATH} PYTHONUNBUFFERED=1
echo "== $(date -u +%FT%TZ) $($bin --version 2>&1) on $device; budget $budget s; $(nproc) cores"
command -v nvidia-smi > /dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm --format=csv,noheader
lscpu | grep -m1 'Model name'
python3 -c 'import torch, yokai; print("torch", torch.__version__, "cuda", torch.cuda.is_available(), "yokai", yokai.__file__)'
[ "$device" = cuda ] && cuda_env

echo "== 1. yokai train quick --device $device, 2 updates ($(left) s left)"
if device_check "$bin" "$device" "$out" 150; then
    echo "== 2. the paper's batch in yokai train: ippo-9c-2p, ippo-16c-2p ($(left) s left)"
    BENCH_TIMEOUT=75 "$here/gpu-bench.sh" "$bin" /tmp/gpu-bench 2 "$device" | tee "$out/bench.txt"
fi

echo "== 3. PyTorch trainer speed, cpu preset's network and levers ($(left) s left)"
# name | overrides | updates
speeds=(
    "paper batch 1024x128, 4 epochs x 4 mb|ppo.num_envs=1024 ppo.rollout_steps=128 ppo.epochs=4 ppo.minibatches=4|2"
    "256x32, 1 epoch x 16 mb|ppo.num_envs=256 ppo.rollout_steps=32 ppo.minibatches=16|4"
    "1024x32, 1 epoch x 16 mb|ppo.num_envs=1024 ppo.rollout_steps=32 ppo.minibatches=16|3"
    "1024x32, 1 epoch x 4 mb|ppo.num_envs=1024 ppo.rollout_steps=32 ppo.minibatches=4|3"
)
for row in "${speeds[@]}"; do
    IFS='|' read -r name set updates <<< "$row"
    [ "$(left)" -gt 200 ] || { echo "skipped: $name"; continue; }
    dir=/tmp/torch-speed/$(echo "$name" | tr -c 'a-z0-9' '-')
    rm -rf "$dir"
    sets=(); for s in $set; do sets+=(--set "$s"); done
    t0=$SECONDS
    timeout 45 python3 -m yokai.torch_train cpu --out "$dir" --device "$device" "${sets[@]}" \
        --max-updates "$updates" --quiet
    echo "exit status $? in $((SECONDS - t0)) s"
    "$here/update-times.py" "$dir/metrics.jsonl" "$name" | tee -a "$out/torch-speed.txt"
done

echo "== 4. cpu levers on the GPU, seeds 0-2 side by side ($(left) s left): $torch_set"
runs=/tmp/gpu-runs
rm -rf "$runs" && mkdir -p "$runs"
resume=()
if [ -n "${RUNS_TAR:-}" ] && [ -f "$RUNS_TAR" ]; then
    tar -xf "$RUNS_TAR" -C "$runs" && resume=(--resume)
fi
sets=(--set run.checkpoint_every=5); for s in $torch_set; do sets+=(--set "$s"); done
train_for=$(($(left) - 100))
[ "$train_for" -gt 20 ] || train_for=0
pids=()
for seed in 0 1 2; do
    [ "$train_for" -gt 0 ] || { echo "no time left to train"; break; }
    # Each seed's env and Python take a core or two; the GPU is shared.
    timeout "$train_for" python3 -m yokai.torch_train cpu --out "$runs/cpu-gpu/seed-$seed" --seed $seed \
        --device "$device" --threads 4 "${sets[@]}" "${resume[@]}" 2> "$runs/train-$seed.log" &
    pids+=($!)
done
[ ${#pids[@]} -gt 0 ] && wait "${pids[@]}"
for seed in 0 1 2; do
    [ -f "$runs/train-$seed.log" ] && echo "seed $seed: $(tail -1 "$runs/train-$seed.log")"
    python3 - "$runs/cpu-gpu/seed-$seed/metrics.jsonl" <<'PY'
import json, os, sys
rows = [json.loads(l) for l in open(sys.argv[1])] if os.path.exists(sys.argv[1]) else []
if rows:
    last, sps = rows[-1], sorted(r["sps"] for r in rows)
    g = last["games"] or {}
    print(f"  {len(rows)} updates, {last['env_steps']:,} env steps, median {sps[len(sps) // 2]:.0f} env steps/s, "
          f"last R {g.get('reward', float('nan')):.2f} EE {g.get('early_end', float('nan')):.2f}")
PY
done

echo "== 5. yokai eval of the three runs ($(left) s left)"
policies=()
for seed in 0 1 2; do
    f=$runs/cpu-gpu/seed-$seed/policy.safetensors
    [ -f "$f" ] && policies+=("$f")
done
if [ ${#policies[@]} -gt 0 ] && [ "$(left)" -gt 30 ]; then
    timeout $(($(left) - 15)) "$bin" eval "${policies[@]}" --games 5000 --out /tmp/gpu-eval 2>&1 | quiet | tail -40
    cp /tmp/gpu-eval/report.md "$out/eval-report.md" 2> /dev/null
    cp /tmp/gpu-eval/matrix.json "$out/eval-matrix.json" 2> /dev/null
    cp /tmp/gpu-eval/summary.json "$out/eval-summary.json" 2> /dev/null
fi
tar -cf "$out/runs.tar" -C "$runs" cpu-gpu 2> /dev/null
echo "== done in $(($(date +%s) - start)) s"

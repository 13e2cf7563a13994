# Sourced by the GPU scripts (gpu-session.sh, gpu-call.sh, gpu-paper-speed.sh, gpu-bench.sh):
# what each of them needs on a machine with an NVIDIA GPU and no Rust toolchain.

# call_start OUT LOG: what every GPU script does first: OUT made, everything the script
# prints from here on also appended to OUT/LOG, and the clock of `left` started.
call_start() {
    mkdir -p "$1"
    exec > >(tee -a "$1/$2") 2>&1
    start=$(date +%s)
}
# Seconds left of the caller's $budget since call_start.
left() { echo $((budget - ($(date +%s) - start))); }

# unpacked BINARY: the binary's path, unpacked to /tmp/yokai first when it is `.xz`
# (stripped and xz'd, a GPU build fits the device tool's 64 MiB).
unpacked() {
    if [[ $1 == *.xz ]]; then
        xz -dc "$1" > /tmp/yokai && chmod +x /tmp/yokai && echo /tmp/yokai
    else
        echo "$1"
    fi
}

# Progress-bar frames are dropped; every other line (an error, a panic) is kept whole.
quiet() { tr '\r' '\n' | grep -v -e '^\s*$' -e '^seed [0-9]* \['; }

# Point burn's CUDA runtime at the CUDA headers and NVRTC when CUDA_PATH / LD_LIBRARY_PATH
# do not already say where they are. NVRTC compiles every kernel against the CUDA headers
# (CUDA_PATH/include/cuda_fp16.h); the toolkit or the pip wheels of PyTorch's CUDA hold them.
cuda_env() {
    if [ -z "${CUDA_PATH:-}" ] && [ ! -f /usr/local/cuda/include/cuda_fp16.h ]; then
        for d in $(python3 -c 'import nvidia, os; [print(os.path.join(p, s)) for p in nvidia.__path__ for s in sorted(os.listdir(p))]' 2> /dev/null); do
            if [ -f "$d/include/cuda_fp16.h" ]; then export CUDA_PATH=$d; break; fi
        done
    fi
    # libnvrtc.so.13 (cudarc loads it by that name): the toolkit's lib64, else the pip wheels'.
    for d in "${CUDA_PATH:-/usr/local/cuda}/lib64" /usr/local/cuda/lib64 \
        $(python3 -c 'import nvidia, os; [print(os.path.join(r, "")) for p in nvidia.__path__ for r, _, fs in os.walk(p) if any(f.startswith("libnvrtc.so") for f in fs)]' 2> /dev/null); do
        if ls "$d"/libnvrtc.so* > /dev/null 2>&1; then export LD_LIBRARY_PATH="$d:${LD_LIBRARY_PATH:-}"; break; fi
    done
    echo "CUDA_PATH=${CUDA_PATH:-(unset: /usr/local/cuda)} LD_LIBRARY_PATH=${LD_LIBRARY_PATH:-}"
}

# device_check BINARY DEVICE OUT SECONDS: 2 updates of `quick` on DEVICE, stopped after
# SECONDS; prints each update's split and returns the training's exit status. CubeCL logs
# every kernel it compiles and autotunes into OUT/cubecl.log (its last 4 MB). On the H200
# (2026-11-27) a binary built with CubeCL's autotune finished no update in 60 s, 230 s or
# 275 s, the GPU idle, one kernel compiled a second, with CUBECL_AUTOTUNE_LEVEL=minimal as
# without (docs/results/gpu-h200-2.md): yokai-train's `cuda` feature now leaves autotune
# out, and the log says whether what is left compiles in time.
# Kernels CubeCL has begun compiling so far, from its log.
kernels_compiled() { grep -c START_KERNEL_COMPILATION /tmp/cubecl.log 2> /dev/null; }

# device_check BINARY DEVICE OUT SECONDS [CONFIG] [UPDATES]: the same with another preset and
# number of updates (default quick, 2); the run stays in /tmp/gpu-check.
device_check() {
    local bin=$1 device=$2 out=$3 seconds=$4 config=${5:-quick} updates=${6:-2} status sampler=
    rm -rf /tmp/gpu-check /tmp/cubecl.log
    # Every 30 s on a GPU: kernels compiled so far, and what the GPU is doing meanwhile.
    if [ "$device" != cpu ]; then
        (while sleep 30; do
            echo "  $(kernels_compiled) kernels compiled;" \
                "GPU $(nvidia-smi --query-gpu=utilization.gpu,memory.used --format=csv,noheader 2> /dev/null)"
        done) &
        sampler=$!
    fi
    CUBECL_DEBUG_LOG=/tmp/cubecl.log timeout "$seconds" "$bin" train "$config" --device "$device" \
        --seeds 0 --max-updates "$updates" --eval-games 0 --out /tmp/gpu-check 2>&1 | quiet
    status=${PIPESTATUS[0]}
    [ -n "$sampler" ] && kill "$sampler" 2> /dev/null
    echo "exit status $status (124: stopped after $seconds s)"
    if [ -f /tmp/cubecl.log ]; then
        echo "cubecl.log: $(wc -l < /tmp/cubecl.log) lines, $(kernels_compiled)" \
            "kernels compiled, $(grep -c '^Autotune\[' /tmp/cubecl.log) autotune timings"
        tail -c 4000000 /tmp/cubecl.log > "$out/cubecl.log"
    fi
    "$gpu_scripts/update-times.py" /tmp/gpu-check/seed-0/metrics.jsonl "$config"
    return "$status"
}

gpu_scripts=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

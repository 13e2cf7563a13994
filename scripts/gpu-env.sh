# Sourced by the GPU scripts (gpu-session.sh, gpu-call.sh) on a machine with an NVIDIA GPU:
# points burn's CUDA runtime at the CUDA headers and NVRTC when CUDA_PATH / LD_LIBRARY_PATH
# do not already say where they are.
#
# NVRTC compiles every kernel against the CUDA headers (CUDA_PATH/include/cuda_fp16.h); the
# toolkit or the pip wheels of PyTorch's CUDA hold them.
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

#!/usr/bin/env bash
# The whole test suite: formatting, lints, every Rust test in release mode (the soak test
# plays 10^6 steps, which needs optimised code), then the Python package built from
# source into a local virtual environment (.venv) and its pytest suite.
# CI runs exactly this (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
# A clean run needs about 9 GB of disk: 2.9 GB of build outputs, 5.8 GB of venv (5.2 GB of
# it PyTorch's CUDA wheels). CI once ran out of disk, so the log says how much there was
# and how much the run took.
disk_report() { echo "disk ($1): $(df -h . | awk 'NR==2 {print $4 " free of " $2}'); target $(du -sh target 2>/dev/null | cut -f1), .venv $(du -sh .venv 2>/dev/null | cut -f1)" >&2; }
# Each phase's start is logged with the seconds since the start, so a log shows where the
# suite's time goes (CI has 40 minutes for all of it).
phase() { echo "== $1 (at ${SECONDS} s)" >&2; }
disk_report start
trap 'phase "end, rc $?"; disk_report end' EXIT
phase "formatting and lints"
cargo fmt --all -- --check
# The CUDA build's stand-in crate is its own workspace (vendor/cubecl-llvm-nvrtc).
rustfmt --edition 2024 --check vendor/cubecl-llvm-nvrtc/src/lib.rs
cargo clippy --workspace --all-targets --release -- -D warnings
# The Python extension built alone must turn on the dependency features the workspace does,
# or the wheel's build below compiles burn and the rest again (python/Cargo.toml).
python3 scripts/wheel-features.py
# The GPU builds (burn's Vulkan and CUDA runtimes) are compiled, not run: CI has no GPU, and
# this keeps `--features vulkan` and `--features cuda` (with cubecl-llvm patched out for
# vendor/cubecl-llvm-nvrtc) from rotting (docs/training.md, "Training on a GPU"). Test
# targets included: the tests that exist only in a GPU build (the backend's device for
# `cuda` and `vulkan`) are type-checked and linted, so they cannot rot unseen either. Both
# features in one build: no code is compiled only without one of them, and the crates they
# share are checked once (a clean run on 2 cores: two builds 6 min 20 s, one 4 min 50 s).
phase "lints of the GPU builds and the lean Python extension"
cargo clippy -p yokai-train -p yokai-cli --features yokai-train/vulkan,yokai-train/cuda --all-targets --release -- -D warnings
# The Python extension without the trainer (no burn), as `MATURIN_PEP517_ARGS=
# --no-default-features pip install ./python` builds it (docs/python.md).
cargo clippy -p yokai-python --no-default-features --release -- -D warnings
phase "Rust tests"
cargo test --workspace --release

# Python: a fresh machine needs nothing but python3 (with venv) and the Rust toolchain.
phase "Python: venv, wheels, PyTorch, browser"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --upgrade pip
# The distribution was called `yokai` before 2026-11-25 (a name PyPI gives another
# project): a venv made then holds it under that name, which would shadow the new one.
.venv/bin/python -m pip uninstall --quiet --yes yokai > /dev/null 2>&1 || true
# The wheel a user without Rust installs, built as `pip wheel ./python` builds it: abi3
# (one wheel for every CPython >= 3.9), tagged manylinux_2_34, the newest glibc symbols
# this Debian 12 build links (a release builds in a manylinux container for older
# systems: .github/workflows/wheels.yml). The test venv installs that same wheel.
rm -rf target/wheel
MATURIN_PEP517_ARGS="--compatibility manylinux_2_34" .venv/bin/python -m pip wheel --quiet \
    --no-deps -w target/wheel ./python
wheel=$(ls target/wheel/*.whl)
.venv/bin/python -m pip install --quiet --force-reinstall --no-deps "$wheel"
.venv/bin/python -m pip install --quiet "${wheel}[test]"
# ... and a fresh venv with only the wheel and PettingZoo, for test_wheel.py, which runs it
# with no cargo on PATH.
rm -rf .venv-wheel
python3 -m venv .venv-wheel
.venv-wheel/bin/python -m pip install --quiet "$wheel" "pettingzoo>=1.24" "gymnasium>=0.29"
export YOKAI_WHEEL_PYTHON="$PWD/.venv-wheel/bin/python"
# PyTorch for the test of python/examples/ppo_torch.py (PyPI's Linux wheel is the CUDA
# build: about 1.5 min and 5 GB the first time; it runs on the CPU without a GPU). PyPI's
# CDN has cut that download mid-file in CI (a CUDA wheel stuck at 136 of 151 MB through
# six resumes), so each try resumes many times and a failed try starts afresh. If PyPI
# still fails, or the disk has under 7 GB free, the suite goes on and test_examples.py says
# it was skipped for want of torch.
torch_installed=0
free_kb=$(df -Pk . | awk 'NR==2 {print $4}')
if [ "$free_kb" -lt $((7 * 1024 * 1024)) ] && ! .venv/bin/python -c "import torch" 2> /dev/null; then
    echo "WARNING: $((free_kb / 1024)) MB of disk free, PyTorch needs about 6 GB: not installed" >&2
    attempts=""
else
    attempts="1 2 3"
fi
for attempt in $attempts; do
    if .venv/bin/python -m pip install --quiet --no-cache-dir --retries 10 --resume-retries 20 torch; then
        torch_installed=1
        break
    fi
    echo "pip install torch failed (try $attempt of 3)" >&2
    [ "$attempt" = 3 ] || sleep 10
done
if [ "$torch_installed" = 0 ] && [ -n "$attempts" ]; then
    echo "WARNING: PyTorch could not be downloaded from PyPI; the PyTorch example's test is skipped" >&2
fi
# The skips python/tests/conftest.py allows, each only where its reason holds here; any
# other skip fails the run.
export YOKAI_STRICT_SKIPS=1
if ! .venv/bin/python -c "import torch" 2> /dev/null; then
    export YOKAI_TORCH_MISSING=1
fi
# jax 0.10 and jaxmarl need Python >= 3.11 (python/pyproject.toml installs them only there):
# below it test_jax.py is skipped, and says why.
if ! .venv/bin/python -c "import sys; sys.exit(sys.version_info < (3, 11))"; then
    export YOKAI_JAX_UNSUPPORTED=1
fi
# The browser test of `yokai serve` drives Debian's Chromium with Selenium (installed with
# the test extra). Install the browser where we may (root on Debian, about 1 min); without
# it that one test is skipped.
if ! command -v chromedriver > /dev/null && [ "$(id -u)" = 0 ] && command -v apt-get > /dev/null; then
    apt-get install -y -q chromium chromium-driver > /dev/null 2>&1 \
        || { apt-get update -q > /dev/null 2>&1 && apt-get install -y -q chromium chromium-driver > /dev/null 2>&1; } \
        || echo "could not install chromium: the browser test will be skipped"
fi
if ! command -v chromedriver > /dev/null || ! command -v chromium > /dev/null; then
    if [ "$(id -u)" != 0 ] || ! command -v apt-get > /dev/null; then
        export YOKAI_NO_BROWSER=1
    fi
fi
# The package without the trainer (no burn) in a venv of its own, for test_lean.py: it
# must play and say clearly what it lacks.
if [ ! -x .venv-lean/bin/python ]; then
    python3 -m venv .venv-lean
fi
rm -rf target/lean-wheel
MATURIN_PEP517_ARGS="--no-default-features" .venv/bin/python -m pip wheel --quiet --no-deps \
    -w target/lean-wheel ./python
.venv-lean/bin/python -m pip uninstall --quiet --yes yokai > /dev/null 2>&1 || true
.venv-lean/bin/python -m pip install --quiet --force-reinstall target/lean-wheel/*.whl
phase "Python tests"
# pytest lists its ten slowest tests at the end, for the same reason as the phase lines.
YOKAI_LEAN_PYTHON="$PWD/.venv-lean/bin/python" .venv/bin/python -m pytest -q -rs --durations=10 python/tests

#!/usr/bin/env bash
# The whole test suite: formatting, lints, every Rust test in release mode (the soak test
# plays 10^6 steps, which needs optimised code), then the Python package built from
# source into a local virtual environment (.venv) and its pytest suite.
# CI runs exactly this (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --release -- -D warnings
cargo test --workspace --release

# Python: a fresh machine needs nothing but python3 (with venv) and the Rust toolchain.
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --upgrade pip
.venv/bin/python -m pip install --quiet "./python[test]"
.venv/bin/python -m pytest -q python/tests

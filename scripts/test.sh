#!/usr/bin/env bash
# The whole test suite: formatting, lints, and every Rust test in release mode (the soak
# test plays 10^6 steps, which needs optimised code). CI runs exactly this (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --release -- -D warnings
cargo test --workspace --release

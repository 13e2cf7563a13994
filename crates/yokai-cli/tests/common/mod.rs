//! What the CLI tests share: running the `yokai` binary built for this test run.

use std::process::{Command, Output};

/// Run `yokai` with `args` and collect its output.
pub fn yokai(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_yokai"))
        .args(args)
        .output()
        .expect("runs")
}

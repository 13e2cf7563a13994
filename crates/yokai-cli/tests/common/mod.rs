//! What the CLI tests share: running the `yokai` binary built for this test run.

// Each test file compiles this module on its own and uses some of it.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Run `yokai` with `args` and collect its output.
pub fn yokai(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_yokai"))
        .args(args)
        .output()
        .expect("runs")
}

/// Run `yokai` with `args`, which must succeed (the panic shows its stderr), and return its
/// standard output.
pub fn yokai_ok(args: &[&str]) -> Vec<u8> {
    let out = yokai(args);
    assert!(
        out.status.success(),
        "yokai {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// Run `yokai` with `args`, which must fail, and return its standard error.
pub fn yokai_err(args: &[&str]) -> String {
    let out = yokai(args);
    assert!(!out.status.success(), "yokai {args:?} succeeded");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The metrics lines of a run without their timing fields, which differ between runs.
pub fn metrics_without_timings(run: &Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(run.join("metrics.jsonl"))
        .unwrap()
        .lines()
        .map(|line| {
            let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
            let m = v.as_object_mut().unwrap();
            for timing in ["sps", "rollout_seconds", "learn_seconds"] {
                m.remove(timing);
            }
            v
        })
        .collect()
}

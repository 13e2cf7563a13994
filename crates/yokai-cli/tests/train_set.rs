//! `yokai train --set FIELD=VALUE`: overrides reach the run and its saved config, and bad
//! ones are refused before anything is written.

mod common;
use common::yokai_err;

/// Overrides that make `quick` a two-update run of 8 games × 8 steps on a small network.
const TINY: [&str; 4] = [
    "ppo.num_envs=8",
    "ppo.rollout_steps=8",
    "ppo.total_steps=128",
    "network.hidden=16",
];

/// `yokai train quick` of seed 0 on one thread into `out`, no evaluation, with `sets` as
/// `--set` overrides.
fn train_quick<'a>(out: &'a str, sets: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "train",
        "quick",
        "--seeds",
        "0",
        "--threads",
        "1",
        "--eval-games",
        "0",
        "--out",
        out,
    ];
    for set in sets {
        args.extend(["--set", set]);
    }
    args
}

#[test]
fn overrides_reach_the_saved_config_and_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("runs");
    let out_s = out_dir.to_str().unwrap();
    let sets = [&TINY[..], &["run.log_every=1", "ppo.lr=0.002"]].concat();
    let out = common::yokai(&train_quick(out_s, &sets));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    // Without a terminal the progress is plain lines: one per tenth of the run reached,
    // here both updates (50 % and 100 %).
    for line in [
        "seed 0: update 1/2 (50 %) | 64 steps",
        "seed 0: update 2/2 (100 %) | 128 steps",
    ] {
        assert!(stderr.contains(line), "no `{line}` in {stderr}");
    }
    let run = out_dir.join("seed-0");
    let saved: toml::Table = std::fs::read_to_string(run.join("config.toml"))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(saved["ppo"]["num_envs"].as_integer(), Some(8));
    assert_eq!(saved["ppo"]["lr"].as_float(), Some(0.002));
    assert_eq!(saved["network"]["hidden"].as_integer(), Some(16));
    // What the preset sets and no override touched stays the preset's.
    assert_eq!(saved["network"]["critic"].as_str(), Some("central"));
    // 128 steps of 8 games × 8 steps: two updates, each logged, at the overridden rate.
    let metrics = std::fs::read_to_string(run.join("metrics.jsonl")).unwrap();
    let lines: Vec<serde_json::Value> = metrics
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[1]["env_steps"], 128);
    assert!((lines[0]["lr"].as_f64().unwrap() - 0.002).abs() < 1e-3);
}

#[test]
fn bad_overrides_are_refused_naming_them_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("runs");
    let out_s = out.to_str().unwrap();
    let err = yokai_err(&["train", "quick", "--out", out_s, "--set", "ppo.lrr=1"]);
    assert!(
        err.contains("--set ppo.lrr=1: unknown field `lrr`"),
        "{err}"
    );
    assert!(err.contains("`lr`"), "{err}");
    let err = yokai_err(&["train", "quick", "--out", out_s, "--set", "ppo.epochs=many"]);
    assert!(err.contains("--set ppo.epochs=many"), "{err}");
    let err = yokai_err(&["train", "quick", "--out", out_s, "--set", "ppo.num_envs=0"]);
    assert!(
        err.contains("configs/quick.toml with --set ppo.num_envs=0"),
        "{err}"
    );
    let err = yokai_err(&["train", "quick", "--out", out_s, "--set", "lr"]);
    assert!(err.contains("FIELD=VALUE"), "{err}");
    let err = yokai_err(&[
        "train", "quick", "--out", out_s, "--resume", "--set", "ppo.lr=1",
    ]);
    assert!(err.contains("--resume"), "{err}");
    assert!(!out.exists(), "a refused command wrote {}", out.display());
}

/// A resumed run trains on its checkpoint's config, not on what the preset says now: the
/// line that opens the command describes the checkpoint's (here its symmetries, set when
/// the run began and absent from the preset).
#[test]
fn a_resumed_run_is_described_by_its_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("runs");
    let out_s = out_dir.to_str().unwrap();
    let sets = [&TINY[..], &["algorithm.symmetries=both"]].concat();
    let mut first = train_quick(out_s, &sets);
    first.extend(["--max-updates", "1"]);
    let out = common::yokai(&first);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("training quick (ippo with both symmetries on "),
        "{stderr}"
    );
    let mut resumed = train_quick(out_s, &[]);
    resumed.push("--resume");
    let out = common::yokai(&resumed);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("resuming quick (ippo with both symmetries on "),
        "{stderr}"
    );
    assert!(stderr.contains("seed 0: update 2/2 (100 %)"), "{stderr}");
}

/// `--resume` reads every seed's checkpoint before any seed trains: where a later seed has
/// none, the command stops at once, naming that seed's folder, and the seed that could
/// resume has not moved (its checkpoint stays at update 1).
#[test]
fn a_resume_missing_a_seeds_checkpoint_stops_before_any_seed_trains() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("runs");
    let out_s = out_dir.to_str().unwrap();
    let mut first = train_quick(out_s, &TINY);
    first.extend(["--max-updates", "1"]);
    let out = common::yokai(&first);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let checkpoint = out_dir.join("seed-0").join("checkpoint.ykc");
    let before = std::fs::read(&checkpoint).unwrap();
    let mut resumed = train_quick(out_s, &[]);
    let seeds = resumed.iter().position(|a| *a == "--seeds").unwrap() + 1;
    resumed[seeds] = "0..2";
    resumed.push("--resume");
    let out = common::yokai(&resumed);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(stderr.contains("seed-1"), "{stderr}");
    assert!(!stderr.contains("seed 0: update"), "{stderr}");
    assert_eq!(
        std::fs::read(&checkpoint).unwrap(),
        before,
        "seed 0 trained"
    );
}

//! `run.snapshot_every` and `yokai average`: snapshots leave training as it was, and a
//! run's last stretch averages into a policy `yokai eval` seats.

mod common;
use common::{yokai_err, yokai_ok};
use std::path::Path;
use yokai_train::TrainedPolicy;

/// Train `quick` shrunk to 4 updates of 8 games × 8 steps, seeds 0 and 1, into `out`, with
/// `extra` overrides.
fn train(out: &Path, extra: &[&str]) {
    let mut args = vec![
        "train",
        "quick",
        "--seeds",
        "0,1",
        "--threads",
        "1",
        "--eval-games",
        "0",
        "--out",
    ];
    args.push(out.to_str().unwrap());
    for set in [
        "ppo.num_envs=8",
        "ppo.rollout_steps=8",
        "ppo.total_steps=256",
        "network.hidden=16",
    ]
    .iter()
    .chain(extra)
    {
        args.extend(["--set", set]);
    }
    yokai_ok(&args);
}

#[test]
fn snapshots_leave_training_unchanged_and_the_last_stretch_averages() {
    let dir = tempfile::tempdir().unwrap();
    let (plain, snapped) = (dir.path().join("plain"), dir.path().join("snapped"));
    train(&plain, &[]);
    train(&snapped, &["run.snapshot_every=1"]);
    for seed in ["seed-0", "seed-1"] {
        assert_eq!(
            common::metrics_without_timings(&plain.join(seed)),
            common::metrics_without_timings(&snapped.join(seed)),
            "{seed}: snapshots changed what the run learned"
        );
        assert!(!plain.join(seed).join("snapshots").exists());
        let names: Vec<String> = std::fs::read_dir(snapped.join(seed).join("snapshots"))
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        let mut names = names;
        names.sort();
        assert_eq!(
            names,
            [
                "policy-000001.ykp",
                "policy-000002.ykp",
                "policy-000003.ykp",
                "policy-000004.ykp"
            ]
        );
    }
    // The last half of 4 updates: the snapshot of update 3 and the final policy (update 4).
    let avg = dir.path().join("avg");
    yokai_ok(&[
        "average",
        snapped.to_str().unwrap(),
        "--last",
        "0.5",
        "-o",
        avg.to_str().unwrap(),
    ]);
    for seed in ["seed-0", "seed-1"] {
        let averaged = TrainedPolicy::load(&avg.join(seed)).unwrap();
        assert_eq!(averaged.header().averaged, [3, 4], "{seed}");
        assert_eq!(averaged.header().update, 4);
        let trained = TrainedPolicy::load(&snapped.join(seed)).unwrap();
        assert!(trained.header().averaged.is_empty());
        // A trained policy's file leaves the field out (its header is as before the field).
        let file = yokai_train::Container::read(&snapped.join(seed).join("policy.ykp")).unwrap();
        assert!(!file.header.contains("averaged"), "{}", file.header);
    }
    let report = dir.path().join("eval");
    yokai_ok(&[
        "eval",
        avg.to_str().unwrap(),
        "--games",
        "4",
        "--threads",
        "1",
        "-o",
        report.to_str().unwrap(),
    ]);
    let matrix = std::fs::read_to_string(report.join("matrix.csv")).unwrap();
    assert_eq!(matrix.lines().count(), 1 + 3, "{matrix}");
}

#[test]
fn a_run_without_snapshots_or_a_bad_stretch_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain");
    train(&plain, &[]);
    let out = dir.path().join("avg");
    let (plain_s, out_s) = (plain.to_str().unwrap(), out.to_str().unwrap());
    let err = yokai_err(&["average", plain_s, "--last", "0.5", "-o", out_s]);
    assert!(
        err.contains("run.snapshot_every") && err.contains("seed-0"),
        "{err}"
    );
    let err = yokai_err(&["average", plain_s, "--last", "2", "-o", out_s]);
    assert!(err.contains("(0, 1]"), "{err}");
    assert!(!out.exists(), "nothing is written when averaging fails");
}

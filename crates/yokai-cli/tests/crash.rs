//! Crash safety: `yokai train` killed with SIGKILL at random moments — between updates, in
//! the middle of an update, while a checkpoint, a metrics line or a replay is being written —
//! and resumed each time, ends with exactly the network and the metrics of a run that was
//! never interrupted.

mod common;

use common::{yokai_err, yokai_ok};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

const CONFIG: &str = "game = \"9c-2p-perfect\"\n[network]\npreset = \"compact\"\nhidden = 16\n\
     [ppo]\nnum_envs = 8\nrollout_steps = 8\nminibatches = 2\nepochs = 1\ntotal_steps = 12800\n\
     [run]\ncheckpoint_every = 1\n";
const UPDATES: u64 = 200;

fn train(config: &Path, out: &Path, resume: bool) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_yokai"));
    c.args([
        "train",
        config.to_str().unwrap(),
        "--seeds",
        "0",
        "--threads",
        "1",
    ])
    .args(["--eval-games", "0", "--out", out.to_str().unwrap()])
    .stdout(Stdio::null())
    .stderr(Stdio::null());
    if resume {
        c.arg("--resume");
    }
    c
}

#[test]
fn a_run_killed_twenty_times_and_resumed_equals_an_uninterrupted_run() {
    let tmp = tempfile::Builder::new()
        .prefix("yokai-crash-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let config = dir.join("tiny.toml");
    std::fs::write(&config, CONFIG).unwrap();

    let whole: PathBuf = dir.join("whole");
    assert!(train(&config, &whole, false).status().unwrap().success());

    let killed = dir.join("killed");
    let run = killed.join("seed-0");
    // Delays from a fixed generator, so a failure can be run again as it happened.
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut delay = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        Duration::from_millis(20 + state % 180)
    };
    let (mut kills, mut attempts, mut mid_write) = (0, 0, 0);
    loop {
        attempts += 1;
        // The run must finish after at least 20 kills, one of them inside a checkpoint
        // write; this bound is what fails if kills never land inside one.
        assert!(
            attempts < 2_000,
            "no finished run with 20 kills and one inside a checkpoint write \
             ({kills} kills, {mid_write} inside a write)"
        );
        // Before the first checkpoint exists there is nothing to resume: start afresh.
        let resume = run.join("checkpoint.ykc").exists();
        let mut child = train(&config, &killed, resume).spawn().unwrap();
        std::thread::sleep(delay());
        match child.try_wait().unwrap() {
            Some(status) => {
                assert!(status.success(), "attempt {attempts} failed: {status}");
                // Where a kill lands is timing: with about one kill in ten inside a write,
                // 20 kills sometimes miss every write, so the run goes on until one hits.
                if kills >= 20 && mid_write >= 1 {
                    break;
                }
                // Finished before enough kills: start the whole run again.
                std::fs::remove_dir_all(&killed).unwrap();
            }
            None => {
                child.kill().unwrap(); // SIGKILL
                child.wait().unwrap();
                kills += 1;
                // A checkpoint being written lives in checkpoint.tmp until it is renamed.
                let tmp = run.join("checkpoint.tmp");
                if tmp.exists() {
                    mid_write += 1;
                    std::fs::remove_file(tmp).unwrap();
                }
            }
        }
    }
    // With a checkpoint after every update and each one flushed to disk, about one kill in
    // ten lands inside a write (15 of 133 on the development machine).
    eprintln!("{kills} kills in {attempts} attempts, {mid_write} while a checkpoint was written");
    let (a, b) = (
        yokai_train::TrainedPolicy::load(&whole.join("seed-0")).unwrap(),
        yokai_train::TrainedPolicy::load(&run).unwrap(),
    );
    assert_eq!(a.header().update, UPDATES);
    assert_eq!(b.header().update, UPDATES);
    assert_eq!(a.parameters(), b.parameters(), "after {kills} kills");
    assert_eq!(
        common::metrics_without_timings(&whole.join("seed-0")),
        common::metrics_without_timings(&run),
        "one metrics line per update, the same values"
    );
    // The report still works on the resumed run.
    yokai_ok(&["eval", run.to_str().unwrap(), "--games", "4"]);
    // A resume with nothing to resume names the checkpoint it looked for.
    let nothing = dir.join("nothing");
    let err = yokai_err(&[
        "train",
        config.to_str().unwrap(),
        "--seeds",
        "0",
        "--out",
        nothing.to_str().unwrap(),
        "--resume",
    ]);
    assert!(err.contains("checkpoint.ykc"), "{err}");
}

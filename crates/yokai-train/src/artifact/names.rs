//! The names of a run directory's files (their layout is described in the `run` module) and of a seed's
//! run inside a method's directory.

use std::path::{Path, PathBuf};

pub const CHECKPOINT: &str = "checkpoint.ykc";
pub const POLICY: &str = "policy.ykp";
/// The policy a trainer outside Rust writes (`python -m yokai.torch_train`): SafeTensors
/// with the training config and game as metadata (`artifact::safetensors`).
pub const SAFETENSORS_POLICY: &str = "policy.safetensors";
pub const METRICS: &str = "metrics.jsonl";
pub const BELIEF_METRICS: &str = "belief.jsonl";
/// The folder of a run's policy snapshots (`run.snapshot_every`).
pub const SNAPSHOTS: &str = "snapshots";

/// The file of the snapshot taken after update `update`: zero-padded so that the names
/// sort in the order of the run.
pub fn snapshot_name(update: u64) -> String {
    format!("policy-{update:06}.ykp")
}

/// Seed `seed`'s run directory inside a method's directory `out`, as `yokai train --seeds`
/// writes it: `out/seed-N`.
pub fn seed_dir(out: &Path, seed: u64) -> PathBuf {
    out.join(format!("seed-{seed}"))
}

/// Seed `seed`'s run in `path` when `path` is a directory of `seed-N` runs, else `path`
/// itself: how `--init-from` and `obl.previous` name one run per seed.
pub fn seed_path(path: &Path, seed: u64) -> PathBuf {
    let per_seed = seed_dir(path, seed);
    if per_seed.is_dir() {
        per_seed
    } else {
        path.to_path_buf()
    }
}

/// The `seed-N` runs inside `path`, by N ascending (empty where it holds none or cannot
/// be read): a method's seeds, as `yokai train --seeds` writes them.
pub fn seed_runs(path: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(path) else {
        return Vec::new();
    };
    let mut runs: Vec<(u64, PathBuf)> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let seed = e
                .file_name()
                .to_str()?
                .strip_prefix("seed-")?
                .parse()
                .ok()?;
            is_run(&e.path()).then(|| (seed, e.path()))
        })
        .collect();
    runs.sort();
    runs.into_iter().map(|(_, dir)| dir).collect()
}

/// Whether `dir` is a run directory: it holds a policy file or a checkpoint (what
/// `TrainedPolicy::load` can seat), or the policy of a PyTorch run.
pub fn is_run(dir: &Path) -> bool {
    dir.join(POLICY).is_file()
        || dir.join(CHECKPOINT).is_file()
        || dir.join(SAFETENSORS_POLICY).is_file()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `seed_runs` lists the `seed-N` folders that hold a run, by N as a number (seed-10
    /// after seed-2), and nothing else.
    #[test]
    fn seed_runs_are_the_seed_folders_holding_runs_in_numeric_order() {
        let dir = std::env::temp_dir().join(format!("yokai-seed-runs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        for name in ["seed-10", "seed-2", "seed-x", "other", "seed-3"] {
            std::fs::create_dir_all(dir.join(name)).unwrap();
            if name != "seed-3" {
                std::fs::write(dir.join(name).join(POLICY), b"").unwrap();
            }
        }
        let runs = seed_runs(&dir);
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(runs, vec![dir.join("seed-2"), dir.join("seed-10")]);
        assert!(seed_runs(&dir).is_empty(), "a missing folder has no runs");
    }
}

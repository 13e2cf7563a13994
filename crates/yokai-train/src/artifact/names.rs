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

/// Seed `seed`'s run in `path` when `path` is a directory of `seed-N` runs, else `path`
/// itself: how `--init-from` and `obl.previous` name one run per seed.
pub fn seed_path(path: &Path, seed: u64) -> PathBuf {
    let per_seed = path.join(format!("seed-{seed}"));
    if per_seed.is_dir() {
        per_seed
    } else {
        path.to_path_buf()
    }
}

/// Whether `dir` is a run directory: it holds a policy file or a checkpoint (what
/// `TrainedPolicy::load` can seat), or the policy of a PyTorch run.
pub fn is_run(dir: &Path) -> bool {
    dir.join(POLICY).is_file()
        || dir.join(CHECKPOINT).is_file()
        || dir.join(SAFETENSORS_POLICY).is_file()
}

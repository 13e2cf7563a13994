//! `[run]`: checkpoints, logging, threads, starting weights.

use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RunConfig {
    /// Write a checkpoint every this many updates (and always after the last one).
    pub checkpoint_every: u64,
    /// Also keep the policy every this many updates, as `RUN/snapshots/policy-UUUUUU.ykp`
    /// (U the update): the material for averaging the weights of a run's last stretch
    /// (`yokai average`) or for following a run's play over time. 0 (the default, and left
    /// out of saved configs) keeps none; snapshots never change what the run learns.
    #[serde(skip_serializing_if = "is_zero")]
    pub snapshot_every: u64,
    /// Append a metrics line every this many updates.
    pub log_every: u64,
    /// Worker threads for the environments and the CPU backend; 0 = one per core.
    pub threads: usize,
    /// Start the network from the parameters of this policy file, checkpoint or run
    /// directory (fine-tuning, curricula) instead of a fresh initialisation; the network
    /// settings and the game must match it. Only the weights are taken: the optimiser, the
    /// step count and the schedules start anew. A relative path is read from the directory
    /// `yokai train` runs in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub init_from: Option<std::path::PathBuf>,
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            checkpoint_every: 50,
            snapshot_every: 0,
            log_every: 1,
            threads: 0,
            init_from: None,
        }
    }
}

fn is_zero(x: &u64) -> bool {
    *x == 0
}

//! Errors of the batched environment.

use yokai_engine::{ActionError, PackError};

/// Errors of the batched environment. A failed `step` changes nothing.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum VecError {
    #[error("expected {expected} actions ({what}), got {got}")]
    ActionCount {
        expected: usize,
        got: usize,
        what: &'static str,
    },
    #[error("env {env}: {source}")]
    Action {
        env: usize,
        #[source]
        source: ActionError,
    },
    #[error("env {env} does not exist (num_envs is {num_envs})")]
    EnvIndex { env: usize, num_envs: usize },
    #[error("env {env}: the saved actions finish the game, so it cannot be restored mid-episode")]
    FinishedOnRestore { env: usize },
    #[error("num_envs must be at least 1")]
    NoEnvs,
    #[error("unknown observation encoding `{0}` (expected image, image-public, image-private, the same with -chw for channels-first, graph, graph-public, graph-private or none)")]
    Encoding(String),
    /// A buffer that the machine's memory cannot hold (a `num_envs` far too large).
    #[error("num_envs = {num_envs} needs {} for the {what} buffer alone, which could not be allocated: use fewer environments", human_bytes(*bytes))]
    Memory {
        what: &'static str,
        bytes: u128,
        num_envs: usize,
    },
    #[error("game {env} of the batch is not a packed game of this config: {source}")]
    Packed {
        env: usize,
        #[source]
        source: PackError,
    },
    #[error("the {what} buffer holds {got} values, but the batch needs {expected}")]
    BufferLength {
        what: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("packed games offer the image encodings and none; a graph's adjacency is a second buffer they do not carry")]
    PackedEncoding,
    #[error("could not start {threads} worker threads: {message}")]
    Threads { threads: usize, message: String },
}

/// `bytes` for people: `97.3 GB`.
fn human_bytes(bytes: u128) -> String {
    let b = bytes as f64;
    match b {
        b if b >= 1e12 => format!("{:.1} TB", b / 1e12),
        b if b >= 1e9 => format!("{:.1} GB", b / 1e9),
        b if b >= 1e6 => format!("{:.1} MB", b / 1e6),
        _ => format!("{bytes} bytes"),
    }
}

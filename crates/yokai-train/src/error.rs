//! The crate's errors: what a person reads when a config, a file or a run is wrong.

use std::path::PathBuf;
use yokai_vec::VecError;

/// Why training cannot go on.
#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    #[error(transparent)]
    Config(#[from] crate::config::TrainConfigError),
    #[error(transparent)]
    File(#[from] FileError),
    #[error(transparent)]
    Backend(#[from] crate::backend::BackendError),
    #[error("environment: {0}")]
    Env(#[from] VecError),
    /// A file that does not fit what reads it (another network, sizes that disagree).
    #[error("{path}: {message}")]
    Mismatch { path: String, message: String },
    /// burn could not read or apply a record (`what`: the network or the optimiser).
    #[error("{path}: cannot load the {what}: {source}")]
    Record {
        path: String,
        what: &'static str,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A JSON part of a file (a header, a loop state, a metrics line) that does not parse;
    /// `what` names the part.
    #[error("{path}: {what}: {source}")]
    Json {
        path: String,
        what: &'static str,
        #[source]
        source: serde_json::Error,
    },
    /// The game config a policy file or checkpoint carries does not parse.
    #[error("{path}: game config: {source}")]
    GameConfig {
        path: String,
        #[source]
        source: yokai_engine::ConfigError,
    },
    /// burn's SafeTensors writer failed (its error type is burn's own; its text is kept).
    #[error("{}: cannot write SafeTensors: {message}", path.display())]
    Export { path: PathBuf, message: String },
    #[error(
        "{}: already holds a run; use --resume to continue it or choose another --out",
        dir.display()
    )]
    RunExists { dir: PathBuf },
    /// An Off-Belief Learning continuation that could not be built (a bug, named).
    #[error("off-belief learning: {0}")]
    Obl(String),
    #[error(
        "{path} was trained on {trained}, not on {game}: its observations and actions do not fit"
    )]
    WrongGame {
        path: String,
        /// Names of the games (configs are large for an error value).
        trained: String,
        game: String,
    },
}

/// A file that cannot be read as a checkpoint or policy, with where and why.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    #[error("{path}: {message}")]
    Io { path: PathBuf, message: String },
    #[error("{path} is not a Yōkai checkpoint or policy file (it does not start with the format's magic bytes)")]
    NotOurs { path: PathBuf },
    #[error("{path} has format version {found}; this build reads version {reads}")]
    Version {
        path: PathBuf,
        found: u32,
        reads: u32,
    },
    #[error("{path} is corrupt: {what}")]
    Corrupt { path: PathBuf, what: String },
    #[error("{path} has no `{section}` section")]
    Missing { path: PathBuf, section: String },
}

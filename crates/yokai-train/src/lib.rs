//! Recurrent actor-critics and PPO training for the Yōkai Learning Environment, on burn.
//!
//! The default backend is burn's pure-Rust `flex` CPU backend. The `vulkan` (and, where its
//! build can download LLVM, `cuda`) feature adds a GPU backend, chosen at run time with
//! [`Backend`], so the same code trains on a GPU.

pub mod backend;
pub mod config;
pub mod distribution;
pub mod export;
pub mod file;
pub mod gae;
pub mod init;
pub mod network;
pub mod obl;
pub mod trainer;

pub use backend::{Backend, BackendError};
pub use config::{
    ActionHead, EncoderKind, EndForm, MemoryKind, NetworkPreset, OblPartner, SymmetrySet,
    TrainConfig, TrainConfigError,
};
pub use file::{Container, FileError};
pub use network::{
    ActorCritic, CnnEncoder, Encoder, GraphEncoder, GruCell, MlpEncoder, Recurrent, TransformerXl,
};
pub use trainer::{default_device, FileHeader, TrainError, Trainer, UpdateStats};
pub mod policy;
pub mod probe;
pub mod run;

pub use network::SeatStep;
pub use policy::{NetworkPolicy, TrainedPolicy};
pub use run::{read_metrics, train_run, RunRequest, RunSummary};

//! Recurrent actor-critics and PPO training for the Yōkai Learning Environment, on burn.
//!
//! The default backend is burn's pure-Rust `flex` CPU backend. The `vulkan` (and, where its
//! build can download LLVM, `cuda`) feature adds a GPU backend, chosen at run time with
//! [`Backend`], so the same code trains on a GPU.
//!
//! Modules depend one way, each only on those above it in this list (CI checks that no two
//! top-level modules import each other, directly or around a loop):
//! - leaves: [`config`], [`device`], [`tensor`], [`init`], [`distribution`], [`gae`],
//!   [`host_kernel`] (what the operations computed on the CPU host share), [`seen`] (a
//!   seat's observation through its Other-Play symmetry);
//! - [`backend`] (devices by name), then [`error`] (every error a person reads);
//! - [`artifact`]: files on disk (container, header, run-directory names, SafeTensors);
//! - [`network`]: the actor-critics;
//! - [`policy`]: trained networks seated as players, [`average`]: their weights averaged,
//!   [`pretrained`]: the agents built in,
//!   and [`source`]: a policy by name (a bot, a pretrained agent or a trained file) and
//!   its END rule, as every front end reads one;
//! - algorithms: [`actor`] (the batched games as the seats see and play them), [`obl`]
//!   (beliefs and fictitious continuations), then [`trainer`] (PPO);
//! - [`probe`] and [`run`] (a run directory over the trainer).

pub mod config;
pub mod device;
pub mod distribution;
pub mod gae;
pub mod host_kernel;
pub mod init;
pub mod seen;
pub mod tensor;

pub mod backend;
pub mod error;

pub mod artifact;
pub mod average;
pub mod network;
pub mod policy;
pub mod pretrained;
pub mod source;

pub mod actor;
pub mod obl;
pub mod trainer;

pub mod probe;
pub mod run;

pub use artifact::{Container, FileHeader};
pub use backend::{Backend, BackendError};
pub use config::{
    ActionHead, BeliefOf, ColourNames, CriticInput, EncoderKind, EndForm, GainBaseline, GainSeats,
    MemoryKind, NetworkPreset, OblPartner, Override, SymmetrySet, TrainConfig, TrainConfigError,
};
pub use device::default_device;
pub use error::{FileError, TrainError};
pub use network::{
    ActorCritic, CnnEncoder, Encoder, GraphEncoder, GruCell, MlpEncoder, Recurrent, SeatStep,
    TransformerXl,
};
pub use policy::{NetworkPolicy, TrainedPolicy};
pub use run::{read_belief_metrics, read_metrics, train_run, RunRequest, RunSummary};
pub use source::{EndRule, PlayRule, PolicySource, SourceError};
pub use trainer::{Trainer, UpdateStats};

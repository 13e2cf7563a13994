//! Everything a run leaves on disk, below the networks and the algorithms that make it: the
//! container format of checkpoints and policy files, their header, the names of a run
//! directory's files, and the SafeTensors export.

pub mod container;
pub mod header;
pub mod names;
pub mod safetensors;
pub mod tensorboard;

pub use container::Container;
pub use header::{check_game, FileHeader};
pub(crate) use header::{load_model, load_record, read_header, record_bytes, PolicyFile};

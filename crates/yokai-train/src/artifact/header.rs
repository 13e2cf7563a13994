//! What a checkpoint or policy file says about itself: its header (kind, training config,
//! game, seed, progress), and opening one by the path a person gives (a file or a run
//! directory) with its network section ready to load.

use super::container::Container;
use super::names::{CHECKPOINT, POLICY, SAFETENSORS_POLICY};
use crate::config::TrainConfig;
use crate::error::{FileError, TrainError};
use burn::module::Module;
use burn::store::ModuleRecord;
use burn::tensor::Bytes;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use yokai_engine::Config;

/// What the header of a checkpoint or policy file says.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FileHeader {
    /// `checkpoint` or `policy`.
    pub kind: String,
    /// The resolved training config (TOML).
    pub train_config: String,
    /// The resolved game config (TOML), so a policy knows the game it was trained for.
    pub game: String,
    pub seed: u64,
    pub update: u64,
    pub env_steps: u64,
    /// For a policy made by averaging weights (`yokai average`): the update of every file
    /// averaged, in order. Empty (and left out of the file) for a trained policy.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub averaged: Vec<u64>,
}

pub(crate) fn read_header(file: &Container, path: &Path) -> Result<FileHeader, TrainError> {
    serde_json::from_str(&file.header).map_err(|source| TrainError::Json {
        path: path.display().to_string(),
        what: "unreadable header",
        source,
    })
}

/// Load network weights, refusing any record whose tensors do not match the network.
pub(crate) fn load_model<M: Module>(model: M, bytes: &[u8], path: &str) -> Result<M, TrainError> {
    let bytes = with_current_names(bytes).map_err(|e| unreadable(path, "network", e.into()))?;
    load_record(model, bytes, path, "network")
}

/// Load a module's record as it was written (no field renamed since), refusing one whose
/// tensors do not match the module: e.g. the OBL belief model a checkpoint keeps (`what`
/// names it in the error).
pub(crate) fn load_record<M: Module>(
    model: M,
    bytes: Bytes,
    path: &str,
    what: &'static str,
) -> Result<M, TrainError> {
    let record = ModuleRecord::from_bytes(bytes).map_err(|e| unreadable(path, what, e.into()))?;
    model
        .try_load_record(record)
        .map_err(|e| unreadable(path, what, e.into()))
}

/// A module's parameters in burn's record format: what the files' network (and belief)
/// sections hold, and what [`load_model`] and [`load_record`] read back.
pub(crate) fn record_bytes<M: Module>(module: M) -> Vec<u8> {
    module
        .into_record()
        .into_bytes()
        .expect("an in-memory record always serialises")
        .to_vec()
}

fn unreadable(
    path: &str,
    what: &'static str,
    source: Box<dyn std::error::Error + Send + Sync>,
) -> TrainError {
    TrainError::Record {
        path: path.to_string(),
        what,
        source,
    }
}

/// The network's fields renamed since files were first written, as tensor path prefixes
/// (old, new): until 2026-11-25 the memory (GRU or Transformer-XL) was the field `gru`.
const RENAMED: &[(&str, &str)] = &[("gru.", "memory.")];

/// A network record's bytes with every renamed tensor under its current name: the bytes
/// as they are when none is renamed (every file written since), else the record rewritten.
fn with_current_names(bytes: &[u8]) -> Result<Bytes, burn_pack::Error> {
    let old_name = |name: &str| RENAMED.iter().any(|(old, _)| name.starts_with(old));
    let reader = burn_pack::Reader::from_bytes(Bytes::from_bytes_vec(bytes.to_vec()))?;
    if !reader.tensor_names().into_iter().any(old_name) {
        return Ok(Bytes::from_bytes_vec(bytes.to_vec()));
    }
    let tensors = reader
        .into_tensors()?
        .into_iter()
        .map(|tensor| {
            let (name, dtype, shape, id, data) = tensor.into_parts()?;
            let name = RENAMED
                .iter()
                .find_map(|(old, new)| name.strip_prefix(old).map(|rest| format!("{new}{rest}")))
                .unwrap_or(name);
            Ok(burn_pack::Tensor::new(name, dtype, shape, id, data))
        })
        .collect::<Result<Vec<_>, burn_pack::Error>>()?;
    burn_pack::Writer::new(tensors).into_bytes()
}

/// The file a policy path names: `path` itself, or for a run directory its `policy.ykp`,
/// else its checkpoint, else the `policy.safetensors` a trainer outside Rust wrote
/// (`python -m yokai.torch_train`).
fn policy_file(path: &Path) -> PathBuf {
    if path.is_dir() {
        let policy = path.join(POLICY);
        let exported = path.join(SAFETENSORS_POLICY);
        if policy.exists() {
            policy
        } else if !path.join(CHECKPOINT).exists() && exported.exists() {
            exported
        } else {
            path.join(CHECKPOINT)
        }
    } else {
        path.to_path_buf()
    }
}

/// A policy file, checkpoint or run directory opened and its header read: the training
/// config and the game it was written for, and where its network's weights are.
pub(crate) struct PolicyFile {
    pub path: PathBuf,
    weights: Weights,
    pub header: FileHeader,
    pub config: TrainConfig,
    pub game: Config,
}

/// Where a policy's weights are: the `model` section of a container, or a SafeTensors
/// file with the training config and the game in its metadata
/// ([`super::safetensors`]).
enum Weights {
    Container(Container),
    Safetensors,
}

impl PolicyFile {
    pub fn open(path: &Path) -> Result<PolicyFile, TrainError> {
        let path = policy_file(path);
        let bytes = std::fs::read(&path).map_err(|e| FileError::Io {
            path: path.clone(),
            message: e.to_string(),
        })?;
        if !bytes.starts_with(super::container::MAGIC) && super::safetensors::looks_like(&bytes) {
            return PolicyFile::from_safetensors(&bytes, path);
        }
        PolicyFile::from_container(Container::from_bytes(&bytes, &path)?, path)
    }

    /// A SafeTensors file whose metadata holds the training config and the game (TOML):
    /// the header is made from them (kind `safetensors`; seed, update and env steps where
    /// the metadata has them, else 0).
    fn from_safetensors(bytes: &[u8], path: PathBuf) -> Result<PolicyFile, TrainError> {
        use super::safetensors::*;
        let meta = read_metadata(bytes, &path)?;
        let text = |key: &str| {
            meta.get(key).cloned().ok_or_else(|| FileError::Missing {
                path: path.clone(),
                section: format!("metadata {key}"),
            })
        };
        let number = |key: &str| -> Result<u64, TrainError> {
            match meta.get(key) {
                None => Ok(0),
                Some(v) => v.parse().map_err(|_| {
                    FileError::Corrupt {
                        path: path.clone(),
                        what: format!("metadata {key} = {v:?} is not a whole number"),
                    }
                    .into()
                }),
            }
        };
        let header = FileHeader {
            kind: "safetensors".into(),
            train_config: text(META_TRAIN_CONFIG)?,
            game: text(META_GAME)?,
            seed: number(META_SEED)?,
            update: number(META_UPDATE)?,
            env_steps: number(META_ENV_STEPS)?,
            averaged: Vec::new(),
        };
        PolicyFile::from_header(header, Weights::Safetensors, path)
    }

    /// A policy file held in memory (the pretrained agents built into the library);
    /// `name` stands for its path in messages and tables.
    pub fn from_bytes(bytes: &[u8], name: &str) -> Result<PolicyFile, TrainError> {
        let path = PathBuf::from(name);
        let file = Container::from_bytes(bytes, &path)?;
        PolicyFile::from_container(file, path)
    }

    fn from_container(file: Container, path: PathBuf) -> Result<PolicyFile, TrainError> {
        let header = read_header(&file, &path)?;
        PolicyFile::from_header(header, Weights::Container(file), path)
    }

    fn from_header(
        header: FileHeader,
        weights: Weights,
        path: PathBuf,
    ) -> Result<PolicyFile, TrainError> {
        let shown = path.display().to_string();
        let config = TrainConfig::from_toml_str(&header.train_config, &shown)?;
        let game = Config::from_toml_str(&header.game, &shown).map_err(|source| {
            TrainError::GameConfig {
                path: shown,
                source,
            }
        })?;
        Ok(PolicyFile {
            path,
            weights,
            header,
            config,
            game,
        })
    }

    /// The network's weights loaded into `model`, which must be the same network.
    pub fn load_into<M: burn::module::Module>(&self, model: M) -> Result<M, TrainError> {
        match &self.weights {
            Weights::Container(file) => {
                let bytes = file.section(&self.path, "model")?;
                load_model(model, bytes, &self.path.display().to_string())
            }
            Weights::Safetensors => super::safetensors::read_into(model, &self.path),
        }
    }
}

/// The error for a network trained on `trained` seated in `game`, if they differ.
pub fn check_game(path: &Path, trained: &Config, game: &Config) -> Result<(), TrainError> {
    if trained == game {
        return Ok(());
    }
    Err(TrainError::WrongGame {
        path: path.display().to_string(),
        trained: trained.to_string(),
        game: game.to_string(),
    })
}

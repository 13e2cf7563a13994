//! Checkpoints and policy files of a run: the header, the network, the optimiser and the
//! loop state, and continuing a run exactly from a checkpoint.

use super::{optimizer, Trainer};
use crate::artifact::{
    check_game, load_model, read_header, record_bytes, Container, FileHeader, PolicyFile,
};
use crate::config::TrainConfig;
use crate::device::default_device;
use crate::error::TrainError;
use crate::network::{Encoder, Recurrent};
use crate::obl::{SavedBelief, BELIEF_CURVE_SECTION, BELIEF_SECTION};
use crate::tensor::parameters;
use burn::module::Module;
use burn::prelude::*;
use burn::tensor::Bytes;
use serde::{Deserialize, Serialize};
use std::path::Path;
use yokai_engine::Config;

/// The loop state a checkpoint saves beside the network and optimiser (the file's form: the
/// trainer keeps these in its actor and, with OBL ≥ 2, its previous level). Everything else
/// is derived: environment steps from the update count, and where episodes start from the
/// games.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct LoopState {
    pub update: u64,
    /// GRU state per row `[rows × H]`.
    pub hidden: Vec<f32>,
    /// Per game: the acting seats' actions so far in its current episode.
    pub history: Vec<Vec<u32>>,
    /// Per game: its episode index.
    #[serde(default)]
    pub episodes: Vec<u64>,
    /// OBL levels ≥ 2: the belief model's memory per row `[rows × H_belief]` (empty
    /// otherwise).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub belief_hidden: Vec<f32>,
}

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    fn header(&self, kind: &str) -> FileHeader {
        FileHeader {
            kind: kind.into(),
            train_config: self.config.to_toml(),
            game: self.game.to_toml(),
            seed: self.seed,
            update: self.update,
            env_steps: self.env_steps(),
            averaged: Vec::new(),
        }
    }

    /// Every parameter value of the network, in module order (records also hold random
    /// parameter ids, so compare these, not record bytes).
    pub fn parameters(&self) -> Vec<f32> {
        parameters(&self.model)
    }

    /// The network's parameters in burn's record format.
    pub fn model_bytes(&self) -> Vec<u8> {
        record_bytes(self.model.clone())
    }

    /// The policy file's content: header and network, no optimiser or loop state.
    pub fn policy(&self) -> Container {
        Container {
            header: serde_json::to_string_pretty(&self.header("policy")).expect("json"),
            sections: vec![("model".into(), self.model_bytes())],
        }
    }

    /// Everything needed to continue the run exactly: with OBL ≥ 2 also the trained belief
    /// model and its curve, so that a resume need not train it again.
    pub fn checkpoint(&self) -> Container {
        let optim = self
            .optim
            .into_bytes()
            .expect("an in-memory optimiser state always serialises")
            .to_vec();
        let belief = self.previous.iter().flat_map(|p| p.belief_sections());
        Container {
            header: serde_json::to_string_pretty(&self.header("checkpoint")).expect("json"),
            sections: [
                ("model".into(), self.model_bytes()),
                ("optimizer".into(), optim),
                (
                    "state".into(),
                    serde_json::to_vec(&LoopState {
                        update: self.update,
                        hidden: self.actor.memory.clone(),
                        history: self.actor.history.clone(),
                        episodes: self.actor.episodes(),
                        belief_hidden: (self.previous.as_ref())
                            .map_or(Vec::new(), |p| p.memory.clone()),
                    })
                    .expect("loop state serialises"),
                ),
            ]
            .into_iter()
            .chain(belief)
            .collect(),
        }
    }

    /// Continue a run from a checkpoint written by [`Trainer::checkpoint`], on the CPU.
    pub fn resume(path: &Path) -> Result<Trainer<E, M>, TrainError> {
        Trainer::resume_on(path, default_device())
    }

    /// Continue a run from a checkpoint on `infer_device` (any backend: checkpoints hold
    /// plain f32 values, so a run can move between the CPU and a GPU). In a build with a GPU
    /// feature, make the device burn's default first ([`crate::Backend::make_burn_default`]):
    /// burn loads the optimiser state on its default device, which is otherwise the GPU.
    pub fn resume_on(path: &Path, infer_device: Device) -> Result<Trainer<E, M>, TrainError> {
        let file = Container::read(path)?;
        let header = read_header(&file, path)?;
        if header.kind != "checkpoint" {
            return Err(TrainError::Mismatch {
                path: path.display().to_string(),
                message: format!(
                    "is a {} file, not a checkpoint (only checkpoints keep the optimiser state)",
                    header.kind
                ),
            });
        }
        let config = TrainConfig::from_toml_str(&header.train_config, &path.display().to_string())?;
        if !E::KINDS.contains(&config.network.encoder()) || M::KIND != config.network.memory {
            return Err(TrainError::Mismatch {
                path: path.display().to_string(),
                message: format!(
                    "holds a network with the {:?} encoder and {:?} memory",
                    config.network.encoder(),
                    config.network.memory
                ),
            });
        }
        // Checkpoints from before 23b00ab (2026-12-02) keep no belief: it is trained again.
        let saved = match file.get(BELIEF_SECTION) {
            Some(model) => Some(SavedBelief {
                path,
                model,
                curve: file.section(path, BELIEF_CURVE_SECTION)?,
            }),
            None => None,
        };
        let mut trainer = Trainer::<E, M>::fresh(config, header.seed, infer_device, saved)?;
        let shown = path.display().to_string();
        trainer.model = load_model(trainer.model, file.section(path, "model")?, &shown)?;
        let optim = file.section(path, "optimizer")?.to_vec();
        trainer.optim = optimizer(&trainer.config)
            .from_bytes(Bytes::from_bytes_vec(optim))
            .map_err(|e| TrainError::Record {
                path: shown.clone(),
                what: "optimiser",
                source: e.into(),
            })?;
        let state: LoopState =
            serde_json::from_slice(file.section(path, "state")?).map_err(|source| {
                TrainError::Json {
                    path: shown.clone(),
                    what: "loop state",
                    source,
                }
            })?;
        let n = trainer.config.ppo.num_envs;
        let belief_memory = trainer.previous.as_mut().map(|p| &mut p.memory);
        if state.hidden.len() != trainer.actor.memory.len()
            || state.belief_hidden.len() != belief_memory.as_ref().map_or(0, |m| m.len())
            || state.episodes.len() != n
            || state.history.len() != n
        {
            return Err(TrainError::Mismatch {
                path: shown,
                message: "loop state sizes do not match its config".into(),
            });
        }
        if let Some(memory) = belief_memory {
            *memory = state.belief_hidden;
        }
        trainer.update = state.update;
        let steps = state.update * trainer.config.ppo.rollout_steps as u64;
        (trainer.actor).restore(steps, &state.episodes, state.history, state.hidden)?;
        Ok(trainer)
    }
}

/// `model` with the parameters of the policy file, checkpoint or run directory `path`
/// (`run.init_from`), which must hold the same network for the same game.
pub(super) fn initial_weights<M: Module>(
    model: M,
    path: &Path,
    config: &TrainConfig,
    game: &Config,
) -> Result<M, TrainError> {
    let opened = PolicyFile::open(path)?;
    let from = std::path::PathBuf::from(format!("run.init_from {}", opened.path.display()));
    if opened.config.network != config.network {
        return Err(TrainError::Mismatch {
            path: from.display().to_string(),
            message: format!(
                "holds a different network ({:?}) from this config's ({:?})",
                opened.config.network, config.network
            ),
        });
    }
    check_game(&from, &opened.game, game)?;
    opened.load_into(model)
}

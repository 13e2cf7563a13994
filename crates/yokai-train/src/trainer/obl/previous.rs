//! OBL levels ≥ 2: the previous level, whose self-play the belief model is trained on and
//! which plays the partners inside the fictitious continuations unless `obl.partner` is
//! `learner` (`partners`).
//!
//! **The belief** conditions on the acting seat's real history: every row's belief memory
//! steps on the row's real observation at every rollout step (`step_belief_memory`) and is
//! saved in checkpoints, so a resume continues it exactly.

use crate::config::TrainConfig;
use crate::error::TrainError;
use crate::obl::learn::{BeliefStats, BeliefTrainConfig, BeliefTrainer, LevelBelow};
use crate::obl::model::BeliefModel;
use crate::TrainedPolicy;
use burn::prelude::*;
use yokai_engine::{derive_seed, Config};

/// Updates at the end of the belief's training whose figures are averaged for the report.
const REPORTED_UPDATES: usize = 20;

/// The level below a level ≥ 2 run: its policy and the belief trained on its games.
pub(crate) struct PreviousLevel {
    pub policy: TrainedPolicy,
    pub belief: BeliefModel,
    /// Every training update's figures, in order (each measured on its rollout before
    /// learning from it): the belief's learning curve.
    pub belief_curve: Vec<BeliefStats>,
}

impl PreviousLevel {
    /// Load `obl.previous` (seed N's `seed-N` inside it where there is one) and train the
    /// belief on its self-play, deterministically in `seed`.
    pub fn load(
        config: &TrainConfig,
        game: &Config,
        seed: u64,
        device: &Device,
    ) -> Result<PreviousLevel, TrainError> {
        let given = config
            .obl
            .previous
            .as_ref()
            .expect("validated: levels ≥ 2 name their previous level");
        let policy = TrainedPolicy::load(&crate::artifact::names::seed_path(given, seed))?;
        policy.check_game(game)?;
        let belief_config =
            BeliefTrainConfig::small(config.obl.belief_hidden, config.obl.belief_updates);
        let mut trainer = BeliefTrainer::new(
            *game,
            belief_config,
            LevelBelow::Network(Box::new(policy.clone())),
            derive_seed(seed, 0xB0B),
            device.clone(),
        )?;
        let belief_curve = (0..config.obl.belief_updates)
            .map(|_| trainer.update())
            .collect();
        Ok(PreviousLevel {
            policy,
            belief: trainer.into_model(),
            belief_curve,
        })
    }

    /// The figures reported: slot-weighted means over the last `REPORTED_UPDATES` updates
    /// of the belief's training (one rollout of 16 games is too few to compare a belief
    /// with its baseline).
    pub fn belief_stats(&self) -> BeliefStats {
        let tail = self.belief_curve.len().saturating_sub(REPORTED_UPDATES);
        BeliefStats::mean(self.belief_curve[tail..].iter().copied())
    }
}

//! OBL levels ≥ 2: the previous level as the partner inside the fictitious continuations,
//! and the belief model trained on its self-play.
//!
//! **The partner's memory.** The previous level is a recurrent network whose memory read
//! the real colours of the cards its seat observed. In a fictitious world those colours are
//! different, so its real memory would carry facts of the real world into the fictitious
//! one. Instead the partner's memory is rebuilt in the fictitious world: the episode so far
//! is replayed from its deal, recoloured (the same actions are legal, whatever the
//! colours), and the partner's network reads its observation of every state. The reference
//! implementation (Hanabi) can reuse the real memory only because its LSTM reads public
//! features only. The replay costs one batched network step per step of the episode so
//! far; the partner's memories of all games are replayed together.
//!
//! **The belief** conditions on the acting seat's real history: every row's belief memory
//! steps on the row's real observation at every rollout step (`step_belief_memory`) and is
//! saved in checkpoints, so a resume continues it exactly.

use crate::config::TrainConfig;
use crate::distribution::sample_legal;
use crate::obl::continuation::random_legal;
use crate::obl::learn::{BeliefStats, BeliefTrainConfig, BeliefTrainer, LevelBelow};
use crate::obl::model::BeliefModel;
use crate::trainer::TrainError;
use crate::TrainedPolicy;
use burn::prelude::*;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{derive_seed, Config, Game, Seat};

/// Updates at the end of the belief's training whose figures are averaged for the report.
const REPORTED_UPDATES: u64 = 20;

/// The level below a level ≥ 2 run: its policy and the belief trained on its games.
pub(crate) struct PreviousLevel {
    pub policy: TrainedPolicy,
    pub belief: BeliefModel,
    /// The belief's figures over its last `REPORTED_UPDATES` training updates (each
    /// measured on its rollout before learning from it).
    pub belief_stats: BeliefStats,
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
        let policy = TrainedPolicy::load(&crate::run::seed_path(given, seed))?;
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
        // The figures reported: slot-weighted means over the last updates (one rollout of
        // 16 games is too few to compare a belief with its baseline).
        let updates = config.obl.belief_updates;
        let tail = updates.min(REPORTED_UPDATES);
        let stats: Vec<BeliefStats> = (0..updates).map(|_| trainer.update()).collect();
        let belief_stats = BeliefStats::mean(stats[(updates - tail) as usize..].iter().copied());
        Ok(PreviousLevel {
            policy,
            belief: trainer.into_model(),
            belief_stats,
        })
    }
}

/// Who plays the partners' turns in the fictitious continuations of one rollout step.
pub(super) enum Partners<'a> {
    /// Level 0: uniformly random legal play.
    Random(&'a mut ChaCha8Rng),
    /// The previous level: per continuation, its partner seats and their memories (rebuilt
    /// in the fictitious world, `[seats × H]`). Every partner seat's memory reads each
    /// state; the acting one samples from its logits.
    Previous {
        policy: &'a TrainedPolicy,
        seats: Vec<Vec<Seat>>,
        states: Vec<Vec<f32>>,
        rng: &'a mut ChaCha8Rng,
    },
}

impl Partners<'_> {
    /// The acting seat's action index in each of `games`, the fictitious games of the
    /// continuations `which` (a partner of the seat each continuation is for). The previous
    /// level's network steps every partner seat of them in one batch.
    pub fn act(&mut self, which: &[usize], games: &[&Game]) -> Vec<usize> {
        match self {
            Partners::Random(rng) => games.iter().map(|g| random_legal(g, rng)).collect(),
            Partners::Previous {
                policy,
                seats,
                states,
                rng,
            } => {
                let rows: Vec<(&Game, Seat)> = which
                    .iter()
                    .zip(games)
                    .flat_map(|(&k, &g)| seats[k].iter().map(move |&s| (g, s)))
                    .collect();
                let memories = which
                    .iter()
                    .flat_map(|&k| std::mem::take(&mut states[k]))
                    .collect();
                let stepped = policy.step_seats(&rows, memories, vec![1.0; rows.len()]);
                let h = policy.hidden_size();
                let mut at = 0;
                let mut actions = Vec::with_capacity(games.len());
                for (&k, &game) in which.iter().zip(games) {
                    let m = seats[k].len();
                    states[k] = stepped.states[at * h..(at + m) * h].to_vec();
                    let j = seats[k]
                        .iter()
                        .position(|&s| s == game.current_seat())
                        .expect("the continuation asks only for partners' actions");
                    let logits = stepped.logits(at + j).expect("the acting seat");
                    actions.push(sample_legal(game, logits, rng));
                    at += m;
                }
                actions
            }
        }
    }
}

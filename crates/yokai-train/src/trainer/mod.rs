//! Recurrent PPO over batched games: IPPO, high-entropy IPPO and Other-Play are presets of
//! this one trainer (docs/spec/training.md).
//!
//! Every seat of every game is one row of the batch, with shared parameters; non-acting
//! seats take NOOP (their only legal action) but still step their memory, so they learn
//! from what partners do. A row's sequence runs across episode ends; the GRU state is
//! zeroed where an episode starts. Minibatches are sets of whole rows, so BPTT covers the
//! full rollout from the state stored at its start.
//!
//! Determinism: weights, action draws, minibatch order and Other-Play symmetries all come
//! from the run seed through counter-based derivations (update, env, episode, seat), so a
//! checkpoint needs no generator state, and a resumed run equals an uninterrupted one.
//!
//! An update reads top to bottom in named phases ([`Trainer::update`]): the schedules, the
//! rollout (the `crate::actor::Actor` plays every game with the network, into a
//! [`rollout::Rollout`]), the value targets (GAE, or Off-Belief Learning's), and the
//! learner (`learner`: PPO epochs over the rollout, the loss and the optimiser step). The
//! add-ons a config switches on (END terms, belief loss, normalised entropy, clustering
//! shaping) are units in `addons`, each owning its rollout column, its gathering and its
//! loss term; `checkpoint` writes files and resumes exactly.

mod addons;
mod checkpoint;
mod choice_terms;
mod learner;
mod minibatch;
#[cfg(test)]
mod obl_tests;
mod rollout;
mod row_groups;

use crate::actor::Actor;
use crate::config::TrainConfig;
use crate::device::default_device;
use crate::error::TrainError;
use crate::network::{ActorCritic, Encoder, GruCell, Recurrent};
use crate::obl::{PreviousLevel, SavedBelief};
use addons::AddOns;
use burn::optim::{AdamConfig, ModuleOptimizer};
use burn::prelude::*;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rollout::Rollout;
use serde::{Deserialize, Serialize};
use yokai_engine::{derive_seed, Config, EpisodeRecord, Metrics, Symmetry};
use yokai_vec::VecEnv;

/// One update's figures, for the metrics log and the progress bar.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct UpdateStats {
    pub update: u64,
    pub env_steps: u64,
    /// Environment steps per second of this update, end to end (rollout and learning).
    pub sps: f64,
    /// Metrics of the games that ended during this update (`None` if none did).
    pub games: Option<Metrics>,
    pub policy_loss: f64,
    pub value_loss: f64,
    /// Mean entropy of the acting seats' policies during the rollout.
    pub entropy: f64,
    pub lr: f64,
    pub shaping: f64,
    /// Mean |log π_new − log π_old| of the first minibatch, before any gradient step: the
    /// learner replays the rollout's sequences, so this is 0 up to float rounding. A larger
    /// value means the recurrent state or the batch layout differs between acting and
    /// learning.
    pub replay_error: f64,
    /// PPO's health, as CleanRL and JaxMARL log it (means over the update's minibatches):
    /// the estimated KL divergence of the learner's policy from the rollout's, measured on
    /// each minibatch before its step (mean of r − 1 − log r over the choosing rows, r the
    /// probability ratio); the share of those rows whose ratio PPO clips; and the global L2
    /// norm of the gradients before `ppo.max_grad_norm` clips them.
    #[serde(default)]
    pub approx_kl: f64,
    #[serde(default)]
    pub clip_fraction: f64,
    #[serde(default)]
    pub grad_norm: f64,
    /// How much of the value targets' variance the critic predicted at the rollout
    /// (1 − Var(return − V) / Var(return), over the rows that learn their value); `None`
    /// when the targets did not vary.
    #[serde(default)]
    pub explained_variance: Option<f64>,
    /// Net change in clustered colours over the rollout's non-final steps, summed over
    /// games: what `ppo.cluster_shaping` paid before its weight (0 when it is off).
    #[serde(default)]
    pub cluster_reward: f64,
    /// With `ppo.belief_gain`, while its weight is above 0: what it paid over the rollout's
    /// non-final steps, summed over games, in nats, before the weight (what the team came to
    /// know of the colours): the net change of the games' potentials, or with
    /// `belief_gain_seats = "waiting"` what the seats came to know between their turns.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub belief_gain: Option<f64>,
    /// The entropy bonus of this update, where it follows a schedule (`ppo.entropy_final`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub entropy_coef: Option<f64>,
    /// With `ppo.belief_aux`: the colour cross-entropy (nats per card) and the share of
    /// cards whose most likely predicted colour is the true one, at the choosing states.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub belief_loss: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub belief_accuracy: Option<f64>,
    /// OBL levels ≥ 2: the belief model's cross-entropy of the true colours (nats per
    /// unseen card) over its last 20 training updates, and that of the first-hand baseline (the
    /// seat's own colours and the counts, which is exact for random play) on the same
    /// cards: below it, the belief reads the previous level's conventions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obl_belief_cross_entropy: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obl_belief_baseline: Option<f64>,
    /// Seconds spent acting (rollout) and learning (epochs) in this update.
    pub rollout_seconds: f64,
    pub learn_seconds: f64,
}

/// A training run of one seed, in memory: encoder `E`, memory `M` (a GRU unless given).
pub struct Trainer<E: Encoder, M: Recurrent = GruCell> {
    config: TrainConfig,
    game: Config,
    seed: u64,
    device: Device,
    infer_device: Device,
    model: ActorCritic<E, M>,
    optim: ModuleOptimizer,
    /// Updates done.
    update: u64,
    /// The games, as the seats see and play them, and every seat's memory.
    actor: Actor,
    addons: AddOns,
    /// Off-Belief Learning levels ≥ 2: the level below and the belief trained on it.
    previous: Option<PreviousLevel>,
    /// The last update's rollout, whose observation and mask buffers the next one
    /// writes over ([`Rollout::reuse`]).
    spare: Option<Rollout>,
}

fn optimizer(config: &TrainConfig) -> ModuleOptimizer {
    AdamConfig::new()
        .with_epsilon(config.ppo.adam_eps as f32)
        .init()
}

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    /// A new run of `config` with `seed`, from freshly initialised weights, on the CPU.
    pub fn new(config: TrainConfig, seed: u64) -> Result<Trainer<E, M>, TrainError> {
        Trainer::new_on(config, seed, default_device())
    }

    /// A new run of `config` with `seed` whose network lives on `infer_device` (a device
    /// from [`crate::Backend::device`]; training uses its autodiff twin). An OBL level
    /// trains with the config for its level: the warm rate and shaping of a level ≥ 2 that
    /// starts from trained weights, no symmetries below `obl.symmetries_from_level`
    /// ([`TrainConfig::for_its_level`]).
    pub fn new_on(
        config: TrainConfig,
        seed: u64,
        infer_device: Device,
    ) -> Result<Trainer<E, M>, TrainError> {
        let mut trainer = Trainer::fresh(config.for_its_level(), seed, infer_device, None)?;
        if let Some(path) = &trainer.config.run.init_from {
            let model = trainer.model.clone();
            trainer.model =
                checkpoint::initial_weights(model, path, &trainer.config, &trainer.game)?;
        }
        Ok(trainer)
    }

    /// A run of `config` with freshly initialised weights (`run.init_from` not applied:
    /// a resumed run takes its weights from its checkpoint), and for an OBL level ≥ 2 the
    /// belief `saved` in its checkpoint, else one trained now.
    fn fresh(
        config: TrainConfig,
        seed: u64,
        infer_device: Device,
        saved: Option<SavedBelief<'_>>,
    ) -> Result<Trainer<E, M>, TrainError> {
        config.validate("config")?;
        let game = config.game_config()?;
        let device = infer_device.clone().autodiff();
        let model = ActorCritic::<E, M>::new(&config, &game, derive_seed(seed, 0xC0FFEE), &device);
        let actor = Actor::for_run(&config, seed, E::encoding(), model.hidden_size())?;
        let previous = if config.obl.level >= 2 {
            Some(PreviousLevel::load(
                &config,
                &game,
                seed,
                actor.rows(),
                &infer_device,
                saved,
            )?)
        } else {
            None
        };
        Ok(Trainer {
            optim: optimizer(&config),
            addons: AddOns::from_config(&config.ppo),
            config,
            game,
            seed,
            device,
            infer_device,
            model,
            update: 0,
            actor,
            previous,
            spare: None,
        })
    }

    pub fn config(&self) -> &TrainConfig {
        &self.config
    }
    pub fn seed(&self) -> u64 {
        self.seed
    }
    /// OBL levels ≥ 2: the belief model's figures at each of its training updates.
    pub fn belief_curve(&self) -> Option<&[crate::obl::learn::BeliefStats]> {
        self.previous.as_ref().map(|p| &p.belief_curve[..])
    }

    pub fn update_count(&self) -> u64 {
        self.update
    }
    pub fn env_steps(&self) -> u64 {
        self.update * (self.config.ppo.num_envs * self.config.ppo.rollout_steps) as u64
    }
    /// Change the run's budget (e.g. to extend a resumed run). Annealing follows the new
    /// total from the next update on.
    pub fn set_total_steps(&mut self, total_steps: u64) {
        self.config.ppo.total_steps = total_steps;
        let ramp = self.config.symmetry_ramp_steps();
        self.actor.set_symmetry_ramp(ramp);
    }
    pub fn is_done(&self) -> bool {
        self.update >= self.config.updates()
    }
    pub fn model(&self) -> &ActorCritic<E, M> {
        &self.model
    }
    /// The batched games (true frame, before any symmetry).
    pub fn env(&self) -> &VecEnv<f32> {
        self.actor.env()
    }
    /// The symmetry row `row` (game `row / P`, seat `row % P`) sees its game through.
    pub fn row_symmetry(&self, row: usize) -> Symmetry {
        self.actor.symmetry(row)
    }
    /// Every row's observation `[rows × L]` and legal mask `[rows × N_a]` as the network
    /// receives them (Other-Play symmetries applied).
    pub fn views(&self) -> (Vec<f32>, Vec<f32>) {
        let a = &self.actor;
        let mut obs = vec![0f32; a.rows() * a.obs_len()];
        let mut masks = vec![0f32; a.rows() * a.n_actions()];
        a.view(&mut obs, &mut masks);
        (obs, masks)
    }
    /// The true colour of every card of `row`'s game, named as the row's seat sees colours
    /// (its symmetry's relabelling applied): the target of `ppo.belief_aux`.
    pub fn view_truth(&self, row: usize, out: &mut [u8]) {
        self.actor.view_truth(row, out)
    }
    /// The last game of env 0 that finished, as played in training (deal and actions).
    pub fn last_finished_game(&self) -> Option<EpisodeRecord> {
        self.actor.last_finished_game()
    }
    /// The games as the network plays them (for tests that replay an episode).
    #[cfg(test)]
    pub(crate) fn actor(&self) -> &Actor {
        &self.actor
    }
    /// Map a row's chosen action from its seat's view back to the true game.
    pub fn to_true_action(&self, row: usize, view_action: usize) -> usize {
        self.actor.to_true_action(row, view_action)
    }

    /// The share of the run done before this update, in [0, 1].
    fn progress(&self) -> f64 {
        self.update as f64 / self.config.updates() as f64
    }

    /// The learning rate, the shaping weight and the entropy bonus at this point of the
    /// run: the rate falls linearly to 0 with `anneal_lr` (after holding over the first
    /// `lr_hold`), the shaping over the first
    /// `shaping_fraction`, the bonus from `entropy_coef` to `entropy_final` when given.
    fn schedules(&self) -> (f64, f64, f32) {
        let c = &self.config.ppo;
        let progress = self.progress();
        let lr = if c.anneal_lr {
            c.lr * ((1.0 - progress) / (1.0 - c.lr_hold as f64)).min(1.0)
        } else {
            c.lr
        };
        let shaping = c.shaping as f64 * (1.0 - progress / c.shaping_fraction as f64).max(0.0);
        let entropy = match c.entropy_final {
            Some(last) => {
                (c.entropy_coef as f64 * (1.0 - progress) + last as f64 * progress) as f32
            }
            None => c.entropy_coef,
        };
        (lr, shaping, entropy)
    }

    /// One PPO update: a rollout of `rollout_steps` steps in every game, then `epochs`
    /// passes over it in `minibatches` sets of whole sequences.
    pub fn update(&mut self) -> Result<UpdateStats, TrainError> {
        let start = std::time::Instant::now();
        // 1. Schedules.
        let (lr, shaping, entropy_coef) = self.schedules();
        // One generator per update serves the action draws, then the minibatch order.
        let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(self.seed, self.update));
        // 2. Rollout, with its value targets (GAE, or OBL's).
        let rollout = self.collect(shaping, &mut rng)?;
        let rollout_seconds = start.elapsed().as_secs_f64();
        // 3. Learning: PPO epochs over the rollout.
        let losses = self.learn_epochs(&rollout, lr, entropy_coef, &mut rng);
        self.update += 1;
        // 4. Report.
        let secs = start.elapsed().as_secs_f64();
        let c = &self.config.ppo;
        let belief = self.previous.as_ref().map(|p| p.belief_stats());
        let stats = UpdateStats {
            update: self.update,
            env_steps: self.env_steps(),
            sps: (c.num_envs * c.rollout_steps) as f64 / secs.max(1e-9),
            games: rollout.games.metrics(),
            policy_loss: losses.policy,
            value_loss: losses.value,
            entropy: rollout.entropy,
            lr,
            shaping,
            replay_error: losses.replay_error,
            approx_kl: losses.approx_kl,
            clip_fraction: losses.clip_fraction,
            grad_norm: losses.grad_norm,
            explained_variance: learner::explained_variance(
                &rollout.values,
                &rollout.returns,
                rollout.value_weight.as_deref().unwrap_or(&[]),
            ),
            cluster_reward: rollout.cluster_reward,
            belief_gain: rollout.belief_gain,
            entropy_coef: c.entropy_final.map(|_| entropy_coef as f64),
            belief_loss: losses.belief.map(|b| b.0),
            belief_accuracy: losses.belief.map(|b| b.1),
            obl_belief_cross_entropy: belief.map(|b| b.cross_entropy),
            obl_belief_baseline: belief.map(|b| b.uniform_cross_entropy),
            rollout_seconds,
            learn_seconds: secs - rollout_seconds,
        };
        self.spare = Some(rollout);
        Ok(stats)
    }
}

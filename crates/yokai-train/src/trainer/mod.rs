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
//! The jobs live in one module each: `rollout` (acting and advantages), `ppo` (the PPO
//! epochs and loss), `checkpoint` (files and exact resume); this module holds the run's
//! state and the update that joins them.

mod checkpoint;
mod minibatch;
mod obl;
mod ppo;
mod rollout;

use crate::config::TrainConfig;
use crate::device::default_device;
use crate::error::TrainError;
use crate::network::{ActorCritic, Encoder, GruCell, Recurrent};
use burn::optim::{AdamConfig, ModuleOptimizer};
use burn::prelude::*;
use checkpoint::LoopState;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use yokai_engine::{derive_seed, Card, Config, EpisodeRecord, Metrics, RecordedGame, Symmetry};
use yokai_vec::{Encoding, VecEnv, VecEnvOptions};

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
    env: VecEnv<f32>,
    state: LoopState,
    /// The symmetries a seat may draw (identity only without Other-Play).
    symmetries: Vec<Symmetry>,
    /// Per row: the seat's symmetry this episode and its inverse.
    row_sym: Vec<(Symmetry, Symmetry)>,
    rows: usize,
    obs_len: usize,
    n_actions: usize,
    /// The last finished game of env 0 (deal seed, actions), to save as a replay.
    last_game: Option<(u64, Vec<u32>)>,
    /// Off-Belief Learning levels ≥ 2: the level below and the belief trained on it.
    previous: Option<obl::PreviousLevel>,
}

/// The seed of a run's batch of games.
fn env_seed(run_seed: u64) -> u64 {
    derive_seed(run_seed, 0xE5)
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
    /// from [`crate::Backend::device`]; training uses its autodiff twin).
    pub fn new_on(
        config: TrainConfig,
        seed: u64,
        infer_device: Device,
    ) -> Result<Trainer<E, M>, TrainError> {
        let mut trainer = Trainer::fresh(config, seed, infer_device)?;
        if let Some(path) = &trainer.config.run.init_from {
            let model = trainer.model.clone();
            trainer.model =
                checkpoint::initial_weights(model, path, &trainer.config, &trainer.game)?;
        }
        Ok(trainer)
    }

    /// A run of `config` with freshly initialised weights (`run.init_from` not applied:
    /// a resumed run takes its weights from its checkpoint).
    fn fresh(
        config: TrainConfig,
        seed: u64,
        infer_device: Device,
    ) -> Result<Trainer<E, M>, TrainError> {
        config.validate("config")?;
        let game = config.game_config()?;
        let device = infer_device.clone().autodiff();
        let model = ActorCritic::<E, M>::new(&config, &game, derive_seed(seed, 0xC0FFEE), &device);
        let n = config.ppo.num_envs;
        let p = game.players();
        let mut options = VecEnvOptions::new(n, env_seed(seed));
        options.encoding = E::encoding();
        options.threads = (config.run.threads > 0).then_some(config.run.threads);
        let env = VecEnv::<f32>::new(game, options)?;
        let obs_len: usize = E::encoding().shape(&game).iter().product();
        let s = config.algorithm.symmetries;
        let symmetries = Symmetry::enumerate(&game, s.colours(), s.rotations(), false);
        let hidden = model.hidden_size();
        let optim = optimizer(&config);
        let previous = if config.obl.level >= 2 {
            Some(obl::PreviousLevel::load(
                &config,
                &game,
                seed,
                &infer_device,
            )?)
        } else {
            None
        };
        let mut trainer = Trainer {
            state: LoopState {
                update: 0,
                hidden: vec![0.0; n * p * hidden],
                history: vec![Vec::new(); n],
                episodes: Vec::new(),
                belief_hidden: previous
                    .as_ref()
                    .map_or(Vec::new(), |b| vec![0.0; n * p * b.belief.hidden_size()]),
            },
            row_sym: vec![(Symmetry::identity(&game), Symmetry::identity(&game)); n * p],
            config,
            game,
            seed,
            device,
            infer_device,
            model,
            optim,
            env,
            symmetries,
            rows: n * p,
            obs_len,
            n_actions: game.num_actions(),
            last_game: None,
            previous,
        };
        for i in 0..n {
            trainer.draw_symmetries(i);
        }
        Ok(trainer)
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
        self.state.update
    }
    pub fn env_steps(&self) -> u64 {
        self.state.update * (self.config.ppo.num_envs * self.config.ppo.rollout_steps) as u64
    }
    /// Change the run's budget (e.g. to extend a resumed run). Annealing follows the new
    /// total from the next update on.
    pub fn set_total_steps(&mut self, total_steps: u64) {
        self.config.ppo.total_steps = total_steps;
    }
    pub fn is_done(&self) -> bool {
        self.state.update >= self.config.updates()
    }
    pub fn model(&self) -> &ActorCritic<E, M> {
        &self.model
    }
    /// The batched games (true frame, before any symmetry).
    pub fn env(&self) -> &VecEnv<f32> {
        &self.env
    }
    /// The symmetry row `row` (game `row / P`, seat `row % P`) sees its game through.
    pub fn row_symmetry(&self, row: usize) -> Symmetry {
        self.row_sym[row].0
    }
    /// Every row's observation `[rows × L]` and legal mask `[rows × N_a]` as the network
    /// receives them (Other-Play symmetries applied).
    pub fn views(&self) -> (Vec<f32>, Vec<f32>) {
        let mut obs = vec![0f32; self.rows * self.obs_len];
        let mut masks = vec![0f32; self.rows * self.n_actions];
        self.view(&mut obs, &mut masks);
        (obs, masks)
    }

    /// Other-Play: each seat of game `env` draws its own symmetry for the game's current
    /// episode, a function of (seed, env, episode, seat).
    fn draw_symmetries(&mut self, env: usize) {
        let p = self.game.players();
        let k = self.symmetries.len() as u64;
        let episode_stream = derive_seed(
            derive_seed(derive_seed(self.seed, 0x0B), env as u64),
            self.env.episodes(env),
        );
        for s in 0..p {
            let pick = derive_seed(episode_stream, s as u64) % k;
            let sym = self.symmetries[pick as usize];
            self.row_sym[env * p + s] = (sym, sym.inverse());
        }
    }

    /// The true colour of every card of `row`'s game, named as the row's seat sees colours
    /// (its symmetry's relabelling applied): the target of `ppo.belief_aux`.
    pub fn view_truth(&self, row: usize, out: &mut [u8]) {
        let game = self.env.game(row / self.game.players());
        let sym = self.row_sym[row].0;
        for (k, colour) in out.iter_mut().enumerate() {
            *colour = sym.map_colour(game.colour_of(Card(k as u8))).0;
        }
    }

    /// Every row's observation and legal mask as its seat sees them (its symmetry applied).
    fn view(&self, obs: &mut [f32], masks: &mut [f32]) {
        let (l, na) = (self.obs_len, self.n_actions);
        let src_obs = self.env.observations();
        let src_masks = self.env.legal_masks();
        let mut mask_f = vec![0f32; na];
        for r in 0..self.rows {
            let (sym, _) = &self.row_sym[r];
            let o_in = &src_obs[r * l..][..l];
            let o_out = &mut obs[r * l..][..l];
            for (m, &b) in mask_f.iter_mut().zip(&src_masks[r * na..][..na]) {
                *m = b as f32;
            }
            let m_out = &mut masks[r * na..][..na];
            if sym.is_identity() {
                o_out.copy_from_slice(o_in);
                m_out.copy_from_slice(&mask_f);
                continue;
            }
            match E::encoding() {
                Encoding::Image(part, layout) => {
                    sym.apply_image_in(&self.game, part, layout, o_in, o_out)
                }
                Encoding::Graph(part) => sym.apply_nodes(&self.game, part, o_in, o_out),
                Encoding::None => Ok(()),
            }
            .expect("buffers sized from the same config");
            sym.apply_mask(&self.game, &mask_f, m_out)
                .expect("buffers sized from the same config");
        }
    }

    fn env_seed(&self) -> u64 {
        env_seed(self.seed)
    }

    /// Per row: 0 where the row's next step starts an episode (its game has no step yet),
    /// which zeroes that row's recurrent state, else 1.
    fn keeps(&self) -> Vec<f32> {
        let p = self.game.players();
        (0..self.rows)
            .map(|r| (self.env.game(r / p).steps() > 0) as u8 as f32)
            .collect()
    }

    /// The last game of env 0 that finished, as played in training (deal and actions).
    pub fn last_finished_game(&self) -> Option<EpisodeRecord> {
        let (seed, actions) = self.last_game.as_ref()?;
        let mut game = RecordedGame::new(self.game, *seed);
        for &a in actions {
            let action = self.game.decode(a as usize).expect("an index of this game");
            game.apply(action)
                .expect("actions recorded from the environment are legal");
        }
        Some(game.into_record())
    }

    /// Map a row's chosen action from its seat's view back to the true game.
    pub fn to_true_action(&self, row: usize, view_action: usize) -> usize {
        self.row_sym[row]
            .1
            .apply_action_index(&self.game, view_action)
    }

    fn progress(&self) -> f64 {
        self.state.update as f64 / self.config.updates() as f64
    }

    /// One PPO update: a rollout of `rollout_steps` steps in every game, then `epochs`
    /// passes over it in `minibatches` sets of whole sequences.
    pub fn update(&mut self) -> Result<UpdateStats, TrainError> {
        let start = std::time::Instant::now();
        let c = self.config.ppo.clone();
        let progress = self.progress();
        let lr = if c.anneal_lr {
            c.lr * (1.0 - progress)
        } else {
            c.lr
        };
        let shaping = c.shaping as f64 * (1.0 - progress / c.shaping_fraction as f64).max(0.0);
        // One generator per update serves the action draws, then the minibatch order.
        let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(self.seed, self.state.update));
        let rollout = self.collect(shaping, &mut rng)?;
        let rollout_seconds = start.elapsed().as_secs_f64();
        let losses = self.learn_epochs(&rollout, lr, &mut rng);
        self.state.update += 1;
        let secs = start.elapsed().as_secs_f64();
        let belief = self.previous.as_ref().map(|p| p.belief_stats());
        Ok(UpdateStats {
            update: self.state.update,
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
            explained_variance: ppo::explained_variance(
                &rollout.values,
                &rollout.returns,
                &rollout.value_weight,
            ),
            cluster_reward: rollout.cluster_reward,
            belief_loss: losses.belief.map(|b| b.0),
            belief_accuracy: losses.belief.map(|b| b.1),
            obl_belief_cross_entropy: belief.map(|b| b.cross_entropy),
            obl_belief_baseline: belief.map(|b| b.uniform_cross_entropy),
            rollout_seconds,
            learn_seconds: secs - rollout_seconds,
        })
    }
}

//! Recurrent PPO over batched games: IPPO, high-entropy IPPO and Other-Play are presets of
//! this one trainer (TRAINING.md).
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

use crate::config::TrainConfig;
use crate::distribution::{chosen_log_prob, entropy, masked_log_softmax, sample_row};
use crate::file::{Container, FileError};
use crate::gae::gae;
use crate::network::{ActorCritic, Encoder, GruCell, Memory};
use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;
use burn::store::ModuleRecord;
use burn::tensor::{Bytes, TensorData};
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::path::Path;
use yokai_engine::{
    derive_seed, Config, EpisodeRecord, ImageLayout, Metrics, MetricsAccumulator, RecordedGame,
    Symmetry,
};
use yokai_vec::{episode_seed, Encoding, VecEnv, VecEnvOptions, VecError};

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
    #[error("{path}: {message}")]
    Mismatch { path: String, message: String },
    #[error("{path}: cannot load the network: {message}")]
    Record { path: String, message: String },
    #[error("{path}: {message}")]
    Io { path: String, message: String },
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
}

/// The loop state a checkpoint saves beside the network and optimiser. Everything else is
/// derived: environment steps from the update count, each game's episode index from the
/// environment (filled in only when saving), and where episodes start from the games.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct LoopState {
    update: u64,
    /// GRU state per row `[rows × H]`.
    hidden: Vec<f32>,
    /// Per game: the acting seats' actions so far in its current episode.
    history: Vec<Vec<u32>>,
    /// Per game: its episode index (written to checkpoints; the environment keeps it live).
    #[serde(default)]
    episodes: Vec<u64>,
}

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
    /// Seconds spent acting (rollout) and learning (epochs) in this update.
    pub rollout_seconds: f64,
    pub learn_seconds: f64,
}

/// A training run of one seed, in memory: encoder `E`, memory `M` (a GRU unless given).
pub struct Trainer<E: Encoder, M: Memory = GruCell> {
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
}

/// The device of inference outside training (evaluation, play, Python): burn's `flex` CPU
/// backend, whatever GPU features are built in. Training picks its device with
/// [`Trainer::new_on`] ([`crate::Backend`]).
pub fn default_device() -> Device {
    Device::flex()
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

fn tensor2(v: Vec<f32>, shape: [usize; 2], device: &Device) -> Tensor<2> {
    Tensor::from_data(TensorData::new(v, shape), device)
}

fn tensor1(v: Vec<f32>, device: &Device) -> Tensor<1> {
    let n = v.len();
    Tensor::from_data(TensorData::new(v, [n]), device)
}

fn to_vec<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .expect("f32 tensor data")
}

impl<E: Encoder, M: Memory> Trainer<E, M> {
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
        let mut trainer = Trainer {
            state: LoopState {
                update: 0,
                hidden: vec![0.0; n * p * hidden],
                history: vec![Vec::new(); n],
                episodes: Vec::new(),
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
                Encoding::Image(part, ImageLayout::Hwc) => {
                    sym.apply_image(&self.game, part, o_in, o_out)
                }
                Encoding::Image(_, ImageLayout::Chw) => {
                    unreachable!("the trainer's encoders read the HWC image of RULES §5")
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
        let (rows, l, na, hsz) = (
            self.rows,
            self.obs_len,
            self.n_actions,
            self.model.hidden_size(),
        );
        let t_len = c.rollout_steps;
        let p = self.game.players();
        let n = c.num_envs;
        let frac = 1.0 - self.progress();
        let lr = if c.anneal_lr { c.lr * frac } else { c.lr };
        let shaping = c.shaping as f64 * frac;
        let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(self.seed, self.state.update));

        // --- rollout ---
        let mut obs = vec![0f32; t_len * rows * l];
        let mut masks = vec![0f32; t_len * rows * na];
        let mut actions = vec![0usize; t_len * rows];
        let mut logps = vec![0f32; t_len * rows];
        let mut values = vec![0f32; t_len * rows];
        let mut rewards = vec![0f32; t_len * rows];
        let mut dones = vec![0f32; t_len * rows];
        let mut keeps = vec![0f32; t_len * rows];
        let mut chooses = vec![false; t_len * rows];
        let h0 = self.state.hidden.clone();
        let net = self.model.valid();
        let dev = self.infer_device.clone();
        let mut joint = vec![0u32; rows];
        let mut games = MetricsAccumulator::default();
        let (mut ent_sum, mut ent_rows) = (0f64, 0u64);
        for t in 0..t_len {
            let (o, m) = (
                &mut obs[t * rows * l..][..rows * l],
                &mut masks[t * rows * na..][..rows * na],
            );
            self.view(o, m);
            let keep = self.keeps();
            keeps[t * rows..][..rows].copy_from_slice(&keep);
            let (out, h) = net.step(
                tensor2(o.to_vec(), [rows, l], &dev),
                tensor2(self.state.hidden.clone(), [rows, hsz], &dev),
                tensor2(keep, [rows, 1], &dev),
            );
            self.state.hidden = to_vec(h);
            let logits = to_vec(out.logits);
            values[t * rows..][..rows].copy_from_slice(&to_vec(out.values));
            let acting = self.env.acting_seats().to_vec();
            for r in 0..rows {
                let u = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
                let (a, lp, h) = sample_row(&logits[r * na..][..na], &m[r * na..][..na], u, false);
                actions[t * rows + r] = a;
                logps[t * rows + r] = lp;
                chooses[t * rows + r] = m[r * na..][..na].iter().filter(|&&x| x > 0.5).count() > 1;
                if acting[r / p] as usize == r % p {
                    ent_sum += h as f64;
                    ent_rows += 1;
                }
                joint[r] = self.to_true_action(r, a) as u32;
            }
            self.env.step_joint(&joint)?;
            for i in 0..n {
                let reward = self.env.rewards()[i] + shaping as f32 * self.env.shaping()[i];
                let done = self.env.dones()[i] == 1;
                for s in 0..p {
                    rewards[t * rows + i * p + s] = reward;
                    dones[t * rows + i * p + s] = done as u8 as f32;
                }
                if done {
                    if let Some(o) = self.env.outcomes()[i] {
                        games.add(&o);
                    }
                    if i == 0 {
                        let mut actions = std::mem::take(&mut self.state.history[0]);
                        actions.push(joint[acting[0] as usize]);
                        // The environment has already moved on to the next episode.
                        let finished = self.env.episodes(0) - 1;
                        let seed = episode_seed(self.env_seed(), 0, finished);
                        self.last_game = Some((seed, actions));
                    }
                    self.state.history[i].clear();
                    self.draw_symmetries(i);
                } else {
                    let seat = acting[i] as usize;
                    self.state.history[i].push(joint[i * p + seat]);
                }
            }
        }
        // Values of the observations after the last step bootstrap the returns; the state
        // reached here is not kept, since the next rollout starts from these observations.
        let mut last_obs = vec![0f32; rows * l];
        let mut last_masks = vec![0f32; rows * na];
        self.view(&mut last_obs, &mut last_masks);
        let (last, _) = net.step(
            tensor2(last_obs, [rows, l], &dev),
            tensor2(self.state.hidden.clone(), [rows, hsz], &dev),
            tensor2(self.keeps(), [rows, 1], &dev),
        );
        let last_values = to_vec(last.values);
        let (adv, returns) = gae(
            &rewards,
            &values,
            &dones,
            &last_values,
            c.gamma,
            c.gae_lambda,
        );

        let rollout_seconds = start.elapsed().as_secs_f64();
        // --- learning ---
        let mb = rows / c.minibatches;
        let (mut pl_sum, mut vl_sum, mut count) = (0f64, 0f64, 0u64);
        let mut replay_error = 0.0;
        let mut order: Vec<usize> = (0..rows).collect();
        for _ in 0..c.epochs {
            for i in (1..rows).rev() {
                let j = (rng.next_u64() % (i as u64 + 1)) as usize;
                order.swap(i, j);
            }
            for k in 0..c.minibatches {
                let end = if k + 1 == c.minibatches {
                    rows
                } else {
                    (k + 1) * mb
                };
                let batch = &order[k * mb..end];
                let (pl, vl, err) = self.learn(
                    batch,
                    Rollout {
                        obs: &obs,
                        masks: &masks,
                        actions: &actions,
                        logps: &logps,
                        values: &values,
                        keeps: &keeps,
                        chooses: &chooses,
                        adv: &adv,
                        returns: &returns,
                        h0: &h0,
                    },
                    lr,
                );
                if count == 0 {
                    replay_error = err;
                }
                pl_sum += pl;
                vl_sum += vl;
                count += 1;
            }
        }
        self.state.update += 1;
        let secs = start.elapsed().as_secs_f64();
        Ok(UpdateStats {
            update: self.state.update,
            env_steps: self.env_steps(),
            sps: (n * t_len) as f64 / secs.max(1e-9),
            games: games.metrics(),
            policy_loss: pl_sum / count as f64,
            value_loss: vl_sum / count as f64,
            entropy: if ent_rows > 0 {
                ent_sum / ent_rows as f64
            } else {
                0.0
            },
            lr,
            shaping,
            replay_error,
            rollout_seconds,
            learn_seconds: secs - rollout_seconds,
        })
    }

    /// One gradient step on the rows `batch` of the rollout; returns the policy and value
    /// losses and the mean |Δ log π| against the rollout before the step.
    fn learn(&mut self, batch: &[usize], ro: Rollout<'_>, lr: f64) -> (f64, f64, f64) {
        let c = &self.config.ppo;
        let (rows, l, na) = (self.rows, self.obs_len, self.n_actions);
        let hsz = self.model.hidden_size();
        let t_len = c.rollout_steps;
        let bm = batch.len();
        let mut obs = Vec::with_capacity(bm * t_len * l);
        let mut keep = Vec::with_capacity(bm * t_len);
        let mut old_v = Vec::with_capacity(bm * t_len);
        let mut ret = Vec::with_capacity(bm * t_len);
        let mut h0 = Vec::with_capacity(bm * hsz);
        // Rows with one legal action (seats waiting for their turn, or a forced NOOP) carry
        // no policy gradient: the actor head, the policy loss and the entropy skip them, so
        // their masks and one-hot actions are not even gathered.
        let mut choosing: Vec<i64> = Vec::new();
        let mut masks = Vec::new();
        let mut one_hot = Vec::new();
        let mut old_logp = Vec::new();
        let mut adv = Vec::new();
        for (j, &r) in batch.iter().enumerate() {
            h0.extend_from_slice(&ro.h0[r * hsz..][..hsz]);
            for t in 0..t_len {
                let i = t * rows + r;
                obs.extend_from_slice(&ro.obs[i * l..][..l]);
                keep.push(ro.keeps[i]);
                old_v.push(ro.values[i]);
                ret.push(ro.returns[i]);
                if ro.chooses[i] {
                    choosing.push((j * t_len + t) as i64);
                    masks.extend_from_slice(&ro.masks[i * na..][..na]);
                    let at = one_hot.len();
                    one_hot.resize(at + na, 0.0);
                    one_hot[at + ro.actions[i]] = 1.0;
                    old_logp.push(ro.logps[i]);
                    adv.push(ro.adv[i]);
                }
            }
        }
        if c.normalize_advantages && adv.len() > 1 {
            let mean = adv.iter().sum::<f32>() / adv.len() as f32;
            let var = adv.iter().map(|a| (a - mean).powi(2)).sum::<f32>() / adv.len() as f32;
            let sd = var.sqrt() + 1e-8;
            adv.iter_mut().for_each(|a| *a = (*a - mean) / sd);
        }
        let d = &self.device;
        let obs: Tensor<3> = Tensor::from_data(TensorData::new(obs, [bm, t_len, l]), d);
        let states = self.model.unroll(
            obs,
            tensor2(h0, [bm, hsz], d),
            tensor2(keep, [bm, t_len], d),
        );
        let old_v = tensor1(old_v, d);
        let ret = tensor1(ret, d);
        let v = self.model.values(states.clone());
        let v_clipped = old_v.clone() + (v.clone() - old_v).clamp(-c.value_clip, c.value_clip);
        let value_loss = (v - ret.clone())
            .square()
            .max_pair((v_clipped - ret).square())
            .mean()
            * 0.5;
        let n = choosing.len();
        let (policy_loss, ent, replay_error) = if n == 0 {
            let zero = Tensor::<1>::zeros([1], d).sum();
            (zero.clone(), zero, 0.0)
        } else {
            let idx = Tensor::<1, Int>::from_data(TensorData::new(choosing, [n]), d);
            let logits = self.model.policy_logits(states.select(0, idx));
            let mask = tensor2(masks, [n, na], d);
            let log_probs = masked_log_softmax(logits, mask.clone());
            let logp = chosen_log_prob(log_probs.clone(), tensor2(one_hot, [n, na], d));
            let ent = entropy(log_probs, mask).mean();
            let adv = tensor1(adv, d);
            let delta = logp - tensor1(old_logp, d);
            let replay_error = delta.clone().abs().mean().into_scalar::<f32>() as f64;
            let ratio = delta.exp();
            let clipped = ratio.clone().clamp(1.0 - c.clip, 1.0 + c.clip);
            let policy_loss = (ratio * adv.clone()).min_pair(clipped * adv).mean().neg();
            (policy_loss, ent, replay_error)
        };
        let loss = policy_loss.clone() + value_loss.clone() * c.value_coef - ent * c.entropy_coef;
        let mut grads = GradientsParams::from_grads(loss.backward(), &self.model);
        clip_global_norm(&self.model, &mut grads, c.max_grad_norm);
        let model = self.model.clone();
        self.model = self.optim.step(lr, model, grads);
        (
            policy_loss.into_scalar::<f32>() as f64,
            value_loss.into_scalar::<f32>() as f64,
            replay_error,
        )
    }

    // --- checkpoints ---

    fn header(&self, kind: &str) -> FileHeader {
        FileHeader {
            kind: kind.into(),
            train_config: self.config.to_toml(),
            game: self.game.to_toml(),
            seed: self.seed,
            update: self.state.update,
            env_steps: self.env_steps(),
        }
    }

    /// Every parameter value of the network, in module order (records also hold random
    /// parameter ids, so compare these, not record bytes).
    pub fn parameters(&self) -> Vec<f32> {
        parameters(&self.model)
    }

    /// The network's parameters in burn's record format.
    pub fn model_bytes(&self) -> Vec<u8> {
        self.model
            .clone()
            .into_record()
            .into_bytes()
            .expect("an in-memory record always serialises")
            .to_vec()
    }

    /// The policy file's content: header and network, no optimiser or loop state.
    pub fn policy(&self) -> Container {
        Container {
            header: serde_json::to_string_pretty(&self.header("policy")).expect("json"),
            sections: vec![("model".into(), self.model_bytes())],
        }
    }

    /// Everything needed to continue the run exactly.
    pub fn checkpoint(&self) -> Container {
        let optim = self
            .optim
            .into_bytes()
            .expect("an in-memory optimiser state always serialises")
            .to_vec();
        Container {
            header: serde_json::to_string_pretty(&self.header("checkpoint")).expect("json"),
            sections: vec![
                ("model".into(), self.model_bytes()),
                ("optimizer".into(), optim),
                (
                    "state".into(),
                    serde_json::to_vec(&LoopState {
                        episodes: (0..self.config.ppo.num_envs)
                            .map(|i| self.env.episodes(i))
                            .collect(),
                        ..self.state.clone()
                    })
                    .expect("loop state serialises"),
                ),
            ],
        }
    }

    /// Continue a run from a checkpoint written by [`Trainer::checkpoint`], on the CPU.
    pub fn resume(path: &Path) -> Result<Trainer<E, M>, TrainError> {
        Trainer::resume_on(path, default_device())
    }

    /// Continue a run from a checkpoint on `infer_device` (any backend: checkpoints hold
    /// plain f32 values, so a run can move between the CPU and a GPU).
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
        if config.network.preset != E::PRESET {
            return Err(TrainError::Mismatch {
                path: path.display().to_string(),
                message: format!("holds a {:?} network", config.network.preset),
            });
        }
        let mut trainer = Trainer::<E, M>::new_on(config, header.seed, infer_device)?;
        let shown = path.display().to_string();
        trainer.model = load_model(trainer.model, file.section(path, "model")?, &shown)?;
        let optim = file.section(path, "optimizer")?.to_vec();
        trainer.optim = optimizer(&trainer.config)
            .from_bytes(Bytes::from_bytes_vec(optim))
            .map_err(|e| TrainError::Record {
                path: shown.clone(),
                message: format!("optimizer: {e}"),
            })?;
        let state: LoopState =
            serde_json::from_slice(file.section(path, "state")?).map_err(|e| {
                TrainError::Mismatch {
                    path: shown.clone(),
                    message: format!("loop state: {e}"),
                }
            })?;
        let n = trainer.config.ppo.num_envs;
        if state.hidden.len() != trainer.state.hidden.len()
            || state.episodes.len() != n
            || state.history.len() != n
        {
            return Err(TrainError::Mismatch {
                path: shown,
                message: "loop state sizes do not match its config".into(),
            });
        }
        for i in 0..n {
            trainer
                .env
                .restore(i, state.episodes[i], &state.history[i])?;
        }
        trainer.state = state;
        for i in 0..n {
            trainer.draw_symmetries(i);
        }
        Ok(trainer)
    }
}

/// Views of one rollout, time-major (`[T, rows, …]`).
struct Rollout<'a> {
    obs: &'a [f32],
    masks: &'a [f32],
    actions: &'a [usize],
    logps: &'a [f32],
    values: &'a [f32],
    keeps: &'a [f32],
    /// Whether the row had more than one legal action at that step.
    chooses: &'a [bool],
    adv: &'a [f32],
    returns: &'a [f32],
    h0: &'a [f32],
}

pub(crate) fn read_header(file: &Container, path: &Path) -> Result<FileHeader, TrainError> {
    serde_json::from_str(&file.header).map_err(|e| TrainError::Mismatch {
        path: path.display().to_string(),
        message: format!("unreadable header: {e}"),
    })
}

/// Load network weights, refusing any record whose tensors do not match the network.
pub(crate) fn load_model<M: Module>(model: M, bytes: &[u8], path: &str) -> Result<M, TrainError> {
    let record = ModuleRecord::from_bytes(Bytes::from_bytes_vec(bytes.to_vec())).map_err(|e| {
        TrainError::Record {
            path: path.to_string(),
            message: e.to_string(),
        }
    })?;
    model
        .try_load_record(record)
        .map_err(|e| TrainError::Record {
            path: path.to_string(),
            message: e.to_string(),
        })
}

/// Every float parameter of a module, flattened in visiting order.
pub fn parameters<M: Module>(model: &M) -> Vec<f32> {
    struct Collect(Vec<f32>);
    impl ModuleVisitor for Collect {
        fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
            self.0.extend(to_vec(param.val()));
        }
    }
    let mut c = Collect(Vec::new());
    model.visit(&mut c);
    c.0
}

/// Scale all gradients together so that their global L2 norm is at most `max_norm`.
fn clip_global_norm<M: Module>(model: &M, grads: &mut GradientsParams, max_norm: f32) {
    struct Norm<'a> {
        grads: &'a GradientsParams,
        sum: f64,
    }
    impl ModuleVisitor for Norm<'_> {
        fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
            if let Some(g) = self.grads.get::<D>(param.id) {
                self.sum += g.square().sum().into_scalar::<f32>() as f64;
            }
        }
    }
    struct Scale<'a> {
        grads: &'a mut GradientsParams,
        factor: f32,
    }
    impl ModuleMapper for Scale<'_> {
        fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
            if let Some(g) = self.grads.remove::<D>(param.id) {
                self.grads.register(param.id, g.mul_scalar(self.factor));
            }
            param
        }
    }
    let mut norm = Norm {
        grads: &*grads,
        sum: 0.0,
    };
    model.visit(&mut norm);
    let total = norm.sum.sqrt() as f32;
    if total > max_norm {
        let mut scale = Scale {
            grads,
            factor: max_norm / (total + 1e-6),
        };
        let _ = model.clone().map(&mut scale);
    }
}

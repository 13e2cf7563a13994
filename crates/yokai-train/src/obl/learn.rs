//! Training the belief model on games of the level below, and measuring it against the
//! exact belief of uniformly random play.
//!
//! Data: every seat of every game, at every step (acting or waiting), with its observation,
//! the cards it has seen first-hand, and the true colours. Each update collects a rollout of
//! the level below in self-play ([`LevelBelow`]: uniformly random legal play, or any
//! [`Policy`] in every seat, such as the previous OBL level) and takes one Adam step per
//! minibatch of whole seat sequences, replayed from the memory state they started the
//! rollout with (as PPO).
//! The loss is the cross-entropy of the true colour of every card the seat has not seen,
//! slot by slot with the true colours of the earlier slots (teacher forcing).
//!
//! Each update also measures, on the same slots, the exact belief of uncommitted play
//! (level 0): its cross-entropy, −log(available_c / Σ available) per slot (summed over a
//! seat's slots: the log of the number of consistent colourings), is the baseline a belief
//! of a later level must beat, and the exact KL of each slot's conditional to the model's
//! says how close the model comes to it on level-0 data.

use super::belief::first_hand_slots;
use super::model::{BeliefModel, SlotInputs};
use crate::distribution::sample_legal;
use crate::tensor::{tensor2, to_vec};
use crate::TrainedPolicy;
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;
use burn::tensor::TensorData;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use yokai_agents::Policy;
use yokai_engine::{derive_seed, Card, Config, Game, Part, Seat};
use yokai_vec::{Encoding, VecEnv, VecEnvOptions, VecError};

/// Who plays the games the belief learns from.
pub enum LevelBelow {
    /// Level 0: uniformly random legal play (its exact belief is known: see `uniform_kl`).
    Random,
    /// A policy in every seat, built afresh for each seat of each episode from a seed
    /// (e.g. `TrainedPolicy::build` of the previous OBL level, or a scripted bot).
    Policy(Box<dyn FnMut(u64) -> Box<dyn Policy> + Send>),
    /// Trained networks (the previous OBL level: one seed's, or every seed's under
    /// `obl.belief_of = "all-seeds"`), game g played by network g mod n in every seat; each
    /// network steps all seats of its games in one batch, its memory read on every step as
    /// in training. With one network, every game is its self-play.
    Networks(Vec<TrainedPolicy>),
}

/// Sizes and learning rate of belief training.
#[derive(Clone, Debug)]
pub struct BeliefTrainConfig {
    pub num_envs: usize,
    pub rollout_steps: usize,
    pub minibatches: usize,
    pub hidden: usize,
    /// Adam's step size, annealed linearly to 0 over `updates`.
    pub lr: f64,
    pub updates: u64,
}

impl BeliefTrainConfig {
    /// 16 games × 16 steps per update in 2 minibatches, lr 3·10⁻³ annealed over `updates`:
    /// what OBL's levels ≥ 2 train their belief with.
    pub fn small(hidden: usize, updates: u64) -> BeliefTrainConfig {
        BeliefTrainConfig {
            num_envs: 16,
            rollout_steps: 16,
            minibatches: 2,
            hidden,
            lr: 3e-3,
            updates,
        }
    }
}

/// One update's figures (or several updates', [`BeliefStats::mean`]), in nats per unseen
/// card. A level ≥ 2 run logs every update's in `RUN/belief.jsonl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BeliefStats {
    /// The model's cross-entropy of the true colours.
    pub cross_entropy: f64,
    /// The exact level-0 belief's cross-entropy on the same slots: the baseline a belief
    /// of a level that follows conventions must beat.
    #[serde(rename = "first_hand_baseline")]
    pub uniform_cross_entropy: f64,
    /// KL(exact level-0 conditional ‖ model conditional), averaged over the slots: with the
    /// true colours before each slot drawn from the exact belief (level-0 data), its sum
    /// over a seat's slots is the KL of the whole colouring (chain rule). Only meaningful
    /// on level-0 data.
    #[serde(rename = "kl_from_first_hand")]
    pub uniform_kl: f64,
    /// Slots (unseen cards of a seat at a step) the figures average over.
    pub slots: usize,
}

impl BeliefStats {
    /// The figures of several batches or updates together: means weighted by their slots.
    pub fn mean(parts: impl IntoIterator<Item = BeliefStats>) -> BeliefStats {
        let mut total = BeliefStats::default();
        for s in parts {
            let w = s.slots as f64;
            total.cross_entropy += s.cross_entropy * w;
            total.uniform_cross_entropy += s.uniform_cross_entropy * w;
            total.uniform_kl += s.uniform_kl * w;
            total.slots += s.slots;
        }
        let n = total.slots.max(1) as f64;
        total.cross_entropy /= n;
        total.uniform_cross_entropy /= n;
        total.uniform_kl /= n;
        total
    }
}

/// A belief model learning from the games of the level below ([`LevelBelow`]).
pub struct BeliefTrainer {
    config: BeliefTrainConfig,
    game: Config,
    seed: u64,
    device: Device,
    model: BeliefModel,
    optim: ModuleOptimizer,
    env: VecEnv<f32>,
    players: LevelBelow,
    /// With a policy below: its seats per game, and the episode they were built for.
    seats: Vec<(u64, Vec<Box<dyn Policy>>)>,
    /// With networks below: each one's memory of its games' rows, `[its rows × H]`.
    below_hidden: Vec<Vec<f32>>,
    /// Every row's memory at the start of the next rollout, `[rows × H]`.
    hidden: Vec<f32>,
    updates: u64,
}

/// One rollout of belief data, time-major `[T, rows, …]`.
struct Rollout {
    obs: Vec<f32>,
    keeps: Vec<f32>,
    truth: Vec<u8>,
    /// Per step and game: the card adjacency `[Y, Y]`.
    adjacency: Vec<f32>,
    /// Per card: its colour where the row's seat has seen it, else `None`.
    first_hand: Vec<Option<u8>>,
}

impl BeliefTrainer {
    pub fn new(
        game: Config,
        config: BeliefTrainConfig,
        players: LevelBelow,
        seed: u64,
        device: Device,
    ) -> Result<BeliefTrainer, VecError> {
        let mut options = VecEnvOptions::new(config.num_envs, derive_seed(seed, 0xBE1));
        options.encoding = Encoding::Graph(Part::Full);
        options.threads = Some(1);
        let env = VecEnv::<f32>::new(game, options)?;
        let device = device.autodiff();
        let model = BeliefModel::new(&game, config.hidden, derive_seed(seed, 0xBE2), &device);
        let rows = config.num_envs * game.players();
        let below_hidden = match &players {
            LevelBelow::Networks(nets) => (0..nets.len())
                .map(|m| {
                    let games = (m..config.num_envs).step_by(nets.len()).count();
                    vec![0.0; games * game.players() * nets[m].hidden_size()]
                })
                .collect(),
            _ => Vec::new(),
        };
        Ok(BeliefTrainer {
            hidden: vec![0.0; rows * config.hidden],
            optim: AdamConfig::new().with_epsilon(1e-5).init(),
            config,
            game,
            seed,
            device,
            model,
            env,
            below_hidden,
            players,
            seats: Vec::new(),
            updates: 0,
        })
    }

    pub fn model(&self) -> &BeliefModel {
        &self.model
    }

    /// The trained model, for inference.
    pub fn into_model(self) -> BeliefModel {
        self.model.valid()
    }

    fn rows(&self) -> usize {
        self.config.num_envs * self.game.players()
    }

    /// `rollout_steps` steps of the level below in every game, with every seat's data.
    fn collect(&mut self) -> Rollout {
        let (rows, p, y) = (self.rows(), self.game.players(), self.game.cards());
        let t_len = self.config.rollout_steps;
        let l: usize = self.game.node_shape(Part::Full).iter().product();
        let mut ro = Rollout {
            obs: Vec::with_capacity(t_len * rows * l),
            keeps: Vec::with_capacity(t_len * rows),
            truth: Vec::with_capacity(t_len * rows * y),
            adjacency: Vec::with_capacity(t_len * self.config.num_envs * y * y),
            first_hand: Vec::with_capacity(t_len * rows * y),
        };
        let mut actions = vec![0u32; self.config.num_envs];
        for t in 0..t_len {
            ro.obs.extend_from_slice(self.env.observations());
            ro.adjacency.extend_from_slice(self.env.adjacency());
            for r in 0..rows {
                let game = self.env.game(r / p);
                ro.keeps.push((game.steps() > 0) as u8 as f32);
                ro.truth
                    .extend((0..y).map(|k| game.colour_of(Card(k as u8)).0));
                ro.first_hand
                    .extend(first_hand_slots(game, Seat((r % p) as u8)));
            }
            let step = self.updates * t_len as u64 + t as u64;
            self.choose(step, &mut actions);
            self.env
                .step(&actions)
                .expect("the level below plays legal actions");
        }
        ro
    }

    /// The acting seat's action in every game at rollout step `step` (a count over the run).
    fn choose(&mut self, step: u64, actions: &mut [u32]) {
        let build = match &mut self.players {
            LevelBelow::Random => {
                let seed = derive_seed(derive_seed(self.seed, 0xBE3), step);
                return self.env.sample_legal(seed, actions);
            }
            LevelBelow::Networks(nets) => {
                let seed = derive_seed(derive_seed(self.seed, 0xBE5), step);
                return choose_by_networks(nets, &self.env, &mut self.below_hidden, seed, actions);
            }
            LevelBelow::Policy(build) => build,
        };
        let p = self.game.players();
        let seats_seed = derive_seed(self.seed, 0xBE4);
        if self.seats.is_empty() {
            self.seats = (0..actions.len()).map(|_| (u64::MAX, Vec::new())).collect();
        }
        for (i, action) in actions.iter_mut().enumerate() {
            let game = self.env.game(i);
            let episode = self.env.episodes(i);
            let (built_for, seats) = &mut self.seats[i];
            if *built_for != episode {
                let episode_seed = yokai_vec::episode_seed(seats_seed, i, episode);
                *seats = (0..p)
                    .map(|s| build(derive_seed(episode_seed, s as u64)))
                    .collect();
                *built_for = episode;
            }
            let actor = game.current_seat();
            let chosen = seats[actor.index()].act(&game.view(actor));
            for (s, seat) in seats.iter_mut().enumerate() {
                seat.observe(&game.view(Seat(s as u8)), actor, chosen);
            }
            *action = self.game.encode(chosen) as u32;
        }
    }

    /// One update: a rollout, then one Adam step per minibatch of whole rows.
    pub fn update(&mut self) -> BeliefStats {
        let ro = self.collect();
        let progress = (self.updates as f64 / self.config.updates.max(1) as f64).min(1.0);
        let lr = self.config.lr * (1.0 - progress);
        let rows: Vec<usize> = (0..self.rows()).collect();
        let mb = rows.len().div_ceil(self.config.minibatches);
        let parts: Vec<BeliefStats> = rows
            .chunks(mb)
            .map(|batch| self.learn(batch, &ro, lr))
            .collect();
        self.updates += 1;
        BeliefStats::mean(parts)
    }

    /// The rows `batch` of the rollout as the belief model learns them: their sequences,
    /// and per slot the model must name (each card the seat has not seen at each step) its
    /// state row, decoder inputs and true colour.
    fn gather(&self, batch: &[usize], ro: &Rollout) -> BeliefBatch {
        let (rows, y, c) = (self.rows(), self.game.cards(), self.game.colours());
        let t_len = self.config.rollout_steps;
        let hsz = self.config.hidden;
        let l: usize = self.game.node_shape(Part::Full).iter().product();
        let f = self.model.features();
        let p = self.game.players();
        let mut out = BeliefBatch::default();
        for (j, &r) in batch.iter().enumerate() {
            out.h0.extend_from_slice(&self.hidden[r * hsz..][..hsz]);
            for t in 0..t_len {
                let i = t * rows + r;
                let o = &ro.obs[i * l..][..l];
                out.obs.extend_from_slice(o);
                out.keep.push(ro.keeps[i]);
                let truth = &ro.truth[i * y..][..y];
                let first = &ro.first_hand[i * y..][..y];
                let adjacency = &ro.adjacency[(t * rows / p + r / p) * y * y..][..y * y];
                for k in 0..y {
                    if first[k].is_some() {
                        continue;
                    }
                    let a = out
                        .inputs
                        .push(&self.game, f, o, adjacency, &truth[..k], first, k);
                    let true_colour = truth[k] as usize;
                    out.uniform -= (a[true_colour] as f64 / a.iter().sum::<usize>() as f64).ln();
                    out.at.push((j * t_len + t) as i64);
                    let mut one_hot = vec![0f32; c];
                    one_hot[true_colour] = 1.0;
                    out.target.extend(one_hot);
                }
            }
        }
        out
    }

    /// One Adam step of the belief model on the rows `batch` of the rollout, at `lr`.
    fn learn(&mut self, batch: &[usize], ro: &Rollout, lr: f64) -> BeliefStats {
        let c = self.game.colours();
        let (t_len, hsz) = (self.config.rollout_steps, self.config.hidden);
        let l: usize = self.game.node_shape(Part::Full).iter().product();
        let bm = batch.len();
        let BeliefBatch {
            obs,
            keep,
            h0,
            at,
            inputs,
            target,
            uniform,
        } = self.gather(batch, ro);
        let d = &self.device;
        let n = at.len();
        let states = self.model.unroll(
            Tensor::from_data(TensorData::new(obs, [bm, t_len, l]), d),
            tensor2(h0, [bm, hsz], d),
            tensor2(keep, [bm, t_len], d),
        );
        // The next rollout starts from the state after this one.
        let last: Vec<f32> = to_vec(
            states
                .clone()
                .reshape([bm, t_len, hsz])
                .narrow(1, t_len - 1, 1)
                .reshape([bm, hsz])
                .detach(),
        );
        for (j, &r) in batch.iter().enumerate() {
            self.hidden[r * hsz..][..hsz].copy_from_slice(&last[j * hsz..][..hsz]);
        }
        if n == 0 {
            return BeliefStats::default();
        }
        let idx = Tensor::<1, Int>::from_data(TensorData::new(at, [n]), d);
        let log_p = self.model.log_probs(states.select(0, idx), &inputs);
        let model_log_p = to_vec(log_p.clone().detach());
        let mut kl = 0f64;
        for (s, a) in inputs.avail.chunks(c).enumerate() {
            let sum: f32 = a.iter().sum();
            for (colour, &count) in a.iter().enumerate().filter(|(_, &x)| x > 0.0) {
                let p = (count / sum) as f64;
                kl += p * (p.ln() - model_log_p[s * c + colour] as f64);
            }
        }
        let loss = (log_p * tensor2(target, [n, c], d)).sum().neg() / n as f32;
        let cross_entropy = loss.clone().into_scalar::<f32>() as f64;
        let grads = GradientsParams::from_grads(loss.backward(), &self.model);
        let model = self.model.clone();
        self.model = self.optim.step(lr, model, grads);
        BeliefStats {
            cross_entropy,
            uniform_cross_entropy: uniform / n as f64,
            uniform_kl: kl / n as f64,
            slots: n,
        }
    }
}

/// A minibatch of the belief model's learning ([`BeliefTrainer::gather`]).
#[derive(Default)]
struct BeliefBatch {
    /// The rows' sequences: observations `[rows × T × L]`, keep flags, first states.
    obs: Vec<f32>,
    keep: Vec<f32>,
    h0: Vec<f32>,
    /// Per slot: its state row (`j·T + t`), decoder inputs and true colour (one-hot).
    at: Vec<i64>,
    inputs: SlotInputs,
    target: Vec<f32>,
    /// Σ −ln(uniform probability of the true colour) over the slots: the baseline.
    uniform: f64,
}

/// Every seat of every game steps its network's memory on its observation (`hidden`, per
/// network and row; game i is network i mod n's); the acting seat of each game samples its
/// action from that network's logits. Every network needs a game (n ≤ games).
fn choose_by_networks(
    nets: &[TrainedPolicy],
    env: &VecEnv<f32>,
    hidden: &mut [Vec<f32>],
    seed: u64,
    actions: &mut [u32],
) {
    let p = env.config().players();
    let n = nets.len();
    // Network m steps every seat of games m, m + n, …: its j-th game's rows are j·p….
    let stepped: Vec<_> = nets
        .iter()
        .zip(hidden.iter_mut())
        .enumerate()
        .map(|(m, (net, hidden))| {
            let rows: Vec<(&Game, Seat)> = (m..actions.len())
                .step_by(n)
                .flat_map(|i| (0..p).map(move |s| (env.game(i), Seat(s as u8))))
                .collect();
            let keep = rows
                .iter()
                .map(|(g, _)| (g.steps() > 0) as u8 as f32)
                .collect();
            let mut stepped = net.step_seats(&rows, std::mem::take(hidden), keep);
            // The new states become the memory; the logits stay in `stepped`.
            *hidden = std::mem::take(&mut stepped.states);
            stepped
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for (i, action) in actions.iter_mut().enumerate() {
        let g = env.game(i);
        let r = (i / n) * p + g.current_seat().index();
        let logits = stepped[i % n].logits(r).expect("the acting seat's logits");
        *action = sample_legal(g, logits, &mut rng) as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A belief model trained on level-0 games comes within 0.003 nats per unseen card of
    /// the exact belief (uniform over the consistent colourings): the exact KL of each
    /// slot's conditional, averaged over the slots of fresh rollouts (each update measures
    /// its rollout before learning from it), over the last 20 of 200 updates.
    #[test]
    fn a_belief_model_trained_on_random_play_matches_the_exact_belief() {
        let game = Config::from_name("9c-2p-perfect").unwrap();
        let config = BeliefTrainConfig::small(32, 200);
        let mut t =
            BeliefTrainer::new(game, config, LevelBelow::Random, 1, Device::flex()).unwrap();
        let mut kl = Vec::new();
        for u in 0..200 {
            let s = t.update();
            assert!(s.slots > 1000, "update {u}: {} unseen-card slots", s.slots);
            kl.push(s.uniform_kl);
        }
        let late: f64 = kl[kl.len() - 20..].iter().sum::<f64>() / 20.0;
        assert!(kl[0] > 0.005, "untrained, the model is off: KL {}", kl[0]);
        // Measured: 0.036 untrained, 0.0022 over the last 20 updates.
        assert!(
            late < 0.003 && late < 0.1 * kl[0],
            "KL per unseen card {late:.5}, at first {:.5}",
            kl[0]
        );
    }

    /// A belief learns what a convention says: trained on the `greedy` bot's self-play
    /// (it moves the cards it has seen next to cards of their colour and places only
    /// correct hints, so where a partner puts a card and a hint tells about its colour),
    /// its cross-entropy falls below the exact belief of uncommitted play — the colours one
    /// has seen and the counts, which no belief can beat on random play — on the same
    /// slots. Measured: 0.020 nats per unseen card above that baseline untrained, 0.0053
    /// below it over the last 20 of 200 updates (0.593 against 0.598; 600 updates gave
    /// 0.0050: what the model reads of this convention is small, see docs/training.md).
    #[test]
    fn a_belief_trained_on_a_convention_beats_the_first_hand_baseline() {
        let game = Config::from_name("9c-2p-perfect").unwrap();
        let config = BeliefTrainConfig::small(32, 200);
        let greedy = LevelBelow::Policy(Box::new(|_| Box::new(yokai_agents::GreedyPolicy::new())));
        let mut t = BeliefTrainer::new(game, config, greedy, 2, Device::flex()).unwrap();
        let stats: Vec<BeliefStats> = (0..200).map(|_| t.update()).collect();
        let mean = |s: &[BeliefStats], f: fn(&BeliefStats) -> f64| {
            s.iter().map(f).sum::<f64>() / s.len() as f64
        };
        let gap =
            |s: &[BeliefStats]| mean(s, |x| x.uniform_cross_entropy) - mean(s, |x| x.cross_entropy);
        let (first, late) = (&stats[..10], &stats[180..]);
        assert!(
            gap(first) < 0.0,
            "untrained: no better than the baseline ({})",
            gap(first)
        );
        assert!(
            gap(late) > 0.003,
            "trained: {:.3} nats per unseen card, baseline {:.3}",
            mean(late, |x| x.cross_entropy),
            mean(late, |x| x.uniform_cross_entropy)
        );
    }
}

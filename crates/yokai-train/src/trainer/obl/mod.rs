//! Off-Belief Learning in the rollout: the value target of every acting seat's action
//! comes from a fictitious continuation (`crate::obl`), not from the real game.
//!
//! At step t, for the acting seat i of each game: draw a colouring from i's belief, apply
//! i's action to the game recoloured so, let the previous level play until i is to act
//! again (or the game ends), and bootstrap from the learner's value of i's memory after it
//! has read its observations of those fictitious steps:
//!
//! `target = Σ_{j<k} γʲ r'_j + γᵏ V(h'_k)` (no bootstrap where the game ended), where
//! `h'_0` is i's state at t (after reading o_t) and `h'_{j+1} = GRU(h'_j, o'_{j+1})`.
//!
//! PPO then uses `target − V(h_t)` as the advantage of the action and `target` as the value
//! target of that row; the waiting seats' rows carry neither (their value loss is off), so
//! the critic learns the OBL value of the acting seats' histories only — the only values a
//! target ever reads.
//!
//! Level 1 draws from the exact belief and plays level 0 (uniformly random) as partner;
//! levels ≥ 2 draw from the belief model trained on the previous level and play the
//! previous level's network as partner (`previous`).

mod memory;
mod previous;

pub(crate) use previous::PreviousLevel;

use super::{tensor2, to_vec, TrainError, Trainer};
use crate::network::{ActorCritic, Encoder, Recurrent};
use crate::obl::{continue_all, first_hand_slots, sample_first_hand_consistent, Continuation};
use memory::{episode_states, step_along};
use previous::Partners;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{derive_seed, Colour, Game, Part, Seat};
use yokai_vec::{episode_seed, Encoding};

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    /// The OBL value target of the acting row of every game at rollout step `t`, given each
    /// row's (true-frame) action in `joint`, the recurrent states after step t's observation
    /// in `self.state.hidden`, and the rollout's shaping weight. Returns (row, target) pairs.
    pub(super) fn obl_targets(
        &self,
        net: &ActorCritic<E, M>,
        t: usize,
        joint: &[u32],
        shaping: f32,
    ) -> Result<Vec<(usize, f32)>, TrainError> {
        let p = self.game.players();
        let n = self.config.ppo.num_envs;
        let gamma = self.config.ppo.gamma;
        let (l, hsz) = (self.obs_len, self.model.hidden_size());
        // One stream per (run, update, step): beliefs and level-0 moves, in game order.
        let step = self.state.update * self.config.ppo.rollout_steps as u64 + t as u64;
        let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(derive_seed(self.seed, 0x0B1), step));
        let mut partner_rng =
            ChaCha8Rng::seed_from_u64(derive_seed(derive_seed(self.seed, 0x0B2), step));
        let colourings = match &self.previous {
            None => (0..n)
                .map(|i| {
                    let game = self.env.game(i);
                    sample_first_hand_consistent(game, game.current_seat(), &mut rng)
                })
                .collect(),
            Some(previous) => self.sample_beliefs(previous, &mut rng)?,
        };
        let partner_states = match &self.previous {
            None => vec![Vec::new(); n],
            Some(previous) => self.partner_memories(previous, &colourings)?,
        };
        let starts: Vec<(&Game, &[Colour], usize)> = colourings
            .iter()
            .enumerate()
            .map(|(i, colours)| {
                let game = self.env.game(i);
                let row = i * p + game.current_seat().index();
                (game, &colours[..], joint[row] as usize)
            })
            .collect();
        let mut partners = match &self.previous {
            None => Partners::Random(&mut partner_rng),
            Some(previous) => Partners::Previous {
                policy: &previous.policy,
                seats: starts
                    .iter()
                    .map(|(g, _, _)| partners_of(g, g.current_seat()))
                    .collect(),
                states: partner_states,
                rng: &mut partner_rng,
            },
        };
        let continued = continue_all(
            &starts,
            &mut |which, games| partners.act(which, games),
            shaping,
            gamma,
            4 * p,
        )
        .map_err(|(i, e)| TrainError::Obl(format!("env {i}, step {t}: {e}")))?;
        let runs: Vec<(usize, Seat, Continuation)> = starts
            .iter()
            .zip(continued)
            .enumerate()
            .map(|(i, ((g, _, _), c))| (i * p + g.current_seat().index(), g.current_seat(), c))
            .collect();
        // Each seat's memory reads its observations of the fictitious steps, from its state at
        // t; a continuation that ended needs no value, so its seat reads nothing.
        let dev = &self.infer_device;
        let sequences: Vec<&[Game]> = runs.iter().map(|(_, _, c)| &c.states[..]).collect();
        let seats: Vec<Vec<Seat>> = runs
            .iter()
            .map(|(_, seat, c)| if c.done { Vec::new() } else { vec![*seat] })
            .collect();
        let mut states: Vec<Vec<f32>> = runs
            .iter()
            .map(|(row, _, _)| self.state.hidden[row * hsz..][..hsz].to_vec())
            .collect();
        step_along(
            &sequences,
            &seats,
            &mut states,
            E::encoding(),
            false,
            &mut |o, h, k| {
                let rows = k.len();
                to_vec(net.recur(
                    tensor2(o, [rows, l], dev),
                    tensor2(h, [rows, hsz], dev),
                    tensor2(k, [rows, 1], dev),
                ))
            },
        );
        // Bootstrap from the value where the seat acts again.
        let open: Vec<usize> = (0..runs.len()).filter(|&k| !runs[k].2.done).collect();
        let values = if open.is_empty() {
            Vec::new()
        } else {
            let h: Vec<f32> = open
                .iter()
                .flat_map(|&k| states[k].iter().copied())
                .collect();
            to_vec(net.values(tensor2(h, [open.len(), hsz], dev)))
        };
        let mut targets: Vec<(usize, f32)> =
            runs.iter().map(|(row, _, c)| (*row, c.reward)).collect();
        for (m, &k) in open.iter().enumerate() {
            targets[k].1 += gamma.powi(runs[k].2.steps() as i32) * values[m];
        }
        Ok(targets)
    }
}

/// Every seat of `game` but `seat`.
fn partners_of(game: &Game, seat: Seat) -> Vec<Seat> {
    (0..game.config().players())
        .map(|s| Seat(s as u8))
        .filter(|&s| s != seat)
        .collect()
}

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    /// The first state of game `i`'s current episode (its deal) and the actions since.
    fn episode_so_far(&self, i: usize) -> (Game, &[u32]) {
        let seed = episode_seed(self.env_seed(), i, self.env.episodes(i));
        (Game::new(self.game, seed), &self.state.history[i])
    }

    /// Levels ≥ 2: every row's belief memory reads its observation of this step (`obs`, the
    /// network's input; `keep` 0 where an episode starts). Every seat's memory steps on
    /// every step, as it did on the previous level's games it learnt from.
    pub(super) fn step_belief_memory(&mut self, obs: &[f32], keep: &[f32]) {
        let Some(previous) = &self.previous else {
            return;
        };
        let graph = Encoding::Graph(Part::Full);
        let rows = keep.len();
        let l: usize = graph.shape(&self.game).iter().product();
        // The compact network reads the same graph observation; the paper's reads the image.
        let written;
        let obs = if E::encoding() == graph {
            obs
        } else {
            let p = self.game.players();
            let mut o = vec![0f32; rows * l];
            for r in 0..rows {
                graph
                    .write(
                        self.env.game(r / p),
                        Seat((r % p) as u8),
                        &mut o[r * l..][..l],
                    )
                    .expect("buffers sized from the same config");
            }
            written = o;
            &written
        };
        let dev = &self.infer_device;
        let hb = previous.belief.hidden_size();
        let h = previous.belief.step(
            tensor2(obs.to_vec(), [rows, l], dev),
            tensor2(
                std::mem::take(&mut self.state.belief_hidden),
                [rows, hb],
                dev,
            ),
            tensor2(keep.to_vec(), [rows, 1], dev),
        );
        self.state.belief_hidden = to_vec(h);
    }

    /// Levels ≥ 2: a colouring per game from the belief model, for its acting seat, from the
    /// memory that seat's real history built (`step_belief_memory`).
    fn sample_beliefs(
        &self,
        previous: &PreviousLevel,
        rng: &mut ChaCha8Rng,
    ) -> Result<Vec<Vec<Colour>>, TrainError> {
        let n = self.config.ppo.num_envs;
        let (y, p, game) = (self.game.cards(), self.game.players(), self.game);
        let hb = previous.belief.hidden_size();
        let dev = self.infer_device.clone();
        let graph = Encoding::Graph(Part::Full);
        let l: usize = graph.shape(&game).iter().product();
        let (mut obs, mut adjacency) = (vec![0f32; n * l], vec![0f32; n * y * y]);
        let mut first = Vec::with_capacity(n * y);
        let mut states = Vec::with_capacity(n * hb);
        for i in 0..n {
            let real = self.env.game(i);
            let seat = real.current_seat();
            let row = i * p + seat.index();
            states.extend_from_slice(&self.state.belief_hidden[row * hb..][..hb]);
            graph
                .write(real, seat, &mut obs[i * l..][..l])
                .expect("buffers sized from the same config");
            real.write_adjacency(&mut adjacency[i * y * y..][..y * y])
                .expect("buffers sized from the same config");
            first.extend(first_hand_slots(real, seat));
        }
        let states = tensor2(states, [n, hb], &dev);
        Ok(previous
            .belief
            .sample(&game, states, &obs, &adjacency, &first, rng))
    }

    /// Levels ≥ 2: every partner seat's memory of the previous level, rebuilt by replaying
    /// each game's episode in its fictitious colouring (`[partners × H]` per game).
    fn partner_memories(
        &self,
        previous: &PreviousLevel,
        colourings: &[Vec<Colour>],
    ) -> Result<Vec<Vec<f32>>, TrainError> {
        let n = self.config.ppo.num_envs;
        let policy = &previous.policy;
        let mut episodes = Vec::with_capacity(n);
        let mut seats = Vec::with_capacity(n);
        for (i, colours) in colourings.iter().enumerate() {
            let (start, history) = self.episode_so_far(i);
            let start = start
                .with_card_colours(colours)
                .map_err(|e| TrainError::Obl(format!("env {i}: belief sample: {e}")))?;
            let replayed = episode_states(start, history);
            let game = self.env.game(i);
            if game.with_card_colours(colours).ok().as_ref() != replayed.last() {
                return Err(TrainError::Obl(format!(
                    "env {i}: replaying the episode's {} actions does not reach its state",
                    history.len()
                )));
            }
            episodes.push(replayed);
            seats.push(partners_of(game, game.current_seat()));
        }
        let sequences: Vec<&[Game]> = episodes.iter().map(|e| &e[..]).collect();
        let mut states: Vec<Vec<f32>> = seats
            .iter()
            .map(|s| vec![0.0; s.len() * policy.hidden_size()])
            .collect();
        step_along(
            &sequences,
            &seats,
            &mut states,
            policy.encoding(),
            true,
            &mut |o, h, k| policy.recur_batch(o, h, k),
        );
        Ok(states)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::MlpEncoder;
    use crate::TrainConfig;
    use burn::module::Module;
    use yokai_agents::belief::colouring::all_colourings;
    use yokai_engine::{Action, Card, Colour};

    fn config() -> TrainConfig {
        let mut c = TrainConfig::from_toml_str(
            "[network]\npreset = \"compact\"\nhidden = 16\n[ppo]\nnum_envs = 8\n\
             rollout_steps = 8\nminibatches = 2\n[obl]\nlevel = 1\n[run]\nthreads = 1\n",
            "test",
        )
        .unwrap();
        c.ppo.total_steps = 64 * 4;
        c
    }

    /// Ending at the first step: the target is R_END in a world drawn from the seat's
    /// level-1 belief, which knows nothing yet, so over many draws its mean is the mean
    /// R_END over all 1,680 colourings of the game's start square (computed here by
    /// listing them), and no value is bootstrapped: the continuation ended.
    #[test]
    fn the_target_of_ending_at_the_start_is_the_mean_over_all_colourings() {
        let trainer = Trainer::<MlpEncoder>::new(config(), 3).unwrap();
        let net = trainer.model.valid();
        let game = *trainer.env.config();
        let end = game.encode(Action::End) as u32;
        let rows = trainer.rows;
        let joint: Vec<u32> = (0..rows)
            .map(|r| if r % 2 == 0 { end } else { 0 })
            .collect();
        // Per game: the mean and the variance of R_END over all colourings.
        let mut exact = [(0f64, 0f64); 8];
        let all = all_colourings(&game);
        for (i, e) in exact.iter_mut().enumerate() {
            let start = trainer.env.game(i);
            let rewards: Vec<f64> = all
                .iter()
                .map(|x| {
                    let colours: Vec<Colour> = (0..9).map(|k| x.colour_of(Card(k))).collect();
                    let mut g = start.with_card_colours(&colours).unwrap();
                    g.apply(Action::End).unwrap().reward as f64
                })
                .collect();
            let mean = rewards.iter().sum::<f64>() / rewards.len() as f64;
            let var =
                rewards.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / rewards.len() as f64;
            *e = (mean, var);
        }
        let draws = 3000;
        let mut sums = [0f64; 8];
        for t in 0..draws {
            let targets = trainer.obl_targets(&net, t, &joint, 1.0).unwrap();
            assert_eq!(targets.len(), 8, "one target per game");
            for (row, target) in targets {
                assert_eq!(row % 2, 0, "seat 0 acts first");
                sums[row / 2] += target as f64;
            }
        }
        for (i, sum) in sums.iter().enumerate() {
            let mean = sum / draws as f64;
            let (want, var) = exact[i];
            let se = (var / draws as f64).sqrt();
            assert!(
                (mean - want).abs() < 5.0 * se,
                "game {i}: mean target {mean:.3}, exact {want:.3} (SE {se:.3})"
            );
        }
    }
}

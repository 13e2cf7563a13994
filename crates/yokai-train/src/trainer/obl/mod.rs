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

mod previous;

pub(crate) use previous::PreviousLevel;

use super::{tensor2, to_vec, TrainError, Trainer};
use crate::network::{ActorCritic, Encoder, Recurrent};
use crate::obl::{
    continue_fictitiously, first_hand_slots, sample_first_hand_consistent, Continuation,
};
use previous::{replay_memory, Partner};
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
        let mut partner_states = match &self.previous {
            None => vec![Vec::new(); n],
            Some(previous) => self.partner_memories(previous, &colourings)?,
        };
        let mut runs: Vec<(usize, Seat, Continuation)> = Vec::with_capacity(n);
        for (i, colours) in colourings.iter().enumerate() {
            let game = self.env.game(i);
            let seat = game.current_seat();
            let row = i * p + seat.index();
            let mut partner = match &self.previous {
                None => Partner::Random(&mut partner_rng),
                Some(previous) => Partner::Previous {
                    policy: &previous.policy,
                    seats: partners_of(game, seat),
                    states: std::mem::take(&mut partner_states[i]),
                    rng: &mut partner_rng,
                },
            };
            let c = continue_fictitiously(
                game,
                colours,
                joint[row] as usize,
                &mut |g| partner.act(g),
                shaping,
                gamma,
                4 * p,
            )
            .map_err(|e| TrainError::Obl(format!("env {i}, step {t}: {e}")))?;
            runs.push((row, seat, c));
        }
        // Step each seat's memory through its fictitious observations, all continuations
        // still running at depth j in one batch; one that ended needs no value.
        let dev = &self.infer_device;
        let encoding = E::encoding();
        let mut states: Vec<Vec<f32>> = runs
            .iter()
            .map(|(row, _, _)| self.state.hidden[row * hsz..][..hsz].to_vec())
            .collect();
        let mut targets: Vec<(usize, f32)> =
            runs.iter().map(|(row, _, c)| (*row, c.reward)).collect();
        let depth = runs.iter().map(|r| r.2.steps()).max().unwrap_or(0);
        for j in 0..depth {
            let live: Vec<usize> = (0..runs.len())
                .filter(|&k| !runs[k].2.done && runs[k].2.steps() > j)
                .collect();
            if live.is_empty() {
                continue;
            }
            let mut obs = vec![0f32; live.len() * l];
            let mut h = Vec::with_capacity(live.len() * hsz);
            for (m, &k) in live.iter().enumerate() {
                let (_, seat, c) = &runs[k];
                encoding
                    .write(&c.states[j], *seat, &mut obs[m * l..][..l])
                    .expect("buffers sized from the same config");
                h.extend_from_slice(&states[k]);
            }
            let rows = live.len();
            let (out, h_new) = net.step(
                tensor2(obs, [rows, l], dev),
                tensor2(h, [rows, hsz], dev),
                tensor2(vec![1.0; rows], [rows, 1], dev),
            );
            let h_new = to_vec(h_new);
            let values = to_vec(out.values);
            for (m, &k) in live.iter().enumerate() {
                states[k].copy_from_slice(&h_new[m * hsz..][..hsz]);
                if runs[k].2.steps() == j + 1 {
                    // The seat acts again here: bootstrap from its value.
                    targets[k].1 += gamma.powi(j as i32 + 1) * values[m];
                }
            }
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
        let mut starts = Vec::with_capacity(n);
        let mut histories = Vec::with_capacity(n);
        let mut seats = Vec::with_capacity(n);
        for (i, colours) in colourings.iter().enumerate() {
            let (start, history) = self.episode_so_far(i);
            let start = start
                .with_card_colours(colours)
                .map_err(|e| TrainError::Obl(format!("env {i}: belief sample: {e}")))?;
            starts.push(start);
            histories.push(history);
            let game = self.env.game(i);
            seats.push(partners_of(game, game.current_seat()));
        }
        let policy = &previous.policy;
        let (replayed, states) = replay_memory(
            starts,
            &histories,
            &seats,
            policy.encoding(),
            policy.hidden_size(),
            &mut |o, h, k| policy.step_batch(o, h, k).1,
        );
        for (i, game) in replayed.iter().enumerate() {
            let real = self.env.game(i).with_card_colours(&colourings[i]);
            if real.as_ref() != Ok(game) {
                return Err(TrainError::Obl(format!(
                    "env {i}: replaying the episode's {} actions does not reach its state",
                    self.state.history[i].len()
                )));
            }
        }
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
        let mut exact = [0f64; 8];
        for (i, e) in exact.iter_mut().enumerate() {
            let start = trainer.env.game(i);
            let all = all_colourings(&game);
            for x in &all {
                let colours: Vec<Colour> = (0..9).map(|k| x.colour_of(Card(k))).collect();
                let mut g = start.with_card_colours(&colours).unwrap();
                *e += g.apply(Action::End).unwrap().reward as f64 / all.len() as f64;
            }
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
            // R_END lies in [−4, 20]; 20 / √3000 bounds 5 standard errors by 0.37.
            assert!(
                (mean - exact[i]).abs() < 0.37,
                "game {i}: mean target {mean:.3}, exact {:.3}",
                exact[i]
            );
        }
    }
}

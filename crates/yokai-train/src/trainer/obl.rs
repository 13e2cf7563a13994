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

use super::{tensor2, to_vec, TrainError, Trainer};
use crate::network::{ActorCritic, Encoder, Recurrent};
use crate::obl::continuation::uniform_random;
use crate::obl::{continue_fictitiously, sample_first_hand_consistent, Continuation};
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{derive_seed, Seat};

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
        let mut partner = uniform_random(&mut partner_rng);
        let mut runs: Vec<(usize, Seat, Continuation)> = Vec::with_capacity(n);
        for i in 0..n {
            let game = self.env.game(i);
            let seat = game.current_seat();
            let row = i * p + seat.index();
            let colours = sample_first_hand_consistent(game, seat, &mut rng);
            let c = continue_fictitiously(
                game,
                &colours,
                joint[row] as usize,
                &mut partner,
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

//! Off-Belief Learning in the rollout: the value target of every acting seat's action
//! comes from a fictitious continuation (`crate::obl`), not from the real game.
//!
//! At step t, for the acting seat i of each game: draw a colouring from i's belief, apply
//! i's action to the game recoloured so, let the partners play (`obl.partner`, below)
//! until i is to act again (or the game ends), and bootstrap from the learner's
//! value of i's memory after it has read its observations of those fictitious steps:
//!
//! `target = Σ_{j<k} γʲ r'_j + γᵏ V(h'_k)` (no bootstrap where the game ended), where
//! `h'_0` is i's state at t (after reading o_t) and `h'_{j+1} = GRU(h'_j, o'_{j+1})`.
//!
//! PPO then uses `target − V(h_t)` as the advantage of the action and `target` as the value
//! target of that row; the waiting seats' rows carry neither (their value loss is off), so
//! the critic learns the OBL value of the acting seats' histories only — the only values a
//! target ever reads.
//!
//! **Who plays the partners** (`obl.partner`). The project's training spec (docs/spec/
//! training.md, row OBL) has the level below play on in the continuation: uniformly random
//! play at level 1, the previous level's network above (`previous`); that is the default.
//! OBL's operator as the paper states it ("future actions will follow π_ℓ", §4) and the
//! reference implementation (every actor of a game shares the learning network's runner,
//! `pyhanabi/act_group.py`; `rlcc/r2d2_actor.cc` asks it for the partner's fictitious move)
//! have the policy being learnt play them: `obl.partner = "learner"`. The past enters
//! through the belief either way.

mod memory;
mod partners;
mod previous;

pub(crate) use previous::PreviousLevel;

use super::{tensor2, to_vec, TrainError, Trainer};
use crate::config::OblPartner;
use crate::network::{shards_on, ActorCritic, Encoder, Recurrent};
use crate::obl::{continue_all, first_hand_slots, sample_first_hand_consistent, Continuation};
use burn::prelude::Device;
use memory::{episode_states, step_along};
use partners::Partners;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{derive_seed, Card, Colour, Game, Part, Seat};
use yokai_vec::{episode_seed, Encoding};

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    /// The OBL value target of the acting row of every game at rollout step `t`, given each
    /// row's (true-frame) action in `joint`, the recurrent states after step t's observation
    /// in `self.state.hidden`, and the rollout's shaping weight.
    pub(super) fn obl_targets(
        &self,
        net: &ActorCritic<E, M>,
        t: usize,
        joint: &[u32],
        shaping: f32,
    ) -> Result<OblStep, TrainError> {
        let p = self.game.players();
        let n = self.config.ppo.num_envs;
        let gamma = self.config.ppo.gamma;
        let hsz = self.model.hidden_size();
        // One stream per (run, update, step): beliefs and partners' moves, in game order.
        let step = self.state.update * self.config.ppo.rollout_steps as u64 + t as u64;
        let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(derive_seed(self.seed, 0x0B1), step));
        let mut partner_rng =
            ChaCha8Rng::seed_from_u64(derive_seed(derive_seed(self.seed, 0x0B2), step));
        let colourings = match &self.previous {
            None if self.config.obl.oracle => {
                (0..n).map(|i| true_colours(self.env.game(i))).collect()
            }
            None => (0..n)
                .map(|i| {
                    let game = self.env.game(i);
                    sample_first_hand_consistent(game, game.current_seat(), &mut rng)
                })
                .collect(),
            Some(previous) => self.sample_beliefs(previous, &mut rng)?,
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
        // Partners play only where the action ends the seat's turn and not the game (after
        // OBSERVE or MOVE the seat acts again at once): only there are their memories built.
        let seats: Vec<Vec<Seat>> = starts
            .iter()
            .map(|&(g, _, a)| {
                let mut after = g.clone();
                let done = after.apply_index(a).map(|s| s.done).unwrap_or(true);
                if done || after.current_seat() == g.current_seat() {
                    Vec::new()
                } else {
                    partners_of(g, g.current_seat())
                }
            })
            .collect();
        let dev = &self.infer_device;
        let learner =
            |rows: &[(&Game, Seat)], states, keep| net.step_seats(rows, states, keep, dev);
        let previous = self.previous.as_ref().map(|p| &p.policy);
        let below = |rows: &[(&Game, Seat)], states, keep| {
            previous
                .expect("a level ≥ 2 run has a previous level")
                .step_seats(rows, states, keep)
        };
        let mut partners = match (self.config.obl.partner, previous) {
            (OblPartner::Previous, None) => Partners::Random(&mut partner_rng),
            (OblPartner::Previous, Some(policy)) => Partners::Network {
                step: &below,
                hidden: policy.hidden_size(),
                states: self.partner_memories(
                    &mut |o, h, k| policy.recur_batch(o, h, k),
                    policy.encoding(),
                    policy.hidden_size(),
                    &colourings,
                    &seats,
                )?,
                seats,
                rng: &mut partner_rng,
            },
            (OblPartner::Learner, _) => Partners::Network {
                step: &learner,
                hidden: hsz,
                states: self.partner_memories(
                    &mut |o, h, k| recur(net, o, h, k, dev),
                    E::encoding(),
                    hsz,
                    &colourings,
                    &seats,
                )?,
                seats,
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
            &mut |o, h, k| recur(net, o, h, k, dev),
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
        Ok(OblStep {
            targets,
            worlds: colourings,
        })
    }
}

/// What OBL computed at one rollout step.
pub(super) struct OblStep {
    /// (row, value target) of every game's acting row.
    pub targets: Vec<(usize, f32)>,
    /// Per game, the card colours drawn from the acting seat's belief: the world its
    /// fictitious continuation ran in, where the END term values ending too.
    pub worlds: Vec<Vec<Colour>>,
}

/// The colour of every card of `game`, by card id.
fn true_colours(game: &Game) -> Vec<Colour> {
    (0..game.config().cards())
        .map(|k| game.colour_of(Card(k as u8)))
        .collect()
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

    /// The memories of the partner seats `seats[i]` of each game `i` in the partners'
    /// network (its memory step `recur`, its observation `encoding`, memories of width
    /// `hidden`), rebuilt by replaying the game's episode in its fictitious colouring
    /// (`[seats × H]` per game; nothing where `seats[i]` is empty).
    ///
    /// The real memories read the real colours of the cards each partner observed; in a
    /// world drawn from the acting seat's belief those colours differ, so the real memory
    /// would carry facts of the real world into the fictitious one. The reference
    /// implementation (Hanabi) reuses the real memory, which is sound there only because its
    /// LSTM reads public features alone. The replay costs one batched network step per step
    /// of the episode so far, all games together.
    fn partner_memories(
        &self,
        recur: &mut dyn FnMut(Vec<f32>, Vec<f32>, Vec<f32>) -> Vec<f32>,
        encoding: Encoding,
        hidden: usize,
        colourings: &[Vec<Colour>],
        seats: &[Vec<Seat>],
    ) -> Result<Vec<Vec<f32>>, TrainError> {
        let mut episodes = Vec::with_capacity(seats.len());
        for (i, colours) in colourings.iter().enumerate() {
            if seats[i].is_empty() {
                episodes.push(Vec::new());
                continue;
            }
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
        }
        let sequences: Vec<&[Game]> = episodes.iter().map(|e| &e[..]).collect();
        let mut states: Vec<Vec<f32>> = seats.iter().map(|s| vec![0.0; s.len() * hidden]).collect();
        step_along(&sequences, seats, &mut states, encoding, true, recur);
        Ok(states)
    }
}

/// One memory step of `net` for the rows of `obs`, `states` and `keep` (flat, as in
/// [`ActorCritic::act`]), in one part per core.
fn recur<E: Encoder, M: Recurrent>(
    net: &ActorCritic<E, M>,
    obs: Vec<f32>,
    states: Vec<f32>,
    keep: Vec<f32>,
    device: &Device,
) -> Vec<f32> {
    net.act(&obs, &states, &keep, &[], device, shards_on(device))
        .states
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
            let targets = trainer.obl_targets(&net, t, &joint, 1.0).unwrap().targets;
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

    /// The partners' memories rebuilt by replaying each episode are the memories the
    /// rollout built, when the colouring replayed is the true one: after a rollout (games
    /// mid-episode and some just dealt), every partner seat's replayed memory equals its
    /// row of the rollout's state once that has read the current observation.
    #[test]
    fn partner_memories_replayed_in_the_true_colours_are_the_real_ones() {
        let mut c = config();
        c.ppo.rollout_steps = 13;
        let mut trainer = Trainer::<MlpEncoder>::new(c, 9).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        trainer.collect(1.0, &mut rng).unwrap();
        let net = trainer.model.valid();
        let (rows, l, na) = (trainer.rows, trainer.obs_len, trainer.n_actions);
        let (mut obs, mut masks) = (vec![0f32; rows * l], vec![0f32; rows * na]);
        trainer.view(&mut obs, &mut masks);
        let dev = trainer.infer_device.clone();
        let real = net
            .act(&obs, &trainer.state.hidden, &trainer.keeps(), &[], &dev, 1)
            .states;
        let truths: Vec<Vec<Colour>> = (0..8).map(|i| true_colours(trainer.env.game(i))).collect();
        let seats: Vec<Vec<Seat>> = (0..8)
            .map(|i| partners_of(trainer.env.game(i), trainer.env.game(i).current_seat()))
            .collect();
        let h = trainer.model.hidden_size();
        let replayed = trainer
            .partner_memories(
                &mut |o, s, k| recur(&net, o, s, k, &dev),
                MlpEncoder::encoding(),
                h,
                &truths,
                &seats,
            )
            .unwrap();
        let lengths: Vec<usize> = (0..8).map(|i| trainer.state.history[i].len()).collect();
        assert!(
            lengths.iter().any(|&n| n > 5),
            "some episode is long: {lengths:?}"
        );
        for i in 0..8 {
            let seat = seats[i][0].index();
            let want = &real[(2 * i + seat) * h..][..h];
            for (a, b) in replayed[i].iter().zip(want) {
                assert!(
                    (a - b).abs() < 1e-5,
                    "game {i} (episode of {}): {a} vs {b}",
                    lengths[i]
                );
            }
        }
    }

    /// `obl.partner` decides who plays the partners: where the seat's action ends its turn
    /// (substep 3) the partners move inside the continuation and the targets differ between
    /// random play (the level below level 1) and the learner; where the seat acts again at
    /// once (MOVE) they are the same.
    #[test]
    fn obl_partner_chooses_who_plays_the_partners() {
        use crate::config::OblPartner;
        use yokai_engine::Substep;
        // After `steps` rollout steps from the deals, one legal action of every game.
        let targets = |partner: OblPartner, steps: usize| {
            let mut c = config();
            c.ppo.rollout_steps = steps;
            c.obl.partner = partner;
            let mut trainer = Trainer::<MlpEncoder>::new(c, 6).unwrap();
            trainer
                .collect(1.0, &mut ChaCha8Rng::seed_from_u64(3))
                .unwrap();
            let mut joint = vec![0u32; trainer.rows];
            let mut ends_turn = Vec::new();
            for i in 0..8 {
                let g = trainer.env.game(i);
                let seat = g.current_seat();
                joint[2 * i + seat.index()] = g.config().encode(g.legal_actions(seat)[0]) as u32;
                ends_turn.push(g.substep() == Substep::Hint);
            }
            let net = trainer.model.valid();
            let step = trainer.obl_targets(&net, 0, &joint, 1.0).unwrap();
            (step.targets, ends_turn)
        };
        // Three steps in: every game is at its first REVEAL/PLACE.
        let (below, ends_turn) = targets(OblPartner::Previous, 3);
        let (learner, _) = targets(OblPartner::Learner, 3);
        assert!(ends_turn.iter().all(|&e| e), "{ends_turn:?}");
        for i in 0..8 {
            assert_ne!(
                below[i].1, learner[i].1,
                "game {i}: the partners' play made no difference"
            );
        }
        // Two steps in, at MOVE: the seat acts again at once, no partner moves.
        let (below, ends_turn) = targets(OblPartner::Previous, 2);
        let (learner, _) = targets(OblPartner::Learner, 2);
        assert!(ends_turn.iter().all(|&e| !e), "{ends_turn:?}");
        assert_eq!(below, learner);
    }

    /// `obl.oracle` runs every continuation in the true colours, where the exact belief
    /// draws other colourings.
    #[test]
    fn the_oracle_draws_the_true_colours() {
        let worlds = |oracle: bool| {
            let mut c = config();
            c.obl.oracle = oracle;
            let trainer = Trainer::<MlpEncoder>::new(c, 4).unwrap();
            let end = trainer.env.config().encode(Action::End) as u32;
            let net = trainer.model.valid();
            let step = trainer
                .obl_targets(&net, 0, &vec![end; trainer.rows], 1.0)
                .unwrap();
            let truths: Vec<Vec<Colour>> =
                (0..8).map(|i| true_colours(trainer.env.game(i))).collect();
            (step.worlds, truths)
        };
        let (drawn, truths) = worlds(true);
        assert_eq!(drawn, truths);
        let (drawn, truths) = worlds(false);
        assert!(
            drawn != truths,
            "the exact belief drew the true colouring in all 8 games"
        );
    }

    /// With the END term on, what END would pay at a rollout step is read in the world the
    /// step's OBL continuation was drawn in, not on the true board: at the first step every
    /// game's END reward is that world's R_END, and some differ from the true board's.
    #[test]
    fn the_end_term_values_ending_in_the_world_drawn_from_the_belief() {
        let mut c = config();
        c.ppo.end_lookahead = 0.5;
        let drawn = Trainer::<MlpEncoder>::new(c.clone(), 5).unwrap();
        let net = drawn.model.valid();
        // The worlds depend on the games and the step's stream only, not on the actions.
        let end = drawn.env.config().encode(Action::End) as u32;
        let worlds = drawn
            .obl_targets(&net, 0, &vec![end; drawn.rows], 1.0)
            .unwrap()
            .worlds;
        let mut trainer = Trainer::<MlpEncoder>::new(c, 5).unwrap();
        let truths: Vec<i32> = (0..8).map(|i| trainer.env.game(i).end_reward()).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let rollout = trainer.collect(1.0, &mut rng).unwrap();
        let mut differ = 0;
        for (i, colours) in worlds.iter().enumerate() {
            let start = drawn.env.game(i);
            let want = start.with_card_colours(colours).unwrap().end_reward();
            let row = 2 * i + start.current_seat().index();
            assert_eq!(rollout.end_rewards[row], want as f32, "game {i}");
            differ += (want != truths[i]) as usize;
        }
        assert!(
            differ > 0,
            "every world paid what the true board pays: {truths:?}"
        );
    }
}

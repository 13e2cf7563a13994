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
//! With `obl.decisions` = n > 1 the continuation runs on until i is to act for the n-th
//! time, the learner playing i's moves in between from `h'_j` (and its partners).
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

use super::Trainer;
use crate::config::OblPartner;
use crate::error::TrainError;
use crate::network::{ActorCritic, Encoder, Recurrent};
use crate::obl::{continue_all, first_hand_slots, sample_first_hand_consistent, Continuation};
use crate::tensor::{tensor2, to_vec};
use memory::step_along;
use partners::{Learner, PartnerNet, Partners};
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{derive_seed, Colour, Game, Part, Seat};
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
            None if self.config.obl.oracle => (0..n)
                .map(|i| self.env.game(i).deal().card_colours)
                .collect(),
            None => (0..n)
                .map(|i| {
                    let game = self.env.game(i);
                    sample_first_hand_consistent(game, game.current_seat(), &mut rng)
                })
                .collect(),
            Some(previous) => self.sample_beliefs(previous, &mut rng)?,
        };
        // Each game recoloured with its draw, once: the world its continuation runs in, which
        // the partners' replay must reach and where the END term values ending.
        let worlds = (0..n)
            .map(|i| {
                self.env
                    .game(i)
                    .with_card_colours(&colourings[i])
                    .map_err(|e| TrainError::Obl(format!("env {i}, step {t}: belief sample: {e}")))
            })
            .collect::<Result<Vec<Game>, _>>()?;
        let starts: Vec<(&Game, usize)> = worlds
            .iter()
            .enumerate()
            .map(|(i, w)| (w, joint[i * p + w.current_seat().index()] as usize))
            .collect();
        // The seat's own memory is the learner's, so where the learner plays the partners
        // (`obl.partner = "learner"`, and so every config with more than one decision) the
        // seat steps in the same batch as they do, first in its continuation's rows, from its
        // memory at t: that holds in the drawn world as it is (the draw keeps every colour the
        // seat has seen). Partners play only where the seat's action ends its turn and not the
        // game (after OBSERVE or MOVE the seat acts again at once), unless the seat plays on
        // for more decisions: only there are their memories replayed.
        let decisions = self.config.obl.decisions as usize;
        let rides = self.config.obl.partner == OblPartner::Learner;
        let seats: Vec<Vec<Seat>> = starts
            .iter()
            .map(|&(g, a)| {
                let mut after = g.clone();
                let seat = g.current_seat();
                if after.apply_index(a).map(|s| s.done).unwrap_or(true) {
                    return Vec::new();
                }
                let mut rows = if rides { vec![seat] } else { Vec::new() };
                if decisions > 1 || after.current_seat() != seat {
                    rows.extend(partners_of(g, seat));
                }
                rows
            })
            .collect();
        let dev = &self.infer_device;
        let learner = Learner { net, device: dev };
        let network: Option<&dyn PartnerNet> = match (self.config.obl.partner, &self.previous) {
            (OblPartner::Learner, _) => Some(&learner),
            (OblPartner::Previous, Some(previous)) => Some(&previous.policy),
            (OblPartner::Previous, None) => None,
        };
        let mut partners = match network {
            None => Partners::Random(&mut partner_rng),
            Some(net) => {
                let own = rides as usize;
                let others: Vec<Vec<Seat>> = seats
                    .iter()
                    .map(|s| s[own.min(s.len())..].to_vec())
                    .collect();
                let mut states = self.partner_memories(net, &colourings, &worlds, &others)?;
                for (i, state) in states.iter_mut().enumerate() {
                    if rides && !seats[i].is_empty() {
                        let seat = self.acting_memory(i, starts[i].0.current_seat());
                        state.splice(0..0, seat.iter().copied());
                    }
                }
                Partners::Network {
                    net,
                    states,
                    seats,
                    rng: &mut partner_rng,
                }
            }
        };
        let continued = continue_all(
            &starts,
            &mut |which, games| partners.act(which, games),
            shaping,
            gamma,
            decisions,
            4 * p * decisions,
        )
        .map_err(|(i, e)| TrainError::Obl(format!("env {i}, step {t}: {e}")))?;
        let runs: Vec<(usize, Seat, Continuation)> = starts
            .iter()
            .zip(continued)
            .enumerate()
            .map(|(i, ((g, _), c))| (i * p + g.current_seat().index(), g.current_seat(), c))
            .collect();
        // Each seat's memory reads its observations of the fictitious steps, from its state at
        // t; a continuation that ended needs no value, so its seat reads nothing. Where the
        // seat stepped beside its partners, the network has read every state but the last
        // (its rows are empty only where the action ended the game).
        let mut states: Vec<Vec<f32>> = match partners.into_states() {
            Some(network) if rides => network
                .into_iter()
                .map(|mut m| {
                    m.truncate(hsz);
                    m
                })
                .collect(),
            _ => runs
                .iter()
                .enumerate()
                .map(|(i, (_, seat, _))| self.acting_memory(i, *seat).to_vec())
                .collect(),
        };
        let sequences: Vec<&[Game]> = runs
            .iter()
            .map(|(_, _, c)| &c.states[if rides { c.steps() - 1 } else { 0 }..])
            .collect();
        let seats: Vec<Vec<Seat>> = runs
            .iter()
            .map(|(_, seat, c)| if c.done { Vec::new() } else { vec![*seat] })
            .collect();
        step_along(
            &sequences,
            &seats,
            &mut states,
            E::encoding(),
            false,
            &mut |o, h, k| learner.recur(o, h, k),
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
        Ok(OblStep { targets, worlds })
    }
}

/// What OBL computed at one rollout step.
pub(super) struct OblStep {
    /// (row, value target) of every game's acting row.
    pub targets: Vec<(usize, f32)>,
    /// Per game, the game recoloured with the draw from the acting seat's belief: the world
    /// its fictitious continuation ran in, where the END term values ending too.
    pub worlds: Vec<Game>,
}

/// Every seat of `game` but `seat`.
fn partners_of(game: &Game, seat: Seat) -> Vec<Seat> {
    (0..game.config().players())
        .map(|s| Seat(s as u8))
        .filter(|&s| s != seat)
        .collect()
}

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    /// The learner's memory of `seat` in game `i` after it read this step's observation.
    fn acting_memory(&self, i: usize, seat: Seat) -> &[f32] {
        let hsz = self.model.hidden_size();
        let row = i * self.game.players() + seat.index();
        &self.state.hidden[row * hsz..][..hsz]
    }

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
}

#[cfg(test)]
mod tests;

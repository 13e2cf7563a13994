//! Off-Belief Learning's value targets in a PPO rollout: the value target of every acting
//! seat's action comes from a fictitious continuation ([`super::continuation`]), not from
//! the real game.
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

use super::memory::step_along;
use super::partners::{partner_memories, Learner, PartnerNet, Partners};
use super::previous::PreviousLevel;
use super::{continue_all, sample_first_hand_consistent, Continuation};
use crate::actor::Actor;
use crate::config::{OblPartner, TrainConfig};
use crate::error::TrainError;
use crate::network::{ActorCritic, Encoder, Recurrent};
use crate::tensor::{tensor2, to_vec};
use burn::prelude::Device;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{derive_seed, Colour, Game, Seat};

/// Everything one rollout step's targets read, named.
pub(crate) struct StepInputs<'a, E: Encoder, M: Recurrent> {
    /// The run's config (`obl`, and `ppo.gamma`).
    pub config: &'a TrainConfig,
    /// The run's seed and the step's index over the run (update · T + t): the beliefs' and
    /// the partners' draws are a function of both.
    pub seed: u64,
    pub step: u64,
    /// The real games, each row's memory after it read step t's observation, and each
    /// game's actions so far.
    pub actor: &'a Actor,
    /// The learner's network, on `device`.
    pub net: &'a ActorCritic<E, M>,
    pub device: &'a Device,
    /// Levels ≥ 2: the level below and its belief.
    pub previous: Option<&'a PreviousLevel>,
    /// Each row's (true-frame) action at this step.
    pub joint: &'a [u32],
    /// The rollout's shaping weight.
    pub shaping: f32,
}

/// The OBL value target of the acting row of every game at one rollout step, in four
/// phases: draw a world per game from the acting seat's belief; decide who steps in each
/// continuation; play the continuations; bootstrap from the seat's value where it acts
/// again.
pub(crate) fn targets<E: Encoder, M: Recurrent>(
    inputs: StepInputs<'_, E, M>,
) -> Result<OblStep, TrainError> {
    let (config, step, actor) = (inputs.config, inputs.step, inputs.actor);
    let p = actor.env().config().players();
    let t = step % config.ppo.rollout_steps as u64;
    // One stream per (run, update, step): beliefs and partners' moves, in game order.
    let stream =
        |salt| ChaCha8Rng::seed_from_u64(derive_seed(derive_seed(inputs.seed, salt), step));
    let mut partner_rng = stream(0x0B2);
    // 1. Worlds.
    let (colourings, worlds) = inputs.draw_worlds(&mut stream(0x0B1), t)?;
    let starts: Vec<(&Game, usize)> = worlds
        .iter()
        .enumerate()
        .map(|(i, w)| (w, inputs.joint[i * p + w.current_seat().index()] as usize))
        .collect();
    // 2. Who steps: the seat's own memory is the learner's, so where the learner plays the
    // partners (`obl.partner = "learner"`, and so every config with more than one
    // decision) the seat steps in the same batch as they do, first in its continuation's
    // rows, from its memory at t: that holds in the drawn world as it is (the draw keeps
    // every colour the seat has seen).
    let rides = config.obl.partner == OblPartner::Learner;
    let decisions = config.obl.decisions as usize;
    let seats: Vec<Vec<Seat>> = starts
        .iter()
        .map(|&(g, a)| stepping_seats(g, a, rides, decisions))
        .collect();
    let learner = Learner {
        net: inputs.net,
        device: inputs.device,
    };
    let network: Option<&dyn PartnerNet> = match (config.obl.partner, inputs.previous) {
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
            let mut states = partner_memories(actor, net, &colourings, &worlds, &others)?;
            for (i, state) in states.iter_mut().enumerate() {
                if rides && !seats[i].is_empty() {
                    let seat = actor.memory_of(i, starts[i].0.current_seat());
                    state.splice(0..0, seat.iter().copied());
                }
            }
            Partners::Network {
                net,
                states,
                seats,
                symmetries: actor.symmetries(),
                rng: &mut partner_rng,
            }
        }
    };
    // 3. The continuations.
    let continued = continue_all(
        &starts,
        &mut |which, games| partners.act(which, games),
        inputs.shaping,
        config.ppo.gamma,
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
    // 4. Bootstrap.
    let ridden = partners.into_states().filter(|_| rides);
    let targets = inputs.bootstrap(&learner, runs, ridden);
    Ok(OblStep { targets, worlds })
}

/// The seats whose memories step in the continuation of the action `a` in world `g`: none
/// where the action ends the game; the seat itself first where it `rides` with its
/// partners; the partners where the action ends the seat's turn (after OBSERVE or MOVE the
/// seat acts again at once), or where the seat plays on for more `decisions`.
fn stepping_seats(g: &Game, a: usize, rides: bool, decisions: usize) -> Vec<Seat> {
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
}

impl<E: Encoder, M: Recurrent> StepInputs<'_, E, M> {
    /// A colouring per game from its acting seat's belief (exact at level 1, the belief
    /// model above, the true one with `obl.oracle`), and each game recoloured with it: the
    /// world its continuation runs in, which the partners' replay must reach and where the
    /// END term values ending.
    #[allow(clippy::type_complexity)]
    fn draw_worlds(
        &self,
        rng: &mut ChaCha8Rng,
        t: u64,
    ) -> Result<(Vec<Vec<Colour>>, Vec<Game>), TrainError> {
        let actor = self.actor;
        let n = actor.env().num_envs();
        let colourings: Vec<Vec<Colour>> = match self.previous {
            None if self.config.obl.oracle => {
                (0..n).map(|i| actor.game(i).deal().card_colours).collect()
            }
            None => (0..n)
                .map(|i| {
                    let game = actor.game(i);
                    sample_first_hand_consistent(game, game.current_seat(), rng)
                })
                .collect(),
            Some(previous) => previous.sample_beliefs(actor, self.device, rng),
        };
        let worlds = (0..n)
            .map(|i| {
                (actor.game(i).with_card_colours(&colourings[i]))
                    .map_err(|e| TrainError::Obl(format!("env {i}, step {t}: belief sample: {e}")))
            })
            .collect::<Result<Vec<Game>, _>>()?;
        Ok((colourings, worlds))
    }

    /// The targets of the continuations `runs` (row, seat, continuation): the discounted
    /// reward, plus where the game goes on the learner's value of the seat's memory once it
    /// has read its observations of the fictitious steps, from its state at t. Where the
    /// seat `ridden` beside its partners, the network has read every state but the last;
    /// a continuation that ended needs no value, so its seat reads nothing.
    fn bootstrap(
        &self,
        learner: &Learner<'_, E, M>,
        runs: Vec<(usize, Seat, Continuation)>,
        ridden: Option<Vec<Vec<f32>>>,
    ) -> Vec<(usize, f32)> {
        let hsz = self.net.hidden_size();
        let gamma = self.config.ppo.gamma;
        let rides = ridden.is_some();
        let mut states: Vec<Vec<f32>> = match ridden {
            Some(network) => network
                .into_iter()
                .map(|mut m| {
                    m.truncate(hsz);
                    m
                })
                .collect(),
            None => runs
                .iter()
                .enumerate()
                .map(|(i, (_, seat, _))| self.actor.memory_of(i, *seat).to_vec())
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
            &self.actor.symmetries(),
            &mut states,
            E::encoding(),
            false,
            &mut |o, h, k| learner.recur(o, h, k),
        );
        let open: Vec<usize> = (0..runs.len()).filter(|&k| !runs[k].2.done).collect();
        let values = if open.is_empty() {
            Vec::new()
        } else {
            let h: Vec<f32> = open
                .iter()
                .flat_map(|&k| states[k].iter().copied())
                .collect();
            to_vec(
                self.net
                    .values(tensor2(h, [open.len(), hsz], self.device), None),
            )
        };
        let mut targets: Vec<(usize, f32)> =
            runs.iter().map(|(row, _, c)| (*row, c.reward)).collect();
        for (m, &k) in open.iter().enumerate() {
            targets[k].1 += gamma.powi(runs[k].2.steps() as i32) * values[m];
        }
        targets
    }
}

/// What OBL computed at one rollout step.
pub(crate) struct OblStep {
    /// (row, value target) of every game's acting row.
    pub targets: Vec<(usize, f32)>,
    /// Per game, the game recoloured with the draw from the acting seat's belief: the world
    /// its fictitious continuation ran in, where the END term values ending too.
    pub worlds: Vec<Game>,
}

/// Every seat of `game` but `seat`.
pub(crate) fn partners_of(game: &Game, seat: Seat) -> Vec<Seat> {
    (0..game.config().players())
        .map(|s| Seat(s as u8))
        .filter(|&s| s != seat)
        .collect()
}

//! The partners' moves inside OBL's fictitious continuations (`obl.partner`): the level
//! below (the spec's rule: uniformly random play at level 1, the previous level's network
//! above) or the policy being learnt (the reference implementation's), with each partner
//! seat's memory rebuilt in the fictitious world (`partner_memories`).

use super::memory::{episode_states, step_along};
use crate::distribution::sample_legal;
use crate::network::{Encoder, Recurrent, SeatStep};
use crate::obl::continuation::random_legal;
use crate::trainer::{TrainError, Trainer};
use rand_chacha::ChaCha8Rng;
use yokai_engine::{Colour, Game, Seat};
use yokai_vec::Encoding;

/// One network step for seats of games, their memories and `keep` flags
/// ([`crate::network::ActorCritic::step_seats`] of whichever network plays the partners).
pub(super) type StepSeats<'a> = dyn Fn(&[(&Game, Seat)], Vec<f32>, Vec<f32>) -> SeatStep + 'a;

/// Who plays the partners' turns in the fictitious continuations of one rollout step.
pub(super) enum Partners<'a> {
    /// Level 0 below level 1: uniformly random legal play.
    Random(&'a mut ChaCha8Rng),
    /// A network (`step`, memories of width `hidden`): per continuation, its partner seats
    /// and their memories (`[seats × H]`). Every partner seat's memory reads each state; the
    /// acting one samples from its logits, as the rollout's seats do.
    Network {
        step: &'a StepSeats<'a>,
        hidden: usize,
        seats: Vec<Vec<Seat>>,
        states: Vec<Vec<f32>>,
        rng: &'a mut ChaCha8Rng,
    },
}

impl Partners<'_> {
    /// The acting seat's action index in each of `games`, the fictitious games of the
    /// continuations `which` (a partner of the seat each continuation is for). A network
    /// steps every partner seat of them in one batch.
    pub fn act(&mut self, which: &[usize], games: &[&Game]) -> Vec<usize> {
        match self {
            Partners::Random(rng) => games.iter().map(|g| random_legal(g, rng)).collect(),
            Partners::Network {
                step,
                hidden,
                seats,
                states,
                rng,
            } => {
                let rows: Vec<(&Game, Seat)> = which
                    .iter()
                    .zip(games)
                    .flat_map(|(&k, &g)| seats[k].iter().map(move |&s| (g, s)))
                    .collect();
                let memories = which
                    .iter()
                    .flat_map(|&k| std::mem::take(&mut states[k]))
                    .collect();
                let stepped = step(&rows, memories, vec![1.0; rows.len()]);
                let h = *hidden;
                let mut at = 0;
                let mut actions = Vec::with_capacity(games.len());
                for (&k, &game) in which.iter().zip(games) {
                    let m = seats[k].len();
                    states[k] = stepped.states[at * h..(at + m) * h].to_vec();
                    let j = seats[k]
                        .iter()
                        .position(|&s| s == game.current_seat())
                        .expect("the continuation asks only for partners' actions");
                    let logits = stepped.logits(at + j).expect("the acting seat");
                    actions.push(sample_legal(game, logits, rng));
                    at += m;
                }
                actions
            }
        }
    }
}

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
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
    pub(super) fn partner_memories(
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

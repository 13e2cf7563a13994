//! The partners' moves inside OBL's fictitious continuations: the policy being learnt,
//! with each partner seat's memory rebuilt in the fictitious world (`partner_memories`).

use crate::distribution::sample_legal;
use crate::network::{ActorCritic, Encoder, Recurrent};
use burn::prelude::*;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{Game, Seat};

/// Who plays the partners' turns in the fictitious continuations of one rollout step: the
/// learner's network `net`, per continuation its partner seats and their memories
/// (`[seats × H]`). Every partner seat's memory reads each state; the acting one samples
/// from its logits, as the rollout's seats do.
pub(super) struct Partners<'a, E: Encoder, M: Recurrent> {
    pub net: &'a ActorCritic<E, M>,
    pub device: &'a Device,
    pub seats: Vec<Vec<Seat>>,
    pub states: Vec<Vec<f32>>,
    pub rng: &'a mut ChaCha8Rng,
}

impl<E: Encoder, M: Recurrent> Partners<'_, E, M> {
    /// The acting seat's action index in each of `games`, the fictitious games of the
    /// continuations `which` (a partner of the seat each continuation is for). The network
    /// steps every partner seat of them in one batch.
    pub fn act(&mut self, which: &[usize], games: &[&Game]) -> Vec<usize> {
        let rows: Vec<(&Game, Seat)> = which
            .iter()
            .zip(games)
            .flat_map(|(&k, &g)| self.seats[k].iter().map(move |&s| (g, s)))
            .collect();
        let memories = which
            .iter()
            .flat_map(|&k| std::mem::take(&mut self.states[k]))
            .collect();
        let stepped = self
            .net
            .step_seats(&rows, memories, vec![1.0; rows.len()], self.device);
        let h = self.net.hidden_size();
        let mut at = 0;
        let mut actions = Vec::with_capacity(games.len());
        for (&k, &game) in which.iter().zip(games) {
            let m = self.seats[k].len();
            self.states[k] = stepped.states[at * h..(at + m) * h].to_vec();
            let j = self.seats[k]
                .iter()
                .position(|&s| s == game.current_seat())
                .expect("the continuation asks only for partners' actions");
            let logits = stepped.logits(at + j).expect("the acting seat");
            actions.push(sample_legal(game, logits, self.rng));
            at += m;
        }
        actions
    }
}

//! The partners' moves inside OBL's fictitious continuations (`obl.partner`): the level
//! below (the spec's rule: uniformly random play at level 1, the previous level's network
//! above) or the policy being learnt (the reference implementation's), with each partner
//! seat's memory rebuilt in the fictitious world (`partner_memories`).

use super::continuation::random_legal;
use super::memory::{episode_states, step_along};
use crate::actor::Actor;
use crate::distribution::sample_seen;
use crate::error::TrainError;
use crate::network::{shards_on, ActorCritic, Encoder, Recurrent, SeatStep};
use crate::policy::TrainedPolicy;
use crate::seen::SeenSeat;
use burn::prelude::Device;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{Colour, Game, Seat, Symmetry};
use yokai_vec::Encoding;

/// A network that can play the partners: the previous level's policy, or the learner's own
/// network on its device ([`Learner`]).
pub(crate) trait PartnerNet {
    /// [`ActorCritic::step_views`]: every seat's memory steps, the acting seats' logits (in
    /// each seat's view).
    fn step_views(&self, rows: &[SeenSeat], states: Vec<f32>, keep: Vec<f32>) -> SeatStep;
    /// One memory step of flat rows (observations, states, keep).
    fn recur(&self, obs: Vec<f32>, states: Vec<f32>, keep: Vec<f32>) -> Vec<f32>;
    fn encoding(&self) -> Encoding;
    fn hidden_size(&self) -> usize;
}

impl PartnerNet for TrainedPolicy {
    fn step_views(&self, rows: &[SeenSeat], states: Vec<f32>, keep: Vec<f32>) -> SeatStep {
        TrainedPolicy::step_views(self, rows, states, keep)
    }
    fn recur(&self, obs: Vec<f32>, states: Vec<f32>, keep: Vec<f32>) -> Vec<f32> {
        self.recur_batch(obs, states, keep)
    }
    fn encoding(&self) -> Encoding {
        TrainedPolicy::encoding(self)
    }
    fn hidden_size(&self) -> usize {
        TrainedPolicy::hidden_size(self)
    }
}

/// The learner's network on the device it acts on.
pub(crate) struct Learner<'a, E: Encoder, M: Recurrent> {
    pub net: &'a ActorCritic<E, M>,
    pub device: &'a Device,
}

impl<E: Encoder, M: Recurrent> PartnerNet for Learner<'_, E, M> {
    fn step_views(&self, rows: &[SeenSeat], states: Vec<f32>, keep: Vec<f32>) -> SeatStep {
        self.net.step_views(rows, states, keep, self.device)
    }
    /// In one part per core, as the rollout acts ([`ActorCritic::act`], no logits).
    fn recur(&self, obs: Vec<f32>, states: Vec<f32>, keep: Vec<f32>) -> Vec<f32> {
        let shards = shards_on(self.device);
        self.net
            .act(&obs, &states, &keep, &[], self.device, shards)
            .states
    }
    fn encoding(&self) -> Encoding {
        E::encoding()
    }
    fn hidden_size(&self) -> usize {
        self.net.hidden_size()
    }
}

/// Who plays the partners' turns in the fictitious continuations of one rollout step.
pub(crate) enum Partners<'a> {
    /// Level 0 below level 1: uniformly random legal play.
    Random(&'a mut ChaCha8Rng),
    /// A network: per continuation, its partner seats and their memories (`[seats × H]`).
    /// Every partner seat's memory reads each state, seen through the seat's symmetry
    /// (`symmetries`, in the actor's row order: the real game's, [`Actor::symmetries`]);
    /// the acting one samples from its logits in that view, as the rollout's seats do.
    Network {
        net: &'a dyn PartnerNet,
        seats: Vec<Vec<Seat>>,
        symmetries: Vec<Symmetry>,
        states: Vec<Vec<f32>>,
        rng: &'a mut ChaCha8Rng,
    },
}

impl Partners<'_> {
    /// A network's memories of each continuation's seats after the play (`None` for random
    /// play, which has none).
    pub fn into_states(self) -> Option<Vec<Vec<f32>>> {
        match self {
            Partners::Random(_) => None,
            Partners::Network { states, .. } => Some(states),
        }
    }

    /// The acting seat's action index in each of `games`, the fictitious games of the
    /// continuations `which` (a partner of the seat each continuation is for). A network
    /// steps every partner seat of them in one batch.
    pub fn act(&mut self, which: &[usize], games: &[&Game]) -> Vec<usize> {
        match self {
            Partners::Random(rng) => games.iter().map(|g| random_legal(g, rng)).collect(),
            Partners::Network {
                net,
                seats,
                symmetries,
                states,
                rng,
            } => {
                let p = games.first().map_or(0, |g| g.config().players());
                let rows: Vec<SeenSeat> = which
                    .iter()
                    .zip(games)
                    .flat_map(|(&k, &game)| {
                        let symmetries = &*symmetries;
                        seats[k].iter().map(move |&seat| SeenSeat {
                            game,
                            seat,
                            symmetry: symmetries[k * p + seat.index()],
                        })
                    })
                    .collect();
                let memories = which
                    .iter()
                    .flat_map(|&k| std::mem::take(&mut states[k]))
                    .collect();
                let stepped = net.step_views(&rows, memories, vec![1.0; rows.len()]);
                let h = net.hidden_size();
                let mut at = 0;
                let mut actions = Vec::with_capacity(games.len());
                for &k in which {
                    let m = seats[k].len();
                    states[k] = stepped.states[at * h..(at + m) * h].to_vec();
                    let j = (0..m)
                        .find(|&j| rows[at + j].acts())
                        .expect("the continuation asks only for the seats given rows");
                    let logits = stepped.logits(at + j).expect("the acting seat");
                    actions.push(sample_seen(&rows[at + j], logits, rng));
                    at += m;
                }
                actions
            }
        }
    }
}

/// The memories, in `net`, of the partner seats `seats[i]` of each game `i`, rebuilt by
/// replaying the game's episode in its fictitious colouring `colourings[i]`, which must
/// reach `worlds[i]`, the game recoloured (`[seats × H]` per game; nothing where
/// `seats[i]` is empty).
///
/// The real memories read the real colours of the cards each partner observed; in a
/// world drawn from the acting seat's belief those colours differ, so the real memory
/// would carry facts of the real world into the fictitious one. The reference
/// implementation (Hanabi) reuses the real memory, which is sound there only because its
/// LSTM reads public features alone. The replay costs one batched network step per step
/// of the episode so far, all games together.
pub(crate) fn partner_memories(
    actor: &Actor,
    net: &dyn PartnerNet,
    colourings: &[Vec<Colour>],
    worlds: &[Game],
    seats: &[Vec<Seat>],
) -> Result<Vec<Vec<f32>>, TrainError> {
    let mut episodes = Vec::with_capacity(seats.len());
    for (i, colours) in colourings.iter().enumerate() {
        if seats[i].is_empty() {
            episodes.push(Vec::new());
            continue;
        }
        let (start, history) = actor.episode_so_far(i);
        let start = start
            .with_card_colours(colours)
            .map_err(|e| TrainError::Obl(format!("env {i}: belief sample: {e}")))?;
        let replayed = episode_states(start, history);
        if replayed.last() != Some(&worlds[i]) {
            return Err(TrainError::Obl(format!(
                "env {i}: replaying the episode's {} actions does not reach its state",
                history.len()
            )));
        }
        episodes.push(replayed);
    }
    let sequences: Vec<&[Game]> = episodes.iter().map(|e| &e[..]).collect();
    let hidden = net.hidden_size();
    let mut states: Vec<Vec<f32>> = seats.iter().map(|s| vec![0.0; s.len() * hidden]).collect();
    step_along(
        &sequences,
        seats,
        &actor.symmetries(),
        &mut states,
        net.encoding(),
        true,
        &mut |o, h, k| net.recur(o, h, k),
    );
    Ok(states)
}

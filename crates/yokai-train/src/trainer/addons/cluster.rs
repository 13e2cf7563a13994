//! `ppo.cluster_shaping`: a reward for every colour that becomes clustered (and a cost for
//! every one that stops being), paid at each step but a game's last, weighed by the
//! shaping's annealed weight. It adds to the reward only: no column, no loss term.

use crate::actor::Actor;
use crate::config::PpoConfig;

#[derive(Clone, Debug)]
pub(in crate::trainer) struct ClusterShaping {
    weight: f32,
}

/// A rollout's tally: per game, its clustered colours after the last step.
pub(in crate::trainer) struct ClusterTally {
    weight: f32,
    clustered: Vec<f32>,
    /// Net change in clustered colours paid so far, unweighted.
    pub paid: f64,
}

impl ClusterShaping {
    pub fn from_config(c: &PpoConfig) -> Option<ClusterShaping> {
        (c.cluster_shaping > 0.0).then_some(ClusterShaping {
            weight: c.cluster_shaping,
        })
    }

    /// Start a rollout whose shaping weight is `shaping` (`None` once it has annealed to 0).
    pub fn start(&self, shaping: f64, actor: &Actor) -> Option<ClusterTally> {
        let weight = shaping as f32 * self.weight;
        (weight > 0.0).then(|| ClusterTally {
            weight,
            clustered: (0..actor.env().num_envs())
                .map(|i| actor.game(i).clustered_colours() as f32)
                .collect(),
            paid: 0.0,
        })
    }
}

impl ClusterTally {
    /// Game `i`'s shaping for the step just taken (`done`: the game ended with it, and has
    /// been dealt again, so it gets none).
    pub fn reward(&mut self, actor: &Actor, i: usize, done: bool) -> Option<f32> {
        let after = actor.game(i).clustered_colours() as f32;
        let change = after - self.clustered[i];
        self.clustered[i] = after;
        // A finished game's last step keeps the game's reward, which counts the clustered
        // colours itself.
        if done {
            return None;
        }
        self.paid += change as f64;
        Some(self.weight * change)
    }
}

//! The add-ons to PPO a config can switch on. Each is one unit that owns its part of every
//! phase: what it records in the rollout (its column), what it gathers into a minibatch
//! shard, and its term of the loss (or, for a reward add-on, its share of the reward). The
//! PPO core asks each unit that is on and knows nothing of what it computes; a new add-on
//! is a new file here and a line at each of those places.
//!
//! - [`end`]: the END entropy bonus and the END term (`ppo.end_entropy_coef`,
//!   `ppo.end_lookahead`), which read what ending would pay.
//! - [`belief_aux`]: the auxiliary belief loss (`ppo.belief_aux`).
//! - [`entropy`]: each row's entropy divided by ln(its legal actions)
//!   (`ppo.entropy_normalized`).
//! - [`cluster`]: the clustering shaping reward (`ppo.cluster_shaping`).
//! - [`belief_gain`]: the reward for what the team comes to know of the colours
//!   (`ppo.belief_gain`), read from the colour layer of [`belief_aux`].

pub(super) mod belief_aux;
pub(super) mod belief_gain;
pub(super) mod cluster;
pub(super) mod end;
pub(super) mod entropy;

use crate::config::PpoConfig;
use belief_aux::BeliefAux;
use belief_gain::BeliefGain;
use cluster::ClusterShaping;
use end::EndAddOn;
use entropy::NormalizedEntropy;

/// The add-ons a config switches on (`None`: off).
#[derive(Clone, Debug, Default)]
pub(super) struct AddOns {
    pub end: Option<EndAddOn>,
    pub belief: Option<BeliefAux>,
    pub entropy: Option<NormalizedEntropy>,
    pub cluster: Option<ClusterShaping>,
    pub gain: Option<BeliefGain>,
}

impl AddOns {
    pub fn from_config(c: &PpoConfig) -> AddOns {
        AddOns {
            end: EndAddOn::from_config(c),
            belief: BeliefAux::from_config(c),
            entropy: NormalizedEntropy::from_config(c),
            cluster: ClusterShaping::from_config(c),
            gain: BeliefGain::from_config(c),
        }
    }
}

/// The add-ons' columns of one rollout (`None` where the add-on is off or records
/// nothing).
#[derive(Default)]
pub(super) struct Columns {
    /// [`end`]: what END would pay per step and row.
    pub end: Option<end::EndRewards>,
    /// [`belief_aux`]: every card's true colour per step and row.
    pub truth: Option<belief_aux::Truth>,
    /// [`belief_gain`]: every game's potential per step (while its weight is above 0).
    pub potentials: Option<belief_gain::Potentials>,
}

/// The add-ons' rows of one minibatch shard, per choosing row.
#[derive(Default)]
pub(super) struct ShardColumns {
    pub end: Option<end::EndRows>,
    pub truth: Option<Vec<f32>>,
    pub entropy_weight: Option<Vec<f32>>,
}

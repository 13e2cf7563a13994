//! `ppo.entropy_normalized`: each choosing row's entropy divided by ln(its legal actions)
//! before the bonus, so that a row with two legal actions and one with 700 are pushed
//! towards uniform play equally hard (a raw entropy bonus favours the rows with many).

use crate::config::PpoConfig;
use crate::tensor::tensor1;
use burn::prelude::*;

#[derive(Clone, Debug)]
pub(in crate::trainer) struct NormalizedEntropy;

impl NormalizedEntropy {
    pub fn from_config(c: &PpoConfig) -> Option<NormalizedEntropy> {
        c.entropy_normalized.then_some(NormalizedEntropy)
    }

    /// Gather: the weight of a choosing row with `legal` legal actions (more than one).
    pub fn gather(&self, legal: u32, weights: &mut Vec<f32>) {
        weights.push(1.0 / (legal as f32).ln());
    }

    /// Loss: the entropy bonus's sum over the shard's rows, each weighted.
    pub fn weigh(&self, row_entropy: Tensor<1>, weights: Vec<f32>, d: &Device) -> Tensor<1> {
        (row_entropy * tensor1(weights, d)).sum()
    }
}

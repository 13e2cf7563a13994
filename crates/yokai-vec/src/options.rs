//! How a batch of games is seeded, encoded and spread over threads.

use crate::Encoding;
use yokai_engine::{derive_seed, ImageLayout, Part};

/// The seed of episode `episode` of environment `env` in a batch seeded with `seed`.
pub fn episode_seed(seed: u64, env: usize, episode: u64) -> u64 {
    derive_seed(derive_seed(seed, env as u64), episode)
}

/// Options of a batched environment.
#[derive(Clone, Copy, Debug)]
pub struct VecEnvOptions {
    pub num_envs: usize,
    pub seed: u64,
    pub encoding: Encoding,
    /// Worker threads; `None` uses one per core.
    pub threads: Option<usize>,
    /// Games per work item. Small enough to balance two threads, large enough to amortise
    /// scheduling; 32 measured best on the 2-core development machine.
    pub chunk: usize,
}

impl VecEnvOptions {
    pub fn new(num_envs: usize, seed: u64) -> VecEnvOptions {
        VecEnvOptions {
            num_envs,
            seed,
            encoding: Encoding::Image(Part::Full, ImageLayout::Hwc),
            threads: None,
            chunk: 32,
        }
    }
}

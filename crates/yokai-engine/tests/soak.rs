//! Soak test: at least 10⁶ random steps across all configurations (release build), checking
//! the cheap invariants at every step and the reference comparisons at one step in 64.
//! In a debug build it plays 2·10⁴ steps so that `cargo test` stays quick.

mod common;

use common::{all_configs, play_checked, Depth};

#[test]
fn a_million_random_steps_keep_every_invariant() {
    let target: usize = if cfg!(debug_assertions) {
        20_000
    } else {
        1_000_000
    };
    let configs = all_configs();
    let mut steps = 0usize;
    let mut games = 0u64;
    while steps < target {
        let config = configs[games as usize % configs.len()];
        let (_, len) = play_checked(config, games, games ^ 0x5eed, Depth::Sampled(64));
        steps += len;
        games += 1;
    }
    // Every check is inside play_checked; this only reports how much was played.
    eprintln!("soak: {steps} steps in {games} games");
}

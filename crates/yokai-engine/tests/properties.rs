//! Property tests over random legal play in every configuration: the invariants of
//! docs/spec/rules.md
//! (see `common::play_checked` for the full list) hold at every step of every game.

mod common;

use common::{all_configs, play_checked, Depth};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn random_play_keeps_every_invariant(config_index in 0usize..14, deal_seed in any::<u64>(), player_seed in any::<u64>()) {
        let configs = all_configs();
        let config = configs[config_index % configs.len()];
        let (record, len) = play_checked(config, deal_seed, player_seed, Depth::Full);
        prop_assert!(len >= 1 && len <= config.max_episode_len());
        prop_assert_eq!(record.actions.len(), len);
    }
}

#[test]
fn every_config_is_covered() {
    // The proptest above draws configs by index; make sure each is played at least once.
    for (i, config) in all_configs().into_iter().enumerate() {
        let (_, len) = play_checked(config, i as u64, 1000 + i as u64, Depth::Full);
        assert!(len <= config.max_episode_len());
    }
}

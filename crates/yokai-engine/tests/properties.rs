//! Property tests over random legal play in every configuration: the invariants of
//! docs/spec/rules.md
//! (see `common::play_checked` for the full list) hold at every step of every game.

mod common;

use common::{all_configs, play_checked, Depth};
use proptest::prelude::*;
use yokai_engine::{Game, Part, Seat};

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

/// Off-Belief Learning's fictitious states (`Game::with_card_colours`): at every step of
/// random play, recolouring the cards (a random permutation of the true colours) leaves
/// what is public untouched — every seat's legal actions and public observation — and the
/// same action then leads to the same public state, turn and end; with the true colours the
/// fictitious game is the real one, so its transition is the real transition.
#[test]
fn recoloured_games_share_the_public_state_and_its_transitions() {
    for (i, config) in all_configs().into_iter().enumerate() {
        let mut player = common::RandomPlayer::new(40 + i as u64);
        let mut game = Game::new(config, 90 + i as u64);
        let [nodes, features] = config.node_shape(Part::Public);
        let (mut a, mut b) = (vec![0f32; nodes * features], vec![0f32; nodes * features]);
        let na = config.num_actions();
        let (mut ma, mut mb) = (vec![0u8; na], vec![0u8; na]);
        while !game.is_over() {
            let truth = game.deal().card_colours;
            assert!(game.with_card_colours(&truth).unwrap() == game);
            let mut shuffled = truth.clone();
            for k in (1..shuffled.len()).rev() {
                shuffled.swap(k, player.below(k + 1));
            }
            let mut fict = game.with_card_colours(&shuffled).unwrap();
            for s in 0..config.players() {
                let seat = Seat(s as u8);
                game.write_nodes(seat, Part::Public, &mut a).unwrap();
                fict.write_nodes(seat, Part::Public, &mut b).unwrap();
                assert_eq!(a, b, "config {i}: public observation of seat {s}");
                game.write_legal_mask(seat, &mut ma);
                fict.write_legal_mask(seat, &mut mb);
                assert_eq!(ma, mb, "config {i}: legal actions of seat {s}");
            }
            let action = player.pick(&game);
            let real = game.apply(action).unwrap();
            let other = fict.apply(action).unwrap();
            assert_eq!(real.done, other.done);
            assert_eq!(fict.current_seat(), game.current_seat());
            assert_eq!(fict.substep(), game.substep());
            assert_eq!(fict.hinted_cards(), game.hinted_cards());
            assert_eq!(fict.occupied(), game.occupied());
        }
    }
}

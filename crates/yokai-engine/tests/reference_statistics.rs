//! Random legal play matches the statistics of the independent reference implementation
//! quoted in docs/spec/rules.md §4 (9c-2p: R = −4.01, win 0.7 %, EE 64 %, LEN 20.2; 9c-3p −4.31;
//! 9c-4p −4.53). Tolerances are about 5 standard errors for the game counts used, so a
//! rules change that shifts any of these by a few percent fails.

mod common;

use common::RandomPlayer;
use yokai_engine::{Config, Game, MetricsAccumulator};

fn random_metrics(name: &str, games: u64) -> yokai_engine::Metrics {
    let config = Config::from_name(name).unwrap();
    let mut acc = MetricsAccumulator::default();
    for seed in 0..games {
        let mut game = Game::new(config, seed);
        let mut player = RandomPlayer::new(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        while !game.is_over() {
            let a = player.pick(&game);
            game.apply(a).unwrap();
        }
        acc.add(&game.outcome().unwrap());
    }
    acc.metrics().unwrap()
}

#[test]
fn nine_cards_two_players_matches_the_reference() {
    let m = random_metrics("9c-2p-perfect", 20_000);
    assert!((m.reward - -4.01).abs() < 0.06, "R {}", m.reward);
    assert!((m.win_rate - 0.007).abs() < 0.003, "win {}", m.win_rate);
    assert!((m.early_end - 0.64).abs() < 0.02, "EE {}", m.early_end);
    assert!((m.length - 20.2).abs() < 0.4, "LEN {}", m.length);
}

#[test]
fn more_players_match_the_reference() {
    let m3 = random_metrics("9c-3p-perfect", 10_000);
    assert!((m3.reward - -4.31).abs() < 0.08, "R {}", m3.reward);
    let m4 = random_metrics("9c-4p-perfect", 10_000);
    assert!((m4.reward - -4.53).abs() < 0.08, "R {}", m4.reward);
}

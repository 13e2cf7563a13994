//! Level 1's belief: exact, because π₀ (uniform random legal play) carries no information.
//!
//! Under π₀ no action depends on a colour, and a placed hint is evidence of nothing (a
//! random seat places any hint on any card). What a seat knows about the colours is then
//! exactly what it has seen first-hand, plus the colour counts of the config: its belief
//! is uniform over the colourings that agree with both. Sampling it is a shuffle of the
//! colours not yet seen onto the cards not yet seen.
//!
//! "Seen first-hand" is every card the seat has observed this episode, whatever the memory
//! mode: OBL's belief conditions on the seat's whole action-observation history, which
//! holds every colour it observed even where its current observation has forgotten it.

use rand_chacha::ChaCha8Rng;
use yokai_agents::belief::colouring::sample_colouring;
use yokai_engine::{Card, Colour, Game, Seat};

/// The cards `seat` has observed in `game`, with their colours.
pub fn first_hand(game: &Game, seat: Seat) -> Vec<(Card, Colour)> {
    game.ever_observed(seat)
        .iter()
        .map(|card| (card, game.colour_of(card)))
        .collect()
}

/// What `seat` has seen of each card id: `Some(colour)` where it observed the card (the
/// form the belief model reads).
pub fn first_hand_slots(game: &Game, seat: Seat) -> Vec<Option<u8>> {
    let seen = game.ever_observed(seat);
    (0..game.config().cards())
        .map(|k| Card(k as u8))
        .map(|card| seen.contains(card).then(|| game.colour_of(card).0))
        .collect()
}

/// One colouring (a colour per card id) drawn uniformly from those consistent with what
/// `seat` has seen first-hand in `game` and with the colour counts.
pub fn sample_first_hand_consistent(game: &Game, seat: Seat, rng: &mut ChaCha8Rng) -> Vec<Colour> {
    let config = game.config();
    let colouring = sample_colouring(config, &first_hand(game, seat), rng);
    (0..config.cards())
        .map(|k| colouring.colour_of(Card(k as u8)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_chacha::rand_core::{Rng, SeedableRng};
    use std::collections::HashMap;
    use yokai_agents::belief::colouring::all_colourings;
    use yokai_engine::Config;

    /// Play `steps` uniformly random legal actions from a seeded deal.
    fn random_history(config: Config, seed: u64, steps: usize) -> Game {
        let mut game = Game::new(config, seed);
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xA5);
        for _ in 0..steps {
            if game.is_over() {
                break;
            }
            let legal = game.legal_actions(game.current_seat());
            let pick = (rng.next_u64() % legal.len() as u64) as usize;
            game.apply(legal[pick]).unwrap();
        }
        game
    }

    /// Over random histories in every preset: the sample keeps every colour the seat saw
    /// and every colour count, whatever the rest.
    #[test]
    fn samples_keep_first_hand_colours_and_the_counts() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for config in Config::presets() {
            for case in 0..40u64 {
                let steps = (case as usize * 7) % config.max_episode_len();
                let game = random_history(config, case, steps);
                for s in 0..config.players() {
                    let seat = Seat(s as u8);
                    let sample = sample_first_hand_consistent(&game, seat, &mut rng);
                    let seen = first_hand(&game, seat);
                    let slots = first_hand_slots(&game, seat);
                    assert_eq!(slots.iter().flatten().count(), seen.len());
                    for &(card, colour) in &seen {
                        assert_eq!(sample[card.index()], colour, "case {case}, seat {s}");
                        assert_eq!(slots[card.index()], Some(colour.0));
                    }
                    let mut counts = vec![0; config.colours()];
                    for colour in &sample {
                        counts[colour.index()] += 1;
                    }
                    assert!(counts.iter().all(|&n| n == config.cards_per_colour()));
                    // The fictitious game accepts it.
                    game.with_card_colours(&sample).unwrap();
                }
            }
        }
    }

    /// The belief is uniform over the consistent colourings: with 3 of the 9 cards seen,
    /// 20 to 90 colourings remain (by how many colours the seen cards show), and each is
    /// drawn with its equal share, within 5 standard errors, in 45,000 draws; no colouring
    /// outside them is ever drawn.
    #[test]
    fn samples_are_uniform_over_the_consistent_colourings() {
        let config = Config::from_name("9c-2p").unwrap();
        // Seat 0 observes cards 0 and 1, moves, reveals; seat 1 plays; seat 0 observes card 2.
        let mut game = random_history(config, 11, 0);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        while game.ever_observed(Seat(0)).len() < 3 {
            let legal = game.legal_actions(game.current_seat());
            let pick = (rng.next_u64() % legal.len() as u64) as usize;
            game.apply(legal[pick]).unwrap();
            assert!(!game.is_over(), "seed 11 reaches three observed cards");
        }
        let seen = first_hand(&game, Seat(0));
        let consistent: Vec<Vec<Colour>> = all_colourings(&config)
            .into_iter()
            .map(|x| (0..9).map(|k| x.colour_of(Card(k))).collect::<Vec<_>>())
            .filter(|x: &Vec<Colour>| seen.iter().all(|&(card, c)| x[card.index()] == c))
            .collect();
        let draws = 45_000;
        let mut counts: HashMap<Vec<Colour>, usize> = HashMap::new();
        for _ in 0..draws {
            *counts
                .entry(sample_first_hand_consistent(&game, Seat(0), &mut rng))
                .or_default() += 1;
        }
        assert_eq!(
            counts.len(),
            consistent.len(),
            "every consistent colouring, no other"
        );
        let p = 1.0 / consistent.len() as f64;
        let se = (draws as f64 * p * (1.0 - p)).sqrt();
        for x in &consistent {
            let n = counts.get(x).copied().unwrap_or(0) as f64;
            assert!(
                (n - draws as f64 * p).abs() < 5.0 * se,
                "{x:?}: {n} draws, expected {:.0}",
                draws as f64 * p
            );
        }
    }
}

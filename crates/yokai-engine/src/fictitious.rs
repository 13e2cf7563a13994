//! Fictitious states for Off-Belief Learning (Hu et al. 2021): the same public state with
//! other hidden colours.
//!
//! OBL values a seat's action by what it would lead to in a world drawn from the seat's
//! *belief*: the cards keep their cells, hints, the turn and every record of who observed
//! what, but each card gets a colour sampled consistently with what the seat has seen. The
//! fictitious game is then an ordinary [`Game`]: the acting seat's action is applied to it
//! and the previous level's policy plays on from there.

use crate::deal::{Deal, DealError};
use crate::game::Game;
use crate::types::Colour;

impl Game {
    /// This game with its cards coloured by `card_colours` (one colour per card id, each
    /// colour on exactly Y/C cards): cells, hints, turn, substep, step count and every
    /// seat's record of which cards it observed are unchanged, so legal actions and the
    /// public observation are the same; what a seat sees of a card it knows is the card's
    /// new colour.
    ///
    /// Face-down hint slots keep their colours. No seat has seen them, and the pile was
    /// dealt independently of the card colours, so the true pile is itself a draw from any
    /// seat's belief about it; the revealed slots are public and must not change anyway.
    ///
    /// With the game's own colours this returns an equal game, so a fictitious transition
    /// under the true colouring is the real transition.
    pub fn with_card_colours(&self, card_colours: &[Colour]) -> Result<Game, DealError> {
        let deal = Deal {
            card_colours: card_colours.to_vec(),
            hint_colours: self.hint_colours[..self.config.hints()].to_vec(),
        };
        deal.validate(&self.config)?;
        let mut game = self.clone();
        game.set_card_colours(card_colours);
        Ok(game)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;
    use crate::types::{Card, CardSet, Seat};

    fn colours(ids: &[u8]) -> Vec<Colour> {
        ids.iter().map(|&c| Colour(c)).collect()
    }

    #[test]
    fn the_cards_take_the_new_colours_and_nothing_else_changes() {
        let config = Config::from_name("9c-2p").unwrap();
        let mut game = Game::new(config, 7);
        for index in [2, 3] {
            game.apply_index(index).unwrap(); // seat 0 observes cards 0 and 1
        }
        let new = colours(&[2, 2, 2, 1, 1, 1, 0, 0, 0]);
        let fict = game.with_card_colours(&new).unwrap();
        for (k, &colour) in new.iter().enumerate() {
            assert_eq!(fict.colour_of(Card(k as u8)), colour);
        }
        assert_eq!(fict.cards_of_colour(Colour(2)), CardSet::first(3));
        assert_eq!(
            fict.cards_of_colour(Colour(0)),
            (6..9).map(Card).collect::<CardSet>()
        );
        assert_eq!(fict.ever_observed(Seat(0)), game.ever_observed(Seat(0)));
        assert_eq!(fict.steps(), game.steps());
        assert_eq!(fict.deal().hint_colours, game.deal().hint_colours);
        assert_eq!(
            game.with_card_colours(&game.deal().card_colours).unwrap(),
            game
        );
    }

    #[test]
    fn colourings_that_break_the_counts_are_refused() {
        let config = Config::from_name("9c-2p").unwrap();
        let game = Game::new(config, 1);
        let err = game
            .with_card_colours(&colours(&[0, 0, 0, 0, 1, 1, 2, 2, 2]))
            .unwrap_err();
        assert!(
            matches!(err, DealError::ColourCount { colour: 0, .. }),
            "{err}"
        );
        let err = game.with_card_colours(&colours(&[0, 1, 2])).unwrap_err();
        assert!(matches!(err, DealError::CardCount { .. }), "{err}");
    }
}

//! The small values of the game, each its own type so that a card id cannot be passed where
//! a hint slot is expected.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Most cards a configuration may have (card sets are `u32` masks).
pub const MAX_CARDS: usize = 32;
/// Most colours (hint colour sets are `u8` masks; RULES §1 allows 2–4).
pub const MAX_COLOURS: usize = 4;
/// Most hint cards (at most one per grid row, and the grid has at most 11 rows).
pub const MAX_HINTS: usize = 11;
/// Most players (RULES §1 allows 2–6).
pub const MAX_PLAYERS: usize = 6;

/// A card, by its id `0..Y` (ids are public; colours are not).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize, PartialOrd, Ord)]
pub struct Card(pub u8);

/// A colour index `0..C`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize, PartialOrd, Ord)]
pub struct Colour(pub u8);

/// A slot of the hint pile `0..H`; slot 0 is the top card of the face-down pile.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize, PartialOrd, Ord)]
pub struct HintSlot(pub u8);

/// A player's seat `0..P`; seat 0 moves first.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize, PartialOrd, Ord)]
pub struct Seat(pub u8);

/// The colours shown on a hint card, as a bit set over colour indices.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default, Serialize, Deserialize)]
pub struct ColourSet(pub u8);

impl Card {
    #[inline(always)]
    pub fn index(self) -> usize {
        self.0 as usize
    }
    #[inline(always)]
    pub fn bit(self) -> u32 {
        1u32 << self.0
    }
}

impl Colour {
    #[inline(always)]
    pub fn index(self) -> usize {
        self.0 as usize
    }
    /// A one-letter name used in text renderings: R, G, B, Y.
    pub fn letter(self) -> char {
        ['R', 'G', 'B', 'Y']
            .get(self.index())
            .copied()
            .unwrap_or('?')
    }
    pub fn name(self) -> &'static str {
        ["red", "green", "blue", "yellow"]
            .get(self.index())
            .copied()
            .unwrap_or("?")
    }
}

impl HintSlot {
    #[inline(always)]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl Seat {
    #[inline(always)]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl ColourSet {
    #[inline(always)]
    pub fn contains(self, colour: Colour) -> bool {
        self.0 >> colour.0 & 1 == 1
    }
    pub fn len(self) -> usize {
        self.0.count_ones() as usize
    }
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    pub fn colours(self) -> impl Iterator<Item = Colour> {
        (0..8u8).filter(move |c| self.0 >> c & 1 == 1).map(Colour)
    }
    /// Letters of the colours, e.g. `RB`.
    pub fn letters(self) -> String {
        self.colours().map(Colour::letter).collect()
    }
}

impl fmt::Display for Card {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "card {}", self.0)
    }
}

impl fmt::Display for Seat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "seat {}", self.0)
    }
}

/// Iterate the set bits of a card mask as cards.
#[inline]
pub fn cards_in(mask: u32) -> impl Iterator<Item = Card> {
    let mut m = mask;
    std::iter::from_fn(move || {
        if m == 0 {
            None
        } else {
            let i = m.trailing_zeros();
            m &= m - 1;
            Some(Card(i as u8))
        }
    })
}

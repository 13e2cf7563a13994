//! The small values of the game, each its own type so that a card id cannot be passed where
//! a hint slot is expected.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Most cards a configuration may have (a [`CardSet`] is a `u32` mask).
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

/// The set operators of a bit-set newtype over an unsigned integer (`|`, `&`, `^`, `!` and
/// their assigning forms), bit for bit: one definition for [`CardSet`] and
/// [`crate::Bitboard`]. `!` complements within the whole integer, so a caller that cares
/// about the board or the game's cards intersects with its universe.
macro_rules! bit_set_ops {
    ($set:ident) => {
        impl std::ops::BitOr for $set {
            type Output = $set;
            #[inline(always)]
            fn bitor(self, rhs: $set) -> $set {
                $set(self.0 | rhs.0)
            }
        }
        impl std::ops::BitAnd for $set {
            type Output = $set;
            #[inline(always)]
            fn bitand(self, rhs: $set) -> $set {
                $set(self.0 & rhs.0)
            }
        }
        impl std::ops::BitXor for $set {
            type Output = $set;
            #[inline(always)]
            fn bitxor(self, rhs: $set) -> $set {
                $set(self.0 ^ rhs.0)
            }
        }
        impl std::ops::Not for $set {
            type Output = $set;
            #[inline(always)]
            fn not(self) -> $set {
                $set(!self.0)
            }
        }
        impl std::ops::BitOrAssign for $set {
            #[inline(always)]
            fn bitor_assign(&mut self, rhs: $set) {
                self.0 |= rhs.0;
            }
        }
        impl std::ops::BitAndAssign for $set {
            #[inline(always)]
            fn bitand_assign(&mut self, rhs: $set) {
                self.0 &= rhs.0;
            }
        }
        impl std::ops::BitXorAssign for $set {
            #[inline(always)]
            fn bitxor_assign(&mut self, rhs: $set) {
                self.0 ^= rhs.0;
            }
        }
    };
}
pub(crate) use bit_set_ops;

/// A set of cards (by id), one bit per card: hinted cards, the cards a seat has seen, the
/// cards of a colour. Iterating yields [`Card`]s, so card ids never travel as bare
/// integers. `!` complements within all 32 possible ids: intersect with
/// [`CardSet::first`] where the game's card count matters.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct CardSet(u32);

impl CardSet {
    pub const EMPTY: CardSet = CardSet(0);

    /// Cards `0..n` (every card of an `n`-card game).
    #[inline(always)]
    pub fn first(n: usize) -> CardSet {
        debug_assert!(n <= MAX_CARDS);
        CardSet(if n >= 32 { u32::MAX } else { (1u32 << n) - 1 })
    }
    #[inline(always)]
    pub fn contains(self, card: Card) -> bool {
        self.0 >> card.0 & 1 == 1
    }
    #[inline(always)]
    pub fn insert(&mut self, card: Card) {
        self.0 |= 1 << card.0;
    }
    #[inline(always)]
    pub fn remove(&mut self, card: Card) {
        self.0 &= !(1 << card.0);
    }
    #[inline(always)]
    pub fn len(self) -> usize {
        self.0.count_ones() as usize
    }
    #[inline(always)]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// The mask itself: bit k is card k (for packing a game into bytes).
    #[inline(always)]
    pub(crate) fn bits(self) -> u32 {
        self.0
    }
    /// The set whose bit k is card k; the caller keeps it within the game's cards.
    #[inline(always)]
    pub(crate) fn from_bits(bits: u32) -> CardSet {
        CardSet(bits)
    }
    /// The cards in increasing id order.
    #[inline]
    pub fn iter(self) -> impl Iterator<Item = Card> {
        let mut m = self.0;
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
}

impl From<Card> for CardSet {
    #[inline(always)]
    fn from(card: Card) -> CardSet {
        CardSet(1 << card.0)
    }
}

impl FromIterator<Card> for CardSet {
    fn from_iter<I: IntoIterator<Item = Card>>(cards: I) -> CardSet {
        let mut set = CardSet::EMPTY;
        cards.into_iter().for_each(|c| set.insert(c));
        set
    }
}

bit_set_ops!(CardSet);

impl fmt::Debug for CardSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CardSet")?;
        f.debug_list().entries(self.iter().map(|c| c.0)).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// A card set built from any list of ids holds exactly those ids, yields them once
        /// each in increasing order, and its operators agree with the same sets as
        /// `BTreeSet`s.
        #[test]
        fn card_sets_behave_as_sets_of_ids(a in prop::collection::vec(0u8..32, 0..40), b in prop::collection::vec(0u8..32, 0..40), n in 0usize..=32) {
            use std::collections::BTreeSet;
            let (sa, sb): (BTreeSet<u8>, BTreeSet<u8>) = (a.iter().copied().collect(), b.iter().copied().collect());
            let (ca, cb): (CardSet, CardSet) = (a.iter().map(|&k| Card(k)).collect(), b.iter().map(|&k| Card(k)).collect());
            let ids = |c: CardSet| c.iter().map(|card| card.0).collect::<Vec<u8>>();
            prop_assert_eq!(ids(ca), sa.iter().copied().collect::<Vec<_>>());
            prop_assert_eq!(ca.len(), sa.len());
            prop_assert_eq!(ca.is_empty(), sa.is_empty());
            prop_assert_eq!(ids(ca | cb), sa.union(&sb).copied().collect::<Vec<_>>());
            prop_assert_eq!(ids(ca & cb), sa.intersection(&sb).copied().collect::<Vec<_>>());
            let all = CardSet::first(n);
            prop_assert_eq!(ids(all), (0..n as u8).collect::<Vec<_>>());
            let rest: Vec<u8> = (0..n as u8).filter(|k| !sa.contains(k)).collect();
            prop_assert_eq!(ids(all & !ca), rest);
            for k in 0..32u8 {
                prop_assert_eq!(ca.contains(Card(k)), sa.contains(&k));
            }
            let mut removed = ca;
            if let Some(&k) = sa.iter().next() {
                removed.remove(Card(k));
                prop_assert!(!removed.contains(Card(k)) && removed.len() + 1 == ca.len());
            }
            prop_assert_eq!(ids(ca ^ cb), sa.symmetric_difference(&sb).copied().collect::<Vec<_>>());
        }
    }
}

//! Colourings: which colour every card has. The belief bot reasons over sets of them.

use rand_chacha::rand_core::Rng;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{Bitboard, Card, CardSet, Colour, ColourSet, Config, PublicView, MAX_COLOURS};

/// One assignment of colours to card ids, as one card set per colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Colouring {
    pub masks: [CardSet; MAX_COLOURS],
}

impl Colouring {
    /// The colouring in which card `k` has `card_colours[k]` (a deal's card colours).
    pub fn from_colours(card_colours: &[Colour]) -> Colouring {
        let mut masks = [CardSet::EMPTY; MAX_COLOURS];
        for (k, colour) in card_colours.iter().enumerate() {
            masks[colour.index()].insert(Card(k as u8));
        }
        Colouring { masks }
    }

    pub fn colour_of(&self, card: Card) -> Colour {
        let c = self
            .masks
            .iter()
            .position(|m| m.contains(card))
            .unwrap_or(0);
        Colour(c as u8)
    }

    /// The part of this colouring on the cards of `known` (what a seat knowing exactly
    /// those cards would see): equal keys mean indistinguishable to that seat.
    pub fn restricted(&self, known: CardSet) -> [CardSet; MAX_COLOURS] {
        self.masks.map(|m| m & known)
    }

    /// How many colours are clustered on the board of `view`.
    pub fn clustered(&self, view: &PublicView<'_>, colours: usize) -> usize {
        let geometry = view.config().geometry();
        self.masks[..colours]
            .iter()
            .filter(|&&mask| {
                let mut cells = Bitboard::EMPTY;
                for card in mask.iter() {
                    cells |= Bitboard::from_index(geometry.index(view.cell_of(card)));
                }
                geometry.is_connected(cells)
            })
            .count()
    }

    /// (correct, wrong) placed hints if the cards were coloured so.
    pub fn hint_tally(&self, view: &PublicView<'_>) -> (i32, i32) {
        let mut tally = (0, 0);
        for slot in 0..view.config().hints() {
            let slot = yokai_engine::HintSlot(slot as u8);
            if let (Some(card), Some(colours)) = (view.hint_card(slot), view.revealed_hint(slot)) {
                if colours.contains(self.colour_of(card)) {
                    tally.0 += 1;
                } else {
                    tally.1 += 1;
                }
            }
        }
        tally
    }

    /// The terminal reward R (RULES §4) if the game ended now, `early` by END.
    pub fn reward_if_over(&self, view: &PublicView<'_>, early: bool) -> i32 {
        let colours = view.config().colours();
        let clustered = self.clustered(view, colours);
        let (correct, wrong) = self.hint_tally(view);
        if clustered == colours {
            5 * view.face_down() as i32 + 2 * view.revealed_unplaced() as i32 + correct - wrong
        } else {
            -(early as i32) - (colours - clustered) as i32 - wrong
        }
    }

    pub fn in_hint(&self, card: Card, hint: ColourSet) -> bool {
        hint.contains(self.colour_of(card))
    }
}

/// Number of colourings of a config: Y! / ((Y/C)!)^C.
pub fn count_colourings(config: &Config) -> u128 {
    let (y, c, k) = (config.cards(), config.colours(), config.cards_per_colour());
    let mut total: u128 = 1;
    let mut left = y as u128;
    for _ in 0..c {
        // choose k of the `left` remaining cards
        let mut choose: u128 = 1;
        for i in 0..k as u128 {
            choose = choose * (left - i) / (i + 1);
        }
        total = total.saturating_mul(choose);
        left -= k as u128;
    }
    total
}

/// Every colouring of a config, in a fixed order. Only for configs where that is small
/// (9c: 1,680).
pub fn all_colourings(config: &Config) -> Vec<Colouring> {
    let (y, c, k) = (config.cards(), config.colours(), config.cards_per_colour());
    let mut out = Vec::new();
    let mut masks = [CardSet::EMPTY; MAX_COLOURS];
    fn fill(
        card: usize,
        y: usize,
        c: usize,
        k: usize,
        masks: &mut [CardSet; MAX_COLOURS],
        out: &mut Vec<Colouring>,
    ) {
        if card == y {
            out.push(Colouring { masks: *masks });
            return;
        }
        for colour in 0..c {
            if masks[colour].len() < k {
                masks[colour].insert(Card(card as u8));
                fill(card + 1, y, c, k, masks, out);
                masks[colour].remove(Card(card as u8));
            }
        }
    }
    fill(0, y, c, k, &mut masks, &mut out);
    out
}

/// A uniformly random colouring that agrees with `known` (colour of each known card).
pub fn sample_colouring(
    config: &Config,
    known: &[(Card, Colour)],
    rng: &mut ChaCha8Rng,
) -> Colouring {
    let (y, c, k) = (config.cards(), config.colours(), config.cards_per_colour());
    let mut masks = [CardSet::EMPTY; MAX_COLOURS];
    let mut known_cards = CardSet::EMPTY;
    for &(card, colour) in known {
        masks[colour.index()].insert(card);
        known_cards.insert(card);
    }
    // The colours still to hand out, shuffled onto the unknown cards (Fisher–Yates).
    let mut pool: Vec<u8> = Vec::with_capacity(y);
    for (colour, mask) in masks.iter().enumerate().take(c) {
        for _ in mask.len()..k {
            pool.push(colour as u8);
        }
    }
    for i in (1..pool.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        pool.swap(i, j);
    }
    let mut next = pool.into_iter();
    for card in (0..y).map(|k| Card(k as u8)) {
        if !known_cards.contains(card) {
            if let Some(colour) = next.next() {
                masks[colour as usize].insert(card);
            }
        }
    }
    Colouring { masks }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nine_card_colourings_are_all_distinct_and_balanced() {
        let config = Config::from_name("9c-2p").unwrap();
        let all = all_colourings(&config);
        assert_eq!(all.len(), 1680);
        assert_eq!(count_colourings(&config), 1680);
        let distinct: std::collections::HashSet<_> = all.iter().collect();
        assert_eq!(distinct.len(), 1680);
        for x in &all {
            assert_eq!(
                x.masks[..3].iter().map(|m| m.len()).collect::<Vec<_>>(),
                [3, 3, 3]
            );
            assert_eq!(x.masks[0] | x.masks[1] | x.masks[2], CardSet::first(9));
        }
        let sixteen = Config::from_name("16c-2p").unwrap();
        assert_eq!(count_colourings(&sixteen), 63_063_000);
    }

    #[test]
    fn sampled_colourings_keep_known_cards_and_counts() {
        use rand_chacha::rand_core::SeedableRng;
        let config = Config::from_name("16c-2p").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let known = [
            (Card(3), Colour(2)),
            (Card(9), Colour(2)),
            (Card(0), Colour(1)),
        ];
        for _ in 0..100 {
            let x = sample_colouring(&config, &known, &mut rng);
            for &(card, colour) in &known {
                assert_eq!(x.colour_of(card), colour);
            }
            assert!(x.masks.iter().all(|m| m.len() == 4));
        }
    }
}

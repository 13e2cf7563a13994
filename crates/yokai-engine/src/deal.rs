//! The hidden part of a game fixed at reset: the colour of every card and of every hint slot.
//!
//! A deal comes from a seed ([`Deal::from_seed`]) or is given explicitly ([`Deal::new`], for
//! hand-made scenarios and cross-checks). Sampling uses ChaCha8 and our own unbiased bounded
//! draw (Lemire's method on `u32`), so a seed gives the same deal on every platform and does
//! not depend on how a `rand` version implements `shuffle`.

use crate::config::Config;
use crate::types::{Colour, ColourSet, MAX_CARDS, MAX_HINTS};
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Colours of all cards (by card id) and of all hint slots (slot 0 is the top of the pile).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Deal {
    pub card_colours: Vec<Colour>,
    pub hint_colours: Vec<ColourSet>,
}

/// Why an explicit deal does not fit its configuration.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DealError {
    #[error("the deal gives {got} card colours but the config has {expected} cards")]
    CardCount { expected: usize, got: usize },
    #[error("card {card} has colour {colour} but the config has only {colours} colours")]
    CardColour {
        card: usize,
        colour: u8,
        colours: usize,
    },
    #[error("colour {colour} is on {got} cards; every colour must be on exactly {expected}")]
    ColourCount {
        colour: usize,
        expected: usize,
        got: usize,
    },
    #[error("the deal gives {got} hint slots but the config has {expected} hints")]
    HintCount { expected: usize, got: usize },
    #[error("hint slot {slot} shows colours outside 0..{colours} or none at all")]
    HintColours { slot: usize, colours: usize },
    #[error(
        "the deal has {got} hints showing {size} colour(s) but the config asks for {expected}"
    )]
    HintSizes {
        size: usize,
        expected: usize,
        got: usize,
    },
    #[error("hint slots {first} and {second} show the same colours; hints are drawn without replacement")]
    DuplicateHint { first: usize, second: usize },
}

/// A seed for stream `stream` of a run seeded with `base` (SplitMix64 finaliser): games,
/// environments and episodes get independent, reproducible seeds that do not depend on the
/// order in which threads reach them.
pub fn derive_seed(base: u64, stream: u64) -> u64 {
    let mut z = base
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(stream.wrapping_add(1).wrapping_mul(0xD1B5_4A32_D192_ED03));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Uniform integer in `0..n` (`n ≥ 1`), unbiased (Lemire 2019): `next_u64() % n` is not
/// (it favours small values whenever n does not divide 2⁶⁴). Every random choice of the
/// workspace among n things draws with this.
#[inline]
pub fn below(rng: &mut ChaCha8Rng, n: u32) -> u32 {
    debug_assert!(n > 0);
    let threshold = n.wrapping_neg() % n;
    loop {
        let m = rng.next_u32() as u64 * n as u64;
        if (m as u32) >= threshold {
            return (m >> 32) as u32;
        }
    }
}

/// Fisher–Yates shuffle with [`below`].
pub fn shuffle<T>(rng: &mut ChaCha8Rng, items: &mut [T]) {
    for i in (1..items.len()).rev() {
        let j = below(rng, i as u32 + 1) as usize;
        items.swap(i, j);
    }
}

impl Deal {
    /// Validate an explicit deal against a configuration.
    pub fn new(
        config: &Config,
        card_colours: Vec<Colour>,
        hint_colours: Vec<ColourSet>,
    ) -> Result<Deal, DealError> {
        let deal = Deal {
            card_colours,
            hint_colours,
        };
        deal.validate(config)?;
        Ok(deal)
    }

    pub fn validate(&self, config: &Config) -> Result<(), DealError> {
        let (y, c, h) = (config.cards(), config.colours(), config.hints());
        if self.card_colours.len() != y {
            return Err(DealError::CardCount {
                expected: y,
                got: self.card_colours.len(),
            });
        }
        let mut counts = [0usize; 8];
        for (card, colour) in self.card_colours.iter().enumerate() {
            if colour.index() >= c {
                return Err(DealError::CardColour {
                    card,
                    colour: colour.0,
                    colours: c,
                });
            }
            counts[colour.index()] += 1;
        }
        for (colour, &got) in counts.iter().enumerate().take(c) {
            if got != config.cards_per_colour() {
                return Err(DealError::ColourCount {
                    colour,
                    expected: config.cards_per_colour(),
                    got,
                });
            }
        }
        if self.hint_colours.len() != h {
            return Err(DealError::HintCount {
                expected: h,
                got: self.hint_colours.len(),
            });
        }
        let all = (1u8 << c) - 1;
        let mut sizes = [0usize; 9];
        for (slot, set) in self.hint_colours.iter().enumerate() {
            if set.is_empty() || set.0 & !all != 0 {
                return Err(DealError::HintColours { slot, colours: c });
            }
            sizes[set.len()] += 1;
            if let Some(first) = self.hint_colours[..slot].iter().position(|s| s == set) {
                return Err(DealError::DuplicateHint {
                    first,
                    second: slot,
                });
            }
        }
        for (size, &got) in sizes.iter().enumerate().skip(1).take(c) {
            if got != config.hints_of_size(size) {
                return Err(DealError::HintSizes {
                    size,
                    expected: config.hints_of_size(size),
                    got,
                });
            }
        }
        Ok(())
    }

    /// A random deal (RULES §1): colours by a uniform permutation of the colour multiset;
    /// for each hint size a random subset of the possible colour sets, then the pile shuffled.
    pub fn from_seed(config: &Config, seed: u64) -> Deal {
        let (cards, hints) = draw(config, seed);
        Deal {
            card_colours: cards[..config.cards()].to_vec(),
            hint_colours: hints[..config.hints()].to_vec(),
        }
    }
}

/// The seeded deal in fixed-size arrays (the first Y card colours and H hint slots are
/// meaningful), so that resetting a game allocates nothing: batched environments reset
/// finished games inside their step loop.
pub(crate) fn draw(config: &Config, seed: u64) -> ([Colour; MAX_CARDS], [ColourSet; MAX_HINTS]) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (y, c) = (config.cards(), config.colours());
    let per = config.cards_per_colour();
    let mut cards = [Colour(0); MAX_CARDS];
    for (i, colour) in cards[..y].iter_mut().enumerate() {
        *colour = Colour((i / per) as u8);
    }
    shuffle(&mut rng, &mut cards[..y]);

    let mut hints = [ColourSet(0); MAX_HINTS];
    let mut len = 0;
    for size in 1..=c {
        let wanted = config.hints_of_size(size);
        if wanted == 0 {
            continue;
        }
        // All colour sets of this size in increasing mask order: at most C(4, 2) = 6.
        let mut candidates = [ColourSet(0); 6];
        let mut n = 0;
        for mask in (1u8..(1 << c)).filter(|m| m.count_ones() as usize == size) {
            candidates[n] = ColourSet(mask);
            n += 1;
        }
        // Partial Fisher–Yates: the first `wanted` entries are a uniform subset.
        for i in 0..wanted {
            let j = i + below(&mut rng, (n - i) as u32) as usize;
            candidates.swap(i, j);
        }
        hints[len..len + wanted].copy_from_slice(&candidates[..wanted]);
        len += wanted;
    }
    shuffle(&mut rng, &mut hints[..len]);
    (cards, hints)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeded_deals_are_valid_and_reproducible() {
        for name in ["9c-2p", "9c-3p", "9c-4p", "16c-2p", "16c-3p", "16c-4p"] {
            let config = Config::from_name(name).unwrap();
            for seed in 0..200 {
                let d = Deal::from_seed(&config, seed);
                d.validate(&config).unwrap();
                assert_eq!(d, Deal::from_seed(&config, seed));
            }
        }
    }

    #[test]
    fn seeded_deals_are_pinned() {
        // Guards the "same seed, same game on every platform and version" promise: if this
        // changes, every recorded replay in the world changes meaning.
        let config = Config::from_name("9c-2p").unwrap();
        let d = Deal::from_seed(&config, 0);
        let colours: Vec<u8> = d.card_colours.iter().map(|c| c.0).collect();
        let hints: Vec<u8> = d.hint_colours.iter().map(|h| h.0).collect();
        assert_eq!(colours, [1, 0, 0, 1, 2, 0, 2, 2, 1]);
        assert_eq!(hints, [1, 5, 3, 6]);
    }

    #[test]
    fn colours_are_roughly_uniform_over_positions() {
        // Each card id gets each of 3 colours with probability 1/3.
        let config = Config::from_name("9c-2p").unwrap();
        let n = 30_000;
        let mut count = [[0u32; 3]; 9];
        for seed in 0..n {
            for (card, colour) in Deal::from_seed(&config, seed)
                .card_colours
                .iter()
                .enumerate()
            {
                count[card][colour.index()] += 1;
            }
        }
        for row in count {
            for c in row {
                let p = c as f64 / n as f64;
                assert!((p - 1.0 / 3.0).abs() < 0.015, "{p}");
            }
        }
    }

    #[test]
    fn explicit_deals_are_checked() {
        let config = Config::from_name("9c-2p").unwrap();
        let good: Vec<Colour> = [0, 0, 0, 1, 1, 1, 2, 2, 2].map(Colour).to_vec();
        let hints = [1u8, 3, 5, 6].map(ColourSet).to_vec();
        assert!(Deal::new(&config, good.clone(), hints.clone()).is_ok());
        let mut bad = good.clone();
        bad[0] = Colour(1);
        assert!(matches!(
            Deal::new(&config, bad, hints.clone()),
            Err(DealError::ColourCount { colour: 0, .. })
        ));
        let dup = [1u8, 3, 3, 6].map(ColourSet).to_vec();
        assert!(matches!(
            Deal::new(&config, good.clone(), dup),
            Err(DealError::DuplicateHint {
                first: 1,
                second: 2
            })
        ));
        let sizes = [1u8, 2, 3, 6].map(ColourSet).to_vec();
        assert!(matches!(
            Deal::new(&config, good.clone(), sizes),
            Err(DealError::HintSizes { size: 1, .. })
        ));
        let out = [1u8, 3, 5, 9].map(ColourSet).to_vec();
        assert!(matches!(
            Deal::new(&config, good, out),
            Err(DealError::HintColours { slot: 3, .. })
        ));
    }
}

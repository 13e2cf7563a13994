//! A game as a fixed-size array of bytes, and back: for front ends that keep the state
//! outside Rust between steps (JAX keeps it in a pytree and steps it through a callback).
//!
//! [`Game::pack`] writes every fact of the state that cannot be derived from the others;
//! [`Game::unpack`] rebuilds the rest (occupied cells, colour sets, which card each hint is
//! on) and refuses bytes it did not write. Why a digest as well as range checks: the range
//! checks keep the engine's indexing in bounds whatever the bytes, and the digest turns an
//! accidental change (a wrong slice, a state of another config, uninitialised memory) into
//! an error instead of a legal-looking game nobody dealt.
//!
//! The layout (all integers little-endian), [`PACKED_LEN`] bytes:
//!
//! | bytes | field |
//! |---|---|
//! | 0 | format version, [`PACKED_FORMAT`] |
//! | 1, 2, 3, 4 | acting seat, substep (0–3), phase (0 playing, 1 ended early, 2 finished), hints revealed |
//! | 5–6 | substeps played (u16) |
//! | 7, 8, 9–12 | last action: 1 if any, its seat, its action index (u32) |
//! | 13–44 | each card's cell (bit index `r·g + c`), cards `0..Y`, zero after |
//! | 45–76 | each card's colour, zero after card `Y − 1` |
//! | 77–87 | each hint slot's colour set, zero after slot `H − 1` |
//! | 88–98 | the card each hint slot is placed on, 255 when none |
//! | 99–122 | per seat the cards it has ever observed (u32 masks; zero for absent seats) |
//! | 123–126 | the cards observed in this turn (u32 mask) |
//! | 127 | zero |
//! | 128–135 | FNV-1a digest of bytes 0–127 (u64) |

use crate::config::Config;
use crate::deal::{Deal, DealError};
use crate::digest::fnv1a;
use crate::game::{Game, LayoutError, Phase, NO_CARD};
use crate::types::{CardSet, Colour, ColourSet, Seat, MAX_CARDS, MAX_HINTS, MAX_PLAYERS};

/// The length of a packed game, whatever the config.
pub const PACKED_LEN: usize = 136;
/// The version byte [`Game::pack`] writes; bumped whenever the layout changes.
pub const PACKED_FORMAT: u8 = 1;

const CELLS: usize = 13;
const COLOURS: usize = CELLS + MAX_CARDS;
const HINT_COLOURS: usize = COLOURS + MAX_CARDS;
const HINT_CARDS: usize = HINT_COLOURS + MAX_HINTS;
const EVER: usize = HINT_CARDS + MAX_HINTS;
const TURN: usize = EVER + 4 * MAX_PLAYERS;
const DIGEST: usize = 128;

/// Why bytes are not a packed game of this config.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PackError {
    #[error("a packed game is {PACKED_LEN} bytes, not {0}")]
    Length(usize),
    #[error(
        "the bytes do not match their digest: they were changed after packing, or are not \
         a packed game"
    )]
    Digest,
    #[error("packed format {0}, but this version of the engine reads format {PACKED_FORMAT}")]
    Format(u8),
    #[error("the deal does not fit the config: {0}")]
    Deal(#[from] DealError),
    #[error("card {card} is on cell index {index}, off the {side}×{side} grid")]
    CellIndex { card: usize, index: u8, side: usize },
    #[error("the cards' cells do not fit the config: {0}")]
    Layout(#[from] LayoutError),
    #[error("{field} is {value}, out of range for this config")]
    Field { field: &'static str, value: u64 },
    #[error("hint slot {slot} is placed on card {card}, which another slot is already on")]
    HintTwice { slot: usize, card: u8 },
    #[error("the phase says {phase:?} but {placed} of {hints} hints are placed")]
    PhasePlaced {
        phase: Phase,
        placed: usize,
        hints: usize,
    },
}

impl Game {
    /// This game as [`PACKED_LEN`] bytes that [`Game::unpack`] turns back into an equal game
    /// (the config is not in the bytes: the caller keeps it).
    pub fn pack(&self) -> [u8; PACKED_LEN] {
        let (y, h) = (self.config.cards(), self.config.hints());
        let mut b = [0u8; PACKED_LEN];
        b[0] = PACKED_FORMAT;
        b[1] = self.current;
        b[2] = self.substep;
        b[3] = match self.phase {
            Phase::Playing => 0,
            Phase::EndedEarly => 1,
            Phase::Finished => 2,
        };
        b[4] = self.revealed;
        b[5..7].copy_from_slice(&self.steps.to_le_bytes());
        if let Some((seat, action)) = self.last_action {
            b[7] = 1;
            b[8] = seat.0;
            b[9..13].copy_from_slice(&(self.config.encode(action) as u32).to_le_bytes());
        }
        b[CELLS..CELLS + y].copy_from_slice(&self.cell_of[..y]);
        for k in 0..y {
            b[COLOURS + k] = self.colour_of[k].0;
        }
        for s in 0..h {
            b[HINT_COLOURS + s] = self.hint_colours[s].0;
        }
        b[HINT_CARDS..HINT_CARDS + MAX_HINTS].copy_from_slice(&self.hint_card);
        for s in 0..self.config.players() {
            b[EVER + 4 * s..][..4].copy_from_slice(&self.ever_observed[s].bits().to_le_bytes());
        }
        b[TURN..TURN + 4].copy_from_slice(&self.turn_observed.bits().to_le_bytes());
        let digest = fnv1a(&b[..DIGEST]);
        b[DIGEST..].copy_from_slice(&digest.to_le_bytes());
        b
    }

    /// The game `bytes` hold, as [`Game::pack`] wrote it for `config`. Every field is checked
    /// (digest, format, deal, cells, hint placements, seats, masks, the last action) and
    /// the first fault is the error; nothing the bytes say can index out of bounds.
    pub fn unpack(config: Config, bytes: &[u8]) -> Result<Game, PackError> {
        if bytes.len() != PACKED_LEN {
            return Err(PackError::Length(bytes.len()));
        }
        let digest = u64::from_le_bytes(bytes[DIGEST..].try_into().expect("8 bytes"));
        if fnv1a(&bytes[..DIGEST]) != digest {
            return Err(PackError::Digest);
        }
        if bytes[0] != PACKED_FORMAT {
            return Err(PackError::Format(bytes[0]));
        }
        let (y, h, p) = (config.cards(), config.hints(), config.players());
        let field = |field: &'static str, value: u64| PackError::Field { field, value };
        let zero_after = |start: usize, used: usize, len: usize, name: &'static str| match bytes
            [start + used..start + len]
            .iter()
            .find(|&&v| v != 0)
        {
            Some(&v) => Err(field(name, v as u64)),
            None => Ok(()),
        };
        zero_after(
            CELLS,
            y,
            MAX_CARDS,
            "a cell of a card the config does not have",
        )?;
        zero_after(
            COLOURS,
            y,
            MAX_CARDS,
            "a colour of a card the config does not have",
        )?;
        zero_after(
            HINT_COLOURS,
            h,
            MAX_HINTS,
            "a hint the config does not have",
        )?;
        zero_after(
            EVER,
            4 * p,
            4 * MAX_PLAYERS,
            "a seat the config does not have",
        )?;
        if bytes[127] != 0 {
            return Err(field("byte 127", bytes[127] as u64));
        }

        let deal = Deal {
            card_colours: bytes[COLOURS..COLOURS + y]
                .iter()
                .map(|&c| Colour(c))
                .collect(),
            hint_colours: bytes[HINT_COLOURS..HINT_COLOURS + h]
                .iter()
                .map(|&c| ColourSet(c))
                .collect(),
        };
        let geo = *config.geometry();
        let mut cells = Vec::with_capacity(y);
        for (card, &index) in bytes[CELLS..CELLS + y].iter().enumerate() {
            if index as usize >= geo.cells() {
                return Err(PackError::CellIndex {
                    card,
                    index,
                    side: geo.side(),
                });
            }
            cells.push(geo.cell(index as usize));
        }
        deal.validate(&config)?;
        let mut game = Game::from_layout(config, &deal, &cells)?;

        let (current, substep, revealed) = (bytes[1], bytes[2], bytes[4]);
        if current as usize >= p {
            return Err(field("the acting seat", current as u64));
        }
        if substep > 3 {
            return Err(field("the substep", substep as u64));
        }
        if revealed as usize > h {
            return Err(field("the number of revealed hints", revealed as u64));
        }
        game.current = current;
        game.substep = substep;
        game.revealed = revealed;
        game.steps = u16::from_le_bytes([bytes[5], bytes[6]]);

        let all = CardSet::first(y);
        for slot in 0..MAX_HINTS {
            let card = bytes[HINT_CARDS + slot];
            if card == NO_CARD {
                continue;
            }
            if slot >= revealed as usize || card as usize >= y {
                return Err(field("a placed hint's card", card as u64));
            }
            if game.hinted.contains(crate::Card(card)) {
                return Err(PackError::HintTwice { slot, card });
            }
            game.hint_card[slot] = card;
            game.card_hint[card as usize] = slot as u8;
            game.hinted.insert(crate::Card(card));
            game.placed += 1;
        }
        let mask = |at: usize, name: &'static str| {
            let bits = u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
            if bits & !all.bits() != 0 {
                return Err(field(name, bits as u64));
            }
            Ok(CardSet::from_bits(bits))
        };
        for s in 0..p {
            game.ever_observed[s] = mask(EVER + 4 * s, "a seat's observed cards")?;
        }
        game.turn_observed = mask(TURN, "the cards observed this turn")?;

        game.phase = match bytes[3] {
            0 => Phase::Playing,
            1 => Phase::EndedEarly,
            2 => Phase::Finished,
            v => return Err(field("the phase", v as u64)),
        };
        let placed = game.placed as usize;
        if (game.phase == Phase::Finished) != (placed == h) {
            return Err(PackError::PhasePlaced {
                phase: game.phase,
                placed,
                hints: h,
            });
        }
        game.last_action = match bytes[7] {
            0 if bytes[8..13].iter().all(|&v| v == 0) => None,
            1 if (bytes[8] as usize) < p => {
                let index = u32::from_le_bytes(bytes[9..13].try_into().expect("4 bytes"));
                let action = config
                    .decode(index as usize)
                    .map_err(|_| field("the last action's index", index as u64))?;
                Some((Seat(bytes[8]), action))
            }
            v => return Err(field("the last action's flag or seat", v as u64)),
        };
        Ok(game)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deal::derive_seed;
    use proptest::prelude::*;

    /// Random play from `seed`, calling `visit` on every state (the last one over).
    fn random_play(config: Config, seed: u64, mut visit: impl FnMut(&Game)) {
        let mut game = Game::new(config, seed);
        let mut r = seed;
        visit(&game);
        while !game.is_over() {
            let legal = game.legal_actions(game.current_seat());
            r = derive_seed(r, 1);
            game.apply(legal[(r % legal.len() as u64) as usize])
                .expect("a legal action");
            visit(&game);
        }
    }

    #[test]
    fn every_state_of_random_play_packs_and_unpacks_to_an_equal_game() {
        for config in Config::presets() {
            for seed in 0..20 {
                random_play(config, seed, |game| {
                    let bytes = game.pack();
                    let back = Game::unpack(config, &bytes).expect("packed by pack");
                    assert!(
                        back == *game,
                        "{config:?} seed {seed}: {game:?} != {back:?}"
                    );
                    assert_eq!(back.pack(), bytes);
                });
            }
        }
    }

    #[test]
    fn a_changed_byte_is_refused_by_the_digest_and_a_short_slice_by_length() {
        let config = Config::from_name("9c-2p-perfect").unwrap();
        let bytes = Game::new(config, 3).pack();
        for i in 0..PACKED_LEN {
            let mut b = bytes;
            b[i] ^= 0x10;
            assert!(
                Game::unpack(config, &b).is_err(),
                "byte {i} changed but accepted"
            );
        }
        assert_eq!(
            Game::unpack(config, &bytes[..100]),
            Err(PackError::Length(100))
        );
        assert_eq!(
            Game::unpack(config, &[0; PACKED_LEN]),
            Err(PackError::Digest)
        );
        // A state of another config is refused, not read as a strange game.
        let other = Config::from_name("16c-2p-perfect").unwrap();
        assert!(Game::unpack(other, &bytes).is_err());
    }

    /// Re-seal `b` with a fresh digest, as a forger would.
    fn reseal(b: &mut [u8; PACKED_LEN]) {
        let digest = fnv1a(&b[..DIGEST]);
        b[DIGEST..].copy_from_slice(&digest.to_le_bytes());
    }

    proptest! {
        /// Forged bytes (one byte of a real state changed and the digest recomputed) are
        /// refused or give a game that can be observed, masked and played without a panic.
        #[test]
        fn forged_bytes_are_refused_or_playable(
            seed in 0u64..1000,
            at in 0usize..200,
            index in 0usize..DIGEST,
            value in any::<u8>(),
        ) {
            let config = Config::from_name("9c-2p-perfect").unwrap();
            let mut states = Vec::new();
            random_play(config, seed, |g| states.push(g.pack()));
            let mut b = states[at % states.len()];
            b[index] = value;
            reseal(&mut b);
            if let Ok(game) = Game::unpack(config, &b) {
                let mut image = vec![0f32; config.image_shape(crate::Part::Full).iter().product()];
                let mut mask = vec![0u8; config.num_actions()];
                for s in 0..config.players() {
                    game.write_image(Seat(s as u8), crate::Part::Full, &mut image).unwrap();
                    game.write_legal_mask(Seat(s as u8), &mut mask);
                }
                let mut game = game;
                if let Some(&a) = game.legal_actions(game.current_seat()).first() {
                    game.apply(a).unwrap();
                }
            }
        }
    }
}

//! Actions and their fixed index layout (RULES §3).
//!
//! | index | action |
//! |---|---|
//! | 0 | NOOP |
//! | 1 | END |
//! | 2 + y | OBSERVE card y |
//! | 2 + Y + y·g² + r·g + c | MOVE card y to row r, column c |
//! | 2 + Y + Y·g² | REVEAL the next face-down hint |
//! | 3 + Y + Y·g² + h·Y + y | PLACE hint slot h on card y |

use crate::bitboard::Cell;
use crate::config::Config;
use crate::types::{Card, HintSlot};
use serde::{Deserialize, Serialize};
use std::fmt;

/// One substep's action of one seat.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum Action {
    /// What non-acting seats submit; the acting seat's only MOVE when no card can move.
    Noop,
    /// End the game early (substep 0 only).
    End,
    Observe(Card),
    Move(Card, Cell),
    /// Turn over the lowest-index face-down hint.
    Reveal,
    Place(HintSlot, Card),
}

/// An action index that is outside the configuration's action space.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("action index {index} is out of range: this configuration has {num_actions} actions (0..{num_actions})")]
pub struct IndexOutOfRange {
    pub index: usize,
    pub num_actions: usize,
}

/// Offsets of the action groups in the flat action space of one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActionLayout {
    pub observe: usize,
    pub movement: usize,
    pub reveal: usize,
    pub place: usize,
    pub len: usize,
}

impl Config {
    /// Offsets of the action groups (RULES §3).
    #[inline(always)]
    pub fn action_layout(&self) -> ActionLayout {
        let y = self.cards();
        let cells = self.geometry().cells();
        let reveal = 2 + y + y * cells;
        ActionLayout {
            observe: 2,
            movement: 2 + y,
            reveal,
            place: reveal + 1,
            len: reveal + 1 + self.hints() * y,
        }
    }

    /// N_a, the size of the per-seat action space.
    #[inline(always)]
    pub fn num_actions(&self) -> usize {
        self.action_layout().len
    }

    /// The index of an action. The action must fit this configuration (card, cell and slot
    /// in range); actions built by [`Config::decode`] or by the engine always do.
    #[inline]
    pub fn encode(&self, action: Action) -> usize {
        let l = self.action_layout();
        match action {
            Action::Noop => 0,
            Action::End => 1,
            Action::Observe(card) => l.observe + card.index(),
            Action::Move(card, cell) => {
                l.movement + card.index() * self.geometry().cells() + self.geometry().index(cell)
            }
            Action::Reveal => l.reveal,
            Action::Place(slot, card) => l.place + slot.index() * self.cards() + card.index(),
        }
    }

    /// The action of an index.
    #[inline]
    pub fn decode(&self, index: usize) -> Result<Action, IndexOutOfRange> {
        let l = self.action_layout();
        let y = self.cards();
        Ok(match index {
            0 => Action::Noop,
            1 => Action::End,
            i if i < l.movement => Action::Observe(Card((i - l.observe) as u8)),
            i if i < l.reveal => {
                let j = i - l.movement;
                let cells = self.geometry().cells();
                Action::Move(Card((j / cells) as u8), self.geometry().cell(j % cells))
            }
            i if i == l.reveal => Action::Reveal,
            i if i < l.len => {
                let j = i - l.place;
                Action::Place(HintSlot((j / y) as u8), Card((j % y) as u8))
            }
            _ => {
                return Err(IndexOutOfRange {
                    index,
                    num_actions: l.len,
                })
            }
        })
    }

    /// Whether every card, cell and slot the action names exists in this configuration.
    pub fn action_fits(&self, action: Action) -> bool {
        let card_ok = |c: Card| c.index() < self.cards();
        match action {
            Action::Noop | Action::End | Action::Reveal => true,
            Action::Observe(c) => card_ok(c),
            Action::Move(c, cell) => card_ok(c) && self.geometry().contains(cell),
            Action::Place(h, c) => card_ok(c) && h.index() < self.hints(),
        }
    }
}

impl fmt::Display for Action {
    /// The readable name used in logs and replays, e.g. `move card 4 to r2c6`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Action::Noop => write!(f, "noop"),
            Action::End => write!(f, "end"),
            Action::Observe(c) => write!(f, "observe card {}", c.0),
            Action::Move(c, cell) => write!(f, "move card {} to {}", c.0, cell),
            Action::Reveal => write!(f, "reveal hint"),
            Action::Place(h, c) => write!(f, "place hint {} on card {}", h.0, c.0),
        }
    }
}

/// A string that is not the name of an action.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{text}` is not an action name (expected e.g. `noop`, `end`, `observe card 3`, `move card 4 to r2c6`, `reveal hint`, `place hint 1 on card 3`)")]
pub struct ActionNameError {
    pub text: String,
}

impl std::str::FromStr for Action {
    type Err = ActionNameError;
    /// Parse the names written by `Display` (case and extra spaces ignored).
    fn from_str(s: &str) -> Result<Action, ActionNameError> {
        let err = || ActionNameError {
            text: s.to_string(),
        };
        let lower = s.trim().to_ascii_lowercase();
        let words: Vec<&str> = lower.split_whitespace().collect();
        let num = |w: &str| w.parse::<u8>().map_err(|_| err());
        let cell = |w: &str| -> Result<Cell, ActionNameError> {
            let rest = w.strip_prefix('r').ok_or_else(err)?;
            let (r, c) = rest.split_once('c').ok_or_else(err)?;
            Ok(Cell {
                row: num(r)?,
                col: num(c)?,
            })
        };
        match words.as_slice() {
            ["noop"] => Ok(Action::Noop),
            ["end"] => Ok(Action::End),
            ["observe", "card", y] => Ok(Action::Observe(Card(num(y)?))),
            ["move", "card", y, "to", c] => Ok(Action::Move(Card(num(y)?), cell(c)?)),
            ["reveal", "hint"] | ["reveal"] => Ok(Action::Reveal),
            ["place", "hint", h, "on", "card", y] => {
                Ok(Action::Place(HintSlot(num(h)?), Card(num(y)?)))
            }
            _ => Err(err()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_matches_rules_for_9c_2p() {
        let c = Config::from_name("9c-2p").unwrap();
        assert_eq!(c.encode(Action::Observe(Card(8))), 10);
        // MOVE card 0 to r0c0 is 2 + 9 = 11; card 1 to r2c6 is 11 + 81 + 2·9 + 6.
        assert_eq!(c.encode(Action::Move(Card(0), Cell::new(0, 0))), 11);
        assert_eq!(
            c.encode(Action::Move(Card(1), Cell::new(2, 6))),
            11 + 81 + 24
        );
        assert_eq!(c.encode(Action::Reveal), 2 + 9 + 9 * 81);
        assert_eq!(c.encode(Action::Place(HintSlot(0), Card(0))), 3 + 9 + 729);
        assert_eq!(c.encode(Action::Place(HintSlot(3), Card(8))), 776);
    }

    #[test]
    fn every_index_round_trips_in_every_preset() {
        for name in ["9c-2p", "9c-3p", "9c-4p", "16c-2p", "16c-3p", "16c-4p"] {
            let c = Config::from_name(name).unwrap();
            for i in 0..c.num_actions() {
                let a = c.decode(i).unwrap();
                assert!(c.action_fits(a));
                assert_eq!(c.encode(a), i, "{name} {a}");
                assert_eq!(a.to_string().parse::<Action>().unwrap(), a);
            }
            assert_eq!(
                c.decode(c.num_actions()),
                Err(IndexOutOfRange {
                    index: c.num_actions(),
                    num_actions: c.num_actions()
                })
            );
        }
    }

    #[test]
    fn names_are_readable() {
        assert_eq!(
            Action::Move(Card(4), Cell::new(2, 6)).to_string(),
            "move card 4 to r2c6"
        );
        assert_eq!(
            Action::Place(HintSlot(1), Card(3)).to_string(),
            "place hint 1 on card 3"
        );
        assert!("move card x to r1c1".parse::<Action>().is_err());
        assert!("fly".parse::<Action>().is_err());
    }
}

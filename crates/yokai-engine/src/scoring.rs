//! Clusters, score and terminal reward (RULES §4).

use crate::bitboard::Bitboard;
use crate::game::{Game, Phase};
use crate::types::{Colour, HintSlot};
use serde::{Deserialize, Serialize};

/// The final facts of a finished game: what metrics are computed from.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize, Deserialize)]
pub struct Outcome {
    /// Terminal reward R (paper eq. 2).
    pub reward: i32,
    /// Board-game score S (meaningful for won games; reported for all).
    pub score: i32,
    pub won: bool,
    pub early_end: bool,
    /// Steps played, END included.
    pub length: u16,
    pub correct_hints: u8,
    pub wrong_hints: u8,
    /// Colours whose cards form one group by themselves.
    pub clustered: u8,
    pub face_down: u8,
    pub revealed_unplaced: u8,
}

impl Game {
    /// Cells of the cards of one colour.
    fn cells_of_colour(&self, colour: Colour) -> Bitboard {
        let mut set = Bitboard::EMPTY;
        for card in self.colour_cards[colour.index()].iter() {
            set |= Bitboard::from_index(self.cell_of[card.index()] as usize);
        }
        set
    }

    /// Whether all cards of `colour` form one 4-connected group by themselves.
    pub fn is_clustered(&self, colour: Colour) -> bool {
        self.config
            .geometry()
            .is_connected(self.cells_of_colour(colour))
    }

    /// Number of clustered colours.
    pub fn clustered_colours(&self) -> usize {
        (0..self.config.colours() as u8)
            .filter(|&c| self.is_clustered(Colour(c)))
            .count()
    }

    /// (correct, wrong) among placed hints.
    pub fn hint_tally(&self) -> (usize, usize) {
        let mut correct = 0;
        for slot in 0..self.config.hints() {
            if let Some(card) = self.hint_card(HintSlot(slot as u8)) {
                if self.hint_colours[slot].contains(self.colour_of[card.index()]) {
                    correct += 1;
                }
            }
        }
        (correct, self.placed as usize - correct)
    }

    /// S = 5·face_down + 2·revealed_unplaced + correct − wrong.
    pub fn score(&self) -> i32 {
        let (correct, wrong) = self.hint_tally();
        5 * self.face_down() as i32 + 2 * self.revealed_unplaced() as i32 + correct as i32
            - wrong as i32
    }

    /// R = S if won, else −d − (C − clustered) − wrong (d = 1 for an early end). Evaluated
    /// on the current board, whether or not the game is over.
    pub(crate) fn outcome_reward(&self) -> i32 {
        self.reward_if_over(self.phase == Phase::EndedEarly)
    }

    /// The reward R that END would pay now (an early end, d = 1), from the true board: what
    /// a trainer with the simulator at hand can use as the exact value of the END action
    /// (`ppo.end_lookahead`). Meaningful where END is legal (a turn's first substep).
    pub fn end_reward(&self) -> i32 {
        self.reward_if_over(true)
    }

    /// R of the current board if the game were over, ended early or not.
    fn reward_if_over(&self, early_end: bool) -> i32 {
        let clustered = self.clustered_colours();
        if clustered == self.config.colours() {
            self.score()
        } else {
            let (_, wrong) = self.hint_tally();
            -(early_end as i32) - (self.config.colours() - clustered) as i32 - wrong as i32
        }
    }

    /// The outcome of a finished game (`None` while it is being played).
    pub fn outcome(&self) -> Option<Outcome> {
        if !self.is_over() {
            return None;
        }
        let (correct, wrong) = self.hint_tally();
        let clustered = self.clustered_colours();
        Some(Outcome {
            reward: self.outcome_reward(),
            score: self.score(),
            won: clustered == self.config.colours(),
            early_end: self.phase == Phase::EndedEarly,
            length: self.steps,
            correct_hints: correct as u8,
            wrong_hints: wrong as u8,
            clustered: clustered as u8,
            face_down: self.face_down() as u8,
            revealed_unplaced: self.revealed_unplaced() as u8,
        })
    }
}

//! Slow, obviously-correct reference implementations of the rules the engine computes fast
//! on bitboards: connectivity by breadth-first search over plain cells, MOVE legality by
//! trying every card and cell, clustering per colour, and the terminal reward of RULES §4
//! from public accessors, and [`check_state`], the invariants every state keeps. The
//! engine's property tests and `yokai soak` check the fast engine against them; nothing in
//! play uses them.

use crate::bitboard::Cell;
use crate::game::{Game, Phase};
use crate::types::{Card, Colour, HintSlot};
use std::collections::{BTreeSet, VecDeque};

/// BFS connectivity on a plain set of cells.
pub fn connected(cells: &BTreeSet<(i32, i32)>) -> bool {
    let Some(&start) = cells.iter().next() else {
        return true;
    };
    let mut seen = BTreeSet::from([start]);
    let mut queue = VecDeque::from([start]);
    while let Some((r, c)) = queue.pop_front() {
        for n in [(r - 1, c), (r + 1, c), (r, c - 1), (r, c + 1)] {
            if cells.contains(&n) && seen.insert(n) {
                queue.push_back(n);
            }
        }
    }
    seen.len() == cells.len()
}

fn cells_of(game: &Game) -> Vec<(i32, i32)> {
    (0..game.config().cards())
        .map(|k| {
            let c = game.cell_of(Card(k as u8));
            (c.row as i32, c.col as i32)
        })
        .collect()
}

/// Reference MOVE legality: try every (card, cell), move it, BFS.
pub fn reference_moves(game: &Game) -> BTreeSet<(u8, Cell)> {
    let g = game.config().grid() as i32;
    let cells = cells_of(game);
    let mut out = BTreeSet::new();
    for (k, &from) in cells.iter().enumerate() {
        if game.is_hinted(Card(k as u8)) {
            continue;
        }
        for r in 0..g {
            for c in 0..g {
                if cells.contains(&(r, c)) {
                    continue;
                }
                let mut after: BTreeSet<(i32, i32)> = cells.iter().copied().collect();
                after.remove(&from);
                after.insert((r, c));
                if connected(&after) {
                    out.insert((k as u8, Cell::new(r as usize, c as usize)));
                }
            }
        }
    }
    out
}

/// Reference clustering: BFS per colour.
pub fn reference_clustered(game: &Game) -> usize {
    let cells = cells_of(game);
    (0..game.config().colours() as u8)
        .filter(|&colour| {
            let set: BTreeSet<(i32, i32)> = cells
                .iter()
                .enumerate()
                .filter(|(k, _)| game.colour_of(Card(*k as u8)) == Colour(colour))
                .map(|(_, &c)| c)
                .collect();
            connected(&set)
        })
        .count()
}

/// Reference terminal reward from RULES §4, computed from public accessors only.
pub fn reference_reward(game: &Game) -> i32 {
    let config = game.config();
    let mut correct = 0;
    let mut wrong = 0;
    let mut revealed_unplaced = 0;
    let mut face_down = 0;
    for h in 0..config.hints() {
        let slot = HintSlot(h as u8);
        match (game.revealed_hint(slot), game.hint_card(slot)) {
            (None, _) => face_down += 1,
            (Some(_), None) => revealed_unplaced += 1,
            (Some(set), Some(card)) => {
                if set.contains(game.colour_of(card)) {
                    correct += 1
                } else {
                    wrong += 1
                }
            }
        }
    }
    let clustered = reference_clustered(game) as i32;
    let c = config.colours() as i32;
    if clustered == c {
        5 * face_down + 2 * revealed_unplaced + correct - wrong
    } else {
        let d = (game.phase() == Phase::EndedEarly) as i32;
        -d - (c - clustered) - wrong
    }
}

/// An invariant of one state (RULES §1, §2, §4) that [`check_state`] found broken.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum StateFault {
    #[error("two cards share a cell")]
    SharedCell,
    #[error("the cards are not one 4-connected group")]
    NotConnected,
    #[error("colour counts {counts:?}, not {each} each")]
    ColourCounts { counts: Vec<usize>, each: usize },
    #[error("hint {0} placed without being revealed")]
    PlacedUnrevealed(usize),
    #[error("{placed} hints placed but {hinted} cards hinted")]
    HintCount { placed: usize, hinted: usize },
}

/// The invariants every state of every game keeps, read from public accessors (cells by
/// plain sets, connectivity by [`connected`]): every card on its own cell, all cards one
/// 4-connected group, each colour on its share of the cards, and every placed hint revealed
/// and on exactly one hinted card. What holds across steps (a hinted card never moves,
/// colours never change) needs the game's history and is the caller's.
pub fn check_state(game: &Game) -> Result<(), StateFault> {
    let config = game.config();
    let y = config.cards();
    let cells = cells_of(game);
    let distinct: BTreeSet<(i32, i32)> = cells.iter().copied().collect();
    if distinct.len() != y {
        return Err(StateFault::SharedCell);
    }
    if !connected(&distinct) {
        return Err(StateFault::NotConnected);
    }
    let mut counts = vec![0usize; config.colours()];
    for k in 0..y {
        let colour = game.colour_of(Card(k as u8)).index();
        if let Some(count) = counts.get_mut(colour) {
            *count += 1;
        }
    }
    let each = config.cards_per_colour();
    if counts.iter().any(|&count| count != each) {
        return Err(StateFault::ColourCounts { counts, each });
    }
    let mut placed = 0;
    for h in 0..config.hints() {
        let slot = HintSlot(h as u8);
        if game.hint_card(slot).is_some() {
            placed += 1;
            if game.revealed_hint(slot).is_none() {
                return Err(StateFault::PlacedUnrevealed(h));
            }
        }
    }
    let hinted = (0..y).filter(|&k| game.is_hinted(Card(k as u8))).count();
    if placed != hinted {
        return Err(StateFault::HintCount { placed, hinted });
    }
    Ok(())
}

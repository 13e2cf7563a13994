//! `greedy`: the plain strategy of a beginner, from first-hand colours only.
//!
//! - OBSERVE the lowest-id unhinted card whose colour it does not see (else the lowest-id
//!   unhinted card not yet observed this turn). Never END early.
//! - MOVE a card it knows next to a known card of the same colour, choosing the move that
//!   gains the most known same-colour contacts, never moving a card that already touches
//!   a known card of its colour. Without such a move it makes the move that loses the
//!   fewest known contacts (lowest action index on ties); NOOP only when nothing can move.
//! - PLACE a revealed hint on a card it knows to be of one of the hint's colours; else
//!   REVEAL; with nothing left to reveal it must place, and then prefers a known fitting
//!   card, else a card whose colour it does not know (never one it knows is wrong).

use crate::Policy;
use yokai_engine::{Action, Card, Cell, HintSlot, SeatView, Substep};

#[derive(Clone, Debug, Default)]
pub struct GreedyPolicy;

impl GreedyPolicy {
    pub fn new() -> GreedyPolicy {
        GreedyPolicy
    }
}

/// Known same-colour neighbours of `card` if it stood on `cell`.
fn contacts(view: &SeatView<'_>, card: Card, cell: Cell) -> i32 {
    let Some(colour) = view.known_colour(card) else {
        return 0;
    };
    view.cards_around(cell)
        .filter(|&other| other != card && view.known_colour(other) == Some(colour))
        .count() as i32
}

/// Cards on the four cells around `cell`, other than `card`.
fn occupied_neighbours(view: &SeatView<'_>, card: Card, cell: Cell) -> i32 {
    view.cards_around(cell)
        .filter(|&other| other != card)
        .count() as i32
}

impl Policy for GreedyPolicy {
    fn name(&self) -> String {
        "greedy".to_string()
    }

    fn reset(&mut self, _seed: u64) {}

    fn act(&mut self, view: &SeatView<'_>) -> Action {
        let cards = view.config().cards();
        match view.substep() {
            Substep::FirstObserve | Substep::SecondObserve => {
                let open = |card: usize| {
                    let c = Card(card as u8);
                    !view.is_hinted(c) && !view.turn_observed().contains(c)
                };
                let unknown =
                    (0..cards).find(|&c| open(c) && view.known_colour(Card(c as u8)).is_none());
                let card = unknown.or_else(|| (0..cards).find(|&c| open(c)));
                card.map_or(Action::End, |c| Action::Observe(Card(c as u8)))
            }
            Substep::Move => {
                let mut best: Option<(i32, Action)> = None;
                view.for_each_legal(|action| {
                    let Action::Move(card, cell) = action else {
                        return;
                    };
                    let now = contacts(view, card, view.cell_of(card));
                    let then = contacts(view, card, cell);
                    // A card touching its colour stays; otherwise count the gain.
                    // Ties go to the cell with most neighbours: a compact board keeps
                    // colours close together.
                    let value = if now > 0 {
                        -1000 - now
                    } else {
                        16 * (then - now) + occupied_neighbours(view, card, cell)
                    };
                    if best.is_none_or(|(b, _)| value > b) {
                        best = Some((value, action));
                    }
                });
                best.map_or(Action::Noop, |(_, a)| a)
            }
            Substep::Hint => {
                let mut fitting = None;
                let mut unknown = None;
                for slot in 0..view.config().hints() {
                    let slot = HintSlot(slot as u8);
                    let Some(colours) = view.revealed_hint(slot) else {
                        continue;
                    };
                    if view.hint_card(slot).is_some() {
                        continue;
                    }
                    for card in (0..cards).map(|c| Card(c as u8)) {
                        if view.is_hinted(card) {
                            continue;
                        }
                        match view.known_colour(card) {
                            Some(colour) if colours.contains(colour) => {
                                fitting = fitting.or(Some(Action::Place(slot, card)))
                            }
                            None => unknown = unknown.or(Some(Action::Place(slot, card))),
                            Some(_) => {}
                        }
                    }
                }
                if let Some(action) = fitting {
                    action
                } else if view.face_down() > 0 {
                    Action::Reveal
                } else {
                    // Forced to place: every placement left is one it cannot vouch for.
                    unknown.unwrap_or_else(|| view.legal_actions()[0])
                }
            }
        }
    }
}

//! Text renderings of a game, for debugging, tests and terminal front ends.
//!
//! Each cell is four characters wide: `R4 ` is card 4, red; `?4` a card whose colour the
//! viewer does not know; a trailing `*` marks a card with a hint on it; `.` is an empty cell.
//! Below the grid, one line per hint slot.

use crate::game::{Game, Phase};
use crate::types::{CardSet, HintSlot, Seat};
use std::fmt::Write;

/// Whose knowledge of colours a rendering shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Viewer {
    Truth,
    Seat(Seat),
}

/// A game prints as its board with every colour shown: what a failing test or a debugger
/// should show. It lives here, beside the drawing, so that `game` does not depend on it.
impl std::fmt::Debug for Game {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&render_truth(self))
    }
}

/// The board with every colour shown (the ground truth).
pub fn render_truth(game: &Game) -> String {
    render(game, Viewer::Truth)
}

/// The board as `seat` sees it: only the colours it knows, face-down hints hidden.
pub fn render_seat(game: &Game, seat: Seat) -> String {
    render(game, Viewer::Seat(seat))
}

fn render(game: &Game, viewer: Viewer) -> String {
    let config = game.config();
    let g = config.grid();
    let mut s = String::new();
    let who = match viewer {
        Viewer::Truth => "ground truth".to_string(),
        Viewer::Seat(seat) => format!("as seen by {seat}"),
    };
    let status = match game.phase() {
        Phase::Playing => format!(
            "{} to play, substep {}",
            game.current_seat(),
            game.substep().index()
        ),
        Phase::EndedEarly => "ended early".to_string(),
        Phase::Finished => "finished (all hints placed)".to_string(),
    };
    let _ = writeln!(s, "{config} · {who} · {status} · step {}", game.steps());
    let known = match viewer {
        Viewer::Truth => CardSet::first(game.config().cards()),
        Viewer::Seat(seat) => game.known_cards(seat),
    };
    let _ = write!(s, "   ");
    for c in 0..g {
        let _ = write!(s, "{c:<4}");
    }
    s.push('\n');
    for r in 0..g {
        let mut line = format!("{r:>2} ");
        for c in 0..g {
            let text = match game.card_at(crate::Cell::new(r, c)) {
                None => ".".to_string(),
                Some(card) => {
                    let letter = if known.contains(card) {
                        game.colour_of(card).letter()
                    } else {
                        '?'
                    };
                    let mark = if game.is_hinted(card) { "*" } else { "" };
                    format!("{letter}{}{mark}", card.0)
                }
            };
            let _ = write!(line, "{text:<4}");
        }
        s.push_str(line.trim_end());
        s.push('\n');
    }
    for slot in 0..config.hints() {
        let h = HintSlot(slot as u8);
        let colours = match (viewer, game.revealed_hint(h)) {
            (_, Some(set)) => set.letters(),
            (Viewer::Truth, None) => format!("({})", game.hint_colours(h).letters()),
            (Viewer::Seat(_), None) => "??".to_string(),
        };
        let state = match (game.revealed_hint(h), game.hint_card(h)) {
            (None, _) => "face down".to_string(),
            (Some(_), None) => "revealed".to_string(),
            (Some(set), Some(card)) => {
                let verdict = match viewer {
                    Viewer::Truth => {
                        if set.contains(game.colour_of(card)) {
                            " (correct)"
                        } else {
                            " (wrong)"
                        }
                    }
                    Viewer::Seat(_) => "",
                };
                format!("on {card}{verdict}")
            }
        };
        let _ = writeln!(s, "hint {slot}: {colours} {state}");
    }
    if let Some((seat, action)) = game.last_action() {
        let _ = writeln!(s, "last: {seat} played {action}");
    }
    if let (Viewer::Truth, Some(o)) = (viewer, game.outcome()) {
        let _ = writeln!(
            s,
            "outcome: R = {}, {}, {} of {} colours clustered, {} correct / {} wrong hints",
            o.reward,
            if o.won { "won" } else { "lost" },
            o.clustered,
            config.colours(),
            o.correct_hints,
            o.wrong_hints
        );
    }
    s
}

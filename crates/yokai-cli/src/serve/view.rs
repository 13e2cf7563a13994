//! What the page is sent: one seat's view of a game as JSON. Only what that seat may know
//! leaves the server (the true colours only once the game is over).

use serde_json::{json, Value};
use yokai_engine::{Action, Card, Game, HintSlot, Seat, Substep};

/// The board as `seat` sees it, with the legal actions when `seat` is to act.
pub fn seat_view(game: &Game, seat: Seat) -> Value {
    board(game, seat, false)
}

/// The board with every colour shown, for replays watched after the fact (the acting
/// seat's legal actions included).
pub fn truth_view(game: &Game) -> Value {
    board(game, game.current_seat(), true)
}

fn board(game: &Game, seat: Seat, all: bool) -> Value {
    let config = game.config();
    let view = game.view(seat);
    let public = view.public();
    let over = game.is_over();
    let cards: Vec<Value> = (0..config.cards())
        .map(|k| {
            let card = Card(k as u8);
            let cell = game.cell_of(card);
            let colour = if over || all {
                Some(game.colour_of(card))
            } else {
                view.known_colour(card)
            };
            json!({
                "id": k,
                "row": cell.row,
                "col": cell.col,
                "colour": colour.map(|c| c.name()),
                "hint": game.hint_on(card).map(|h| h.0),
                "observed": public.turn_observed().contains(card),
            })
        })
        .collect();
    let hints: Vec<Value> = (0..config.hints())
        .map(|h| {
            let slot = HintSlot(h as u8);
            let card = public.hint_card(slot);
            let colours = public.revealed_hint(slot);
            let state = match (card, colours) {
                (Some(_), _) => "placed",
                (None, Some(_)) => "revealed",
                (None, None) => "face down",
            };
            json!({
                "slot": h,
                "state": state,
                "card": card.map(|c| c.0),
                "colours": colours.map(|set| set.colours().map(|c| c.name()).collect::<Vec<_>>()),
            })
        })
        .collect();
    let legal: Vec<Value> = if !over && game.current_seat() == seat {
        view.legal_actions()
            .into_iter()
            .map(|a| action_json(config.encode(a), a))
            .collect()
    } else {
        Vec::new()
    };
    json!({
        "viewer": seat.0,
        "grid": config.grid(),
        "colours": config.colours(),
        "cards": cards,
        "hints": hints,
        "turn": game.current_seat().0,
        "substep": game.substep() as u8,
        "substep_name": substep_name(game),
        "step": game.steps(),
        "over": over,
        "outcome": game.outcome(),
        "last_action": public
            .last_action()
            .map(|(s, a)| json!({"seat": s.0, "name": a.to_string()})),
        "legal": legal,
    })
}

/// One legal action: its index (what the page sends back), its name, and its parts, so the
/// page can offer it by clicking the card, cell or hint it concerns.
pub fn action_json(index: usize, action: Action) -> Value {
    let (kind, card, cell, hint) = match action {
        Action::Noop => ("noop", None, None, None),
        Action::End => ("end", None, None, None),
        Action::Observe(c) => ("observe", Some(c.0), None, None),
        Action::Move(c, x) => ("move", Some(c.0), Some([x.row, x.col]), None),
        Action::Reveal => ("reveal", None, None, None),
        Action::Place(h, c) => ("place", Some(c.0), None, Some(h.0)),
    };
    json!({"index": index, "name": action.to_string(), "kind": kind, "card": card, "cell": cell, "hint": hint})
}

fn substep_name(game: &Game) -> &'static str {
    if game.is_over() {
        return "game over";
    }
    match game.substep() {
        Substep::FirstObserve => "observe a card or end the game",
        Substep::SecondObserve => "observe a second card",
        Substep::Move => "move a card",
        Substep::Hint => "reveal or place a hint",
    }
}

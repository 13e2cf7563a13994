//! One turn of a game as an SVG picture, like the paper's example games: the true board on
//! the left, one seat's view on the right, hinted cards outlined in their hint's colours,
//! the hint slots below each board, clusters counted, and the action in words.
//!
//! Every card is one `<rect class="card …" data-card="ID" data-colour="NAME">` element, so
//! pictures can be checked (and styled) by machines as well as read by people.

use crate::plots::escape;
use std::fmt::Write;
use yokai_engine::{Action, CardSet, Cell, Colour, Game, HintSlot, Seat};

const CELL: usize = 36;
const MARGIN: usize = 24;
const TOP: usize = 72;

fn fill(colour: Option<Colour>) -> &'static str {
    match colour.map(|c| c.index()) {
        Some(0) => "#d62728",
        Some(1) => "#2ca02c",
        Some(2) => "#1f77b4",
        Some(3) => "#e6b800",
        _ => "#b0b0b0",
    }
}

/// Whose knowledge a board panel shows.
#[derive(Clone, Copy)]
enum Panel {
    Truth,
    Seat(Seat),
}

/// The picture of `game` (the state before `action`, if any) seen by `seat`.
pub fn render_turn(game: &Game, seat: Seat, action: Option<(Seat, Action)>, title: &str) -> String {
    let config = game.config();
    let g = config.grid();
    let board = g * CELL;
    let hints_h = 28 + 22 * config.hints().div_ceil(4);
    let width = 3 * MARGIN + 2 * board;
    let height = TOP + board + hints_h + 40;
    let mut s = String::new();
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\" font-size=\"13\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    let _ = writeln!(
        s,
        "<text x=\"{MARGIN}\" y=\"20\" font-size=\"15\" font-weight=\"bold\">{}</text>",
        escape(title)
    );
    let said = match action {
        Some((actor, a)) => format!("{actor} plays: {a}"),
        None => match game.outcome() {
            Some(o) => format!(
                "game over: R = {}, {} ({} steps)",
                o.reward,
                if o.won { "won" } else { "not won" },
                o.length
            ),
            None => String::new(),
        },
    };
    let _ = writeln!(
        s,
        "<text x=\"{MARGIN}\" y=\"40\" class=\"action\">{}</text>",
        escape(&said)
    );
    panel(&mut s, game, Panel::Truth, MARGIN, TOP);
    panel(&mut s, game, Panel::Seat(seat), 2 * MARGIN + board, TOP);
    let clustered = game.clustered_colours();
    let _ = writeln!(
        s,
        "<text x=\"{MARGIN}\" y=\"{}\" class=\"clusters\">clustered colours: {clustered} of {}</text>",
        height - 12,
        config.colours()
    );
    s.push_str("</svg>\n");
    s
}

/// One seat's turn of a game: its actions in order and the game after them.
pub struct Turn<'a> {
    pub seat: Seat,
    pub actions: Vec<Action>,
    pub after: &'a Game,
}

/// Split a game's states (each state before an action with that action, then the end, as
/// `yokai replay` lists them) into turns: the actions one seat takes in a row.
pub fn turns(states: &[(Game, Option<(Seat, Action)>)]) -> Vec<Turn<'_>> {
    let mut out: Vec<Turn<'_>> = Vec::new();
    for (i, (_, action)) in states.iter().enumerate() {
        let (Some((seat, action)), Some((after, _))) = (*action, states.get(i + 1)) else {
            continue;
        };
        match out.last_mut() {
            Some(turn) if turn.seat == seat => {
                turn.actions.push(action);
                turn.after = after;
            }
            _ => out.push(Turn {
                seat,
                actions: vec![action],
                after,
            }),
        }
    }
    out
}

/// Turns per row of a game sheet.
const SHEET_COLUMNS: usize = 4;
/// Lines of actions a turn's column has room for.
const SHEET_ACTION_LINES: usize = 5;

/// A whole game on one picture, as the paper draws its example games: one column per turn
/// (the seat's actions, then the true board above and that seat's view below, both as the
/// turn left them), four turns to a row, the outcome in the title. Empty without turns.
pub fn render_sheet(turns: &[Turn<'_>], title: &str) -> String {
    let Some(first) = turns.first() else {
        return String::new();
    };
    let config = first.after.config();
    let board = config.grid() * CELL;
    let hints_h = 28 + 22 * config.hints().div_ceil(4);
    let column = board + MARGIN;
    let head = 24 + 16 * SHEET_ACTION_LINES;
    let cell_h = head + 2 * (board + hints_h + 24);
    let rows = turns.len().div_ceil(SHEET_COLUMNS);
    let width = MARGIN + SHEET_COLUMNS.min(turns.len()) * column;
    let height = 56 + rows * cell_h;
    let mut s = String::new();
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\" font-size=\"13\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{MARGIN}\" y=\"28\" font-size=\"16\" font-weight=\"bold\">{}</text>\n",
        escape(title)
    );
    for (k, turn) in turns.iter().enumerate() {
        let x0 = MARGIN + (k % SHEET_COLUMNS) * column;
        let y0 = 56 + (k / SHEET_COLUMNS) * cell_h;
        let _ = writeln!(
            s,
            "<g class=\"turn\" data-turn=\"{}\" data-seat=\"{}\"><text x=\"{x0}\" y=\"{}\" \
             font-weight=\"bold\">turn {}: {} · clustered colours {} of {}</text>",
            k + 1,
            turn.seat.index(),
            y0 + 14,
            k + 1,
            turn.seat,
            turn.after.clustered_colours(),
            config.colours()
        );
        let mut lines: Vec<String> = turn.actions.iter().map(|a| a.to_string()).collect();
        if lines.len() > SHEET_ACTION_LINES {
            let more = lines.len() - (SHEET_ACTION_LINES - 1);
            lines.truncate(SHEET_ACTION_LINES - 1);
            lines.push(format!("… and {more} more"));
        }
        for (j, line) in lines.iter().enumerate() {
            let _ = writeln!(
                s,
                "<text class=\"action\" x=\"{x0}\" y=\"{}\" font-size=\"12\">{}</text>",
                y0 + 32 + 16 * j,
                escape(line)
            );
        }
        let top = y0 + head + 16;
        panel(&mut s, turn.after, Panel::Truth, x0, top);
        let below = top + board + hints_h + 24;
        panel(&mut s, turn.after, Panel::Seat(turn.seat), x0, below);
        s.push_str("</g>\n");
    }
    s.push_str("</svg>\n");
    s
}

/// One board (the truth, or a seat's knowledge) with its hint slots, its top-left corner
/// at (`x0`, `top`); its label sits just above.
fn panel(s: &mut String, game: &Game, who: Panel, x0: usize, top: usize) {
    let config = game.config();
    let g = config.grid();
    let (label, known, class) = match who {
        Panel::Truth => (
            "ground truth".to_string(),
            CardSet::first(game.config().cards()),
            "truth",
        ),
        Panel::Seat(seat) => (format!("{seat}'s view"), game.known_cards(seat), "view"),
    };
    let _ = writeln!(
        s,
        "<g class=\"panel {class}\"><text x=\"{x0}\" y=\"{}\">{label}</text>",
        top - 4
    );
    let _ = writeln!(
        s,
        "<rect x=\"{x0}\" y=\"{top}\" width=\"{w}\" height=\"{w}\" fill=\"#f6f6f6\" stroke=\"#ddd\"/>",
        w = g * CELL
    );
    for r in 0..g {
        for c in 0..g {
            let Some(card) = game.card_at(Cell::new(r, c)) else {
                continue;
            };
            let (x, y) = (x0 + c * CELL + 2, top + r * CELL + 2);
            let colour = known.contains(card).then(|| game.colour_of(card));
            let name = colour.map_or("unknown", |c| c.name());
            let hint = game.hint_on(card);
            let stroke = match hint {
                Some(slot) => {
                    let shown = match who {
                        Panel::Truth => Some(game.hint_colours(slot)),
                        Panel::Seat(_) => game.revealed_hint(slot),
                    };
                    let first = shown.and_then(|set| set.colours().next());
                    format!(
                        " stroke=\"{}\" stroke-width=\"4\" data-hint=\"{}\"",
                        if first.is_some() { fill(first) } else { "#000" },
                        shown.map_or("?".into(), |set| set.letters())
                    )
                }
                None => String::new(),
            };
            let _ = writeln!(
                s,
                "<rect class=\"card {class}\" data-card=\"{}\" data-colour=\"{name}\" x=\"{x}\" y=\"{y}\" \
                 width=\"{w}\" height=\"{w}\" rx=\"4\" fill=\"{}\"{stroke}/>",
                card.0,
                fill(colour),
                w = CELL - 4
            );
            let label = if colour.is_some() {
                card.0.to_string()
            } else {
                format!("?{}", card.0)
            };
            let _ = writeln!(
                s,
                "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"white\" font-weight=\"bold\">{label}</text>",
                x + (CELL - 4) / 2,
                y + CELL / 2 + 3
            );
        }
    }
    // Hint slots, four per row, below the board.
    let y0 = top + g * CELL + 10;
    for slot in 0..config.hints() {
        let h = HintSlot(slot as u8);
        let (x, y) = (x0 + (slot % 4) * 80, y0 + (slot / 4) * 22);
        let set = match who {
            Panel::Truth => Some(game.hint_colours(h)),
            Panel::Seat(_) => game.revealed_hint(h),
        };
        let text = match (set, game.hint_card(h)) {
            (Some(set), Some(card)) => format!("{} on {}", set.letters(), card.0),
            (Some(set), None) => set.letters(),
            (None, Some(card)) => format!("? on {}", card.0),
            (None, None) => "face down".into(),
        };
        let _ = writeln!(
            s,
            "<rect class=\"hint\" x=\"{x}\" y=\"{y}\" width=\"74\" height=\"18\" rx=\"3\" fill=\"none\" stroke=\"#888\"/>\
             <text x=\"{}\" y=\"{}\" font-size=\"11\">{}</text>",
            x + 4,
            y + 13,
            escape(&text)
        );
    }
    s.push_str("</g>\n");
}

#[cfg(test)]
mod tests {
    use super::*;
    use yokai_engine::{Config, RecordedGame};

    /// Count `class="card CLASS"` elements and check each one's colour against the game.
    fn cards_in(svg: &str, class: &str, game: &Game, known: CardSet) -> usize {
        let needle = format!("class=\"card {class}\" data-card=\"");
        let mut n = 0;
        for part in svg.split(&needle).skip(1) {
            let id: u8 = part[..part.find('"').unwrap()].parse().unwrap();
            let colour = part
                .split("data-colour=\"")
                .nth(1)
                .and_then(|p| p.split('"').next())
                .unwrap();
            let card = yokai_engine::Card(id);
            let want = if known.contains(card) {
                game.colour_of(card).name()
            } else {
                "unknown"
            };
            assert_eq!(colour, want, "card {id} in {class}");
            n += 1;
        }
        n
    }

    #[test]
    fn one_card_element_per_card_with_the_right_colour_in_each_panel() {
        let config = Config::from_name("9c-2p-perfect").unwrap();
        let mut game = RecordedGame::new(config, 11);
        let mut k = 0usize;
        while !game.game().is_over() {
            let seat = game.game().current_seat();
            let legal = game.game().legal_actions(seat);
            let action = legal[k * 31 % legal.len()];
            let svg = render_turn(game.game(), Seat(0), Some((seat, action)), "test");
            let g = game.game();
            let all = CardSet::first(config.cards());
            assert_eq!(cards_in(&svg, "truth", g, all), config.cards());
            assert_eq!(
                cards_in(&svg, "view", g, g.known_cards(Seat(0))),
                config.cards()
            );
            assert!(svg.contains(&escape(&action.to_string())));
            game.apply(action).unwrap();
            k += 1;
        }
        let svg = render_turn(game.game(), Seat(1), None, "end");
        assert!(svg.contains("game over: R ="));
    }

    /// A game sheet has one column per turn, each turn's actions in order, and every card in
    /// both of its boards with the colours the truth and the acting seat's knowledge give.
    #[test]
    fn a_sheet_shows_every_turn_with_its_actions_and_both_boards() {
        let config = Config::from_name("9c-2p-perfect").unwrap();
        let mut game = RecordedGame::new(config, 5);
        let mut states = Vec::new();
        let mut k = 0usize;
        while !game.game().is_over() {
            let seat = game.game().current_seat();
            // Never END, so the game has several turns.
            let moves: Vec<Action> = game
                .game()
                .legal_actions(seat)
                .into_iter()
                .filter(|a| *a != Action::End)
                .collect();
            let action = moves[k * 17 % moves.len()];
            states.push((game.game().clone(), Some((seat, action))));
            game.apply(action).unwrap();
            k += 1;
        }
        states.push((game.game().clone(), None));
        let turns = turns(&states);
        // Turns alternate seats and hold every action once, in order.
        assert!(turns.len() >= 4);
        assert!(turns.windows(2).all(|w| w[0].seat != w[1].seat));
        let actions: Vec<Action> = turns.iter().flat_map(|t| t.actions.clone()).collect();
        let played: Vec<Action> = states
            .iter()
            .filter_map(|(_, a)| a.map(|(_, a)| a))
            .collect();
        assert_eq!(actions, played);
        let svg = render_sheet(&turns, "a game");
        assert_eq!(svg.matches("<g class=\"turn\"").count(), turns.len());
        let all = CardSet::first(config.cards());
        for (k, turn) in turns.iter().enumerate() {
            let part = svg.split("<g class=\"turn\"").nth(k + 1).unwrap();
            assert!(
                part.contains(&format!("turn {}: {}", k + 1, turn.seat)),
                "{part}"
            );
            for a in turn.actions.iter().take(SHEET_ACTION_LINES - 1) {
                assert!(
                    part.contains(&escape(&a.to_string())),
                    "{a} in turn {}",
                    k + 1
                );
            }
            assert_eq!(cards_in(part, "truth", turn.after, all), config.cards());
            let known = turn.after.known_cards(turn.seat);
            assert_eq!(cards_in(part, "view", turn.after, known), config.cards());
        }
        assert!(render_sheet(&[], "none").is_empty());
    }
}

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
    panel(&mut s, game, Panel::Truth, MARGIN);
    panel(&mut s, game, Panel::Seat(seat), 2 * MARGIN + board);
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

fn panel(s: &mut String, game: &Game, who: Panel, x0: usize) {
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
        TOP - 4
    );
    let _ = writeln!(
        s,
        "<rect x=\"{x0}\" y=\"{TOP}\" width=\"{w}\" height=\"{w}\" fill=\"#f6f6f6\" stroke=\"#ddd\"/>",
        w = g * CELL
    );
    for r in 0..g {
        for c in 0..g {
            let Some(card) = game.card_at(Cell::new(r, c)) else {
                continue;
            };
            let (x, y) = (x0 + c * CELL + 2, TOP + r * CELL + 2);
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
    let y0 = TOP + g * CELL + 10;
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
}

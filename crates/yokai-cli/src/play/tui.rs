//! The terminal UI of `yokai play` (ratatui + crossterm; works over SSH). All game logic
//! lives in [`Session`]; this file only draws it and turns terminal events into keys.

use super::session::{Effect, Key, Session};
use anyhow::Context;
use ratatui::crossterm::event::{
    self, DisableMouseCapture, EnableMouseCapture, Event, KeyCode, KeyEventKind, MouseButton,
    MouseEventKind,
};
use ratatui::crossterm::execute;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, List, ListItem, ListState, Paragraph, Wrap};
use ratatui::Frame;
use yokai_engine::{CardSet, Cell, Colour, Game, HintSlot, Phase, Seat};

pub fn run(session: &mut Session, color: bool) -> anyhow::Result<()> {
    let mut terminal = ratatui::init();
    let _ = execute!(std::io::stdout(), EnableMouseCapture);
    let result = event_loop(&mut terminal, session, color);
    let _ = execute!(std::io::stdout(), DisableMouseCapture);
    ratatui::restore();
    result
}

fn event_loop(
    terminal: &mut ratatui::DefaultTerminal,
    session: &mut Session,
    color: bool,
) -> anyhow::Result<()> {
    let mut message = String::new();
    // Where the action list was drawn and its first visible item, to map mouse clicks.
    let mut list = (Rect::default(), 0usize);
    loop {
        terminal
            .draw(|f| list = draw(f, session, color, &message))
            .context("cannot draw")?;
        let key = match event::read().context("cannot read the terminal")? {
            Event::Key(k) if k.kind == KeyEventKind::Press => match k.code {
                KeyCode::Up => Key::Up,
                KeyCode::Down => Key::Down,
                KeyCode::PageUp => Key::PageUp,
                KeyCode::PageDown => Key::PageDown,
                KeyCode::Enter => Key::Enter,
                KeyCode::Esc => Key::Esc,
                KeyCode::Char(c) => Key::Char(c),
                _ => continue,
            },
            Event::Mouse(m) => match m.kind {
                MouseEventKind::ScrollUp => Key::Up,
                MouseEventKind::ScrollDown => Key::Down,
                MouseEventKind::Down(MouseButton::Left) => {
                    let (area, offset) = list;
                    let inside = m.column > area.x
                        && m.column + 1 < area.x + area.width
                        && m.row > area.y
                        && m.row + 1 < area.y + area.height;
                    if inside && !session.is_over() {
                        let index = offset + (m.row - area.y - 1) as usize;
                        match session.click(index) {
                            Ok(_) => message.clear(),
                            Err(e) => message = e.to_string(),
                        }
                    }
                    continue;
                }
                _ => continue,
            },
            _ => continue,
        };
        if session.is_over() && key != Key::Up && key != Key::Down {
            return Ok(());
        }
        match session.handle(key) {
            Ok(Effect::Quit) => return Ok(()),
            Ok(_) => message.clear(),
            Err(e) => message = e.to_string(),
        }
    }
}

fn colour_style(colour: Colour, color: bool) -> Style {
    if !color {
        return Style::default().add_modifier(Modifier::BOLD);
    }
    Style::default().fg(match colour.index() {
        0 => Color::Red,
        1 => Color::Green,
        2 => Color::Blue,
        _ => Color::Yellow,
    })
}

/// The grid as the viewer knows it (`None`: the true board).
fn board(game: &Game, viewer: Option<Seat>, color: bool) -> Vec<Line<'static>> {
    let g = game.config().grid();
    let known = viewer.map_or(CardSet::first(game.config().cards()), |s| {
        game.known_cards(s)
    });
    let mut lines = vec![Line::from(
        std::iter::once("   ".to_string())
            .chain((0..g).map(|c| format!("{c:<4}")))
            .collect::<String>(),
    )];
    for r in 0..g {
        let mut spans = vec![Span::raw(format!("{r:>2} "))];
        for c in 0..g {
            match game.card_at(Cell::new(r, c)) {
                None => spans.push(Span::raw(".   ")),
                Some(card) => {
                    let hinted = game.is_hinted(card);
                    let (text, mut style) = if known.contains(card) {
                        let colour = game.colour_of(card);
                        (
                            format!("{}{}", colour.letter(), card.0),
                            colour_style(colour, color),
                        )
                    } else {
                        (format!("?{}", card.0), Style::default())
                    };
                    if hinted {
                        style = style.add_modifier(Modifier::UNDERLINED);
                    }
                    let mark = if hinted { "*" } else { "" };
                    spans.push(Span::styled(format!("{text}{mark}"), style));
                    spans.push(Span::raw(
                        " ".repeat(4usize.saturating_sub(text.len() + mark.len())),
                    ));
                }
            }
        }
        lines.push(Line::from(spans));
    }
    lines.push(Line::raw(""));
    for slot in 0..game.config().hints() {
        let h = HintSlot(slot as u8);
        let colours = match (viewer, game.revealed_hint(h)) {
            (_, Some(set)) => set.letters(),
            (None, None) => format!("({})", game.hint_colours(h).letters()),
            (Some(_), None) => "face down".into(),
        };
        let on = game
            .hint_card(h)
            .map_or(String::new(), |c| format!(" on card {}", c.0));
        lines.push(Line::raw(format!("hint {slot}: {colours}{on}")));
    }
    lines
}

/// Draw the screen; returns the action list's area and first visible item.
fn draw(f: &mut Frame, session: &Session, color: bool, message: &str) -> (Rect, usize) {
    let game = session.game();
    let rows = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Min(10),
            Constraint::Length(8),
            Constraint::Length(2),
        ])
        .split(f.area());
    let top = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Length(42), Constraint::Min(30)])
        .split(rows[0]);
    let viewer = session.viewer();
    let status = match game.phase() {
        Phase::Playing => format!(
            "{} ({}) to play · substep {} · step {}",
            game.current_seat(),
            session.names()[game.current_seat().index()],
            game.substep().index(),
            game.steps()
        ),
        _ => "game over".into(),
    };
    let hidden = session.curtain();
    let mut list = (Rect::default(), 0);
    let (title, lines) = if session.is_over() {
        ("the true board".to_string(), board(game, None, color))
    } else if hidden {
        (
            "hidden".to_string(),
            vec![Line::raw(format!(
                "{} must play next. Press Enter when only {} can see the screen.",
                game.current_seat(),
                game.current_seat()
            ))],
        )
    } else {
        (format!("{viewer}'s view"), board(game, Some(viewer), color))
    };
    f.render_widget(
        Paragraph::new(lines).block(Block::default().borders(Borders::ALL).title(title)),
        top[0],
    );
    if session.is_over() {
        let text = match game.outcome() {
            Some(o) => format!(
                "Game over after {} steps.\n\nR = {}  ({})\nscore {}\ncorrect hints {}, wrong hints {}\nclustered colours {}\n\nPress any key to leave.",
                o.length,
                o.reward,
                if o.won { "won" } else { "not won" },
                o.score,
                o.correct_hints,
                o.wrong_hints,
                o.clustered
            ),
            None => String::new(),
        };
        f.render_widget(
            Paragraph::new(text).block(Block::default().borders(Borders::ALL).title("result")),
            top[1],
        );
    } else {
        let legal = if hidden { Vec::new() } else { session.legal() };
        let items: Vec<ListItem> = legal.iter().map(|a| ListItem::new(a.to_string())).collect();
        let mut state = ListState::default();
        if !items.is_empty() {
            state.select(Some(session.selected()));
        }
        let highlight = if color {
            Style::default()
                .bg(Color::DarkGray)
                .add_modifier(Modifier::BOLD)
        } else {
            Style::default().add_modifier(Modifier::REVERSED)
        };
        f.render_stateful_widget(
            List::new(items)
                .block(
                    Block::default()
                        .borders(Borders::ALL)
                        .title("legal actions (↑/↓ or click, Enter; q quits)"),
                )
                .highlight_style(highlight)
                .highlight_symbol("> "),
            top[1],
            &mut state,
        );
        list = (top[1], state.offset());
    }
    let log = session.log();
    let recent: Vec<Line> = log
        .iter()
        .skip(log.len().saturating_sub(6))
        .map(|l| Line::raw(l.clone()))
        .collect();
    f.render_widget(
        Paragraph::new(recent)
            .wrap(Wrap { trim: true })
            .block(Block::default().borders(Borders::ALL).title("last actions")),
        rows[1],
    );
    let bottom = if message.is_empty() {
        status
    } else {
        format!("{status} · {message}")
    };
    f.render_widget(Paragraph::new(bottom), rows[2]);
    list
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::play::session::Player;
    use ratatui::backend::TestBackend;
    use yokai_agents::RandomPolicy;
    use yokai_engine::{Card, Config};

    /// The screen `draw` paints for `session`, as lines of text.
    fn screen(session: &Session) -> Vec<String> {
        let mut terminal = ratatui::Terminal::new(TestBackend::new(110, 40)).unwrap();
        terminal
            .draw(|f| {
                draw(f, session, false, "");
            })
            .unwrap();
        let buffer = terminal.backend().buffer().clone();
        (0..buffer.area.height)
            .map(|y| {
                (0..buffer.area.width)
                    .map(|x| buffer[(x, y)].symbol().to_string())
                    .collect::<String>()
            })
            .collect()
    }

    /// The acting human's first legal action that does not END the game.
    fn play_on(s: &mut Session) {
        let legal = s.legal();
        let action = legal
            .iter()
            .copied()
            .find(|a| *a != yokai_engine::Action::End)
            .unwrap_or(legal[0]);
        s.choose(action).unwrap();
    }

    fn session(players: Vec<(String, Player)>, seed: u64) -> Session {
        let config = Config::from_name(&format!("9c-{}p-perfect", players.len())).unwrap();
        Session::new(config, seed, players).unwrap()
    }

    /// Every card's cell shows its colour letter where the viewer knows it and `?` where
    /// not; the status line, the legal actions and, at the end, the true board and the
    /// outcome are on screen.
    #[test]
    fn the_screen_shows_what_the_viewer_knows_and_the_legal_actions() {
        let mut s = session(
            vec![
                ("human".into(), Player::Human),
                ("random".into(), Player::Bot(Box::new(RandomPolicy::new(2)))),
            ],
            7,
        );
        // Observe two cards: seat 0 then knows their colours.
        play_on(&mut s);
        play_on(&mut s);
        let text = screen(&s).join("\n");
        let game = s.game();
        let known = game.known_cards(Seat(0));
        let cards = game.config().cards();
        assert!(known.len() >= 2, "two cards observed");
        for id in 0..cards {
            let card = Card(id as u8);
            let shown = if known.contains(card) {
                format!("{}{id}", game.colour_of(card).letter())
            } else {
                format!("?{id}")
            };
            assert!(
                text.contains(&shown),
                "card {id} should show as {shown}:\n{text}"
            );
        }
        assert!(text.contains("seat 0's view"), "{text}");
        assert!(text.contains("seat 0 (human) to play"), "{text}");
        for action in s.legal().iter().take(5) {
            assert!(
                text.contains(&action.to_string()),
                "{action} not listed:\n{text}"
            );
        }
        // Played to the end by the bots' moves and the first legal move of the human.
        while !s.is_over() {
            play_on(&mut s);
        }
        let text = screen(&s).join("\n");
        let o = s.game().outcome().unwrap();
        assert!(text.contains("the true board"), "{text}");
        assert!(text.contains(&format!("R = {}", o.reward)), "{text}");
        assert!(
            !text.contains("?0 "),
            "every colour shows at the end:\n{text}"
        );
    }

    /// Between two humans' turns (hot seat) the board is hidden and no action is listed.
    #[test]
    fn the_curtain_hides_the_board_between_humans() {
        let mut s = session(
            vec![
                ("human".into(), Player::Human),
                ("human".into(), Player::Human),
            ],
            3,
        );
        while !s.curtain() {
            play_on(&mut s);
        }
        let lines = screen(&s);
        let text = lines.join("\n");
        assert!(
            text.contains("seat 1 must play next. Press Enter"),
            "{text}"
        );
        // Above the public log of past actions: no card and no legal action.
        let panes: String = lines
            .iter()
            .take_while(|l| !l.contains("last actions"))
            .cloned()
            .collect();
        assert!(!panes.contains("?0"), "no card while hidden:\n{text}");
        assert!(
            !panes.contains("observe card"),
            "no action while hidden:\n{text}"
        );
    }
}

//! `yokai replay FILE`: step through a saved game in the terminal, or render every turn as
//! an SVG or PNG picture.

use crate::svg::render_turn;
use std::io::{BufRead, IsTerminal, Write};
use std::path::{Path, PathBuf};
use yokai_engine::{render_seat, render_truth, Game, Replay, Seat};

#[derive(clap::Args)]
pub struct Args {
    /// A replay file (JSON lines) written by `yokai play --save`, `yokai eval --replays` or
    /// `yokai train`.
    file: PathBuf,
    /// Whose view to show beside the true board.
    #[arg(long, default_value_t = 0)]
    seat: u8,
    /// Write one SVG per turn (and one for the end) into this directory.
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Write one PNG per turn (rendered from the SVG; text needs a system font).
    #[arg(long)]
    png: Option<PathBuf>,
}

pub fn read(path: &Path) -> Result<Replay, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Replay::from_jsonl(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Every state of the game (before each action, then the end) with the action taken.
fn states(replay: &Replay) -> Result<Vec<(Game, Option<String>)>, String> {
    let mut out = Vec::new();
    let record = replay.record();
    let last = record
        .replay_with(|before, action, _| {
            let who = &replay.header.seats.get(before.current_seat().index());
            let text = format!(
                "{} ({}) plays: {action}",
                before.current_seat(),
                who.map_or("?", |s| s.as_str())
            );
            out.push((before.clone(), Some(text)));
        })
        .map_err(|e| e.to_string())?;
    out.push((last, None));
    Ok(out)
}

pub fn run(args: Args) -> Result<(), String> {
    let replay = read(&args.file)?;
    let config = replay.header.config;
    if args.seat as usize >= config.players() {
        return Err(format!("--seat {} does not exist in {config}", args.seat));
    }
    let seat = Seat(args.seat);
    let states = states(&replay)?;
    let title = |i: usize| {
        format!(
            "{config} · {} · step {i} of {}",
            replay.header.seats.join(" + "),
            states.len() - 1
        )
    };
    let pictures = args.svg.is_some() || args.png.is_some();
    for (dir, kind) in [(&args.svg, "svg"), (&args.png, "png")] {
        let Some(dir) = dir else { continue };
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        let mut fonts = None;
        for (i, (game, action)) in states.iter().enumerate() {
            let acting = action.as_ref().map(|_| game.current_seat());
            let act = acting.zip(replay.steps.get(i).map(|s| {
                config
                    .decode(s.action as usize)
                    .expect("the replay was checked")
            }));
            let svg = render_turn(game, seat, act, &title(i));
            let path = dir.join(format!("turn-{i:03}.{kind}"));
            let bytes = if kind == "svg" {
                svg.into_bytes()
            } else {
                let db =
                    fonts.get_or_insert_with(|| std::sync::Arc::new(crate::plots::system_fonts()));
                crate::plots::png(&svg, db.clone())?
            };
            std::fs::write(&path, bytes)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        eprintln!(
            "wrote {} {kind} pictures to {}",
            states.len(),
            dir.display()
        );
    }
    if pictures {
        return Ok(());
    }
    let interactive = std::io::stdin().is_terminal() && std::io::stdout().is_terminal();
    let stdin = std::io::stdin();
    let mut input = stdin.lock();
    let mut out = std::io::stdout();
    for (i, (game, action)) in states.iter().enumerate() {
        let text = format!(
            "── {} ──\n{}\n{}\n{}\n",
            title(i),
            render_truth(game),
            render_seat(game, seat),
            action.clone().unwrap_or_else(|| match game.outcome() {
                Some(o) => format!(
                    "game over: R = {} ({})",
                    o.reward,
                    if o.won { "won" } else { "not won" }
                ),
                None => "the record stops here (game not finished)".into(),
            })
        );
        out.write_all(text.as_bytes()).map_err(|e| e.to_string())?;
        if interactive && i + 1 < states.len() {
            print!("[Enter: next step, q: quit] ");
            out.flush().map_err(|e| e.to_string())?;
            let mut line = String::new();
            input.read_line(&mut line).map_err(|e| e.to_string())?;
            if line.trim() == "q" {
                break;
            }
        }
    }
    Ok(())
}

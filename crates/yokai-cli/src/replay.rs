//! `yokai replay FILE`: step through a saved game in the terminal, or render every turn as
//! an SVG or PNG picture.

use crate::svg::{render_sheet, render_turn, turns};
use anyhow::{bail, Context};
use std::io::{BufRead, IsTerminal, Write};
use std::path::{Path, PathBuf};
use yokai_engine::{render_seat, render_truth, Action, Game, Replay, Seat};

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
    /// Write the whole game on one picture, as the paper draws its example games: a column
    /// per turn with the seat's actions, the true board above and that seat's view below.
    /// An SVG, or a PNG where the path ends in `.png`.
    #[arg(long, value_name = "FILE")]
    sheet: Option<PathBuf>,
}

pub fn read(path: &Path) -> anyhow::Result<Replay> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    Replay::from_jsonl(&text).with_context(|| format!("{}", path.display()))
}

/// A state of the game and, unless it is the last one, who acted in it and how.
type State = (Game, Option<(Seat, Action)>);

/// Every state of the game (before each action, then the end) with the seat to act and
/// the action it took.
fn states(replay: &Replay) -> anyhow::Result<Vec<State>> {
    let mut out = Vec::new();
    let last = replay.record().replay_with(|before, action, _| {
        out.push((before.clone(), Some((before.current_seat(), action))));
    })?;
    out.push((last, None));
    Ok(out)
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let replay = read(&args.file)?;
    let config = replay.header.config;
    if args.seat as usize >= config.players() {
        bail!("--seat {} does not exist in {config}", args.seat);
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
    if let Some(path) = &args.sheet {
        let outcome = match states.last().and_then(|(g, _)| g.outcome()) {
            Some(o) => format!(
                "R = {}, {}",
                o.reward,
                if o.won { "won" } else { "not won" }
            ),
            None => "not finished".into(),
        };
        let title = format!(
            "{config} · {} · {outcome} in {} steps",
            replay.header.seats.join(" + "),
            states.len() - 1
        );
        let turns = turns(&states);
        if turns.is_empty() {
            bail!("{} has no actions to draw", args.file.display());
        }
        let svg = render_sheet(&turns, &title);
        let bytes = if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"))
        {
            crate::plots::png(&svg, crate::plots::system_fonts())?
        } else {
            svg.into_bytes()
        };
        std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))?;
        eprintln!(
            "wrote the game's {} turns to {}",
            turns.len(),
            path.display()
        );
        return Ok(());
    }
    let dirs: Vec<(&PathBuf, &str)> = [(&args.svg, "svg"), (&args.png, "png")]
        .into_iter()
        .filter_map(|(dir, kind)| dir.as_ref().map(|d| (d, kind)))
        .collect();
    let pictures = !dirs.is_empty();
    for (dir, _) in &dirs {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let fonts = args.png.is_some().then(crate::plots::system_fonts);
    for (i, (game, action)) in states.iter().enumerate() {
        if !pictures {
            break;
        }
        let svg = render_turn(game, seat, *action, &title(i));
        for (dir, kind) in &dirs {
            let path = dir.join(format!("turn-{i:03}.{kind}"));
            let bytes = match &fonts {
                Some(db) if *kind == "png" => crate::plots::png(&svg, db.clone())?,
                _ => svg.clone().into_bytes(),
            };
            std::fs::write(&path, bytes)
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
    }
    for (dir, kind) in &dirs {
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
            action.map_or_else(
                || match game.outcome() {
                    Some(o) => format!(
                        "game over: R = {} ({})",
                        o.reward,
                        if o.won { "won" } else { "not won" }
                    ),
                    None => "the record stops here (game not finished)".into(),
                },
                |(actor, a)| {
                    let who = replay.header.seats.get(actor.index());
                    format!("{actor} ({}) plays: {a}", who.map_or("?", |s| s.as_str()))
                },
            )
        );
        out.write_all(text.as_bytes())?;
        if interactive && i + 1 < states.len() {
            print!("[Enter: next step, q: quit] ");
            out.flush()?;
            let mut line = String::new();
            input.read_line(&mut line)?;
            if line.trim() == "q" {
                break;
            }
        }
    }
    Ok(())
}

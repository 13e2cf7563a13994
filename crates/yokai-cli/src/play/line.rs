//! The plain line mode of `yokai play`: text in, text out, for screen readers, scripts and
//! dumb terminals. Type the number of an action or its name (`observe card 4`).

use super::session::{Key, Session};
use anyhow::{anyhow, bail, Context};
use std::io::{BufRead, Write};
use yokai_engine::{render_seat, render_truth, Action};

pub fn run(
    session: &mut Session,
    input: &mut dyn BufRead,
    out: &mut dyn Write,
) -> anyhow::Result<()> {
    let io = |e: std::io::Error| anyhow!(e).context("cannot write to the terminal");
    let mut shown_log = 0;
    let mut line = String::new();
    let mut read = |line: &mut String| -> anyhow::Result<bool> {
        line.clear();
        let n = input.read_line(line).context("cannot read input")?;
        Ok(n > 0)
    };
    loop {
        for entry in &session.log()[shown_log..] {
            writeln!(out, "  {entry}").map_err(io)?;
        }
        shown_log = session.log().len();
        if session.is_over() {
            let game = session.game();
            writeln!(out, "\n{}", render_truth(game)).map_err(io)?;
            if let Some(o) = game.outcome() {
                writeln!(
                    out,
                    "game over after {} steps: R = {} ({}, score {}, {} correct and {} wrong hints)",
                    o.length,
                    o.reward,
                    if o.won { "won" } else { "not won" },
                    o.score,
                    o.correct_hints,
                    o.wrong_hints
                )
                .map_err(io)?;
            }
            return Ok(());
        }
        let Some(seat) = session.human_to_act() else {
            bail!("no human seat is to act");
        };
        if session.curtain() {
            writeln!(
                out,
                "\n=== {seat}'s turn: press Enter when only {seat} can see the screen ==="
            )
            .map_err(io)?;
            out.flush().map_err(io)?;
            if !read(&mut line)? {
                bail!("input ended before the game finished");
            }
            session.handle(Key::Enter)?;
            continue;
        }
        writeln!(out, "\n{}", render_seat(session.game(), seat)).map_err(io)?;
        let legal = session.legal();
        for (i, a) in legal.iter().enumerate() {
            writeln!(out, "  {i:>3}: {a}").map_err(io)?;
        }
        loop {
            write!(out, "{seat}> ").map_err(io)?;
            out.flush().map_err(io)?;
            if !read(&mut line)? {
                bail!("input ended before the game finished");
            }
            let text = line.trim();
            if text.is_empty() {
                continue;
            }
            if text == "q" || text == "quit" {
                bail!("quit before the game finished");
            }
            let action = match text.parse::<usize>() {
                Ok(i) if i < legal.len() => Ok(legal[i]),
                Ok(i) => Err(anyhow!(
                    "{i} is not one of the listed numbers (0..{})",
                    legal.len()
                )),
                Err(_) => text
                    .parse::<Action>()
                    .map_err(|e| anyhow!("{e}; type a listed number or an action's name")),
            };
            match action.and_then(|a| session.choose(a)) {
                Ok(()) => break,
                Err(e) => writeln!(out, "{e}").map_err(io)?,
            }
        }
    }
}

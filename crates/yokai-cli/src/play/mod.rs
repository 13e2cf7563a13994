//! `yokai play`: people and policies at one table, in a terminal UI or in plain lines.

pub mod line;
pub mod session;
pub mod tui;

use anyhow::{anyhow, Context};
use session::{Player, Session};
use std::io::IsTerminal;
use std::path::PathBuf;
use yokai_engine::Config;
use yokai_train::PolicySource;

#[derive(clap::Args)]
pub struct Args {
    /// Game configuration: a short name or a TOML file.
    #[arg(short, long, default_value = "9c-2p-perfect")]
    config: String,
    /// Who sits where, seat 0 first, comma-separated: `human`, a built-in policy (`random`,
    /// `greedy`, `belief`), a pretrained agent (`pretrained:quick/0`) or a trained
    /// policy's path. Missing seats are filled with
    /// `belief`. Several humans play hot-seat: the board is hidden between their turns.
    #[arg(short, long, default_value = "human")]
    seats: String,
    /// Deal (and bot) seed; default: a new one each time.
    #[arg(long)]
    seed: Option<u64>,
    /// Plain line mode (numbered actions, type a number or a name): for screen readers,
    /// scripts and piped input. Used automatically when input is not a terminal.
    #[arg(long)]
    line: bool,
    /// No colours in the terminal UI (colours are then shown as letters only).
    #[arg(long)]
    no_color: bool,
    /// Save the game as a replay file (JSON lines) when it ends.
    #[arg(long)]
    save: Option<PathBuf>,
}

/// The seats of `--seats` (comma-separated, seat 0 first), checked against `config`'s
/// number of players; missing seats get `belief`.
pub fn seat_names(seats: &str, config: &Config) -> anyhow::Result<Vec<String>> {
    let mut names: Vec<String> = seats
        .split(',')
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect();
    if names.len() > config.players() {
        return Err(anyhow!(
            "{} seats given, but {config} has {}",
            names.len(),
            config.players()
        ));
    }
    names.resize(config.players(), "belief".into());
    Ok(names)
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let config = Config::resolve(&args.config)?;
    let names = seat_names(&args.seats, &config)?;
    let seed = args.seed.unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64)
    });
    let mut players = Vec::new();
    for name in &names {
        if name == "human" {
            players.push((name.clone(), Player::Human));
            continue;
        }
        let entry = PolicySource::parse(name)?;
        entry.check_game(&config)?;
        let bot = entry.build(seed ^ players.len() as u64);
        players.push((entry.name(), Player::Bot(bot)));
    }
    let mut session = Session::new(config, seed, players)?;
    let line = args.line || !std::io::stdin().is_terminal();
    if line {
        let stdin = std::io::stdin();
        let mut input = stdin.lock();
        let mut out = std::io::stdout();
        println!("{config}, seed {seed}: {}", names.join(", "));
        line::run(&mut session, &mut input, &mut out)?;
    } else {
        tui::run(&mut session, !args.no_color)?;
        if let Some(o) = session.game().outcome() {
            println!(
                "game over: R = {} ({})",
                o.reward,
                if o.won { "won" } else { "not won" }
            );
        }
    }
    if let Some(path) = args.save {
        std::fs::write(&path, session.replay().to_jsonl())
            .with_context(|| format!("cannot write {}", path.display()))?;
        eprintln!("saved the replay to {}", path.display());
    }
    Ok(())
}

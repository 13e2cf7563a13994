//! `yokai playthrough`: one game written step by step — board, legal actions, a digest of
//! every observation encoding of every seat, the action and what it paid — or, with
//! `--write DIR`, the whole golden set the engine's tests compare against.

use anyhow::Context;
use std::path::PathBuf;
use yokai_engine::{golden_set, playthrough, Chooser, Config};

#[derive(clap::Args)]
pub struct Args {
    /// Game configuration: a short name (9c-2p-perfect, 16c-4p-imperfect, …) or a TOML file.
    #[arg(default_value = "9c-2p-perfect")]
    config: String,
    /// Seed of the deal and of the random player.
    #[arg(short, long, default_value_t = 1)]
    seed: u64,
    /// The player never chooses END, so the game runs to its last hint.
    #[arg(long)]
    never_end: bool,
    /// Write the golden set (every preset, a random and a never-END game each) into DIR,
    /// one file per game, instead of printing one game. The engine's test compares
    /// crates/yokai-engine/tests/playthroughs/ with what this writes.
    #[arg(long, value_name = "DIR")]
    write: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if let Some(dir) = args.write {
        std::fs::create_dir_all(&dir).with_context(|| format!("{}", dir.display()))?;
        let set = golden_set();
        for game in &set {
            let path = dir.join(&game.file_name);
            let text = playthrough(game.config, game.seed, game.chooser);
            std::fs::write(&path, text).with_context(|| format!("{}", path.display()))?;
        }
        eprintln!("wrote {} playthroughs into {}", set.len(), dir.display());
        return Ok(());
    }
    let config = Config::resolve(&args.config)?;
    let chooser = if args.never_end {
        Chooser::NeverEnd
    } else {
        Chooser::Random
    };
    print!("{}", playthrough(config, args.seed, chooser));
    Ok(())
}

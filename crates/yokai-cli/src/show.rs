//! `yokai show`: the deal of a seed, every colour face up, to look at a starting position.

use yokai_engine::{Config, Game};

#[derive(clap::Args)]
pub struct Args {
    /// Game configuration: a short name (9c-2p-perfect, 16c-4p-imperfect, …) or a TOML file.
    #[arg(short, long, default_value = "9c-2p-perfect")]
    config: String,
    /// Seed of the deal.
    #[arg(short, long, default_value_t = 0)]
    seed: u64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let config = Config::resolve(&args.config)?;
    let game = Game::new(config, args.seed);
    print!("{}", yokai_engine::render_truth(&game));
    Ok(())
}

//! `yokai random`: random legal play, the reference point every learned policy must beat.

use anyhow::bail;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use yokai_agents::{Policy, RandomPolicy};
use yokai_engine::{derive_seed, Config, Game, Metrics, MetricsAccumulator, Outcome};

#[derive(clap::Args)]
pub struct Args {
    /// Game configuration: a short name (9c-2p-perfect, 16c-4p-imperfect, …) or a TOML file.
    #[arg(short, long, default_value = "9c-2p-perfect")]
    config: String,
    /// Number of games to play.
    #[arg(short, long, default_value_t = 20_000)]
    games: u64,
    /// Base seed: game i is dealt from a seed derived from (seed, i), so results do not
    /// depend on the number of threads.
    #[arg(short, long, default_value_t = 0)]
    seed: u64,
    /// Never choose END (the docs/spec/rules.md reference row "never choosing END").
    #[arg(long)]
    never_end: bool,
    /// Print the metrics as JSON instead of a table.
    #[arg(long)]
    json: bool,
}

fn play_one(config: Config, seed: u64, never_end: bool) -> Outcome {
    let mut game = Game::new(config, seed);
    let mut policy = RandomPolicy::new(seed ^ 0xA5A5_A5A5);
    while !game.is_over() {
        let view = game.view(game.current_seat());
        let mut action = policy.act(&view);
        while never_end && action == yokai_engine::Action::End {
            action = policy.act(&view);
        }
        game.apply(action)
            .expect("the random policy picks from the legal actions");
    }
    game.outcome().expect("the game is over")
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let config = Config::resolve(&args.config)?;
    if args.games == 0 {
        bail!("--games must be at least 1");
    }
    let bar = ProgressBar::new(args.games).with_style(
        ProgressStyle::with_template(
            "{spinner} {msg} [{bar:30}] {pos}/{len} games ({per_sec}, eta {eta})",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message(format!("random play on {config}"));
    let chunk = 1000u64;
    let acc = (0..args.games.div_ceil(chunk))
        .into_par_iter()
        .map(|c| {
            let mut acc = MetricsAccumulator::default();
            for i in c * chunk..((c + 1) * chunk).min(args.games) {
                acc.add(&play_one(config, derive_seed(args.seed, i), args.never_end));
            }
            bar.inc(acc.games);
            acc
        })
        .reduce(MetricsAccumulator::default, |mut a, b| {
            a.merge(&b);
            a
        });
    bar.finish_and_clear();
    let m = acc.metrics().expect("at least one game");
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&m).expect("metrics serialize")
        );
    } else {
        print_table(&config.to_string(), &m);
    }
    Ok(())
}

fn print_table(config: &str, m: &Metrics) {
    let wee = m
        .win_given_early_end
        .map_or("–".to_string(), |w| format!("{:.1}", 100.0 * w));
    println!(
        "uniformly random legal policy on {config}, {} games",
        m.games
    );
    println!("| R | win % | SEE % | EE % | WEE % | LEN | correct hints | wrong hints |");
    println!("|---|---|---|---|---|---|---|---|");
    println!(
        "| {:.2} ± {:.2} | {:.1} | {:.1} | {:.1} | {} | {:.1} | {:.2} | {:.2} |",
        m.reward,
        m.reward_se,
        100.0 * m.win_rate,
        100.0 * m.successful_early_end,
        100.0 * m.early_end,
        wee,
        m.length,
        m.correct_hints,
        m.wrong_hints
    );
}

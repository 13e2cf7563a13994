//! `yokai eval`: self-play and cross-play of policies, averaged over seat permutations.

use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use yokai_agents::eval::{play_group, seatings, PolicyFactory};
use yokai_agents::{Policy, PolicySpec};
use yokai_engine::{Config, Metrics, MetricsAccumulator};
use yokai_train::TrainedPolicy;

#[derive(clap::Args)]
pub struct Args {
    /// Policies: built-in names (`random`, `greedy`, `belief`), with parameters as
    /// `belief:continue_win=0.9`, or paths of trained policy files, checkpoints or run
    /// directories. Every pair (a policy with itself included) plays.
    #[arg(required = true)]
    policies: Vec<String>,
    /// Game configuration: a short name or a TOML file. Default: the game the trained
    /// policies were trained on, else 9c-2p-perfect.
    #[arg(short, long)]
    config: Option<String>,
    /// Games per pair of policies, split evenly over the seatings that use both.
    #[arg(short, long, default_value_t = 5_000)]
    games: u64,
    /// Base seed: the same policies and seed give the same tables.
    #[arg(short, long, default_value_t = 0)]
    seed: u64,
    /// Output directory for report.md, matrix.csv and matrix.json.
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Also save this many games of every pair as replay files in OUT/replays.
    #[arg(long, default_value_t = 0, requires = "out")]
    replays: u64,
}

/// One cell of the cross-play matrix.
pub struct Cell {
    pub row: usize,
    pub col: usize,
    pub metrics: Metrics,
}

/// A policy in an evaluation: a built-in bot or a trained network.
pub enum Entry {
    Builtin(PolicySpec),
    Trained(Box<TrainedPolicy>),
}

impl Entry {
    /// A built-in name, or a path to a policy file, checkpoint or run directory.
    pub fn parse(text: &str) -> Result<Entry, String> {
        let path = Path::new(text);
        if path.exists() {
            return TrainedPolicy::load(path)
                .map(|p| Entry::Trained(Box::new(p)))
                .map_err(|e| e.to_string());
        }
        text.parse::<PolicySpec>().map(Entry::Builtin).map_err(|e| {
            format!("{e}; a trained policy is given as the path of a policy file, checkpoint or run directory")
        })
    }

    pub fn name(&self) -> String {
        match self {
            Entry::Builtin(spec) => spec.to_string(),
            Entry::Trained(p) => p.path().display().to_string(),
        }
    }

    pub fn build(&self, seed: u64) -> Box<dyn Policy> {
        match self {
            Entry::Builtin(spec) => spec.build(seed),
            Entry::Trained(p) => p.build(seed),
        }
    }

    /// A trained network fits only the game it was trained on.
    pub fn check_game(&self, config: &Config) -> Result<(), String> {
        match self {
            Entry::Trained(p) if p.game() != config => Err(format!(
                "{} was trained on {}, not on {config}: its observations and actions do not fit",
                p.path().display(),
                p.game()
            )),
            _ => Ok(()),
        }
    }
}

pub fn run(args: Args) -> Result<(), String> {
    if args.games == 0 {
        return Err("--games must be at least 1".into());
    }
    let entries = args
        .policies
        .iter()
        .map(|p| Entry::parse(p))
        .collect::<Result<Vec<_>, _>>()?;
    // Trained policies bring their game; a --config must agree with it.
    let config = match (
        &args.config,
        entries.iter().find_map(|e| match e {
            Entry::Trained(p) => Some(*p.game()),
            Entry::Builtin(_) => None,
        }),
    ) {
        (Some(name), _) => Config::resolve(name).map_err(|e| e.to_string())?,
        (None, Some(game)) => game,
        (None, None) => Config::resolve("9c-2p-perfect").map_err(|e| e.to_string())?,
    };
    let names: Vec<String> = entries.iter().map(Entry::name).collect();
    let cells = evaluate(&config, &entries, args.games, args.seed, args.threads)?;
    let trained: Vec<usize> = (0..entries.len())
        .filter(|&i| matches!(entries[i], Entry::Trained(_)))
        .collect();
    let seeds = (trained.len() >= 2).then_some(trained.as_slice());
    let report = report(&config, &names, &cells, args.games, seeds);
    print!("{report}");
    if let Some(dir) = args.out {
        write_outputs(&dir, &names, &cells, &report)?;
        if args.replays > 0 {
            let pairs: Vec<(usize, usize)> = cells.iter().map(|c| (c.row, c.col)).collect();
            save_replays(
                &config,
                &entries,
                &pairs,
                args.replays,
                args.seed,
                &dir.join("replays"),
            )?;
        }
        eprintln!("wrote {}", dir.display());
    }
    Ok(())
}

/// Play `games` games of each pair (first seating that uses both) and save them as
/// replay files `I-J-gameK.jsonl` in `dir`.
pub fn save_replays(
    config: &Config,
    entries: &[Entry],
    pairs: &[(usize, usize)],
    games: u64,
    seed: u64,
    dir: &Path,
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    for &(i, j) in pairs {
        let seating = seatings(&[i, j], config.players())
            .into_iter()
            .next()
            .expect("at least one seating");
        for k in 0..games {
            let game_seed = yokai_engine::derive_seed(seed, 1_000_000 + k);
            let mut policies: Vec<Box<dyn Policy>> = seating
                .iter()
                .enumerate()
                .map(|(s, &e)| entries[e].build(yokai_engine::derive_seed(game_seed, s as u64)))
                .collect();
            let episode = yokai_agents::play_episode(*config, game_seed, game_seed, &mut policies)
                .map_err(|e| e.to_string())?;
            let names = seating.iter().map(|&e| entries[e].name()).collect();
            let replay = yokai_engine::Replay::from_record(&episode.record, Some(game_seed), names)
                .map_err(|e| e.to_string())?;
            let path = dir.join(format!("{i}-{j}-game{k}.jsonl"));
            std::fs::write(&path, replay.to_jsonl())
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
    }
    Ok(())
}

/// Every pair of `entries` (each with itself included) over all seatings that use both.
pub fn evaluate(
    config: &Config,
    entries: &[Entry],
    games: u64,
    seed: u64,
    threads: Option<usize>,
) -> Result<Vec<Cell>, String> {
    for e in entries {
        e.check_game(config)?;
    }
    let config = *config;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| format!("could not start threads: {e}"))?;
    let n = entries.len();
    let pairs: Vec<(usize, usize)> = (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect();
    let players = config.players();
    let per_pair: Vec<(usize, usize, Vec<Vec<usize>>, u64)> = pairs
        .iter()
        .map(|&(i, j)| {
            let s = seatings(&[i, j], players);
            let games = games.div_ceil(s.len() as u64);
            (i, j, s, games)
        })
        .collect();
    let total: u64 = per_pair.iter().map(|(_, _, s, g)| s.len() as u64 * g).sum();
    let bar = ProgressBar::new(total).with_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} games ({per_sec}, eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let factories: Vec<Box<PolicyFactory<'_>>> = entries
        .iter()
        .map(|entry| Box::new(move |seed| entry.build(seed)) as Box<PolicyFactory<'_>>)
        .collect();
    let names: Vec<String> = entries.iter().map(Entry::name).collect();
    let mut cells = Vec::new();
    for (i, j, seatings, games) in per_pair {
        bar.set_message(format!("{} + {}", names[i], names[j]));
        let mut acc = MetricsAccumulator::default();
        for seating in &seatings {
            let seats: Vec<&PolicyFactory<'_>> =
                seating.iter().map(|&k| factories[k].as_ref()).collect();
            let part = pool
                .install(|| play_group(config, &seats, games, seed, &|g| bar.inc(g)))
                .map_err(|e| e.to_string())?;
            acc.merge(&part);
        }
        let metrics = acc.metrics().expect("at least one game");
        cells.push(Cell {
            row: i,
            col: j,
            metrics,
        });
    }
    bar.finish_and_clear();
    Ok(cells)
}

fn pct(x: f64) -> String {
    format!("{:.1}", 100.0 * x)
}

fn row_of(m: &Metrics) -> String {
    format!(
        "{:.2} ± {:.2} | {} | {} | {} | {} | {:.1}",
        m.reward,
        m.reward_se,
        pct(m.win_rate),
        pct(m.successful_early_end),
        pct(m.early_end),
        m.win_given_early_end.map_or("–".into(), pct),
        m.length
    )
}

/// The Markdown report: self-play of each policy, then the cross-play matrix of R.
/// Mean and standard error over a set of per-seed values.
fn mean_se(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    if xs.len() < 2 {
        return (mean, 0.0);
    }
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The paper's table row for a group of seeds of one algorithm: SP over the diagonal,
/// XP over the pairs of different seeds, each as mean ± SE over those entries.
pub fn paper_table(names: &[String], cells: &[Cell], group: &[usize]) -> String {
    let sp: Vec<&Metrics> = cells
        .iter()
        .filter(|c| c.row == c.col && group.contains(&c.row))
        .map(|c| &c.metrics)
        .collect();
    let xp: Vec<&Metrics> = cells
        .iter()
        .filter(|c| c.row != c.col && group.contains(&c.row) && group.contains(&c.col))
        .map(|c| &c.metrics)
        .collect();
    let fmt = |ms: &[&Metrics], f: &dyn Fn(&Metrics) -> f64, scale: f64| {
        if ms.is_empty() {
            return "–".to_string();
        }
        let (m, se) = mean_se(&ms.iter().map(|m| f(m) * scale).collect::<Vec<_>>());
        format!("{m:.2} ± {se:.2}")
    };
    let mut out = format!(
        "## Paper table ({} seeds; mean ± SE over seeds for SP, over pairs of seeds for XP)\n\n\
         | seeds | SP R | SP SEE % | SP LEN | XP R | XP SEE % | XP EE % | XP LEN |\n|---|---|---|---|---|---|---|---|\n",
        group.len()
    );
    let label: Vec<&str> = group.iter().map(|&i| names[i].as_str()).collect();
    out += &format!(
        "| {} | {} | {} | {} | {} | {} | {} | {} |\n",
        label.join(", "),
        fmt(&sp, &|m| m.reward, 1.0),
        fmt(&sp, &|m| m.successful_early_end, 100.0),
        fmt(&sp, &|m| m.length, 1.0),
        fmt(&xp, &|m| m.reward, 1.0),
        fmt(&xp, &|m| m.successful_early_end, 100.0),
        fmt(&xp, &|m| m.early_end, 100.0),
        fmt(&xp, &|m| m.length, 1.0),
    );
    out
}

pub fn report(
    config: &Config,
    names: &[String],
    cells: &[Cell],
    games: u64,
    seeds: Option<&[usize]>,
) -> String {
    let mut out = format!(
        "# Evaluation on {config}\n\n{games} games per pair, averaged over seat permutations.\n\n"
    );
    if let Some(group) = seeds.filter(|g| !g.is_empty()) {
        out += &paper_table(names, cells, group);
        out += "\n";
    }
    out += "## Self-play\n\n| policy | R | win % | SEE % | EE % | WEE % | LEN |\n|---|---|---|---|---|---|---|\n";
    for c in cells.iter().filter(|c| c.row == c.col) {
        out += &format!("| {} | {} |\n", names[c.row], row_of(&c.metrics));
    }
    if names.len() > 1 {
        out += "\n## Cross-play\n\n| pair | R | win % | SEE % | EE % | WEE % | LEN |\n|---|---|---|---|---|---|---|\n";
        for c in cells.iter().filter(|c| c.row != c.col) {
            out += &format!(
                "| {} + {} | {} |\n",
                names[c.row],
                names[c.col],
                row_of(&c.metrics)
            );
        }
        out += "\n## Matrix of R\n\n|  |";
        for n in names {
            out += &format!(" {n} |");
        }
        out += "\n|---|";
        out += &"---|".repeat(names.len());
        out += "\n";
        for (i, name) in names.iter().enumerate() {
            out += &format!("| {name} |");
            for j in 0..names.len() {
                let (a, b) = (i.min(j), i.max(j));
                let c = cells
                    .iter()
                    .find(|c| c.row == a && c.col == b)
                    .expect("every pair played");
                out += &format!(" {:.2} |", c.metrics.reward);
            }
            out += "\n";
        }
    }
    out
}

pub fn write_outputs(
    dir: &Path,
    names: &[String],
    cells: &[Cell],
    report: &str,
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let write = |file: &str, text: String| {
        let path = dir.join(file);
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    write("report.md", report.to_string())?;
    let mut csv = String::from(
        "row,col,games,reward,reward_se,win_rate,see,ee,wee,length,correct_hints,wrong_hints\n",
    );
    for c in cells {
        let m = &c.metrics;
        csv += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{}\n",
            names[c.row],
            names[c.col],
            m.games,
            m.reward,
            m.reward_se,
            m.win_rate,
            m.successful_early_end,
            m.early_end,
            m.win_given_early_end
                .map_or(String::new(), |w| w.to_string()),
            m.length,
            m.correct_hints,
            m.wrong_hints
        );
    }
    write("matrix.csv", csv)?;
    let json: Vec<serde_json::Value> = cells
        .iter()
        .map(
            |c| serde_json::json!({"row": names[c.row], "col": names[c.col], "metrics": c.metrics}),
        )
        .collect();
    write(
        "matrix.json",
        serde_json::to_string_pretty(&json).expect("metrics serialize"),
    )
}

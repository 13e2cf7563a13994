//! `yokai eval`: self-play and cross-play of policies, averaged over seat permutations.

use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use yokai_agents::eval::{play_group, seatings, PolicyFactory};
use yokai_agents::PolicySpec;
use yokai_engine::{Config, Metrics, MetricsAccumulator};

#[derive(clap::Args)]
pub struct Args {
    /// Policies: built-in names (`random`, `greedy`, `belief`), with parameters as
    /// `belief:continue_win=0.9`. Every pair (a policy with itself included) plays.
    #[arg(required = true)]
    policies: Vec<String>,
    /// Game configuration: a short name or a TOML file.
    #[arg(short, long, default_value = "9c-2p-perfect")]
    config: String,
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
}

/// One cell of the cross-play matrix.
struct Cell {
    row: usize,
    col: usize,
    metrics: Metrics,
}

pub fn run(args: Args) -> Result<(), String> {
    let config = Config::resolve(&args.config).map_err(|e| e.to_string())?;
    if args.games == 0 {
        return Err("--games must be at least 1".into());
    }
    let specs = args
        .policies
        .iter()
        .map(|p| {
            if std::path::Path::new(p).exists() {
                return Err(format!(
                    "`{p}` is a file: loading trained policies is not implemented yet \
                     (built-in policies: {})",
                    PolicySpec::builtin_names().join(", ")
                ));
            }
            p.parse::<PolicySpec>().map_err(|e| e.to_string())
        })
        .collect::<Result<Vec<_>, _>>()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .map_err(|e| format!("could not start threads: {e}"))?;
    let n = specs.len();
    let pairs: Vec<(usize, usize)> = (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect();
    let players = config.players();
    let per_pair: Vec<(usize, usize, Vec<Vec<usize>>, u64)> = pairs
        .iter()
        .map(|&(i, j)| {
            let s = seatings(&[i, j], players);
            let games = args.games.div_ceil(s.len() as u64);
            (i, j, s, games)
        })
        .collect();
    let total: u64 = per_pair.iter().map(|(_, _, s, g)| s.len() as u64 * g).sum();
    let bar = ProgressBar::new(total).with_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} games ({per_sec}, eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let factories: Vec<Box<PolicyFactory<'_>>> = specs
        .iter()
        .map(|spec| Box::new(move |seed| spec.build(seed)) as Box<PolicyFactory<'_>>)
        .collect();
    let mut cells = Vec::new();
    for (i, j, seatings, games) in per_pair {
        bar.set_message(format!("{} + {}", specs[i], specs[j]));
        let mut acc = MetricsAccumulator::default();
        for seating in &seatings {
            let seats: Vec<&PolicyFactory<'_>> =
                seating.iter().map(|&k| factories[k].as_ref()).collect();
            let part = pool
                .install(|| play_group(config, &seats, games, args.seed, &|g| bar.inc(g)))
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
    let names: Vec<String> = specs.iter().map(|s| s.to_string()).collect();
    let report = report(&config, &names, &cells, args.games);
    print!("{report}");
    if let Some(dir) = args.out {
        write_outputs(&dir, &names, &cells, &report)?;
        eprintln!("wrote {}", dir.display());
    }
    Ok(())
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
fn report(config: &Config, names: &[String], cells: &[Cell], games: u64) -> String {
    let mut out = format!(
        "# Evaluation on {config}\n\n{games} games per pair, averaged over seat permutations.\n\n\
         ## Self-play\n\n| policy | R | win % | SEE % | EE % | WEE % | LEN |\n|---|---|---|---|---|---|---|\n"
    );
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

fn write_outputs(
    dir: &PathBuf,
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

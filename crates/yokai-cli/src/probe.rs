//! `yokai probe`: linear probes of the colours on the board in trained policies' memories
//! (per board position, as the paper, or per card id), step by step through a game, in
//! self-play (held-out episodes) and with other partners.

use crate::plots::{self, Series};
use anyhow::Context;
use std::fmt::Write as _;
use std::path::PathBuf;
use yokai_train::probe::study::{Setting, Study, StudyError};
use yokai_train::probe::{StepAccuracy, Target};
use yokai_train::TrainedPolicy;

#[derive(clap::Args)]
pub struct Args {
    /// Trained runs to probe: run directories, policy files or checkpoints.
    #[arg(required = true)]
    runs: Vec<PathBuf>,
    /// Partners for cross-play (trained runs): each probed run's memory is read in games
    /// with each partner in every other seat, the run in each seat in turn, by the probes
    /// fitted on its self-play.
    #[arg(long, num_args = 1..)]
    partners: Vec<PathBuf>,
    /// Self-play games per run (80 % of episodes fit the probes, 20 % test them) and games
    /// per seating with each partner; at least 50 (the paper: 5,000). Steps that fewer
    /// than 20 seat states reach (late steps of short games) are left out.
    #[arg(long, default_value_t = 5000)]
    games: usize,
    /// What each probe names: `position` (the colour of the card on each board position
    /// that cards reach often enough, as the paper) or `card` (each card id's colour,
    /// wherever it lies).
    #[arg(long, value_enum, default_value_t = By::Position)]
    by: By,
    /// Seed of the deals and of the actions sampled.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Where probe.csv, probe.json and probe.svg/png go.
    #[arg(short, long, default_value = "runs/probe")]
    out: PathBuf,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum By {
    Position,
    Card,
}

/// One probed setting's curve, named for the report.
struct Curve {
    run: String,
    setting: String,
    steps: Vec<StepAccuracy>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let load = |path: &PathBuf| TrainedPolicy::load(path).map_err(anyhow::Error::from);
    let runs: Vec<TrainedPolicy> = args.runs.iter().map(load).collect::<Result<_, _>>()?;
    let partners: Vec<TrainedPolicy> = args.partners.iter().map(load).collect::<Result<_, _>>()?;
    let (target, what) = match args.by {
        By::Position => (Target::Position, "board position"),
        By::Card => (Target::Card, "card"),
    };
    let study =
        Study::new(&runs, &partners, args.games, args.seed, target).map_err(|e| match e {
            StudyError::TooFewGames { .. } => anyhow::Error::from(e).context("--games"),
            e => e.into(),
        })?;
    // One game for every run and partner: one chance level, one plot.
    let game = *study.game();
    let curves: Vec<Curve> = study
        .run(|k| {
            eprintln!(
                "probing {}: {} self-play games",
                args.runs[k].display(),
                args.games
            )
        })
        .into_iter()
        .map(|c| Curve {
            run: args.runs[c.run].display().to_string(),
            setting: match c.setting {
                Setting::SelfPlay => "self-play".into(),
                Setting::With(k) => format!("with {}", args.partners[k].display()),
            },
            steps: c.steps,
        })
        .collect();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let chance = 1.0 / game.colours() as f64;
    let mut csv_rows = Vec::new();
    let mut json = Vec::new();
    let mut series = Vec::new();
    let mut table = String::from(
        "| run | setting | all cards | oracle | belief head | unseen cards | oracle (unseen) | belief head (unseen) |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    for c in &curves {
        for s in &c.steps {
            let row = |cards: &str, acc: f64, oracle: f64, head: Option<f64>| {
                vec![
                    c.run.clone(),
                    c.setting.clone(),
                    s.step.to_string(),
                    cards.to_string(),
                    format!("{acc:.4}"),
                    format!("{oracle:.4}"),
                    s.rows.to_string(),
                    head.map(|h| format!("{h:.4}")).unwrap_or_default(),
                ]
            };
            csv_rows.push(row("all", s.all, s.oracle_all, s.head));
            if let (Some(u), Some(o)) = (s.unseen, s.oracle_unseen) {
                csv_rows.push(row("unseen", u, o, s.head_unseen));
            }
            json.push(serde_json::json!({
                "run": c.run, "setting": c.setting, "step": s.step, "rows": s.rows,
                "all": s.all, "oracle_all": s.oracle_all, "head": s.head,
                "unseen": s.unseen, "oracle_unseen": s.oracle_unseen,
                "head_unseen": s.head_unseen,
            }));
        }
        let mean = |f: &dyn Fn(&StepAccuracy) -> Option<f64>| {
            let v: Vec<f64> = c.steps.iter().filter_map(f).collect();
            if v.is_empty() {
                "–".to_string()
            } else {
                format!("{:.1} %", 100.0 * v.iter().sum::<f64>() / v.len() as f64)
            }
        };
        let _ = writeln!(
            table,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            c.run,
            c.setting,
            mean(&|s| Some(s.all)),
            mean(&|s| Some(s.oracle_all)),
            mean(&|s| s.head),
            mean(&|s| s.unseen),
            mean(&|s| s.oracle_unseen),
            mean(&|s| s.head_unseen)
        );
        let points = |f: &dyn Fn(&StepAccuracy) -> Option<f64>| {
            c.steps
                .iter()
                .filter_map(|s| f(s).map(|v| (s.step as f64, v)))
                .collect()
        };
        // Legends name runs and partners by their last two path components.
        let setting = match c.setting.strip_prefix("with ") {
            Some(partner) => format!("with {}", short(partner)),
            None => c.setting.clone(),
        };
        series.push(Series {
            label: format!("{} {setting}", short(&c.run)),
            points: points(&|s| s.unseen),
        });
        if c.steps.iter().any(|s| s.head_unseen.is_some()) {
            series.push(Series {
                label: format!("{} {setting} belief head", short(&c.run)),
                points: points(&|s| s.head_unseen),
            });
        }
        if c.setting == "self-play" {
            series.push(Series {
                label: format!("{} oracle", short(&c.run)),
                points: points(&|s| s.oracle_unseen),
            });
        }
    }
    let longest = curves
        .iter()
        .flat_map(|c| c.steps.iter().map(|s| s.step))
        .max()
        .unwrap_or(1);
    series.push(Series {
        label: "chance".into(),
        points: vec![(0.0, chance), (longest as f64, chance)],
    });
    let write = |name: &str, text: &str| {
        let path = args.out.join(name);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
    };
    let header = [
        "run", "setting", "step", "cards", "accuracy", "oracle", "rows", "head",
    ];
    write("probe.csv", &crate::table::csv_text(&header, csv_rows))?;
    write(
        "probe.json",
        &serde_json::to_string_pretty(&json).expect("json values serialise"),
    )?;
    let svg = plots::lines_svg(
        &format!(
            "Linear probes by {what}: colours of unopened cards read from the memory \
             (and by the belief head, where there is one)"
        ),
        "game step",
        "accuracy",
        &series,
    );
    plots::write_both(&args.out, "probe", &svg)?;
    println!(
        "Linear probes of the colours on the board by {what} (mean over game steps; \"unseen\": \
         cards the seat has not opened; \"belief head\": the network's own colour layer, where \
         it has one; chance {:.1} %; {} games)\n\n{table}",
        100.0 * chance,
        args.games
    );
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

/// The last two path components of a run, for legends.
fn short(path: &str) -> String {
    let parts: Vec<&str> = path.trim_end_matches('/').rsplit('/').take(2).collect();
    parts.into_iter().rev().collect::<Vec<_>>().join("/")
}

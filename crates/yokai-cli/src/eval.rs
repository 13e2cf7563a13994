//! `yokai eval`: self-play and cross-play of policies, averaged over seat permutations.

use crate::plots;
use crate::summary::{
    paper_rows, shared, summarise, table_row, DistinctSet, EvalSummary, GroupSummary, TABLE_HEAD,
};
use anyhow::{bail, Context};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use yokai_agents::eval::{
    cross_play, cross_play_plan, distinct_cross_play, distinct_sets, seatings, PairResult,
    PolicyFactory, Progress,
};
use yokai_agents::Policy;
use yokai_engine::{Config, Metrics};
use yokai_train::source::{play_rule_label, run_dir_of};
use yokai_train::{EndRule, PlayRule, PolicySource};

#[derive(clap::Args)]
pub struct Args {
    /// Policies: built-in names (`random`, `greedy`, `belief`), with parameters as
    /// `belief:continue_win=0.9`, pretrained agents built in (`pretrained:quick/0`; an
    /// unknown name lists them), or paths of trained policy files, checkpoints or run
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
    /// Games of more than 2 seats: the most sets of n distinct seeds per method that play
    /// the paper's cross-play J_XP, each over every seating (all sets when there are no
    /// more; else a sample drawn from --seed). Pairs of seeds are played as well.
    #[arg(long, default_value_t = 20)]
    xp_sets: usize,
    /// How trained policies choose END: `file` (as each one's training config says,
    /// `act.end_threshold`), `draw` (like any other action), or a probability P in (0, 1)
    /// (END wherever the network gives it more than P, else never). Bots keep their own
    /// rules. A trained policy that decides END is named with its threshold in the tables.
    #[arg(long, default_value = "file")]
    end: EndRule,
    /// Draw trained policies' moves from softmax(logits / T) (`act.temperature`): 1 is the
    /// trained distribution, 0 the most likely legal move (greedy play, how Hanabi agents
    /// are usually evaluated). Default: as each one's training config says. END decided by
    /// a threshold keeps reading P(END) at temperature 1. Bots keep their own draws.
    #[arg(long, value_name = "T")]
    temperature: Option<f64>,
}

/// Expand the policy arguments: a quoted glob in the last path component
/// (`runs/op/seed-*`, `runs/op/seed-[0-3]`; the `glob` crate's syntax), or a method
/// directory holding `seed-N` runs, becomes every matching run; anything else is passed
/// through.
pub fn expand(args: &[String]) -> anyhow::Result<Vec<String>> {
    let mut out = Vec::new();
    for arg in args {
        let path = Path::new(arg);
        use yokai_train::artifact::names::is_run;
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let (dir, pattern) = if name.contains(['*', '?', '[']) {
            let pattern = glob::Pattern::new(name)
                .with_context(|| format!("`{arg}` is not a valid pattern"))?;
            (path.parent().unwrap_or(Path::new(".")), Some(pattern))
        } else if path.is_dir() && !is_run(path) {
            (path, None)
        } else {
            out.push(arg.clone());
            continue;
        };
        let dir = if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        };
        let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
            .with_context(|| format!("cannot list {}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                let n = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
                match &pattern {
                    Some(pattern) => pattern.matches(n),
                    None => p.is_dir() && is_run(p),
                }
            })
            .collect();
        if found.is_empty() {
            bail!("`{arg}` matches no policy file or run directory");
        }
        // seed-2 before seed-10.
        found.sort_by_key(|p| {
            let n = p
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or("")
                .to_string();
            let digits: String = n.chars().filter(|c| c.is_ascii_digit()).collect();
            (
                n.trim_end_matches(|c: char| c.is_ascii_digit()).to_string(),
                digits.parse::<u64>().unwrap_or(0),
                n,
            )
        });
        out.extend(found.into_iter().map(|p| p.display().to_string()));
    }
    Ok(out)
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.games == 0 {
        bail!("--games must be at least 1");
    }
    let mut entries = expand(&args.policies)?
        .iter()
        .map(|p| PolicySource::parse(p))
        .collect::<Result<Vec<_>, _>>()?;
    let rule = PlayRule {
        end: args.end,
        temperature: args.temperature,
    };
    for entry in &mut entries {
        entry.set_play_rule(rule, false)?;
    }
    // Trained policies bring their game; a --config must agree with it.
    let config = match (&args.config, entries.iter().find_map(PolicySource::game)) {
        (Some(name), _) => Config::resolve(name)?,
        (None, Some(game)) => game,
        (None, None) => Config::resolve("9c-2p-perfect")?,
    };
    let names: Vec<String> = entries.iter().map(PolicySource::name).collect();
    let results = evaluate(&config, &entries, args.games, args.seed, args.threads)?;
    let mut groups = summarise_groups(&entries, &names, &results);
    let play = Play {
        config: &config,
        entries: &entries,
        games: args.games,
        seed: args.seed,
        threads: args.threads,
    };
    play.distinct_cross_play(&mut groups, args.xp_sets)?;
    match args.out {
        None => print!(
            "{}",
            report(&config, &names, &results, args.games, &groups, &[])
        ),
        Some(dir) => {
            let text = write_outputs(&dir, &config, &entries, &results, args.games, &groups)?;
            print!("{text}");
            if args.replays > 0 {
                let pairs: Vec<(usize, usize)> = results.iter().map(|c| (c.row, c.col)).collect();
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
    }
    Ok(())
}

/// Play `games` games of each pair (first seating that uses both) and save them as
/// replay files `I-J-gameK.jsonl` in `dir`.
pub fn save_replays(
    config: &Config,
    entries: &[PolicySource],
    pairs: &[(usize, usize)],
    games: u64,
    seed: u64,
    dir: &Path,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
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
            let episode = yokai_agents::play_episode(*config, game_seed, game_seed, &mut policies)?;
            let names = seating.iter().map(|&e| entries[e].name()).collect();
            let replay =
                yokai_engine::Replay::from_record(&episode.record, Some(game_seed), names)?;
            let path = dir.join(format!("{i}-{j}-game{k}.jsonl"));
            std::fs::write(&path, replay.to_jsonl())
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
    }
    Ok(())
}

/// What an evaluation plays with: the game, the policies, games per entry, base seed and
/// threads.
pub struct Play<'a> {
    pub config: &'a Config,
    pub entries: &'a [PolicySource],
    pub games: u64,
    pub seed: u64,
    pub threads: Option<usize>,
}

impl Play<'_> {
    /// Games of more than 2 seats: for every method (`groups`, from [`summarise_groups`])
    /// with at least as many seeds as seats, up to `max_sets` sets of n distinct seeds,
    /// `games` games each over every seating, recorded in the method's summary. Nothing
    /// for 2 seats, where the pairs are the sets.
    pub fn distinct_cross_play(
        &self,
        groups: &mut [GroupSummary],
        max_sets: usize,
    ) -> anyhow::Result<()> {
        let players = self.config.players();
        if players <= 2 {
            return Ok(());
        }
        let methods = groups_of(self.entries);
        let plans: Vec<Vec<Vec<usize>>> = methods
            .iter()
            .map(|(_, members)| distinct_sets(members, players, max_sets, self.seed))
            .collect();
        let total: u64 = plans
            .iter()
            .flatten()
            .map(|set| {
                let n = seatings(set, players).len() as u64;
                n * self.games.div_ceil(n)
            })
            .sum();
        if total == 0 {
            return Ok(());
        }
        let pool = worker_pool(self.threads)?;
        let bar = games_bar(total);
        bar.set_message(format!("sets of {players} distinct seeds"));
        let factories = factories(self.entries);
        let policies: Vec<&PolicyFactory<'_>> = factories.iter().map(|f| f.as_ref()).collect();
        let names: Vec<String> = self.entries.iter().map(PolicySource::name).collect();
        for ((method, _), sets) in methods.iter().zip(&plans) {
            let played = pool.install(|| {
                distinct_cross_play(*self.config, &policies, sets, self.games, self.seed, &|g| {
                    bar.inc(g)
                })
            })?;
            let sets = played
                .into_iter()
                .map(|r| DistinctSet {
                    seeds: r.members.iter().map(|&i| names[i].clone()).collect(),
                    metrics: r.metrics,
                })
                .collect();
            if let Some(g) = groups.iter_mut().find(|g| &g.name == method) {
                g.set_distinct(sets);
            }
        }
        bar.finish_and_clear();
        Ok(())
    }
}

/// Every pair of `entries` (each with itself included) over all seatings that use both.
pub fn evaluate(
    config: &Config,
    entries: &[PolicySource],
    games: u64,
    seed: u64,
    threads: Option<usize>,
) -> anyhow::Result<Vec<PairResult>> {
    for e in entries {
        e.check_game(config)?;
    }
    let pool = worker_pool(threads)?;
    let plan = cross_play_plan(entries.len(), config.players(), games);
    let total: u64 = plan.iter().map(|(_, _, s, g)| s.len() as u64 * g).sum();
    let bar = games_bar(total);
    let factories = factories(entries);
    let policies: Vec<&PolicyFactory<'_>> = factories.iter().map(|f| f.as_ref()).collect();
    let names: Vec<String> = entries.iter().map(PolicySource::name).collect();
    let results = pool.install(|| {
        cross_play(*config, &policies, games, seed, &|p| match p {
            Progress::Pair { row, col } => {
                bar.set_message(format!("{} + {}", names[row], names[col]))
            }
            Progress::Games(g) => bar.inc(g),
        })
    })?;
    bar.finish_and_clear();
    Ok(results)
}

/// A training curve as drawn: smoothed over a 25th of its points, so that noisy
/// per-update figures read as a line.
fn curve(raw: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    plots::smooth(&raw, (raw.len() / 25).max(1))
}

/// The pool the games run on: `threads` workers, or one per core.
fn worker_pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .context("could not start threads")
}

/// One seat-maker per entry, for the library's cross-play loops.
fn factories(entries: &[PolicySource]) -> Vec<Box<PolicyFactory<'_>>> {
    entries
        .iter()
        .map(|entry| Box::new(move |seed| entry.build(seed)) as Box<PolicyFactory<'_>>)
        .collect()
}

/// A progress bar over `total` games, its message naming what plays.
fn games_bar(total: u64) -> ProgressBar {
    ProgressBar::new(total).with_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} games ({per_sec}, eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    )
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

/// Trained policies grouped by method: seeds are run directories `METHOD/seed-N`, so the
/// group is the parent directory. Each group becomes one row of the paper's table.
pub fn groups_of(entries: &[PolicySource]) -> Vec<(String, Vec<usize>)> {
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    for (i, e) in entries.iter().enumerate() {
        let Some(p) = e.trained() else { continue };
        let run = run_dir_of(p.path());
        let method = run
            .parent()
            .map(|d| d.display().to_string())
            .filter(|d| !d.is_empty())
            .unwrap_or_else(|| run.display().to_string());
        // Seeds that choose END by different rules are different methods.
        let method = method + &play_rule_label(p);
        match groups.iter_mut().find(|(m, _)| *m == method) {
            Some((_, members)) => members.push(i),
            None => groups.push((method, vec![i])),
        }
    }
    groups
}

/// The paper's table for the groups of trained seeds in an evaluation.
pub fn summarise_groups(
    entries: &[PolicySource],
    names: &[String],
    results: &[PairResult],
) -> Vec<GroupSummary> {
    let flat: Vec<(usize, usize, Metrics)> =
        results.iter().map(|c| (c.row, c.col, c.metrics)).collect();
    groups_of(entries)
        .iter()
        .map(|(method, members)| {
            let mut g = summarise(method, names, &flat, members);
            let trained = || members.iter().filter_map(|&i| entries[i].trained());
            // Through its shortest decimal: 0.07, not 0.07000000029802322.
            g.entropy_coef = shared(trained().map(|p| p.config().ppo.entropy_coef.to_string()))
                .and_then(|a| a.parse::<f64>().ok());
            g.env_steps = shared(trained().map(|p| p.header().env_steps));
            g
        })
        .collect()
}

pub fn report(
    config: &Config,
    names: &[String],
    results: &[PairResult],
    games: u64,
    groups: &[GroupSummary],
    pictures: &[(&str, &str)],
) -> String {
    let mut out = format!(
        "# Evaluation on {config}\n\n{games} games per pair, averaged over seat permutations.\n\n"
    );
    if !groups.is_empty() {
        out += if groups.iter().any(|g| g.xp_distinct.is_some()) {
            "## Paper table\n\nMean ± standard error over seeds (SP: each seed with itself) and over sets of \
             distinct seeds (XP: every set of as many different seeds of a method as the game has seats, \
             over every seating: the paper's J_XP). Shares in %.\n\n"
        } else {
            "## Paper table\n\nMean ± standard error over seeds (SP: each seed with itself; XP: every pair of \
             different seeds of a method). Shares in %.\n\n"
        };
        out += TABLE_HEAD;
        for g in groups {
            out += &table_row(g);
        }
        out += &paper_rows(crate::paper::main_table(), &config.to_string());
        out += "\n";
    }
    for (title, file) in pictures {
        out += &format!("![{title}]({file})\n\n");
    }
    out += "## Self-play\n\n| policy | R | win % | SEE % | EE % | WEE % | LEN |\n|---|---|---|---|---|---|---|\n";
    for c in results.iter().filter(|c| c.row == c.col) {
        out += &format!("| {} | {} |\n", names[c.row], row_of(&c.metrics));
    }
    if names.len() > 1 {
        out += "\n## Cross-play\n\n| pair | R | win % | SEE % | EE % | WEE % | LEN |\n|---|---|---|---|---|---|---|\n";
        for c in results.iter().filter(|c| c.row != c.col) {
            out += &format!(
                "| {} + {} | {} |\n",
                names[c.row],
                names[c.col],
                row_of(&c.metrics)
            );
        }
        for g in groups.iter().filter(|g| !g.xp_sets.is_empty()) {
            out += &format!(
                "\n## Cross-play of {} distinct seeds: {}\n\n| set | R | win % | SEE % | EE % | WEE % | LEN |\n|---|---|---|---|---|---|---|\n",
                config.players(),
                g.name
            );
            for set in &g.xp_sets {
                out += &format!("| {} | {} |\n", set.seeds.join(" + "), row_of(&set.metrics));
            }
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
                let c = results
                    .iter()
                    .find(|c| c.row == a && c.col == b)
                    .expect("every pair played");
                out += &format!(" {:.2} |", c.metrics.reward);
            }
            out += "\n";
        }
    }
    out += &border_usage(names, results, config.grid());
    out
}

/// The paper's border-usage diagnostic: how often card moves land on the grid's outer ring,
/// per self-play and cross-play entry. The grid (g × g) cuts the real game's unbounded table
/// short there, so frequent use would mean the policies play a game the grid changes.
fn border_usage(names: &[String], results: &[PairResult], grid: usize) -> String {
    let mut out = format!(
        "\n## Border usage\n\nCard moves per game, and those onto the grid's outer ring (row or \
         column 0 or {}).\n\n| policy or pair | card moves per game | onto the border per game | \
         share of moves % |\n|---|---|---|---|\n",
        grid - 1
    );
    for c in results {
        let (Some(moves), Some(border)) = (c.metrics.card_moves, c.metrics.border_moves) else {
            continue;
        };
        let who = if c.row == c.col {
            names[c.row].clone()
        } else {
            format!("{} + {}", names[c.row], names[c.col])
        };
        let share = if moves > 0.0 {
            format!("{:.2}", 100.0 * border / moves)
        } else {
            "–".into()
        };
        out += &format!("| {who} | {moves:.2} | {border:.3} | {share} |\n");
    }
    out
}

/// Write report.md (with pictures), matrix.csv, matrix.json, summary.json, the XP heatmap
/// and, for trained runs, their learning curves into `dir`; returns the report.
pub fn write_outputs(
    dir: &Path,
    config: &Config,
    entries: &[PolicySource],
    results: &[PairResult],
    games: u64,
    groups: &[GroupSummary],
) -> anyhow::Result<String> {
    let names: Vec<String> = entries.iter().map(PolicySource::name).collect();
    let names = &names;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let write = |file: &str, text: String| {
        let path = dir.join(file);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
    };
    let mut pictures = Vec::new();
    let n = names.len();
    let mut matrix = vec![vec![0.0; n]; n];
    for c in results {
        matrix[c.row][c.col] = c.metrics.reward;
        matrix[c.col][c.row] = c.metrics.reward;
    }
    plots::write_both(
        dir,
        "xp_heatmap",
        &plots::heatmap_svg(
            &format!("R of each pair on {config} (diagonal: self-play)"),
            names,
            &matrix,
        ),
    )?;
    pictures.push(("cross-play heatmap", "xp_heatmap.png"));
    let runs: Vec<(String, PathBuf)> = entries
        .iter()
        .filter_map(|e| Some((e.name(), run_dir_of(e.trained()?.path()))))
        .filter(|(_, d)| d.join(yokai_train::artifact::names::METRICS).exists())
        .collect();
    if !runs.is_empty() {
        let mut ret = Vec::new();
        let mut see = Vec::new();
        for (name, run) in &runs {
            let log = yokai_train::read_metrics(run)?;
            let points = |f: &dyn Fn(&yokai_engine::Metrics) -> f64| {
                curve(
                    log.iter()
                        .filter_map(|s| s.games.map(|m| (s.env_steps as f64, f(&m))))
                        .collect(),
                )
            };
            ret.push(plots::Series {
                label: name.clone(),
                points: points(&|m| m.reward),
            });
            see.push(plots::Series {
                label: name.clone(),
                points: points(&|m| 100.0 * m.successful_early_end),
            });
        }
        plots::write_both(
            dir,
            "learning_return",
            &plots::lines_svg(
                "Return R during training (no shaping)",
                "environment steps",
                "R",
                &ret,
            ),
        )?;
        plots::write_both(
            dir,
            "learning_see",
            &plots::lines_svg("SEE during training", "environment steps", "SEE %", &see),
        )?;
        pictures.push(("learning curves: return", "learning_return.png"));
        pictures.push(("learning curves: SEE", "learning_see.png"));
        // OBL levels ≥ 2: how much their belief models know beyond first-hand facts.
        let mut gain = Vec::new();
        for (name, run) in &runs {
            let Some(curve_log) = yokai_train::read_belief_metrics(run)? else {
                continue;
            };
            let points = curve(
                (curve_log.iter().enumerate())
                    .map(|(k, b)| ((k + 1) as f64, b.uniform_cross_entropy - b.cross_entropy))
                    .collect(),
            );
            gain.push(plots::Series {
                label: name.clone(),
                points,
            });
        }
        if !gain.is_empty() {
            plots::write_both(
                dir,
                "learning_belief",
                &plots::lines_svg(
                    "Belief model: first-hand baseline minus its cross-entropy (above 0: it reads the level below)",
                    "updates",
                    "nats per unseen card",
                    &gain,
                ),
            )?;
            pictures.push(("learning curves: belief model", "learning_belief.png"));
        }
    }
    let report = report(config, names, results, games, groups, &pictures);
    let summary = EvalSummary {
        game: config.to_string(),
        games_per_pair: games,
        groups: groups.to_vec(),
    };
    write(
        "summary.json",
        serde_json::to_string_pretty(&summary).expect("summary serialises"),
    )?;
    write("report.md", report.to_string())?;
    let csv = crate::table::csv_text(
        &[
            "row",
            "col",
            "games",
            "reward",
            "reward_se",
            "win_rate",
            "see",
            "ee",
            "wee",
            "length",
            "correct_hints",
            "wrong_hints",
        ],
        results.iter().map(|c| {
            let m = &c.metrics;
            vec![
                names[c.row].clone(),
                names[c.col].clone(),
                m.games.to_string(),
                m.reward.to_string(),
                m.reward_se.to_string(),
                m.win_rate.to_string(),
                m.successful_early_end.to_string(),
                m.early_end.to_string(),
                m.win_given_early_end
                    .map_or(String::new(), |w| w.to_string()),
                m.length.to_string(),
                m.correct_hints.to_string(),
                m.wrong_hints.to_string(),
            ]
        }),
    );
    write("matrix.csv", csv)?;
    let json: Vec<serde_json::Value> = results
        .iter()
        .map(
            |c| serde_json::json!({"row": names[c.row], "col": names[c.col], "metrics": c.metrics}),
        )
        .collect();
    write(
        "matrix.json",
        serde_json::to_string_pretty(&json).expect("metrics serialize"),
    )?;
    Ok(report)
}

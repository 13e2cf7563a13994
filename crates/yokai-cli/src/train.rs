//! `yokai train`: train seeds of a config, then evaluate them against each other.

use crate::eval::{evaluate, save_replays, summarise_groups, write_outputs, Play};
use anyhow::{anyhow, Context};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use yokai_agents::PolicySpec;
use yokai_engine::Config;
use yokai_train::artifact::names::{seed_dir, seed_path};
use yokai_train::run::checkpoint_config;
use yokai_train::PolicySource;
use yokai_train::{train_run, RunRequest, TrainConfig, TrainedPolicy};

#[derive(clap::Args)]
pub struct Args {
    /// Training config: a preset name (quick, quick-op, cpu, ippo-9c-2p, he-9c-2p, op-9c-2p, …;
    /// see configs/) or a path to a TOML file.
    #[arg(default_value = "quick")]
    config: String,
    /// Seeds to train: `0..3` (3 seeds: 0, 1, 2), `0,4,7` or one number.
    #[arg(long, default_value = "0..3")]
    seeds: String,
    /// Directory of the runs (one `seed-N` folder per seed). Default: runs/<config name>.
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// Continue the runs in --out from their checkpoints instead of starting new ones.
    #[arg(long)]
    resume: bool,
    /// Stop each seed after this many updates (it can be resumed later).
    #[arg(long)]
    max_updates: Option<u64>,
    /// Override the config's total environment steps.
    #[arg(long)]
    steps: Option<u64>,
    /// Set one field of the training config, as in the file: `--set ppo.lr=1e-3 --set
    /// network.head=pointer` (repeatable; later ones win). The value is read as TOML, or
    /// as a string where it is not TOML. An unknown field or a bad value is refused, and
    /// the run's saved config.toml shows the result. Not with --resume (the checkpoint's
    /// config governs a resumed run).
    #[arg(long = "set", value_name = "FIELD=VALUE", conflicts_with = "resume")]
    set: Vec<yokai_train::Override>,
    /// Start each new run from the weights of a trained policy (fine-tuning, curricula):
    /// a policy file, a checkpoint, a run directory, or a directory of `seed-N` runs (seed
    /// N then starts from `seed-N`). The network and game must match the config's; the
    /// optimiser and schedules start anew. Sets the config's `run.init_from`.
    #[arg(long, value_name = "PATH", conflicts_with = "resume")]
    init_from: Option<PathBuf>,
    /// Games per pair in the evaluation after training; 0 skips it.
    #[arg(long, default_value_t = 1_000)]
    eval_games: u64,
    /// Worker threads in all (default: all cores), shared among the seeds trained at once.
    #[arg(long)]
    threads: Option<usize>,
    /// Seeds trained at the same time, each on max(1, threads / jobs) threads (default: all
    /// seeds, at most two per thread). Each seed's run is the same whichever seeds train
    /// beside it, up to float rounding with a different thread count.
    #[arg(long)]
    jobs: Option<usize>,
    /// Where the network trains: `cpu` (always built), `cuda` or `vulkan` (GPU; built with
    /// `--features cuda` / `--features vulkan`), or `gpu` for the GPU backend built in (CUDA
    /// first). The environment steps on the CPU either way.
    #[arg(long, default_value = "cpu")]
    device: yokai_train::Backend,
    /// Off-Belief Learning configs: train these levels in sequence, `1..3` (levels 1 and 2)
    /// or one number, each into `<out>/level-L/seed-N` with the level below
    /// (`<out>/level-(L-1)`) as its previous level and its starting weights (--init-from
    /// applies to level 1); the evaluation runs after each level.
    #[arg(long, value_name = "A..B")]
    levels: Option<String>,
}

/// `--seeds`: `0..3`, `0,4,7` or `5` ([`yokai_agents::parse_seeds`]).
pub fn parse_seeds(text: &str) -> anyhow::Result<Vec<u64>> {
    yokai_agents::parse_seeds(text).map_err(|e| anyhow!("--seeds {e}"))
}

/// The config named `name` (a preset or a file) with `overrides` applied, and its name.
fn load_config(
    name: &str,
    overrides: &[yokai_train::Override],
) -> anyhow::Result<(TrainConfig, String)> {
    Ok(TrainConfig::named(name, overrides)?)
}

impl Args {
    /// Where the network trains (`--device`).
    pub fn device(&self) -> yokai_train::Backend {
        self.device
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let seeds = parse_seeds(&args.seeds)?;
    let (mut config, name) = load_config(&args.config, &args.set)?;
    if let Some(steps) = args.steps {
        config.ppo.total_steps = steps;
    }
    if let Some(from) = &args.init_from {
        config.run.init_from = Some(from.clone());
    }
    config.validate("config")?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("runs").join(&name));
    let Some(levels) = &args.levels else {
        return train_and_evaluate(&args, &config, &name, &seeds, &out);
    };
    // Levels count from 1: parse them as seeds are parsed, then plan the chain.
    let levels = yokai_agents::parse_seeds(levels).map_err(|e| anyhow!("--levels {e}"))?;
    let levels: Vec<u32> = levels
        .into_iter()
        .map(|l| l.min(u32::MAX as u64) as u32)
        .collect();
    let chain = yokai_train::obl::levels::plan(&config, &levels, &out)
        .with_context(|| format!("--levels with {name}"))?;
    for level in chain {
        let label = format!("{name} level {}", level.level);
        train_and_evaluate(&args, &level.config, &label, &seeds, &level.dir)?;
    }
    Ok(())
}

/// Train `seeds` of `config` into `out`, then evaluate them.
fn train_and_evaluate(
    args: &Args,
    config: &TrainConfig,
    name: &str,
    seeds: &[u64],
    out: &Path,
) -> anyhow::Result<()> {
    // Each seed's run config, decided once: a resumed run trains on its checkpoint's,
    // whatever the command's preset says now. Read before any seed starts, so a missing or
    // broken checkpoint stops the command at once.
    let runs = seeds
        .iter()
        .map(|&seed| Ok((seed, run_config(args, config, out, seed)?)))
        .collect::<anyhow::Result<VecDeque<(u64, TrainConfig)>>>()?;
    // Every seed of a command shares the game and the algorithm: describe the first's.
    let first = runs.front().map_or(config, |(_, c)| c);
    let game = first.game_config()?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = args.threads.unwrap_or(cores).max(1);
    // By default every seed at once, up to two per thread: a compact run keeps about one
    // core busy, and 3 seeds side by side on 2 cores train 1.8× as fast as one after the
    // other (scripts/jobs-ab.sh, docs/training.md).
    let jobs = args
        .jobs
        .unwrap_or(seeds.len().min(2 * threads))
        .clamp(1, seeds.len());
    let threads_per_job = (threads / jobs).max(1);
    eprintln!(
        "{} {name} ({}) for seeds {seeds:?} into {}, {jobs} at a time on \
         {threads_per_job} thread(s) each",
        if args.resume { "resuming" } else { "training" },
        describe(first, &game, args.device),
        out.display()
    );
    // Seeds are independent runs: `jobs` workers take them in order from a queue, each on
    // its own thread pool.
    let progress = MultiProgress::new();
    let queue = Mutex::new(runs);
    let finished = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                let pool = match rayon::ThreadPoolBuilder::new()
                    .num_threads(threads_per_job)
                    .build()
                {
                    Ok(pool) => pool,
                    Err(e) => {
                        let e = Err(anyhow!("could not start threads: {e}"));
                        finished.lock().expect("no panic").push((u64::MAX, e));
                        return;
                    }
                };
                loop {
                    let Some((seed, config)) = queue.lock().expect("no panic").pop_front() else {
                        return;
                    };
                    let job = SeedJob {
                        args,
                        config,
                        out,
                        threads: threads_per_job,
                        progress: &progress,
                    };
                    let result = pool.install(move || job.train(seed));
                    let failed = result.is_err();
                    finished.lock().expect("no panic").push((seed, result));
                    if failed {
                        // Stop taking seeds: the first error is reported once all stop.
                        queue.lock().expect("no panic").clear();
                        return;
                    }
                }
            });
        }
    });
    let mut finished = finished.into_inner().expect("no panic");
    finished.sort_by_key(|(seed, _)| *seed);
    let mut dirs = Vec::new();
    for (_, result) in finished {
        dirs.push(result?);
    }
    if args.eval_games == 0 {
        return Ok(());
    }
    let mut entries = Vec::new();
    for dir in &dirs {
        let p = TrainedPolicy::load(dir)?;
        entries.push(PolicySource::Trained(Box::new(p)));
    }
    entries.push(PolicySource::Builtin(PolicySpec::Random));
    let names: Vec<String> = entries.iter().map(PolicySource::name).collect();
    eprintln!(
        "evaluating {} policies and random, {} games per pair",
        dirs.len(),
        args.eval_games
    );
    let results = evaluate(&game, &entries, args.eval_games, 0, args.threads)?;
    let mut groups = summarise_groups(&entries, &names, &results);
    let play = Play {
        config: &game,
        entries: &entries,
        games: args.eval_games,
        seed: 0,
        threads: args.threads,
    };
    play.distinct_cross_play(&mut groups, 20)?;
    let eval_dir = out.join("eval");
    let text = write_outputs(
        &eval_dir,
        &game,
        &entries,
        &results,
        args.eval_games,
        &groups,
    )?;
    print!("{text}");
    let group: Vec<usize> = (0..dirs.len()).collect();
    // Two self-play games of every seed, to look at with `yokai replay`.
    let selfplay: Vec<(usize, usize)> = group.iter().map(|&i| (i, i)).collect();
    save_replays(&game, &entries, &selfplay, 2, 0, &eval_dir.join("replays"))?;
    eprintln!("wrote {}", eval_dir.display());
    Ok(())
}

/// What a run trains, in a few words: "obl with both symmetries on 9c-2p-perfect, compact
/// network with the mlp encoder, on cpu". The symmetries are named because an OBL chain can
/// switch them on at a level (`obl.symmetries_from_level`).
fn describe(config: &TrainConfig, game: &Config, device: yokai_train::Backend) -> String {
    let symmetries = match config.algorithm.symmetries {
        yokai_train::SymmetrySet::None => String::new(),
        s => format!(" with {} symmetries", format!("{s:?}").to_lowercase()),
    };
    format!(
        "{}{symmetries} on {game}, {} network with the {} encoder, on {device}",
        config.algorithm.name,
        format!("{:?}", config.network.preset).to_lowercase(),
        config.network.encoder(),
    )
}

/// The config seed `seed` trains on: with --resume its checkpoint's (with --steps applied),
/// otherwise the command's, where seed N starts from `seed-N` when `run.init_from` (from
/// --init-from, the config, or --levels: the level below) is a directory of runs.
fn run_config(
    args: &Args,
    config: &TrainConfig,
    out: &Path,
    seed: u64,
) -> anyhow::Result<TrainConfig> {
    if args.resume {
        let mut c = checkpoint_config(&seed_dir(out, seed))?;
        if let Some(steps) = args.steps {
            c.ppo.total_steps = steps;
        }
        return Ok(c);
    }
    let mut c = config.clone();
    c.run.init_from = c.run.init_from.map(|from| seed_path(&from, seed));
    Ok(c)
}

/// What training one seed needs from the command.
struct SeedJob<'a> {
    args: &'a Args,
    /// The seed's run config ([`run_config`]).
    config: TrainConfig,
    out: &'a Path,
    threads: usize,
    progress: &'a MultiProgress,
}

impl SeedJob<'_> {
    /// Train (or resume) one seed's run with a progress bar; its directory when it is done.
    fn train(self, seed: u64) -> anyhow::Result<PathBuf> {
        let args = self.args;
        let dir = seed_dir(self.out, seed);
        let mut run_config = self.config;
        run_config.run.threads = self.threads;
        let total = run_config.updates();
        let bar = self.progress.add(
            ProgressBar::new(total).with_style(
                ProgressStyle::with_template(
                    "seed {prefix} [{bar:25}] {pos}/{len} updates {msg} (eta {eta})",
                )
                .expect("valid template")
                .progress_chars("=> "),
            ),
        );
        bar.set_prefix(seed.to_string());
        let request = RunRequest {
            config: &run_config,
            seed,
            dir: &dir,
            resume: args.resume,
            max_updates: args.max_updates,
            backend: args.device,
        };
        // Without a terminal (a job under nohup, a batch system, a pipe) the bars are hidden:
        // plain lines instead, at every tenth of the run and at least every 10 minutes.
        let mut plain = self
            .progress
            .is_hidden()
            .then(|| PlainProgress::new(seed, total));
        let summary = train_run(&request, &mut |s, _| {
            bar.set_position(s.update);
            let r = s.games.map_or("–".into(), |m| format!("{:+.2}", m.reward));
            let status = format!(
                "{} steps | {:.0} SPS | R {r} | H {:.2}",
                s.env_steps, s.sps, s.entropy
            );
            if let Some(plain) = &mut plain {
                plain.report(s.update, &status);
            }
            bar.set_message(format!("| {status}"));
        })?;
        bar.finish_and_clear();
        self.progress.remove(&bar);
        let last = summary.last.as_ref();
        // OBL levels ≥ 2: how much the belief reads of the level below.
        let belief = last
            .and_then(|s| Some((s.obl_belief_cross_entropy?, s.obl_belief_baseline?)))
            .map_or(String::new(), |(ce, base)| {
                format!("; belief {ce:.3} nats per unseen card (first-hand baseline {base:.3})")
            });
        let line = format!(
            "seed {seed}: {} updates, {} env steps ({} now, in {:.0} s: {:.0} SPS); last R {}{belief} → {}",
            summary.updates,
            summary.env_steps,
            summary.env_steps_here,
            summary.seconds,
            summary.env_steps_here as f64 / summary.seconds.max(1e-9),
            last.and_then(|s| s.games)
                .map_or("–".into(), |m| format!("{:+.2}", m.reward)),
            dir.display()
        );
        // Printed above the bars still running (plain stderr when hidden).
        if self.progress.is_hidden() {
            eprintln!("{line}");
        } else {
            let _ = self.progress.println(line);
        }
        Ok(dir)
    }
}

/// A seed's progress as plain lines on stderr, for runs without a terminal.
struct PlainProgress {
    seed: u64,
    total: u64,
    /// The next tenth of the run to report.
    next_tenth: u64,
    last: std::time::Instant,
}

impl PlainProgress {
    /// Lines at least this far apart report even between tenths (long runs).
    const HEARTBEAT: std::time::Duration = std::time::Duration::from_secs(600);

    fn new(seed: u64, total: u64) -> PlainProgress {
        PlainProgress {
            seed,
            total: total.max(1),
            next_tenth: 1,
            last: std::time::Instant::now(),
        }
    }

    /// After update `update` (1-based): a line where it reaches the next tenth of the
    /// run, or 10 minutes passed since the last line.
    fn report(&mut self, update: u64, status: &str) {
        let tenth = update * 10 / self.total;
        if tenth < self.next_tenth && self.last.elapsed() < Self::HEARTBEAT {
            return;
        }
        self.next_tenth = tenth + 1;
        self.last = std::time::Instant::now();
        eprintln!(
            "seed {}: update {update}/{} ({} %) | {status}",
            self.seed,
            self.total,
            update * 100 / self.total
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use yokai_train::config::PRESETS;

    #[test]
    fn a_bad_seed_list_names_the_option() {
        assert_eq!(parse_seeds("0..3").unwrap(), vec![0, 1, 2]);
        let err = parse_seeds("3..3").unwrap_err().to_string();
        assert_eq!(err, "--seeds `3..3` is empty (A..B excludes B)");
    }

    /// The shipped preset `name`, parsed.
    fn preset(name: &str) -> TrainConfig {
        let (_, text) = PRESETS.iter().find(|(n, _)| *n == name).unwrap();
        TrainConfig::from_toml_str(text, name).unwrap()
    }

    /// `cpu-fast` says it is `cpu` on 20M steps instead of 40M; nothing else may drift.
    #[test]
    fn cpu_fast_is_the_cpu_preset_on_a_shorter_budget() {
        let (cpu, mut fast) = (preset("cpu"), preset("cpu-fast"));
        assert_eq!(
            (cpu.ppo.total_steps, fast.ppo.total_steps),
            (40_000_000, 20_000_000)
        );
        fast.ppo.total_steps = cpu.ppo.total_steps;
        assert_eq!(cpu, fast);
    }

    /// `cpu-op` says it is `cpu` (levers) with Other-Play's symmetries, the learning rate
    /// and the budget measured for it (docs/results/cpu-op-lr-2e-3.md); nothing else may
    /// drift.
    #[test]
    fn cpu_op_is_cpu_with_the_symmetries_its_rate_and_budget() {
        let (cpu, mut op) = (preset("cpu"), preset("cpu-op"));
        assert_eq!(op.algorithm.name, "op");
        assert_eq!(op.algorithm.symmetries, yokai_train::SymmetrySet::Both);
        assert_eq!((op.ppo.lr, op.ppo.total_steps), (2e-3, 48_000_000));
        assert_eq!((cpu.ppo.lr, cpu.ppo.total_steps), (3e-3, 40_000_000));
        op.algorithm = cpu.algorithm.clone();
        (op.ppo.lr, op.ppo.total_steps) = (cpu.ppo.lr, cpu.ppo.total_steps);
        assert_eq!(cpu, op);
    }

    /// `obl-cpu` says it is OBL with `cpu-fast`'s levers, 2M steps per level, four
    /// decisions per continuation (the learner as partner) and levels ≥ 2 at a lower rate
    /// without shaping; nothing else may drift.
    #[test]
    fn obl_cpu_is_cpu_fast_with_obls_targets() {
        let (fast, mut obl) = (preset("cpu-fast"), preset("obl-cpu"));
        assert_eq!((obl.obl.level, obl.obl.decisions), (1, 4));
        assert_eq!(obl.obl.partner, yokai_train::config::OblPartner::Learner);
        assert_eq!(obl.ppo.total_steps, 2_000_000);
        assert_eq!(
            (obl.obl.warm_lr, obl.obl.warm_shaping),
            (Some(1e-3), Some(0.0))
        );
        obl.algorithm.name = fast.algorithm.name.clone();
        obl.obl = Default::default();
        obl.ppo.total_steps = fast.ppo.total_steps;
        assert_eq!(fast, obl);
    }

    /// `quick` (the main job) says it is `cpu-fast` with a central critic at 10M steps, and
    /// `quick-op` that it is `quick` with Other-Play's symmetries; nothing else may drift.
    #[test]
    fn quick_is_cpu_fast_with_a_central_critic_and_quick_op_adds_the_symmetries() {
        let (fast, mut quick) = (preset("cpu-fast"), preset("quick"));
        assert_eq!(quick.network.critic, yokai_train::CriticInput::Central);
        assert_eq!(quick.ppo.total_steps, 10_000_000);
        let mut op = preset("quick-op");
        assert_eq!(op.algorithm.symmetries, yokai_train::SymmetrySet::Both);
        op.algorithm = quick.algorithm.clone();
        assert_eq!(op, quick);
        quick.network.critic = fast.network.critic;
        quick.ppo.total_steps = fast.ppo.total_steps;
        quick.run.checkpoint_every = fast.run.checkpoint_every;
        assert_eq!(fast, quick);
    }
}

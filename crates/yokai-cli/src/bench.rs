//! `yokai bench`: environment steps per second with random legal actions, beside the
//! paper's H100 figures.

use anyhow::{anyhow, bail};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;
use std::time::{Duration, Instant};
use yokai_engine::{Config, Scalar};
use yokai_vec::{VecEnv, VecEnvOptions};

#[derive(clap::Args)]
pub struct Args {
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
    /// Measured seconds per row (after a short warm-up).
    #[arg(long, default_value_t = 2.0)]
    seconds: f64,
    /// Configs to measure (comma-separated short names).
    #[arg(
        long,
        default_value = "9c-2p-perfect,16c-2p-perfect",
        value_delimiter = ','
    )]
    configs: Vec<String>,
    /// Numbers of parallel games (comma-separated).
    #[arg(long, default_value = "512,1024,2048", value_delimiter = ',')]
    envs: Vec<usize>,
    /// Observation dtypes to measure: f32, u8 (comma-separated).
    #[arg(long, default_value = "f32,u8", value_delimiter = ',')]
    dtypes: Vec<String>,
    /// Observation encodings written for every seat each step (comma-separated): `image` is
    /// RULES §5's `[g, g+1, F]`, `image-chw` the same values channels-first `[F, g, g+1]`
    /// (what conv layers take, and cheaper to update in place); also graph, none, ….
    #[arg(long, default_value = "image-chw,image", value_delimiter = ',')]
    encodings: Vec<String>,
    /// Measure every row this many times and report the median, with the lowest and highest
    /// reading beside it: on a shared machine single readings can move by a third. The runs
    /// go round all rows N times, so every row is sampled across the whole measurement.
    #[arg(long, default_value_t = 1)]
    repeats: usize,
    /// Games per work item handed to a thread.
    #[arg(long, default_value_t = 32)]
    chunk: usize,
    /// Print one JSON object per row instead of a table.
    #[arg(long)]
    json: bool,
}

/// The paper's JAX environment on an NVIDIA H100, random legal actions (`paper.rs`).
fn paper_h100(config: &Config, envs: usize) -> Option<f64> {
    let name = config.short_name()?;
    let base = name
        .strip_suffix("-perfect")
        .or(name.strip_suffix("-imperfect"))?;
    crate::paper::h100_steps_per_second(base, envs)
}

/// Steps per second (one step = one substep of one game) of random legal play.
fn measure<T: Scalar + Default>(
    config: Config,
    options: VecEnvOptions,
    seconds: f64,
) -> anyhow::Result<f64> {
    let mut env = VecEnv::<T>::new(config, options)?;
    let n = options.num_envs;
    let mut actions = vec![0u32; n];
    let mut round = 0u64;
    let mut run_for = |env: &mut VecEnv<T>, limit: Duration| -> anyhow::Result<(u64, Duration)> {
        let start = Instant::now();
        let mut iterations = 0u64;
        while start.elapsed() < limit {
            for _ in 0..8 {
                env.sample_legal(round, &mut actions);
                env.step(&actions)?;
                round += 1;
                iterations += 1;
            }
        }
        Ok((iterations, start.elapsed()))
    };
    let warm_up = Duration::from_secs_f64((seconds / 5.0).min(0.5));
    let measured = Duration::from_secs_f64(seconds);
    // The loop runs on the environment's worker threads, as a Rust rollout loop would, so
    // each call splits its games without a hand-over from an outside thread.
    let (iterations, elapsed) = env.on_workers(|env| {
        run_for(env, warm_up)?;
        run_for(env, measured)
    })?;
    Ok((iterations * n as u64) as f64 / elapsed.as_secs_f64())
}

/// One line of the report: what is measured.
struct Row {
    config: Config,
    encoding_name: String,
    options: VecEnvOptions,
    dtype: Dtype,
}

#[derive(Clone, Copy)]
enum Dtype {
    F32,
    U8,
}

impl Dtype {
    fn parse(name: &str) -> anyhow::Result<Dtype> {
        match name {
            "f32" => Ok(Dtype::F32),
            "u8" => Ok(Dtype::U8),
            other => Err(anyhow!("unknown dtype `{other}` (expected f32 or u8)")),
        }
    }
    fn name(self) -> &'static str {
        match self {
            Dtype::F32 => "f32",
            Dtype::U8 => "u8",
        }
    }
}

impl Row {
    fn measure(&self, seconds: f64) -> anyhow::Result<f64> {
        match self.dtype {
            Dtype::F32 => measure::<f32>(self.config, self.options, seconds),
            Dtype::U8 => measure::<u8>(self.config, self.options, seconds),
        }
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.seconds <= 0.0 || !args.seconds.is_finite() {
        bail!("--seconds must be positive");
    }
    if args.repeats == 0 {
        bail!("--repeats must be at least 1");
    }
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let rows = rows(&args, threads)?;
    // Repeats go round the rows rather than one row at a time: the machine's speed drifts
    // over minutes, and this way every row's samples span the whole run.
    let bar = ProgressBar::new((rows.len() * args.repeats) as u64).with_style(
        ProgressStyle::with_template("{spinner} measuring [{bar:30}] {pos}/{len} runs (eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let mut samples = vec![Vec::with_capacity(args.repeats); rows.len()];
    for _ in 0..args.repeats {
        for (row, samples) in rows.iter().zip(&mut samples) {
            samples.push(row.measure(args.seconds)?);
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    if !args.json {
        println!(
            "random legal actions, observations for every seat + legal masks, {threads} thread(s), {} s per run",
            args.seconds
        );
        let steps = if args.repeats > 1 {
            format!("steps/s, median of {} (range)", args.repeats)
        } else {
            "steps/s".to_string()
        };
        println!("| config | games | encoding | dtype | {steps} | paper H100 | ratio |");
        println!("|---|---|---|---|---|---|---|");
    }
    for (row, mut samples) in rows.iter().zip(samples) {
        samples.sort_by(f64::total_cmp);
        let sps = samples[samples.len() / 2];
        let (config, envs, encoding_name, dtype) = (
            row.config,
            row.options.num_envs,
            &row.encoding_name,
            row.dtype.name(),
        );
        let paper = paper_h100(&config, envs);
        if args.json {
            println!(
                "{}",
                json!({"config": config.to_string(), "envs": envs, "dtype": dtype, "threads": threads,
                   "encoding": encoding_name, "steps_per_second": sps.round(),
                   "samples": samples.iter().map(|s| s.round()).collect::<Vec<_>>(),
                   "paper_h100": paper, "ratio": paper.map(|p| sps / p)})
            );
        } else {
            let (p, r) = match paper {
                Some(p) => (format!("{p:.0}"), format!("{:.1}×", sps / p)),
                None => ("–".into(), "–".into()),
            };
            let spread = if samples.len() > 1 {
                format!(" ({:.0}–{:.0})", samples[0], samples[samples.len() - 1])
            } else {
                String::new()
            };
            println!(
                "| {config} | {envs} | {encoding_name} | {dtype} | {sps:.0}{spread} | {p} | {r} |"
            );
        }
    }
    Ok(())
}

/// Every (config, games, encoding, dtype) the options ask for, checked before any is
/// measured so that a typo fails at once rather than after minutes of measuring.
fn rows(args: &Args, threads: usize) -> anyhow::Result<Vec<Row>> {
    let encodings = args
        .encodings
        .iter()
        .map(|name| yokai_vec::Encoding::parse(name).map(|e| (name.as_str(), e)))
        .collect::<Result<Vec<_>, _>>()?;
    let dtypes = args
        .dtypes
        .iter()
        .map(|d| Dtype::parse(d))
        .collect::<Result<Vec<_>, _>>()?;
    let mut rows = Vec::new();
    for name in &args.configs {
        let config = Config::resolve(name)?;
        for &envs in &args.envs {
            if envs == 0 {
                bail!("--envs: every number of games must be at least 1");
            }
            for &(encoding_name, encoding) in &encodings {
                for &dtype in &dtypes {
                    rows.push(Row {
                        config,
                        encoding_name: encoding_name.to_string(),
                        options: VecEnvOptions {
                            encoding,
                            threads: Some(threads),
                            chunk: args.chunk,
                            ..VecEnvOptions::new(envs, 0)
                        },
                        dtype,
                    });
                }
            }
        }
    }
    Ok(rows)
}

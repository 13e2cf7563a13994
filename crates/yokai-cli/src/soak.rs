//! `yokai soak`: random legal play through the batched environment across every preset
//! config, checking the rules' invariants at every step of every game and replaying a
//! sample of the finished games against the engine's slow reference implementations
//! (`yokai_engine::reference`). A long soak (10⁹ steps) is how the engine earns trust beyond
//! its tests; docs/reliability.md reports the runs.

use anyhow::{anyhow, bail, Context};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use std::collections::BTreeSet;
use std::time::Instant;
use yokai_engine::reference::{check_state, reference_moves, reference_reward};
use yokai_engine::{Action, Config, Game, Seat, Substep};
use yokai_vec::{episode_seed, Encoding, VecEnv, VecEnvOptions};

#[derive(clap::Args)]
pub struct Args {
    /// Environment steps in all (one step = one substep of one game), shared evenly by the
    /// configs; `1e9` and `2_000_000` are accepted.
    #[arg(long, default_value = "1e7", value_parser = parse_steps)]
    steps: u64,
    /// Games stepped together per config.
    #[arg(long, default_value_t = 256)]
    envs: usize,
    /// Replay one finished game in this many against the reference implementations (their
    /// MOVE check tries every card on every cell: slow on purpose).
    #[arg(long, default_value_t = 1000)]
    sample: u64,
    /// Base seed of the deals and of the random actions.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Worker threads of the environments (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

fn parse_steps(text: &str) -> anyhow::Result<u64> {
    let clean = text.replace('_', "");
    clean
        .parse::<u64>()
        .ok()
        .or_else(|| {
            clean
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x >= 1.0)
                .map(|x| x as u64)
        })
        .ok_or_else(|| anyhow!("`{text}` is not a number of steps"))
}

/// What a soak found, per config and in all.
#[derive(Default)]
struct Tally {
    steps: u64,
    games: u64,
    replayed: u64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let configs = Config::presets();
    if args.envs == 0 || args.sample == 0 {
        bail!("--envs and --sample must be at least 1");
    }
    let per_config = args.steps / configs.len() as u64;
    let bar = ProgressBar::new(per_config * configs.len() as u64).with_style(
        ProgressStyle::with_template("soak [{bar:25}] {pos}/{len} steps {msg} (eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let start = Instant::now();
    let mut total = Tally::default();
    for (k, &config) in configs.iter().enumerate() {
        bar.set_message(config.to_string());
        let seed = args.seed.wrapping_add(k as u64);
        let tally = soak_config(config, &args, seed, per_config, &bar)
            .with_context(|| format!("{config}"))?;
        println!(
            "{config}: {} steps, {} games, {} replayed against the reference: no violation",
            tally.steps, tally.games, tally.replayed
        );
        total.steps += tally.steps;
        total.games += tally.games;
        total.replayed += tally.replayed;
    }
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();
    println!(
        "all {} configs: {} steps, {} games, {} replayed; {:.0} s ({:.0} steps/s with the checks)",
        configs.len(),
        total.steps,
        total.games,
        total.replayed,
        secs,
        total.steps as f64 / secs.max(1e-9)
    );
    Ok(())
}

fn soak_config(
    config: Config,
    args: &Args,
    seed: u64,
    steps: u64,
    bar: &ProgressBar,
) -> anyhow::Result<Tally> {
    let n = args.envs;
    let mut options = VecEnvOptions::new(n, seed);
    options.encoding = Encoding::None;
    options.threads = args.threads;
    let mut env = VecEnv::<u8>::new(config, options)?;
    let (p, na) = (config.players(), config.num_actions());
    let mut actions = vec![0u32; n];
    let mut histories: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut tally = Tally::default();
    let mut t = 0u64;
    while tally.steps < steps {
        // Masks: the acting seat has a legal action; every other seat has NOOP alone.
        let masks = env.legal_masks();
        for i in 0..n {
            let acting = env.acting_seats()[i] as usize;
            for s in 0..p {
                let row = &masks[(i * p + s) * na..][..na];
                let legal = row.iter().filter(|&&m| m == 1).count();
                if s == acting {
                    if legal == 0 {
                        bail!("env {i}: the acting seat {s} has no legal action");
                    }
                } else if legal != 1 || row[0] != 1 {
                    bail!("env {i}: waiting seat {s} may play more than NOOP");
                }
            }
        }
        env.sample_legal(seed.wrapping_add(t).wrapping_mul(0x9E37_79B9), &mut actions);
        t += 1;
        env.step(&actions)?;
        tally.steps += n as u64;
        for i in 0..n {
            histories[i].push(actions[i]);
            if env.dones()[i] == 1 {
                tally.games += 1;
                let actions_of_game = std::mem::take(&mut histories[i]);
                if tally.games % args.sample == 0 {
                    let episode = env.episodes(i) - 1;
                    let outcome = env.outcomes()[i].context("a finished game without outcome")?;
                    replay_against_reference(
                        config,
                        episode_seed(seed, i, episode),
                        &actions_of_game,
                        outcome.reward,
                    )
                    .with_context(|| format!("env {i} episode {episode}"))?;
                    tally.replayed += 1;
                }
            }
        }
        let env_ref = &env;
        (0..n)
            .into_par_iter()
            .try_for_each(|i| check_state(env_ref.game(i)).with_context(|| format!("env {i}")))?;
        bar.inc(n as u64);
    }
    Ok(tally)
}

/// Replay a finished game from its deal: at every MOVE substep the engine's legal moves
/// equal the reference's, and the final reward equals the reference reward and the one the
/// batched environment reported.
fn replay_against_reference(
    config: Config,
    deal_seed: u64,
    actions: &[u32],
    reported: i32,
) -> anyhow::Result<()> {
    let mut game = Game::new(config, deal_seed);
    for (step, &index) in actions.iter().enumerate() {
        if game.substep() == Substep::Move {
            let seat: Seat = game.current_seat();
            let engine: BTreeSet<_> = game
                .legal_actions(seat)
                .into_iter()
                .filter_map(|a| match a {
                    Action::Move(card, cell) => Some((card.0, cell)),
                    _ => None,
                })
                .collect();
            if engine != reference_moves(&game) {
                return Err(anyhow!(
                    "step {step}: legal moves differ from the reference"
                ));
            }
        }
        game.apply_index(index as usize)
            .with_context(|| format!("step {step}"))?;
    }
    if !game.is_over() {
        bail!("the replayed game did not finish");
    }
    let reference = reference_reward(&game);
    if reference != reported {
        return Err(anyhow!(
            "reward {reported} reported, the reference says {reference}"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_parse_in_plain_and_scientific_notation() {
        assert_eq!(parse_steps("1e9").unwrap(), 1_000_000_000);
        assert_eq!(parse_steps("2_000_000").unwrap(), 2_000_000);
        assert!(parse_steps("lots").is_err());
        assert!(parse_steps("-5").is_err());
    }

    #[test]
    fn the_invariants_hold_through_play_and_a_bad_reward_is_caught() {
        let config = Config::from_name("9c-3p-imperfect").unwrap();
        let mut game = Game::new(config, 4);
        let mut actions = Vec::new();
        while !game.is_over() {
            check_state(&game).unwrap();
            let legal = game.legal_actions(game.current_seat());
            let a = legal[actions.len() * 7 % legal.len()];
            actions.push(config.encode(a) as u32);
            game.apply(a).unwrap();
        }
        let reward = game.outcome().unwrap().reward;
        replay_against_reference(config, 4, &actions, reward).unwrap();
        let e = replay_against_reference(config, 4, &actions, reward + 1).unwrap_err();
        assert!(e.to_string().contains("the reference says"), "{e}");
        let e =
            replay_against_reference(config, 4, &actions[..actions.len() - 1], reward).unwrap_err();
        assert!(e.to_string().contains("did not finish"), "{e}");
    }
}

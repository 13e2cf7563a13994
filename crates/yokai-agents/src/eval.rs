//! Playing many games: a group of policies in fixed seats, and cross-play over every seat
//! permutation. Games are split across threads in fixed chunks, and game i is dealt from
//! `derive_seed(seed, i)`, so results do not depend on the number of threads.

use crate::{play_episode, PlayError, Policy};
use rayon::prelude::*;
use yokai_engine::{derive_seed, Config, Metrics, MetricsAccumulator};

/// Makes a fresh policy for a seat from a seed (one per seat and worker).
pub type PolicyFactory<'a> = dyn Fn(u64) -> Box<dyn Policy> + Sync + 'a;

/// Games per work item.
const CHUNK: u64 = 64;

/// Play `games` games with `seats[s]` in seat `s`; `progress(n)` is called as games finish.
pub fn play_group(
    config: Config,
    seats: &[&PolicyFactory<'_>],
    games: u64,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<MetricsAccumulator, PlayError> {
    (0..games.div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let mut policies: Vec<Box<dyn Policy>> = seats
                .iter()
                .enumerate()
                .map(|(s, make)| make(derive_seed(seed ^ 0x5eed_5eed, (chunk << 8) | s as u64)))
                .collect();
            let mut acc = MetricsAccumulator::default();
            for i in chunk * CHUNK..((chunk + 1) * CHUNK).min(games) {
                let episode = play_episode(
                    config,
                    derive_seed(seed, i),
                    derive_seed(!seed, i),
                    &mut policies,
                )?;
                acc.add(&episode.outcome);
                acc.add_moves(&config, &episode.record.actions);
            }
            progress(acc.games);
            Ok(acc)
        })
        .try_reduce(MetricsAccumulator::default, |mut a, b| {
            a.merge(&b);
            Ok(a)
        })
}

/// One entry of a cross-play table: the games of the policies `row` and `col`.
#[derive(Clone, Debug)]
pub struct PairResult {
    pub row: usize,
    pub col: usize,
    pub metrics: Metrics,
}

/// What [`cross_play`] reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum Progress {
    /// The pair of policies now playing.
    Pair { row: usize, col: usize },
    /// This many more games finished.
    Games(u64),
}

/// The pairs of `n` policies (each with itself included, `row ≤ col`) with their seatings
/// at `players` seats and the games each seating plays: `games` per pair, split evenly
/// over its seatings (rounded up).
pub fn cross_play_plan(
    n: usize,
    players: usize,
    games: u64,
) -> Vec<(usize, usize, Vec<Vec<usize>>, u64)> {
    (0..n)
        .flat_map(|i| (i..n).map(move |j| (i, j)))
        .map(|(i, j)| {
            let s = seatings(&[i, j], players);
            let per = games.div_ceil(s.len() as u64);
            (i, j, s, per)
        })
        .collect()
}

/// Every pair of `policies` (each with itself included) over all seatings that use both,
/// `games` per pair ([`cross_play_plan`]), game i of every seating dealt from `seed`: the
/// paper's cross-play table, run in the current rayon pool.
pub fn cross_play(
    config: Config,
    policies: &[&PolicyFactory<'_>],
    games: u64,
    seed: u64,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Vec<PairResult>, PlayError> {
    let mut results = Vec::new();
    for (row, col, seatings, games) in cross_play_plan(policies.len(), config.players(), games) {
        progress(Progress::Pair { row, col });
        let metrics = play_seatings(config, policies, &seatings, games, seed, &|g| {
            progress(Progress::Games(g))
        })?;
        results.push(PairResult { row, col, metrics });
    }
    Ok(results)
}

/// The paper's cross-play J_XP for `players` > 2 seats: every set of `players` distinct
/// policies, each over all its seatings (the permutations of the set), not pairs that fill
/// the table with repeats. One result per set.
#[derive(Clone, Debug)]
pub struct SetResult {
    /// The set's policies (indices, ascending).
    pub members: Vec<usize>,
    pub metrics: Metrics,
}

/// The sets of `players` distinct policies among `group` (ascending, in lexicographic
/// order), at most `max_sets` of them: all when there are no more, else `max_sets` drawn
/// without replacement from `seed` (then sorted), so that 12 seeds at 4 seats (495 sets)
/// stay affordable. Empty when the group is smaller than the table.
pub fn distinct_sets(
    group: &[usize],
    players: usize,
    max_sets: usize,
    seed: u64,
) -> Vec<Vec<usize>> {
    let mut members = group.to_vec();
    members.sort_unstable();
    members.dedup();
    let mut all = Vec::new();
    let mut current = Vec::with_capacity(players);
    fn choose(
        members: &[usize],
        from: usize,
        players: usize,
        current: &mut Vec<usize>,
        out: &mut Vec<Vec<usize>>,
    ) {
        if current.len() == players {
            out.push(current.clone());
            return;
        }
        for k in from..members.len() {
            current.push(members[k]);
            choose(members, k + 1, players, current, out);
            current.pop();
        }
    }
    if players > 0 {
        choose(&members, 0, players, &mut current, &mut all);
    }
    if all.len() > max_sets {
        // A seeded partial Fisher-Yates shuffle picks `max_sets` of them.
        for k in 0..max_sets {
            let pick = k + (derive_seed(seed, k as u64) % (all.len() - k) as u64) as usize;
            all.swap(k, pick);
        }
        all.truncate(max_sets);
        all.sort();
    }
    all
}

/// Each of `sets` (from [`distinct_sets`]) over all its seatings, `games` per set split
/// evenly over them (rounded up), game i of every seating dealt from `seed`: the paper's
/// J_XP, run in the current rayon pool. `progress` hears of every finished game.
pub fn distinct_cross_play(
    config: Config,
    policies: &[&PolicyFactory<'_>],
    sets: &[Vec<usize>],
    games: u64,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<SetResult>, PlayError> {
    let mut results = Vec::new();
    for members in sets {
        let all = seatings(members, config.players());
        let per = games.div_ceil(all.len() as u64);
        let metrics = play_seatings(config, policies, &all, per, seed, progress)?;
        results.push(SetResult {
            members: members.clone(),
            metrics,
        });
    }
    Ok(results)
}

/// `games` games in each of `seatings` (policy indices per seat), merged: one entry of a
/// cross-play table. Every seating plays at least one game, so there are metrics.
fn play_seatings(
    config: Config,
    policies: &[&PolicyFactory<'_>],
    seatings: &[Vec<usize>],
    games: u64,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Metrics, PlayError> {
    let mut acc = MetricsAccumulator::default();
    for seating in seatings {
        let seats: Vec<&PolicyFactory<'_>> = seating.iter().map(|&k| policies[k]).collect();
        acc.merge(&play_group(config, &seats, games, seed, progress)?);
    }
    Ok(acc
        .metrics()
        .expect("every seating plays at least one game"))
}

/// Every arrangement of `members` (indices into a list of policies) over the seats: all
/// permutations of a group, with repetition when the group is smaller than the table
/// (e.g. two policies at three seats: every seating that uses both).
pub fn seatings(members: &[usize], players: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut current = Vec::with_capacity(players);
    fn extend(
        members: &[usize],
        players: usize,
        current: &mut Vec<usize>,
        out: &mut Vec<Vec<usize>>,
    ) {
        if current.len() == players {
            if members.iter().all(|m| current.contains(m)) {
                out.push(current.clone());
            }
            return;
        }
        for &m in members {
            current.push(m);
            extend(members, players, current, out);
            current.pop();
        }
    }
    let mut distinct = members.to_vec();
    distinct.sort_unstable();
    distinct.dedup();
    extend(&distinct, players, &mut current, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PolicySpec;
    use std::sync::atomic::{AtomicU64, Ordering};

    /// The cross-play table of two bots is, pair by pair, the groups `play_group` plays in
    /// each seating, merged; it reports every pair before its games and every game once.
    #[test]
    fn cross_play_is_every_pair_over_its_seatings() {
        let config = Config::resolve("9c-2p-perfect").unwrap();
        let specs = [PolicySpec::Random, PolicySpec::Greedy];
        let makers: Vec<Box<PolicyFactory<'_>>> = specs
            .iter()
            .map(|s| Box::new(move |seed| s.build(seed)) as Box<PolicyFactory<'_>>)
            .collect();
        let policies: Vec<&PolicyFactory<'_>> = makers.iter().map(|m| m.as_ref()).collect();
        let (games, seed) = (101, 7);
        let played = AtomicU64::new(0);
        let pairs = std::sync::Mutex::new(Vec::new());
        let results = cross_play(config, &policies, games, seed, &|p| match p {
            Progress::Pair { row, col } => pairs.lock().unwrap().push((row, col)),
            Progress::Games(g) => {
                played.fetch_add(g, Ordering::Relaxed);
            }
        })
        .unwrap();
        let order: Vec<(usize, usize)> = results.iter().map(|r| (r.row, r.col)).collect();
        assert_eq!(order, [(0, 0), (0, 1), (1, 1)]);
        assert_eq!(*pairs.lock().unwrap(), order);
        let plan = cross_play_plan(2, 2, games);
        let total: u64 = plan.iter().map(|(_, _, s, g)| s.len() as u64 * g).sum();
        // Self-play: one seating of 101 games; cross-play: two seatings of 51.
        assert_eq!(total, 101 + 2 * 51 + 101);
        assert_eq!(played.load(Ordering::Relaxed), total);
        for (result, (_, _, seatings, per)) in results.iter().zip(&plan) {
            let mut want = MetricsAccumulator::default();
            for seating in seatings {
                let seats: Vec<&PolicyFactory<'_>> = seating.iter().map(|&k| policies[k]).collect();
                want.merge(&play_group(config, &seats, *per, seed, &|_| {}).unwrap());
            }
            assert_eq!(result.metrics, want.metrics().unwrap());
        }
        // Greedy never ends early; random ends most games early.
        assert_eq!(results[2].metrics.early_end, 0.0);
        assert!(results[0].metrics.early_end > 0.5);
    }

    /// Border usage as `play_group` counts it equals a recount from the game states: for
    /// every game (the same deals and policy seeds), replay it and look where each moved
    /// card lies after its move. Over random play on 9c and 16c, 2 and 4 players.
    #[test]
    fn border_moves_are_the_moved_cards_that_land_on_the_outer_ring() {
        for name in ["9c-2p-perfect", "9c-4p-perfect", "16c-2p-perfect"] {
            let config = Config::resolve(name).unwrap();
            let make = |seed| PolicySpec::Random.build(seed);
            let seats: Vec<&PolicyFactory<'_>> = vec![&make; config.players()];
            let (games, seed) = (300u64, 11u64);
            let got = play_group(config, &seats, games, seed, &|_| {}).unwrap();
            let (mut moves, mut border) = (0u64, 0u64);
            let edge = config.grid() as u8 - 1;
            for i in 0..games {
                let chunk = i / CHUNK;
                let mut policies: Vec<Box<dyn Policy>> = (0..config.players())
                    .map(|s| make(derive_seed(seed ^ 0x5eed_5eed, (chunk << 8) | s as u64)))
                    .collect();
                // A chunk's policies play its games in order: replay the chunk up to game i.
                let mut record = None;
                for j in chunk * CHUNK..=i {
                    let e = play_episode(
                        config,
                        derive_seed(seed, j),
                        derive_seed(!seed, j),
                        &mut policies,
                    )
                    .unwrap();
                    record = Some(e.record);
                }
                let mut game = yokai_engine::Game::new(config, derive_seed(seed, i));
                for &a in &record.unwrap().actions {
                    let action = config.decode(a as usize).unwrap();
                    game.apply(action).unwrap();
                    if let yokai_engine::Action::Move(card, _) = action {
                        let cell = game.cell_of(card);
                        moves += 1;
                        border += [cell.row, cell.col].iter().any(|&x| x == 0 || x == edge) as u64;
                    }
                }
            }
            assert_eq!(
                (got.card_moves, got.border_moves),
                (moves, border),
                "{name}"
            );
            assert!(moves > games, "{name}: random play moves cards");
            if name == "9c-2p-perfect" {
                assert!(border > 0, "random play reaches the border now and then");
            }
        }
    }

    /// Sets of distinct policies: every combination while there are few, a seeded sample
    /// of `max_sets` (the same for the same seed) when there are many; none when the group
    /// cannot fill the table.
    #[test]
    fn distinct_sets_are_the_combinations_or_a_seeded_sample_of_them() {
        let all = distinct_sets(&[4, 1, 7, 9], 3, 20, 0);
        assert_eq!(all, [[1, 4, 7], [1, 4, 9], [1, 7, 9], [4, 7, 9]]);
        assert!(distinct_sets(&[0, 1], 3, 20, 0).is_empty());
        let group: Vec<usize> = (0..12).collect();
        assert_eq!(distinct_sets(&group, 4, 1000, 0).len(), 495);
        let sample = distinct_sets(&group, 4, 20, 5);
        assert_eq!(sample.len(), 20);
        assert_eq!(sample, distinct_sets(&group, 4, 20, 5));
        assert_ne!(sample, distinct_sets(&group, 4, 20, 6));
        let mut unique = sample.clone();
        unique.dedup();
        assert_eq!(unique.len(), 20, "drawn without replacement");
        assert!(sample
            .iter()
            .all(|s| s.len() == 4 && s.windows(2).all(|w| w[0] < w[1])));
    }

    /// A set of three distinct bots at three seats plays all 6 seatings, the games split
    /// evenly, each seating the group `play_group` plays.
    #[test]
    fn distinct_cross_play_is_each_set_over_every_seating() {
        let config = Config::resolve("9c-3p-perfect").unwrap();
        let specs = [PolicySpec::Random, PolicySpec::Greedy, PolicySpec::Random];
        let makers: Vec<Box<PolicyFactory<'_>>> = specs
            .iter()
            .map(|s| Box::new(move |seed| s.build(seed)) as Box<PolicyFactory<'_>>)
            .collect();
        let policies: Vec<&PolicyFactory<'_>> = makers.iter().map(|m| m.as_ref()).collect();
        let played = AtomicU64::new(0);
        let sets = distinct_sets(&[0, 1, 2], 3, 20, 0);
        let results = distinct_cross_play(config, &policies, &sets, 30, 9, &|g| {
            played.fetch_add(g, Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(results.len(), 1);
        assert_eq!(results[0].members, [0, 1, 2]);
        assert_eq!(played.load(Ordering::Relaxed), 6 * 5);
        let mut want = MetricsAccumulator::default();
        for seating in seatings(&[0, 1, 2], 3) {
            assert_eq!(seating.len(), 3);
            let seats: Vec<&PolicyFactory<'_>> = seating.iter().map(|&k| policies[k]).collect();
            want.merge(&play_group(config, &seats, 5, 9, &|_| {}).unwrap());
        }
        assert_eq!(results[0].metrics, want.metrics().unwrap());
    }
}

//! Playing many games: a group of policies in fixed seats, and cross-play over every seat
//! permutation. Games are split across threads in fixed chunks, and game i is dealt from
//! `derive_seed(seed, i)`, so results do not depend on the number of threads.

use crate::{play_episode, PlayError, Policy};
use rayon::prelude::*;
use yokai_engine::{derive_seed, Config, MetricsAccumulator};

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
            }
            progress(acc.games);
            Ok(acc)
        })
        .try_reduce(MetricsAccumulator::default, |mut a, b| {
            a.merge(&b);
            Ok(a)
        })
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

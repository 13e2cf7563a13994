//! Stepping recurrent memories along sequences of game states outside the batched
//! environment: the learner's memory through a fictitious continuation, and the partners'
//! memories through an episode replayed in a fictitious colouring.

use crate::seen::SeenSeat;
use yokai_engine::{Game, Seat, Symmetry};
use yokai_vec::Encoding;

/// Step memories along per-game sequences of states, all games together: at depth j every
/// game whose sequence has a state j steps the memories of its seats `seats[g]` on their
/// observations (in `encoding`, each seen through its symmetry: `symmetries[g·P + seat]`,
/// the actor's row order) of that state, in one batched `step(obs, states, keep)`.
/// `states[g]` holds the seats' memories (`seats[g].len()` rows) before the first state and
/// after the last on return; `fresh` zeroes them at depth 0 (an episode's start).
pub(crate) fn step_along(
    sequences: &[&[Game]],
    seats: &[Vec<Seat>],
    symmetries: &[Symmetry],
    states: &mut [Vec<f32>],
    encoding: Encoding,
    fresh: bool,
    step: &mut dyn FnMut(Vec<f32>, Vec<f32>, Vec<f32>) -> Vec<f32>,
) {
    let Some(config) = sequences
        .iter()
        .flat_map(|s| s.first())
        .map(|g| *g.config())
        .next()
    else {
        return;
    };
    let l: usize = encoding.shape(&config).iter().product();
    let depth = sequences.iter().map(|s| s.len()).max().unwrap_or(0);
    for j in 0..depth {
        let live: Vec<usize> = (0..sequences.len())
            .filter(|&g| sequences[g].len() > j && !seats[g].is_empty())
            .collect();
        let rows: usize = live.iter().map(|&g| seats[g].len()).sum();
        if rows == 0 {
            continue;
        }
        let mut obs = vec![0f32; rows * l];
        let mut h = Vec::with_capacity(rows);
        let mut r = 0;
        for &g in &live {
            for &seat in &seats[g] {
                let view = SeenSeat {
                    game: &sequences[g][j],
                    seat,
                    symmetry: symmetries[g * config.players() + seat.index()],
                };
                view.write(encoding, &mut obs[r * l..][..l]);
                r += 1;
            }
            h.extend_from_slice(&states[g]);
        }
        let keep = vec![(j > 0 || !fresh) as u8 as f32; rows];
        let new = step(obs, h, keep);
        let mut at = 0;
        for &g in &live {
            let n = states[g].len();
            states[g].copy_from_slice(&new[at..at + n]);
            at += n;
        }
    }
}

/// The states of an episode from `start` through `history` (action indices): `start` and
/// the state after each action, the last one the episode's current state.
pub(crate) fn episode_states(start: Game, history: &[u32]) -> Vec<Game> {
    let mut states = Vec::with_capacity(history.len() + 1);
    states.push(start);
    for &action in history {
        let mut next = states[states.len() - 1].clone();
        next.apply_index(action as usize)
            .expect("a recorded action is legal in any colouring");
        states.push(next);
    }
    states
}

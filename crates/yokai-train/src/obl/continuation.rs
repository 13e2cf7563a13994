//! One fictitious continuation: a seat's action in a world drawn from its belief, then the
//! partners' play until the seat is to act again (or, with `decisions` n > 1, until it is
//! to act for the n-th time, its own moves in between played in that world too).
//!
//! How far it runs (docs/training.md): a turn is four substeps of one seat, so after the
//! seat's OBSERVE or MOVE it acts again at once (one step), and after its REVEAL or PLACE
//! the partners play their turns first (1 + 4·(P − 1) steps). The paper's K = 4·P bounds
//! this (per decision) and is kept as a limit; with the rules as they are it never binds.

use rand_chacha::ChaCha8Rng;
use yokai_engine::{ActionError, Colour, DealError, Game};

/// What one fictitious continuation gave.
#[derive(Clone, Debug)]
pub struct Continuation {
    /// The fictitious game after each step taken (the seat's action first): the seat's
    /// recurrent memory reads its observation of each, in order.
    pub states: Vec<Game>,
    /// Σ γʲ (rⱼ + shaping · sⱼ) over the steps taken: game reward r and shaping s.
    pub reward: f32,
    /// The game ended inside the continuation (no value to bootstrap from).
    pub done: bool,
}

impl Continuation {
    /// Steps taken (at least 1).
    pub fn steps(&self) -> usize {
        self.states.len()
    }
}

/// Why a continuation could not be built: a colouring that breaks the counts, or an action
/// that is not legal (both are bugs of the caller, named here instead of a panic).
#[derive(Debug, thiserror::Error)]
pub enum ContinuationError {
    #[error("fictitious colouring: {0}")]
    Colouring(#[from] DealError),
    #[error("fictitious step: {0}")]
    Action(#[from] ActionError),
}

/// Apply the acting seat's action `action` (an action index) to `game` recoloured with
/// `colours`, then let `partner` (the partners' policy: an action index for the
/// acting seat of a game) play until that seat is to act again, the game ends, or `horizon`
/// steps have been taken.
pub fn continue_fictitiously(
    game: &Game,
    colours: &[Colour],
    action: usize,
    partner: &mut impl FnMut(&Game) -> usize,
    shaping: f32,
    gamma: f32,
    horizon: usize,
) -> Result<Continuation, ContinuationError> {
    let fict = game.with_card_colours(colours)?;
    let mut one = continue_all(
        &[(&fict, action)],
        &mut |_, games| vec![partner(games[0])],
        shaping,
        gamma,
        1,
        horizon,
    )
    .map_err(|(_, e)| e)?;
    Ok(one.remove(0))
}

/// [`continue_fictitiously`] for many games at once, `starts` holding each one's game
/// already recoloured (the fictitious world, [`Game::with_card_colours`]) and the action.
/// The continuations step in lockstep, so that `players` runs once per step for all that
/// are still open (the network then steps all their seats in one batch): it is given their
/// indices in `starts` and their fictitious games, and returns an action index of each
/// game's acting seat, in order.
///
/// Each continuation stops where its seat is to act for the `decisions`-th time since the
/// start (1: where it acts again; the seat's own moves before that come from `players`
/// too), where its game ends, or after `horizon` steps. An error names the start.
pub fn continue_all(
    starts: &[(&Game, usize)],
    players: &mut impl FnMut(&[usize], &[&Game]) -> Vec<usize>,
    shaping: f32,
    gamma: f32,
    decisions: usize,
    horizon: usize,
) -> Result<Vec<Continuation>, (usize, ContinuationError)> {
    let mut fict: Vec<Game> = starts.iter().map(|&(g, _)| g.clone()).collect();
    let mut out: Vec<Continuation> = (0..starts.len())
        .map(|_| Continuation {
            states: Vec::with_capacity(horizon.min(16)),
            reward: 0.0,
            done: false,
        })
        .collect();
    let mut discount = vec![1f32; starts.len()];
    let mut reached = vec![0usize; starts.len()];
    let mut next: Vec<usize> = starts.iter().map(|s| s.1).collect();
    let mut open: Vec<usize> = (0..starts.len()).collect();
    while !open.is_empty() {
        let mut still = Vec::with_capacity(open.len());
        for &k in &open {
            let step = fict[k].apply_index(next[k]).map_err(|e| (k, e.into()))?;
            let c = &mut out[k];
            c.reward += discount[k] * (step.reward as f32 + shaping * step.shaping as f32);
            discount[k] *= gamma;
            c.states.push(fict[k].clone());
            c.done = step.done;
            reached[k] += (fict[k].current_seat() == starts[k].0.current_seat()) as usize;
            if !(step.done || reached[k] >= decisions || c.states.len() >= horizon) {
                still.push(k);
            }
        }
        if !still.is_empty() {
            let games: Vec<&Game> = still.iter().map(|&k| &fict[k]).collect();
            for (&k, a) in still.iter().zip(players(&still, &games)) {
                next[k] = a;
            }
        }
        open = still;
    }
    Ok(out)
}

/// π₀, the level below level 1: a uniformly random legal action index of the acting seat.
pub fn random_legal(game: &Game, rng: &mut ChaCha8Rng) -> usize {
    let legal = game.legal_actions(game.current_seat());
    let pick = yokai_engine::deal::below(rng, legal.len() as u32) as usize;
    game.config().encode(legal[pick])
}

/// π₀ as a partner for [`continue_fictitiously`].
pub fn uniform_random(rng: &mut ChaCha8Rng) -> impl FnMut(&Game) -> usize + '_ {
    move |game: &Game| random_legal(game, rng)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::obl::sample_first_hand_consistent;
    use rand_chacha::rand_core::SeedableRng;
    use yokai_engine::{Action, Cell, Config, Deal, Seat, Substep};

    /// The OBL value of END at the first step of a hand-built game, against the value
    /// computed by hand. The nine cards lie in one row, seat 0 has seen none, so its level-1
    /// belief is uniform over the 1,680 colourings of three colours in a row of nine:
    /// - all three clustered (three blocks): 3! = 6 colourings, R = 5·4 = 20;
    /// - one given colour in one block: 7! / (3! 3!) = 140 (the block as one unit), two
    ///   given colours: 5! / 3! = 20, so exactly two clustered: 3·(20 − 6) = 42, R = −2;
    /// - exactly one: 3·140 − 2·42 − 3·6 = 318, R = −3; none: 1,680 − 366 = 1,314, R = −4.
    ///
    /// E[R_END] = (6·20 − 42·2 − 318·3 − 1314·4) / 1680 = −6174 / 1680 = −3.675. The
    /// standard deviation is 1.50, so 20,000 draws give it within ±0.05 (4.7 SE).
    #[test]
    fn the_level_one_value_of_ending_on_a_hand_built_board_is_the_hand_computed_one() {
        let config = Config::from_name("9c-2p").unwrap();
        let deal = Deal {
            card_colours: [0, 1, 2, 0, 1, 2, 0, 1, 2].map(Colour).to_vec(),
            hint_colours: Game::new(config, 0).deal().hint_colours,
        };
        let row: Vec<Cell> = (0..9).map(|c| Cell::new(4, c)).collect();
        let game = Game::from_layout(config, &deal, &row).unwrap();
        assert_eq!(game.substep(), Substep::FirstObserve);
        let end = config.encode(Action::End);
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let mut partner_rng = ChaCha8Rng::seed_from_u64(18);
        let mut partner = uniform_random(&mut partner_rng);
        let draws = 20_000;
        let mut total = 0f64;
        for _ in 0..draws {
            let colours = sample_first_hand_consistent(&game, Seat(0), &mut rng);
            let c =
                continue_fictitiously(&game, &colours, end, &mut partner, 1.0, 0.99, 8).unwrap();
            assert!(c.done && c.steps() == 1);
            total += c.reward as f64;
        }
        let mean = total / draws as f64;
        assert!(
            (mean + 3.675).abs() < 0.05,
            "mean R_END {mean}, by hand −3.675"
        );
    }

    /// With the true colours, the continuation's first step is the real transition; the
    /// continuation stops where the seat is to act again: one step within its turn, five
    /// (its hint step and the partner's turn) after its last substep in a 2-player game.
    #[test]
    fn the_continuation_is_the_real_transition_and_stops_when_the_seat_acts_again() {
        let config = Config::from_name("9c-2p").unwrap();
        let mut game = Game::new(config, 4);
        let truth = game.deal().card_colours;
        let mut partner_rng = ChaCha8Rng::seed_from_u64(2);
        // A random partner that never ENDs, so that its whole turn is played.
        let mut pi0 = |g: &Game| {
            let mut legal = g.legal_actions(g.current_seat());
            legal.retain(|&a| a != Action::End);
            let pick = yokai_engine::deal::below(&mut partner_rng, legal.len() as u32);
            g.config().encode(legal[pick as usize])
        };
        for substep in 0..4 {
            // Seat 0's first legal action other than END, so that the game goes on.
            let action = game
                .legal_actions(Seat(0))
                .into_iter()
                .find(|&a| a != Action::End)
                .map(|a| config.encode(a))
                .unwrap();
            let mut real = game.clone();
            real.apply_index(action).unwrap();
            if substep < 3 {
                // Within the turn the partner is never asked.
                let c = continue_fictitiously(
                    &game,
                    &truth,
                    action,
                    &mut |_| unreachable!(),
                    0.0,
                    1.0,
                    8,
                )
                .unwrap();
                assert_eq!(c.steps(), 1);
                assert!(
                    c.states[0] == real,
                    "substep {substep}: the real transition"
                );
            } else {
                let c =
                    continue_fictitiously(&game, &truth, action, &mut pi0, 0.0, 1.0, 8).unwrap();
                assert!(c.states[0] == real);
                assert_eq!(c.steps(), 5, "the hint step and the partner's four");
                assert_eq!(c.states[4].current_seat(), Seat(0));
                // A horizon below that cuts it short.
                let cut =
                    continue_fictitiously(&game, &truth, action, &mut pi0, 0.0, 1.0, 3).unwrap();
                assert_eq!(cut.steps(), 3);
            }
            game = real;
        }
    }

    /// With `decisions` = d the continuation stops where its seat is to act for the d-th
    /// time (its own moves in between asked of the players), so it extends the one of d − 1
    /// decisions: over games at random points of play, continued with a players' rule that
    /// is a function of the game alone, d = 1..4.
    #[test]
    fn a_continuation_of_d_decisions_stops_at_the_seats_dth_turn_and_extends_d_minus_one() {
        let config = Config::from_name("9c-2p").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let players = |g: &Game| {
            let mut legal = g.legal_actions(g.current_seat());
            legal.retain(|&a| a != Action::End);
            g.config().encode(legal[(g.steps() * 5 + 3) % legal.len()])
        };
        let mut checked = 0;
        for d in 0..30u64 {
            let mut g = Game::new(config, 100 + d);
            for _ in 0..(d % 13) {
                let a = players(&g);
                g.apply_index(a).unwrap();
            }
            let seat = g.current_seat();
            let colours = sample_first_hand_consistent(&g, seat, &mut rng);
            let world = g.with_card_colours(&colours).unwrap();
            let action = players(&world);
            let mut before: Option<Continuation> = None;
            for decisions in 1..=4 {
                let mut asked_of_seat = 0;
                let c = continue_all(
                    &[(&world, action)],
                    &mut |_, gs| {
                        asked_of_seat += (gs[0].current_seat() == seat) as usize;
                        vec![players(gs[0])]
                    },
                    1.0,
                    0.99,
                    decisions,
                    64,
                )
                .unwrap()
                .remove(0);
                let turns = c.states.iter().filter(|s| s.current_seat() == seat).count();
                if c.done {
                    assert!(turns <= decisions);
                } else {
                    assert_eq!(turns, decisions, "game {d}: stops at the d-th decision");
                    assert_eq!(c.states.last().unwrap().current_seat(), seat);
                    assert_eq!(asked_of_seat, decisions - 1, "the seat's moves in between");
                    checked += 1;
                }
                if let Some(b) = &before {
                    assert_eq!(c.states[..b.steps()], b.states[..], "extends d − 1");
                    if !b.done {
                        assert!(c.steps() > b.steps());
                    }
                }
                before = Some(c);
            }
        }
        assert!(
            checked > 60,
            "most continuations ran their decisions: {checked}"
        );
    }

    /// The continuations of many games stepped in lockstep are each what its game's own
    /// continuation gives, with a partner that is a function of the game alone (so that the
    /// order of the partner's calls cannot matter): games at random points of random play,
    /// each continued from a belief sample and a random legal action (END among them).
    #[test]
    fn continuations_in_lockstep_are_the_games_own() {
        let config = Config::from_name("9c-2p").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let partner = |g: &Game| {
            let legal = g.legal_actions(g.current_seat());
            let pick = (g.steps() * 7 + legal.len()) % legal.len();
            g.config().encode(legal[pick])
        };
        let mut games = Vec::new();
        for d in 0..40u64 {
            let mut g = Game::new(config, d);
            for _ in 0..(d * 3 % 25) {
                if g.is_over() {
                    break;
                }
                let mut legal = g.legal_actions(g.current_seat());
                legal.retain(|&a| a != Action::End);
                let a = legal[yokai_engine::deal::below(&mut rng, legal.len() as u32) as usize];
                g.apply(a).unwrap();
            }
            if !g.is_over() {
                games.push(g);
            }
        }
        assert!(games.len() > 30);
        let colourings: Vec<Vec<Colour>> = games
            .iter()
            .map(|g| sample_first_hand_consistent(g, g.current_seat(), &mut rng))
            .collect();
        let actions: Vec<usize> = games.iter().map(|g| random_legal(g, &mut rng)).collect();
        let worlds: Vec<Game> = games
            .iter()
            .zip(&colourings)
            .map(|(g, c)| g.with_card_colours(c).unwrap())
            .collect();
        let starts: Vec<(&Game, usize)> =
            worlds.iter().zip(&actions).map(|(w, &a)| (w, a)).collect();
        let mut calls = 0;
        let together = continue_all(
            &starts,
            &mut |which, gs| {
                calls += 1;
                assert_eq!(which.len(), gs.len());
                gs.iter().map(|g| partner(g)).collect()
            },
            1.0,
            0.99,
            1,
            8,
        )
        .unwrap();
        let mut longest = 0;
        for (k, ((g, colours), &a)) in games.iter().zip(&colourings).zip(&actions).enumerate() {
            let alone =
                continue_fictitiously(g, colours, a, &mut |g| partner(g), 1.0, 0.99, 8).unwrap();
            let both = &together[k];
            assert_eq!(both.states, alone.states, "game {k}");
            assert_eq!(
                (both.reward, both.done),
                (alone.reward, alone.done),
                "game {k}"
            );
            longest = longest.max(alone.steps());
        }
        assert!(longest > 1, "some continuation had partner steps");
        assert_eq!(calls, longest - 1, "one partner call per lockstep step");
    }
}

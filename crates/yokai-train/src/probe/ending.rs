//! When a trained policy ENDs, against what its seat knows first-hand.
//!
//! END pays well only on a clustered board, and a seat can only be sure of one where its
//! knowledge pins the colours down. This study plays a policy in self-play by its own play
//! rule and, at every state where the acting seat may END, records the policy's P(END)
//! beside the seat's **first-hand outlook**: over the colourings that agree with every card
//! it has observed itself and with the colour counts (Off-Belief Learning's level-1
//! belief, which reads nothing into its partner's moves or hints), the share in which the
//! board is clustered and the mean reward END would pay. The summary then splits the END
//! chances by that outlook (never clustered, unsure, sure) and asks two questions a
//! training change must answer differently: do the agents reach boards they know to be
//! clustered, and do they END there?
//!
//! For policies with conventions (IPPO, Other-Play) the first-hand outlook is a lower
//! bound of what the seat knows: their partners' moves and hints carry information too.

use crate::distribution::{decide_end_row, draw_row, end_probability, unit_draw};
use crate::TrainedPolicy;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use yokai_agents::belief::colouring::{
    all_colourings, count_colourings, sample_colouring, Colouring,
};
use yokai_engine::{derive_seed, Action, Config, Game, Seat};

/// Configs with at most this many colourings are outlooked exactly (every colouring that
/// agrees with the seat's knowledge; 9 cards: 1,680, 12 cards: 34,650); larger ones from
/// [`SAMPLED_COLOURINGS`] draws of the first-hand belief.
pub const EXACT_COLOURINGS: u128 = 40_000;

/// Draws per state where the colourings are too many to list.
pub const SAMPLED_COLOURINGS: usize = 1024;

/// What the acting seat can tell about ending from what it has observed itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Outlook {
    /// Share of the colourings consistent with its first-hand knowledge in which every
    /// colour is clustered: 1 means the seat knows that END wins.
    pub win: f64,
    /// Mean reward END would pay over those colourings.
    pub reward: f64,
}

/// The colourings an outlook averages over: all of a small config's, or draws.
enum Colourings {
    All(Vec<Colouring>),
    /// Boxed: the generator is 300 bytes, the list 24.
    Sampled(Box<ChaCha8Rng>),
}

/// Whether outlooks on `config` list every consistent colouring (else they are estimates).
pub fn is_exact(config: &Config) -> bool {
    count_colourings(config) <= EXACT_COLOURINGS
}

/// Computes first-hand outlooks for one config.
pub struct Outlooker {
    config: Config,
    colourings: Colourings,
}

impl Outlooker {
    /// Exact where the config's colourings number at most [`EXACT_COLOURINGS`]; otherwise
    /// sampled with draws that follow `seed`.
    pub fn new(config: &Config, seed: u64) -> Outlooker {
        let colourings = if is_exact(config) {
            Colourings::All(all_colourings(config))
        } else {
            Colourings::Sampled(Box::new(ChaCha8Rng::seed_from_u64(derive_seed(
                seed, 0x0E7,
            ))))
        };
        Outlooker {
            config: *config,
            colourings,
        }
    }

    /// `seat`'s first-hand outlook on ending `game` now.
    pub fn outlook(&mut self, game: &Game, seat: Seat) -> Outlook {
        let colours = self.config.colours();
        let view = game.public_view();
        let seen = game.ever_observed(seat);
        let truth = Colouring::from_colours(&game.deal().card_colours);
        let (mut n, mut won, mut paid) = (0usize, 0usize, 0i64);
        let mut tally = |x: &Colouring| {
            n += 1;
            won += (x.clustered(&view, colours) == colours) as usize;
            paid += x.reward_if_over(&view, true) as i64;
        };
        match &mut self.colourings {
            Colourings::All(all) => {
                let known = truth.restricted(seen);
                all.iter()
                    .filter(|x| x.restricted(seen) == known)
                    .for_each(&mut tally);
            }
            Colourings::Sampled(rng) => {
                let first_hand = crate::obl::belief::first_hand(game, seat);
                for _ in 0..SAMPLED_COLOURINGS {
                    tally(&sample_colouring(&self.config, &first_hand, rng));
                }
            }
        }
        // The true colouring is always consistent, so n ≥ 1.
        Outlook {
            win: won as f64 / n as f64,
            reward: paid as f64 / n as f64,
        }
    }
}

/// One state where the acting seat could END.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EndChance {
    /// Game index and game step.
    pub game: u32,
    pub step: u16,
    /// The policy's P(END) over the legal actions at temperature 1 (the probability its
    /// END rule reads).
    pub p_end: f64,
    /// Whether it ENDed here, by its play rule.
    pub ended: bool,
    /// What the seat knew first-hand.
    pub first_hand: Outlook,
    /// The true board: clustered, and what END paid.
    pub won: bool,
    pub reward: i32,
}

/// Play `games` self-play games of `policy` (in every seat, each with its own memory; its
/// play rule: END rule and temperature) and record every END chance. Deals and draws
/// follow `seed`.
pub fn end_chances(policy: &TrainedPolicy, games: usize, seed: u64) -> Vec<EndChance> {
    let config = *policy.game();
    let (p, h) = (config.players(), policy.hidden_size());
    let end = config.encode(Action::End);
    let mut outlooker = Outlooker::new(&config, seed);
    let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(seed, 0xE4D));
    let (mut mask, mut scratch) = (vec![0f32; config.num_actions()], Vec::new());
    let mut out = Vec::new();
    for first in (0..games).step_by(64) {
        let batch = (games - first).min(64);
        let mut live: Vec<Game> = (0..batch)
            .map(|g| Game::new(config, derive_seed(seed, (first + g) as u64)))
            .collect();
        let mut states = vec![vec![0f32; batch * h]; p];
        let mut step = 0u16;
        while live.iter().any(|g| !g.is_over()) {
            let open: Vec<usize> = (0..batch).filter(|&g| !live[g].is_over()).collect();
            // Every seat's memory reads the state; the acting seats' logits come with it.
            let stepped: Vec<_> = (0..p)
                .map(|s| {
                    let seat = Seat(s as u8);
                    super::step_memories(policy, &live, &open, seat, &mut states[s], step == 0)
                })
                .collect();
            for (k, &g) in open.iter().enumerate() {
                let game = &live[g];
                let seat = game.current_seat();
                let logits = stepped[seat.index()]
                    .logits(k)
                    .expect("the acting seat's logits");
                game.write_legal_mask(seat, &mut mask);
                let u = unit_draw(&mut rng);
                let chance = (mask[end] > 0.5).then(|| EndChance {
                    game: (first + g) as u32,
                    step,
                    p_end: end_probability(logits, &mask, end),
                    ended: false,
                    first_hand: outlooker.outlook(game, seat),
                    won: game.clustered_colours() == config.colours(),
                    reward: game.end_reward(),
                });
                let a = match policy.end_threshold() {
                    Some(t) => decide_end_row(
                        logits,
                        &mut mask,
                        u,
                        end,
                        t,
                        policy.temperature(),
                        &mut scratch,
                    ),
                    None => draw_row(logits, &mask, u, policy.temperature(), &mut scratch),
                };
                out.extend(chance.map(|c| EndChance {
                    ended: a == end,
                    ..c
                }));
                live[g]
                    .apply_index(a)
                    .expect("drawn among the legal actions");
            }
            step += 1;
        }
    }
    out
}

/// The bins of first-hand P(clustered) the summary splits END chances by: "knows END
/// loses" (0), five fifths of the unsure range, "knows END wins" (1).
pub const BINS: usize = 7;

/// The bin of an outlook: 0 where no consistent colouring is clustered, `BINS − 1` where
/// every one is, else the fifth of (0, 1) its P(clustered) falls in ((0, 0.2] → 1, …,
/// (0.8, 1) → 5).
pub fn bin_of(outlook: &Outlook) -> usize {
    match outlook.win {
        w if w <= 0.0 => 0,
        w if w >= 1.0 => BINS - 1,
        w => ((w * 5.0).ceil() as usize).clamp(1, 5),
    }
}

/// How a report names bin `k`.
pub fn bin_label(k: usize) -> String {
    match k {
        0 => "0: knows END loses".into(),
        k if k == BINS - 1 => "1: knows END wins".into(),
        k if k == BINS - 2 => "(0.8, 1)".into(),
        k => format!("({:.1}, {:.1}]", (k - 1) as f64 / 5.0, k as f64 / 5.0),
    }
}

/// The END chances of one bin of first-hand P(clustered).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BinRow {
    pub bin: String,
    /// Chances in the bin, and their share of all chances.
    pub chances: usize,
    pub share: f64,
    /// Mean P(END) and the share the policy ENDed at.
    pub p_end: f64,
    pub ended: f64,
    /// Mean first-hand P(clustered) and expected END reward; share truly clustered.
    pub first_hand_win: f64,
    pub first_hand_reward: f64,
    pub won: f64,
}

/// The study's answer for one policy.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EndSummary {
    pub games: usize,
    /// Whether the first-hand outlooks were exact (else sampled).
    pub exact: bool,
    pub chances: usize,
    /// By first-hand P(clustered), [`BINS`] rows.
    pub rows: Vec<BinRow>,
    /// Share of games with at least one chance where the seat knew END wins.
    pub games_with_sure_win: f64,
    /// Share of games ENDed, and of games ENDed where the seat knew END wins.
    pub games_ended: f64,
    pub games_ended_sure: f64,
    /// Over the ENDs: mean first-hand P(clustered) and expected reward, and the share won.
    pub ends_first_hand_win: f64,
    pub ends_first_hand_reward: f64,
    pub ends_won: f64,
}

impl EndSummary {
    pub fn of(chances: &[EndChance], games: usize, exact: bool) -> EndSummary {
        let mean = |xs: &[&EndChance], f: &dyn Fn(&EndChance) -> f64| {
            xs.iter().map(|c| f(c)).sum::<f64>() / xs.len().max(1) as f64
        };
        let rows = (0..BINS)
            .map(|bin| {
                let xs: Vec<&EndChance> = chances
                    .iter()
                    .filter(|c| bin_of(&c.first_hand) == bin)
                    .collect();
                BinRow {
                    bin: bin_label(bin),
                    chances: xs.len(),
                    share: xs.len() as f64 / chances.len().max(1) as f64,
                    p_end: mean(&xs, &|c| c.p_end),
                    ended: mean(&xs, &|c| c.ended as u8 as f64),
                    first_hand_win: mean(&xs, &|c| c.first_hand.win),
                    first_hand_reward: mean(&xs, &|c| c.first_hand.reward),
                    won: mean(&xs, &|c| c.won as u8 as f64),
                }
            })
            .collect();
        let sure = |c: &EndChance| bin_of(&c.first_hand) == BINS - 1;
        let mut with_sure: Vec<u32> = chances.iter().filter(|c| sure(c)).map(|c| c.game).collect();
        with_sure.sort_unstable();
        with_sure.dedup();
        let ends: Vec<&EndChance> = chances.iter().filter(|c| c.ended).collect();
        let per_game = |n: usize| n as f64 / games.max(1) as f64;
        EndSummary {
            games,
            exact,
            chances: chances.len(),
            rows,
            games_with_sure_win: per_game(with_sure.len()),
            games_ended: per_game(ends.len()),
            games_ended_sure: per_game(ends.iter().filter(|c| sure(c)).count()),
            ends_first_hand_win: mean(&ends, &|c| c.first_hand.win),
            ends_first_hand_reward: mean(&ends, &|c| c.first_hand.reward),
            ends_won: mean(&ends, &|c| c.won as u8 as f64),
        }
    }
}

/// [`end_chances`] and their [`EndSummary`].
pub fn study(policy: &TrainedPolicy, games: usize, seed: u64) -> EndSummary {
    EndSummary::of(
        &end_chances(policy, games, seed),
        games,
        is_exact(policy.game()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_chacha::rand_core::Rng;

    /// States of 9c-2p games: random play without END (boards seldom clustered) and the
    /// `belief` bot's self-play (which clusters them and observes with a plan), every state
    /// of every game, both seats.
    fn states() -> Vec<Game> {
        let config = Config::from_name("9c-2p").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let mut out = Vec::new();
        for case in 0..400u64 {
            let mut game = Game::new(config, case);
            let mut bots: Vec<Box<dyn yokai_agents::Policy>> = (0..2)
                .map(|s| {
                    "belief"
                        .parse::<yokai_agents::PolicySpec>()
                        .unwrap()
                        .build(s)
                })
                .collect();
            let bot_game = case % 2 == 0;
            while !game.is_over() {
                out.push(game.clone());
                let seat = game.current_seat();
                let action = if bot_game {
                    bots[seat.index()].act(&game.view(seat))
                } else {
                    let legal: Vec<Action> = game
                        .legal_actions(seat)
                        .into_iter()
                        .filter(|&a| a != Action::End)
                        .collect();
                    legal[(rng.next_u64() % legal.len() as u64) as usize]
                };
                for (s, bot) in bots.iter_mut().enumerate() {
                    bot.observe(&game.view(Seat(s as u8)), seat, action);
                }
                game.apply(action).unwrap();
            }
        }
        out
    }

    /// A seat's exact first-hand outlook is certain exactly where it must be: where it says
    /// "END wins" the true board is clustered (and pays what it expects, up to the placed
    /// hints it cannot check); where it says "END loses" the board is not clustered; and the
    /// sampled outlook
    /// (larger configs' path) agrees with the exact one within 5 standard errors.
    #[test]
    fn first_hand_outlooks_are_sure_only_where_the_seat_knows() {
        let config = Config::from_name("9c-2p").unwrap();
        assert!(is_exact(&config));
        let mut exact = Outlooker::new(&config, 0);
        let mut sampled = Outlooker {
            config,
            colourings: Colourings::Sampled(Box::new(ChaCha8Rng::seed_from_u64(9))),
        };
        let mut seen = [0usize; 3];
        let mut compared = 0;
        for (i, game) in states().iter().enumerate() {
            for s in 0..config.players() {
                let seat = Seat(s as u8);
                let o = exact.outlook(game, seat);
                let won = game.clustered_colours() == config.colours();
                assert!((0.0..=1.0).contains(&o.win));
                let bin = bin_of(&o);
                seen[(bin > 0) as usize + (bin == BINS - 1) as usize] += 1;
                match bin {
                    b if b == BINS - 1 => {
                        assert!(won, "state {i}: sure of a win that is not there");
                        // Sure of the clustering, the seat may still be unsure whether a
                        // placed hint is right (+1 or −1 each): the expected reward lies
                        // within 2 per placed hint of the true one.
                        let placed = game.hinted_cards().len() as f64;
                        assert!(
                            (o.reward - game.end_reward() as f64).abs() <= 2.0 * placed + 1e-9,
                            "state {i}: expects {}, pays {}",
                            o.reward,
                            game.end_reward()
                        );
                    }
                    0 => assert!(!won, "state {i}: sure of a loss"),
                    _ => {}
                }
                if i % 25 == 0 {
                    compared += 1;
                    let m = sampled.outlook(game, seat);
                    let se = (o.win * (1.0 - o.win) / SAMPLED_COLOURINGS as f64).sqrt();
                    assert!(
                        (m.win - o.win).abs() <= 5.0 * se + 1e-9,
                        "state {i}: sampled {} against exact {}",
                        m.win,
                        o.win
                    );
                }
            }
        }
        // Sure wins are rare even for the `belief` bot, which trusts its partner's
        // conventions (3 states in these games); `a_seat_that_knows_every_colour_is_sure`
        // builds them.
        assert!(
            seen[0] > 100 && seen[1] > 100 && compared > 100,
            "{seen:?}, {compared}"
        );
        assert!(seen[2] > 0, "{seen:?}");
    }
    /// A seat that has observed 8 of 9 cards knows the ninth from the counts: recoloured
    /// with any colouring (the cards it saw take the new colours), its outlook is a sure
    /// win where the recoloured board is clustered, with exactly the reward END pays, and a
    /// sure loss where it is not. Seat 0 observes a card it has not seen whenever it can,
    /// and hints are placed on cards it has seen, so by its fourth turn it has seen 8.
    #[test]
    fn a_seat_that_knows_every_colour_is_sure() {
        let config = Config::from_name("9c-2p").unwrap();
        let colourings = all_colourings(&config);
        let mut outlooker = Outlooker::new(&config, 0);
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let (mut wins, mut losses) = (0, 0);
        for case in 0..40u64 {
            let mut game = Game::new(config, case);
            let seat0 = Seat(0);
            while game.ever_observed(seat0).len() < 8 {
                assert!(!game.is_over(), "case {case}: seat 0 saw too few cards");
                let seat = game.current_seat();
                let seen = game.ever_observed(seat0);
                let legal: Vec<Action> = game
                    .legal_actions(seat)
                    .into_iter()
                    .filter(|&a| a != Action::End)
                    .collect();
                let wanted: Vec<Action> = legal
                    .iter()
                    .copied()
                    .filter(|&a| match a {
                        Action::Observe(card) => seat != seat0 || !seen.contains(card),
                        Action::Place(_, card) => seen.contains(card),
                        _ => true,
                    })
                    .collect();
                let pool = if wanted.is_empty() { &legal } else { &wanted };
                game.apply(pool[(rng.next_u64() % pool.len() as u64) as usize])
                    .unwrap();
            }
            for x in &colourings {
                let colours: Vec<_> = (0..9).map(|k| x.colour_of(yokai_engine::Card(k))).collect();
                let recoloured = game.with_card_colours(&colours).unwrap();
                let o = outlooker.outlook(&recoloured, seat0);
                if recoloured.clustered_colours() == config.colours() {
                    wins += 1;
                    assert_eq!(o.win, 1.0, "case {case}");
                    assert_eq!(o.reward, recoloured.end_reward() as f64, "case {case}");
                } else {
                    losses += 1;
                    assert_eq!(o.win, 0.0, "case {case}");
                    assert_eq!(o.reward, recoloured.end_reward() as f64, "case {case}");
                }
            }
        }
        assert!(wins > 20 && losses > 20, "{wins} wins, {losses} losses");
    }
}

#[cfg(test)]
mod study_tests {
    use super::*;

    /// A pretrained `cpu-op` agent (END decided above 0.6) in 9c-2p self-play: every END
    /// chance is at the start of a turn (game steps 0, 4, 8, … in order, one per turn until
    /// the game ends), a game ENDs at most once and only at its last chance, the policy ENDs
    /// exactly where P(END) exceeds its threshold, and sure outlooks agree with the truth.
    /// With END drawn instead, some ENDs fall below the threshold.
    #[test]
    fn every_turn_start_is_a_chance_and_the_end_rule_is_the_policys() {
        let mut policy = crate::pretrained::load("pretrained:cpu-op/0").unwrap();
        let games = 128;
        let chances = end_chances(&policy, games, 3);
        let threshold = policy.end_threshold().expect("cpu-op decides END") as f64;
        let mut by_game: Vec<Vec<&EndChance>> = vec![Vec::new(); games];
        for c in &chances {
            assert!((0.0..=1.0).contains(&c.p_end));
            assert_eq!(c.ended, c.p_end > threshold, "{c:?}");
            by_game[c.game as usize].push(c);
        }
        let mut ended = 0;
        for (g, cs) in by_game.iter().enumerate() {
            assert!(!cs.is_empty(), "game {g}: the first turn may END");
            for (k, c) in cs.iter().enumerate() {
                assert_eq!(c.step as usize, 4 * k, "game {g}: turns of 4 steps");
                assert!(
                    !c.ended || k + 1 == cs.len(),
                    "game {g}: ENDed, then played on"
                );
            }
            // A game that does not END places its 4th hint at the end of its 8th turn.
            let last = cs.last().unwrap();
            assert!(last.ended || cs.len() == 8, "game {g}: {} turns", cs.len());
            ended += last.ended as usize;
        }
        assert!(ended > games / 2, "cpu-op ENDs most games: {ended}");
        let s = EndSummary::of(&chances, games, true);
        assert_eq!(
            s.rows.iter().map(|r| r.chances).sum::<usize>(),
            chances.len()
        );
        assert_eq!(s.games_ended, ended as f64 / games as f64);
        let sure = &s.rows[BINS - 1];
        assert!(sure.chances == 0 || sure.won == 1.0);
        assert_eq!(s.rows[0].won, 0.0);

        policy.set_end_threshold(None).unwrap();
        let drawn = end_chances(&policy, games, 3);
        assert!(
            drawn.iter().any(|c| c.ended && c.p_end <= threshold),
            "a drawn END below the threshold"
        );
    }
}

//! Linear probes of card colours in a trained policy's recurrent state (the paper's
//! appendix "probing" figure): how well a linear read-out of the memory names each card's
//! colour, step by step through a game, in self-play and with other partners, for all cards
//! and for the cards the seat has not seen itself.
//!
//! - [`record`] plays games with trained networks in the seats and keeps, for the seats asked
//!   for, the memory after every step with the true colours and what the seat has seen.
//! - [`LinearProbe`] (one per card id) is fitted on the memories of some episodes and
//!   [`evaluate`]d on others, against chance and the *perfect-memory oracle*: a reader that
//!   knows every colour the seat saw and, for the others, names the colour with the most
//!   cards left (what first-hand memory and the counts allow without any inference from
//!   partners).
//! - [`study::Study`] is what `yokai probe` runs: those steps for runs and partners.

mod logistic;
pub mod study;

pub use logistic::LinearProbe;

use crate::distribution::sample_legal;
use crate::TrainedPolicy;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{derive_seed, Card, CardSet, Config, Game, Seat};

/// Memories recorded in games, one row per (episode, step, recorded seat).
#[derive(Clone, Debug, Default)]
pub struct Records {
    pub hidden: usize,
    /// `[rows × hidden]`: the seat's memory after reading the state.
    pub states: Vec<f32>,
    /// `[rows × Y]`: every card's true colour.
    pub colours: Vec<u8>,
    /// Per row: the cards the seat has observed itself.
    pub seen: Vec<CardSet>,
    /// Per row: the game step (0 = the first state) and the episode index.
    pub steps: Vec<u16>,
    pub episodes: Vec<u32>,
}

impl Records {
    pub fn len(&self) -> usize {
        self.steps.len()
    }
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }
    /// Add `other`'s rows after these (both recorded with the same memory width).
    pub fn append(&mut self, other: Records) {
        assert_eq!(self.hidden, other.hidden, "records of one memory width");
        self.states.extend(other.states);
        self.colours.extend(other.colours);
        self.seen.extend(other.seen);
        self.steps.extend(other.steps);
        self.episodes.extend(other.episodes);
    }
}

/// Play `games` games of `game` with `seats[s]` in seat s (batches of up to 64 games, actions
/// sampled from each network's policy), recording the seats `recorded[s]`. Deals and
/// actions are a function of `seed`.
pub fn record(
    game: &Config,
    seats: &[&TrainedPolicy],
    recorded: &[bool],
    games: usize,
    seed: u64,
) -> Records {
    let (p, y) = (game.players(), game.cards());
    assert_eq!(seats.len(), p, "one policy per seat");
    // The recorded seats' memory width (the partners' may differ).
    let widths: Vec<usize> = seats
        .iter()
        .zip(recorded)
        .filter(|(_, &r)| r)
        .map(|(policy, _)| policy.hidden_size())
        .collect();
    assert!(
        widths.windows(2).all(|w| w[0] == w[1]),
        "the recorded seats share one memory width"
    );
    let hidden = widths.first().copied().unwrap_or(0);
    let mut out = Records {
        hidden,
        ..Records::default()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(seed, 0x9B0));
    for first in (0..games).step_by(64) {
        let batch = (games - first).min(64);
        let mut live: Vec<Game> = (0..batch)
            .map(|g| Game::new(*game, derive_seed(seed, (first + g) as u64)))
            .collect();
        let mut states: Vec<Vec<f32>> = (0..p)
            .map(|s| vec![0f32; batch * seats[s].hidden_size()])
            .collect();
        let mut step = 0u16;
        while live.iter().any(|g| !g.is_over()) {
            let open: Vec<usize> = (0..batch).filter(|&g| !live[g].is_over()).collect();
            let mut steps = Vec::with_capacity(p);
            for (s, policy) in seats.iter().enumerate() {
                let h = policy.hidden_size();
                let rows: Vec<(&Game, Seat)> =
                    open.iter().map(|&g| (&live[g], Seat(s as u8))).collect();
                let rows_h = open
                    .iter()
                    .flat_map(|&g| states[s][g * h..][..h].iter().copied())
                    .collect();
                let keep = vec![(step > 0) as u8 as f32; open.len()];
                let stepped = policy.step_seats(&rows, rows_h, keep);
                let new = &stepped.states;
                for (k, &g) in open.iter().enumerate() {
                    states[s][g * h..][..h].copy_from_slice(&new[k * h..][..h]);
                    if recorded[s] {
                        let game = &live[g];
                        out.states.extend_from_slice(&new[k * h..][..h]);
                        out.colours
                            .extend((0..y).map(|c| game.colour_of(Card(c as u8)).0));
                        out.seen.push(game.ever_observed(Seat(s as u8)));
                        out.steps.push(step);
                        out.episodes.push((first + g) as u32);
                    }
                }
                steps.push(stepped);
            }
            for (k, &g) in open.iter().enumerate() {
                let actor = live[g].current_seat();
                let lg = steps[actor.index()]
                    .logits(k)
                    .expect("the acting seat's logits");
                let a = sample_legal(&live[g], lg, &mut rng);
                live[g]
                    .apply_index(a)
                    .expect("sampled among the legal actions");
            }
            step += 1;
        }
    }
    out
}

/// One probe per card id, fitted on the rows of `records` whose episode `train` accepts.
pub fn fit(game: &Config, records: &Records, train: impl Fn(u32) -> bool) -> Vec<LinearProbe> {
    let (y, h) = (game.cards(), records.hidden);
    let rows: Vec<usize> = (0..records.len())
        .filter(|&r| train(records.episodes[r]))
        .collect();
    let x: Vec<f32> = rows
        .iter()
        .flat_map(|&r| records.states[r * h..][..h].iter().copied())
        .collect();
    (0..y)
        .map(|k| {
            let labels: Vec<u8> = rows.iter().map(|&r| records.colours[r * y + k]).collect();
            LinearProbe::fit(&x, &labels, h, game.colours())
        })
        .collect()
}

/// Accuracy at one game step, over the cards of the rows at that step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepAccuracy {
    pub step: usize,
    /// Share of all cards whose colour the probe names right, and the oracle's share.
    pub all: f64,
    pub oracle_all: f64,
    /// The same over the cards the seat has not seen itself (`None` if it has seen all).
    pub unseen: Option<f64>,
    pub oracle_unseen: Option<f64>,
    /// Rows (seat states) at this step.
    pub rows: usize,
}

/// The perfect-memory oracle's guess for card `k`: its colour where seen, else the colour
/// with the most cards not seen (the lowest such colour on a tie).
fn oracle(game: &Config, colours: &[u8], seen: CardSet, k: usize) -> u8 {
    if seen.contains(Card(k as u8)) {
        return colours[k];
    }
    let mut left = vec![game.cards_per_colour(); game.colours()];
    for card in seen.iter() {
        left[colours[card.index()] as usize] -= 1;
    }
    let best = (0..left.len()).max_by_key(|&c| (left[c], usize::MAX - c));
    best.unwrap_or(0) as u8
}

/// Accuracy per game step of `probes` on the rows of `records` whose episode `test`
/// accepts (steps with fewer than `min_rows` rows are left out: too few to say).
pub fn evaluate(
    game: &Config,
    probes: &[LinearProbe],
    records: &Records,
    test: impl Fn(u32) -> bool,
    min_rows: usize,
) -> Vec<StepAccuracy> {
    let (y, h) = (game.cards(), records.hidden);
    let longest = records.steps.iter().copied().max().unwrap_or(0) as usize;
    // Per step: [all hits, all oracle, all n, unseen hits, unseen oracle, unseen n, rows].
    let mut sums = vec![[0usize; 7]; longest + 1];
    for r in (0..records.len()).filter(|&r| test(records.episodes[r])) {
        let state = &records.states[r * h..][..h];
        let colours = &records.colours[r * y..][..y];
        let seen = records.seen[r];
        let s = &mut sums[records.steps[r] as usize];
        s[6] += 1;
        for (k, probe) in probes.iter().enumerate() {
            let hit = (probe.predict(state) == colours[k]) as usize;
            let sure = (oracle(game, colours, seen, k) == colours[k]) as usize;
            s[0] += hit;
            s[1] += sure;
            s[2] += 1;
            if !seen.contains(Card(k as u8)) {
                s[3] += hit;
                s[4] += sure;
                s[5] += 1;
            }
        }
    }
    sums.iter()
        .enumerate()
        .filter(|(_, s)| s[6] >= min_rows.max(1))
        .map(|(step, s)| {
            let share = |a: usize, n: usize| (n > 0).then(|| a as f64 / n as f64);
            StepAccuracy {
                step,
                all: s[0] as f64 / s[2] as f64,
                oracle_all: s[1] as f64 / s[2] as f64,
                unseen: share(s[3], s[5]),
                oracle_unseen: share(s[4], s[5]),
                rows: s[6],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cross-play records the probed seat's memory at its own width, whatever its partner's:
    /// a partner with a narrower memory in seat 0, the probed network in seat 1.
    #[test]
    fn records_hold_the_recorded_seats_memories() {
        use crate::{MlpEncoder, TrainConfig, Trainer};
        let tmp = tempfile::tempdir().unwrap();
        let policy = |hidden: usize| {
            let mut c = TrainConfig::from_toml_str(
                "[network]\npreset = \"compact\"\n[ppo]\nnum_envs = 4\nrollout_steps = 4\n\
                 minibatches = 1\n[run]\nthreads = 1\n",
                "test",
            )
            .unwrap();
            c.network.hidden = hidden;
            let t = Trainer::<MlpEncoder>::new(c, 1).unwrap();
            let path = tmp.path().join(format!("h{hidden}.ykp"));
            t.policy().write_atomic(&path).unwrap();
            TrainedPolicy::load(&path).unwrap()
        };
        let (narrow, wide) = (policy(8), policy(16));
        let game = *wide.game();
        let r = record(&game, &[&narrow, &wide], &[false, true], 3, 0);
        assert_eq!(r.hidden, 16);
        assert!(!r.is_empty());
        assert_eq!(r.states.len(), r.len() * 16);
        assert_eq!(r.colours.len(), r.len() * game.cards());
        let y = game.cards();
        // Rows come step by step, the games of a batch side by side: each episode's rows
        // count its steps from 0, one by one.
        let mut next_step = std::collections::HashMap::new();
        for i in 0..r.len() {
            let episode = r.episodes[i];
            let deal = Game::new(game, derive_seed(0, episode as u64));
            let colours: Vec<u8> = deal.deal().card_colours.iter().map(|c| c.0).collect();
            assert_eq!(&r.colours[i * y..][..y], &colours[..], "row {i}");
            let step = next_step.entry(episode).or_insert(0u16);
            assert_eq!(r.steps[i], *step, "row {i}");
            *step += 1;
            // At the first state nothing is seen, and the memory is the wide network's
            // first step from zero on seat 1's view of the deal.
            if r.steps[i] == 0 {
                assert!(r.seen[i].is_empty(), "row {i}");
                let want = wide.step_seats(&[(&deal, Seat(1))], vec![0.0; 16], vec![0.0]);
                assert_eq!(&r.states[i * 16..][..16], &want.states[..], "row {i}");
            }
        }
        assert_eq!(r.steps.iter().filter(|&&s| s == 0).count(), 3, "3 games");
    }

    /// The oracle knows seen cards and otherwise names the colour with most cards left.
    #[test]
    fn the_oracle_reads_first_hand_colours_and_the_counts() {
        let game = Config::from_name("9c-2p").unwrap();
        let colours = [0, 0, 0, 1, 1, 1, 2, 2, 2];
        // Seen: cards 0, 1 (colour 0) and 3 (colour 1): left 1, 2, 3 → colour 2 for the rest.
        let seen = CardSet::from_iter([Card(0), Card(1), Card(3)]);
        assert_eq!(oracle(&game, &colours, seen, 0), 0);
        assert_eq!(oracle(&game, &colours, seen, 3), 1);
        for k in [2, 4, 5, 6, 7, 8] {
            assert_eq!(oracle(&game, &colours, seen, k), 2, "card {k}");
        }
        // Nothing seen: a tie, the lowest colour.
        assert_eq!(oracle(&game, &colours, CardSet::EMPTY, 5), 0);
    }

    /// With memories that hold every colour linearly (a one-hot per card), the probes read
    /// every card at every step, seen or not; with memories of noise they read chance.
    #[test]
    fn probes_read_a_linear_code_and_not_noise() {
        let game = Config::from_name("9c-2p").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut noise = move || crate::distribution::unit_draw(&mut rng) as f32;
        for signal in [true, false] {
            let mut r = Records {
                hidden: 27,
                ..Records::default()
            };
            for episode in 0..300u32 {
                let deal = Game::new(game, episode as u64).deal().card_colours;
                for step in 0..4u16 {
                    for (k, c) in deal.iter().enumerate() {
                        for colour in 0..3 {
                            let code = (signal && c.0 == colour) as u8 as f32;
                            r.states.push(code + 0.1 * noise());
                        }
                        r.colours.push(deal[k].0);
                    }
                    r.seen.push(CardSet::from(Card(0)));
                    r.steps.push(step);
                    r.episodes.push(episode);
                }
            }
            let probes = fit(&game, &r, |e| e % 5 != 0);
            let acc = evaluate(&game, &probes, &r, |e| e % 5 == 0, 1);
            assert_eq!(acc.len(), 4);
            for a in &acc {
                let unseen = a.unseen.unwrap();
                if signal {
                    assert!(a.all > 0.99 && unseen > 0.99, "{a:?}");
                } else {
                    assert!((unseen - 1.0 / 3.0).abs() < 0.08, "{a:?}");
                }
                assert_eq!(a.rows, 60);
            }
        }
    }
}

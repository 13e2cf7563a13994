//! Linear probes of card colours in a trained policy's recurrent state (the paper's §5.3
//! "probing" figure): how well a linear read-out of the memory names the colours on the
//! board, step by step through a game, in self-play and with other partners, for all cards
//! and for the cards the seat has not seen itself ("unopened").
//!
//! - [`record`] plays games with trained networks in the seats and keeps, for the seats asked
//!   for, the memory after every step with the true colours, where each card lies and what
//!   the seat has seen.
//! - A [`LinearProbe`] per board position (the paper's probes: the colour of whatever card
//!   lies there) or per card id ([`Target`]) is fitted on the memories of some episodes and
//!   [`evaluate`]d on others, against chance and the *perfect-memory oracle*: a reader that
//!   knows every colour the seat saw and, for the others, names the colour with the most
//!   cards left (what first-hand memory and the counts allow without any inference from
//!   partners).
//! - Where the network has a colour layer (the belief head of `ppo.belief_aux`), its own
//!   guess of every card's colour is recorded beside the memory and scored on the same
//!   states: what the head the loss trained reads, which a linear probe of the memory alone
//!   may miss (the head also reads the observation).
//! - [`study::Study`] is what `yokai probe` runs: those steps for runs and partners.
//!
//! [`ending`] probes a different question with the same kind of self-play: where a policy
//! could END, what it did against what its seat knew first-hand (`yokai probe-end`).

pub mod ending;
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
    /// `[rows × Y]`: the board position (cell index, row-major over the g × g grid) each
    /// card lies on. Empty where the records were made without positions (then only
    /// per-card probes can be fitted).
    pub cells: Vec<u8>,
    /// Per row: the cards the seat has observed itself.
    pub seen: Vec<CardSet>,
    /// `[rows × Y]`: the belief head's guess of every card's colour
    /// ([`TrainedPolicy::colour_guesses`]); empty where the recorded network has no colour
    /// layer.
    pub head: Vec<u8>,
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
        self.cells.extend(other.cells);
        self.seen.extend(other.seen);
        self.head.extend(other.head);
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
                let stepped = step_memories(
                    policy,
                    &live,
                    &open,
                    Seat(s as u8),
                    &mut states[s],
                    step == 0,
                );
                let new = &stepped.states;
                if recorded[s] && policy.has_colour_layer() {
                    let rows: Vec<(&Game, Seat)> =
                        open.iter().map(|&g| (&live[g], Seat(s as u8))).collect();
                    let guesses = policy.colour_guesses(&rows, new);
                    out.head
                        .extend(guesses.expect("a network with a colour layer guesses"));
                }
                for (k, &g) in open.iter().enumerate() {
                    if recorded[s] {
                        let game = &live[g];
                        out.states.extend_from_slice(&new[k * h..][..h]);
                        out.colours
                            .extend((0..y).map(|c| game.colour_of(Card(c as u8)).0));
                        let cells = game.config().geometry();
                        out.cells
                            .extend((0..y).map(|c| cells.index(game.cell_of(Card(c as u8))) as u8));
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

/// One step of `seat`'s memory in each game `open` of `live`, with `policy`: `states` holds
/// the memory of every game (`policy.hidden_size()` wide each) and gets the new ones back;
/// `first` starts fresh memories. Returns the step (the new states of the open games in
/// order, and the acting seats' logits).
pub(crate) fn step_memories(
    policy: &TrainedPolicy,
    live: &[Game],
    open: &[usize],
    seat: Seat,
    states: &mut [f32],
    first: bool,
) -> crate::SeatStep {
    let h = policy.hidden_size();
    let rows: Vec<(&Game, Seat)> = open.iter().map(|&g| (&live[g], seat)).collect();
    let rows_h = open
        .iter()
        .flat_map(|&g| states[g * h..][..h].iter().copied())
        .collect();
    let keep = vec![!first as u8 as f32; open.len()];
    let stepped = policy.step_seats(&rows, rows_h, keep);
    for (k, &g) in open.iter().enumerate() {
        states[g * h..][..h].copy_from_slice(&stepped.states[k * h..][..h]);
    }
    stepped
}

/// What each probe names: one card id's colour, wherever it lies, or the colour of the card
/// on one board position (the paper's probes: positions are what a player sees, and cards
/// move between them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    Card,
    Position,
}

/// Why probes cannot be fitted.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ProbeError {
    #[error("probes by board position need the cards' positions, and these records have none")]
    NoPositions,
}

/// Board positions need this many training rows with a card on them to get a probe (the
/// grid's far cells are rarely reached).
pub const MIN_POSITION_ROWS: usize = 50;

/// The fitted probes: `(index, probe)` with the index a card id or a cell index.
#[derive(Clone, Debug)]
pub struct Probes {
    pub target: Target,
    pub probes: Vec<(usize, LinearProbe)>,
}

/// The card probe `index` reads in row `r`: that card, or the card on that cell (none if
/// the cell is empty).
fn card_of(records: &Records, y: usize, target: Target, index: usize, r: usize) -> Option<usize> {
    match target {
        Target::Card => Some(index),
        Target::Position => records.cells[r * y..][..y]
            .iter()
            .position(|&c| c as usize == index),
    }
}

/// Probes fitted on the rows of `records` whose episode `train` accepts: one per card id,
/// or one per board position that holds a card in at least [`MIN_POSITION_ROWS`] of them.
pub fn fit(
    game: &Config,
    records: &Records,
    train: impl Fn(u32) -> bool,
    target: Target,
) -> Result<Probes, ProbeError> {
    let (y, h) = (game.cards(), records.hidden);
    if target == Target::Position && records.cells.len() != records.len() * y {
        return Err(ProbeError::NoPositions);
    }
    let rows: Vec<usize> = (0..records.len())
        .filter(|&r| train(records.episodes[r]))
        .collect();
    let indices = match target {
        Target::Card => y,
        Target::Position => game.geometry().cells(),
    };
    let probes = (0..indices)
        .filter_map(|index| {
            let (mut x, mut labels) = (Vec::new(), Vec::new());
            for &r in &rows {
                if let Some(k) = card_of(records, y, target, index, r) {
                    x.extend_from_slice(&records.states[r * h..][..h]);
                    labels.push(records.colours[r * y + k]);
                }
            }
            let enough = target == Target::Card || labels.len() >= MIN_POSITION_ROWS;
            enough.then(|| (index, LinearProbe::fit(&x, &labels, h, game.colours())))
        })
        .collect();
    Ok(Probes { target, probes })
}

/// Accuracy at one game step, over the cards of the rows at that step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepAccuracy {
    pub step: usize,
    /// Share of all cards (or occupied positions) whose colour the probes name right, and
    /// the oracle's share.
    pub all: f64,
    pub oracle_all: f64,
    /// The same over the cards the seat has not seen itself, "unopened" (`None` if it has
    /// seen all).
    pub unseen: Option<f64>,
    pub oracle_unseen: Option<f64>,
    /// The belief head's share of all cards and of unseen ones (`None` without a colour
    /// layer in the records, or no unseen card).
    pub head: Option<f64>,
    pub head_unseen: Option<f64>,
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
    probes: &Probes,
    records: &Records,
    test: impl Fn(u32) -> bool,
    min_rows: usize,
) -> Vec<StepAccuracy> {
    let (y, h) = (game.cards(), records.hidden);
    let longest = records.steps.iter().copied().max().unwrap_or(0) as usize;
    // Per step: [all hits, all oracle, all n, unseen hits, unseen oracle, unseen n, rows,
    // all head, unseen head].
    let mut sums = vec![[0usize; 9]; longest + 1];
    let with_head = records.head.len() == records.len() * y && !records.is_empty();
    for r in (0..records.len()).filter(|&r| test(records.episodes[r])) {
        let state = &records.states[r * h..][..h];
        let colours = &records.colours[r * y..][..y];
        let seen = records.seen[r];
        let s = &mut sums[records.steps[r] as usize];
        s[6] += 1;
        for (index, probe) in &probes.probes {
            let Some(k) = card_of(records, y, probes.target, *index, r) else {
                continue;
            };
            let hit = (probe.predict(state) == colours[k]) as usize;
            let sure = (oracle(game, colours, seen, k) == colours[k]) as usize;
            let head = with_head && records.head[r * y + k] == colours[k];
            s[0] += hit;
            s[1] += sure;
            s[2] += 1;
            s[7] += head as usize;
            if !seen.contains(Card(k as u8)) {
                s[3] += hit;
                s[4] += sure;
                s[5] += 1;
                s[8] += head as usize;
            }
        }
    }
    sums.iter()
        .enumerate()
        .filter(|(_, s)| s[6] >= min_rows.max(1) && s[2] > 0)
        .map(|(step, s)| {
            let share = |a: usize, n: usize| (n > 0).then(|| a as f64 / n as f64);
            StepAccuracy {
                step,
                all: s[0] as f64 / s[2] as f64,
                oracle_all: s[1] as f64 / s[2] as f64,
                unseen: share(s[3], s[5]),
                oracle_unseen: share(s[4], s[5]),
                head: with_head.then(|| s[7] as f64 / s[2] as f64),
                head_unseen: share(s[8], s[5]).filter(|_| with_head),
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
            let c = TrainConfig::tiny_for_tests(hidden);
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
        assert_eq!(r.cells.len(), r.len() * game.cards());
        assert!(
            r.head.is_empty(),
            "a network without a colour layer guesses nothing"
        );
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
            // Each card's position: where the deal puts it at the first state.
            if r.steps[i] == 0 {
                let at: Vec<u8> = (0..y)
                    .map(|k| game.geometry().index(deal.cell_of(Card(k as u8))) as u8)
                    .collect();
                assert_eq!(&r.cells[i * y..][..y], &at[..], "row {i}");
            }
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
            let probes = fit(&game, &r, |e| e % 5 != 0, Target::Card).unwrap();
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

    /// The belief head's guesses are scored on the same rows as the oracle: a head right
    /// on cards 0–4 and wrong on 5–8, with card 0 seen, reads 5/9 of all cards and 4/8 of
    /// unseen ones; records without guesses have no head share.
    #[test]
    fn the_belief_heads_guesses_are_scored_on_all_and_unseen_cards() {
        let game = Config::from_name("9c-2p").unwrap();
        let mut r = Records {
            hidden: 1,
            ..Records::default()
        };
        for episode in 0..10u32 {
            let deal = Game::new(game, episode as u64).deal().card_colours;
            r.states.push(episode as f32);
            r.colours.extend(deal.iter().map(|c| c.0));
            r.head
                .extend(deal.iter().enumerate().map(|(k, c)| match k < 5 {
                    true => c.0,
                    false => (c.0 + 1) % 3,
                }));
            r.seen.push(CardSet::from(Card(0)));
            r.steps.push(0);
            r.episodes.push(episode);
        }
        let probes = fit(&game, &r, |_| true, Target::Card).unwrap();
        let [a] = evaluate(&game, &probes, &r, |_| true, 1)[..] else {
            panic!("one step")
        };
        assert_eq!(a.head, Some(5.0 / 9.0));
        assert_eq!(a.head_unseen, Some(4.0 / 8.0));
        r.head.clear();
        let [a] = evaluate(&game, &probes, &r, |_| true, 1)[..] else {
            panic!("one step")
        };
        assert_eq!((a.head, a.head_unseen), (None, None));
    }

    /// A network with a colour layer has its guesses recorded row by row beside its
    /// memories: at each game's first state, the guesses recorded are what the network
    /// guesses from that state and the memory recorded with it.
    #[test]
    fn records_hold_the_belief_heads_guesses_of_their_rows() {
        use crate::{MlpEncoder, TrainConfig, Trainer};
        let tmp = tempfile::tempdir().unwrap();
        let c = TrainConfig::from_toml_str(
            "[network]\npreset = \"compact\"\nhead = \"pointer\"\nhidden = 8\n\
             [ppo]\nbelief_aux = 0.5\nnum_envs = 4\nrollout_steps = 4\nminibatches = 1\n\
             [run]\nthreads = 1\n",
            "test",
        )
        .unwrap();
        let path = tmp.path().join("belief.ykp");
        let t = Trainer::<MlpEncoder>::new(c, 1).unwrap();
        t.policy().write_atomic(&path).unwrap();
        let policy = TrainedPolicy::load(&path).unwrap();
        let game = *policy.game();
        let (y, h) = (game.cards(), policy.hidden_size());
        let r = record(&game, &[&policy, &policy], &[true, false], 5, 2);
        assert_eq!(r.head.len(), r.len() * y);
        let mut checked = 0;
        for i in (0..r.len()).filter(|&i| r.steps[i] == 0) {
            let deal = Game::new(game, derive_seed(2, r.episodes[i] as u64));
            let state = &r.states[i * h..][..h];
            let guesses = policy.colour_guesses(&[(&deal, Seat(0))], state).unwrap();
            assert_eq!(&r.head[i * y..][..y], &guesses[..], "row {i}");
            checked += 1;
        }
        assert_eq!(checked, 5);
        // An untrained head's guesses are not all one colour (else the check says little).
        assert!(r.head.iter().any(|&c| c != r.head[0]));
    }

    /// Probes by board position read the colour of whatever card lies there: with memories
    /// that code the colour on each of 9 positions (the cards shuffled over them every
    /// episode), position probes read every occupied position, card probes only chance, and
    /// positions never occupied get no probe. Records without positions refuse them.
    #[test]
    fn position_probes_read_the_board_where_card_probes_cannot() {
        use yokai_engine::Cell;
        let game = Config::from_name("9c-2p").unwrap();
        let g = game.geometry();
        let used: Vec<u8> = (0..9)
            .map(|k| g.index(Cell::new(3 + k / 3, 3 + k % 3)) as u8)
            .collect();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut draw =
            move |n: usize| (crate::distribution::unit_draw(&mut rng) * n as f64) as usize % n;
        let mut r = Records {
            hidden: 27,
            ..Records::default()
        };
        for episode in 0..400u32 {
            let colours = Game::new(game, episode as u64).deal().card_colours;
            // Card k lies on used[place[k]].
            let mut place: Vec<usize> = (0..9).collect();
            for i in (1..9).rev() {
                place.swap(i, draw(i + 1));
            }
            for step in 0..2u16 {
                let mut memory = vec![0f32; 27];
                for k in 0..9 {
                    memory[place[k] * 3 + colours[k].0 as usize] = 1.0;
                }
                r.states.extend(memory);
                r.colours.extend(colours.iter().map(|c| c.0));
                r.cells.extend((0..9).map(|k| used[place[k]]));
                r.seen.push(CardSet::EMPTY);
                r.steps.push(step);
                r.episodes.push(episode);
            }
        }
        let by_position = fit(&game, &r, |e| e % 5 != 0, Target::Position).unwrap();
        let mut indices: Vec<usize> = by_position.probes.iter().map(|(i, _)| *i).collect();
        indices.sort();
        let mut want: Vec<usize> = used.iter().map(|&c| c as usize).collect();
        want.sort();
        assert_eq!(
            indices, want,
            "a probe for each occupied position, none elsewhere"
        );
        for a in evaluate(&game, &by_position, &r, |e| e % 5 == 0, 1) {
            assert!(a.all > 0.99 && a.unseen.unwrap() > 0.99, "{a:?}");
        }
        let by_card = fit(&game, &r, |e| e % 5 != 0, Target::Card).unwrap();
        for a in evaluate(&game, &by_card, &r, |e| e % 5 == 0, 1) {
            assert!(a.all < 0.6, "a card's colour is not where it lies: {a:?}");
        }
        r.cells.clear();
        assert_eq!(
            fit(&game, &r, |_| true, Target::Position).unwrap_err(),
            ProbeError::NoPositions
        );
    }
}

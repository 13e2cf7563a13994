//! `ppo.belief_gain`: a reward for what the team comes to know of the colours. A game's
//! potential is Φ(s) = Σ over its seats and cards of log p(the card's true colour), p the
//! colour layer of `ppo.belief_aux` at the seat's state (its observation and memory); every
//! step that is not an episode's last adds weight × (Φ(s') − Φ(s)) to both seats' reward,
//! the weight falling linearly to 0 over the first `ppo.belief_gain_fraction` of the run.
//!
//! Why: the agents' moves tell their partner the colours only late in a game
//! (docs/results/cpu-belief-head.md), and the game pays for telling only through the END it
//! makes right, tens of steps later. This pays a hint or a move at once for what the seats
//! can infer from it. The sum telescopes over a game, so it shifts a game's return by
//! Φ(last state) − Φ(first) and changes no policy's ranking but through that last term,
//! which rewards ending a game with the colours known; the anneal takes even that away.
//! With `ppo.belief_gain_baseline = "counting"` a seat's share counts only the cards it has
//! not opened, each as log p − log p_counting: what it infers beyond counting, which only
//! its partner's moves can tell it. With `ppo.belief_gain_seats = "waiting"` only what a
//! seat came to know while it waited is paid: its share at the first state of a turn less
//! its share at the last state it acted at, paid at the step that hands it the turn. That
//! is no longer a potential (what a seat learns on its own turn, opening cards, is left
//! out), so it changes which policies are best while its weight lasts. Both ends are states
//! the seat acts at, the only ones the belief loss trains the colour layer on; a share read
//! at a waiting state would add, at every turn, however the layer reads untrained states.
//! With `"centred"` each of those payments is less the rollout's mean over the handovers at
//! the same step of a game, so that the turns a game lasts are not paid in themselves. With
//! `"turn"` the centred payments go to the advantages of the turn that earned them (the
//! choices of the seat whose turn the handover ends, but the turn's first), not to the
//! reward: no value learns them and no earlier step carries them, so the END decision is
//! left to the game's reward; centred in the reward, each state's expected payment for
//! going on is not zero, and the seats learnt to END early to escape it.
//! Its column is the rollout's potentials; it adds to the reward (or, `"turn"`, the
//! advantages), no loss term.
//! On `cpu` at 40M steps neither potential form moved self-play
//! (docs/results/cpu-belief-gain.md): with a critic that keeps up, what lasts of a
//! potential-based payment is its end term. The waiting form did not either at weight 0.5,
//! and at 1.0 paid for more turns (docs/results/cpu-belief-gain-waiting.md).

use crate::actor::Actor;
use crate::config::{GainBaseline, GainSeats, PpoConfig};
use yokai_engine::{Card, Seat, Substep};

#[derive(Clone, Debug)]
pub(in crate::trainer) struct BeliefGain {
    weight: f32,
    fraction: f32,
    baseline: GainBaseline,
    seats: GainSeats,
    /// [`GainSeats::Waiting`]: per row, its share at the last state its seat acted at in
    /// the current game, carried from one rollout to the next (not saved in checkpoints:
    /// a resumed run pays no seat's first turn).
    held: Vec<Option<f32>>,
}

/// One rollout's potentials: per step (the rollout's `T` and the state after its last) and
/// row, the row's seat's share of Φ at the state before that step is taken, and per step
/// and game the seat that acts there.
pub(in crate::trainer) struct Potentials {
    weight: f32,
    baseline: GainBaseline,
    seats: GainSeats,
    games: usize,
    phi: Vec<f32>,
    acting: Vec<u8>,
    /// Per step and game, the steps its game had taken at the state before that step.
    steps: Vec<u16>,
    /// Per step and game, whether the state before that step is a turn's first (its seat
    /// may END there): [`GainSeats::Turn`] credits no such step.
    turn_first: Vec<bool>,
    /// Per step and game (`[T × games]`), the weighted payment [`Potentials::pay`] worked
    /// out (0 where none).
    payments: Vec<f32>,
    /// [`GainSeats::Waiting`]: [`BeliefGain`]'s held shares, at the rollout's start and
    /// then, once paid, at its end.
    held: Vec<Option<f32>>,
    /// Scratch: one row's true colours in its seat's view, and (counting baseline) how
    /// many of its unopened cards each colour has.
    truth: Vec<u8>,
    left: Vec<f32>,
}

impl BeliefGain {
    pub fn from_config(c: &PpoConfig) -> Option<BeliefGain> {
        (c.belief_gain > 0.0).then_some(BeliefGain {
            weight: c.belief_gain,
            fraction: c.belief_gain_fraction,
            baseline: c.belief_gain_baseline,
            seats: c.belief_gain_seats,
            held: Vec::new(),
        })
    }

    /// The weight at `progress` (the share of the run done, in [0, 1]).
    pub fn weight_at(&self, progress: f64) -> f32 {
        self.weight * (1.0 - progress / self.fraction as f64).max(0.0) as f32
    }

    /// Rollout: the column of a rollout of `t_len` steps at `progress`; `None` once the
    /// weight has annealed to 0 (the colour layer then runs on the choosing rows only).
    pub fn column(&self, progress: f64, t_len: usize, actor: &Actor) -> Option<Potentials> {
        let weight = self.weight_at(progress);
        let games = actor.env().num_envs();
        (weight > 0.0).then(|| Potentials {
            weight,
            baseline: self.baseline,
            seats: self.seats,
            games,
            phi: vec![0.0; (t_len + 1) * actor.rows()],
            acting: vec![0; (t_len + 1) * games],
            steps: vec![0; (t_len + 1) * games],
            turn_first: vec![false; (t_len + 1) * games],
            payments: Vec::new(),
            held: {
                let mut held = self.held.clone();
                held.resize(actor.rows(), None);
                held
            },
            truth: Vec::new(),
            left: Vec::new(),
        })
    }

    /// After a rollout is paid: the shares its seats held at its end.
    pub fn keep(&mut self, paid: &Potentials) {
        self.held.clone_from(&paid.held);
    }

    /// Per row, the share held from the last state its seat acted at (empty before the
    /// first rollout).
    #[cfg(test)]
    pub fn held(&self) -> &[Option<f32>] {
        &self.held
    }
}

impl Potentials {
    /// Rollout: the potentials of the states at step `t` (`0..=T`), from every row's colour
    /// log-probabilities `[rows × Y × C]` (as [`crate::network::Acted`] gives them) and
    /// the true colours each row's seat would name.
    pub fn record(&mut self, t: usize, log_probs: &[f32], actor: &Actor) {
        let (rows, y) = (actor.rows(), actor.game(0).config().cards());
        let c = log_probs.len() / (rows * y);
        let p = rows / self.games;
        self.truth.resize(y, 0);
        for r in 0..rows {
            actor.view_truth(r, &mut self.truth);
            let row = &log_probs[r * y * c..][..y * c];
            let head = |k: usize| row[k * c + self.truth[k] as usize];
            let phi: f32 = match self.baseline {
                GainBaseline::None => (0..y).map(head).sum(),
                GainBaseline::Counting => {
                    let opened = actor.game(r / p).known_cards(Seat((r % p) as u8));
                    let unopened = || (0..y).filter(|&k| !opened.contains(Card(k as u8)));
                    // Σ over unopened cards of log p − log(left[colour] / n) is Σ log p −
                    // Σ over colours of left · log(left / n).
                    self.left.clear();
                    self.left.resize(c, 0.0);
                    for k in unopened() {
                        self.left[self.truth[k] as usize] += 1.0;
                    }
                    let n: f32 = self.left.iter().sum();
                    let counting: f32 = (self.left.iter().filter(|&&x| x > 0.0))
                        .map(|&x| x * (x / n).ln())
                        .sum();
                    unopened().map(head).sum::<f32>() - counting
                }
            };
            self.phi[t * rows + r] = phi;
        }
        let acting = actor.env().acting_seats();
        self.acting[t * self.games..][..self.games].copy_from_slice(acting);
        for i in 0..self.games {
            let game = actor.game(i);
            self.steps[t * self.games + i] = game.steps().min(u16::MAX as usize) as u16;
            self.turn_first[t * self.games + i] = game.substep() == Substep::FirstObserve;
        }
    }

    /// The potential recorded for game `i` at step `t` (the sum of its seats' shares).
    #[cfg(test)]
    pub fn at(&self, t: usize, i: usize) -> f32 {
        let p = self.phi.len() / self.acting.len();
        self.phi[(t * self.games + i) * p..][..p].iter().sum()
    }

    /// The seat acting in game `i` at step `t`.
    #[cfg(test)]
    pub fn acting_at(&self, t: usize, i: usize) -> u8 {
        self.acting[t * self.games + i]
    }

    /// Row `r`'s share recorded at step `t`.
    #[cfg(test)]
    pub fn share_at(&self, t: usize, r: usize) -> f32 {
        let rows = self.phi.len() / (self.rollout_steps() + 1);
        self.phi[t * rows + r]
    }

    /// The rollout's steps T: every column holds the states before each step and the one
    /// after the last, T + 1 per game.
    fn rollout_steps(&self) -> usize {
        self.acting.len() / self.games - 1
    }

    /// Value targets: adds each step's weighted gain to both rows of its game in `rewards`
    /// (`[T × rows]`), but at the step that ends a game (`dones`, same shape), whose next
    /// state is a new game's. A step's gain is the change of its game's potential, or with
    /// [`GainSeats::Waiting`] what the seat it hands the turn to came to know since it last
    /// acted, or with [`GainSeats::Centred`] that less the rollout's mean over the
    /// handovers at the same step of a game. With [`GainSeats::Turn`] (the centred gains)
    /// nothing is added here: [`Potentials::credit`] adds them to the advantages. Returns
    /// the gain before the weight and before centring, summed over steps and games (nats).
    pub fn pay(&mut self, rewards: &mut [f32], dones: &[f32]) -> f64 {
        let t_len = self.rollout_steps();
        let rows = self.phi.len() / (t_len + 1);
        let p = rows / self.games;
        // Per step and game, the gain its step pays (`None`: nothing to pay).
        let mut gains = vec![None; t_len * self.games];
        for t in 0..t_len {
            for i in 0..self.games {
                let row = |t: usize, s: usize| t * rows + i * p + s;
                let acting = self.acting[t * self.games + i] as usize;
                self.held[i * p + acting] = Some(self.phi[row(t, acting)]);
                if dones[row(t, 0)] > 0.5 {
                    self.held[i * p..][..p].fill(None);
                    continue;
                }
                gains[t * self.games + i] = match self.seats {
                    GainSeats::All => Some(
                        (0..p)
                            .map(|s| self.phi[row(t + 1, s)] - self.phi[row(t, s)])
                            .sum(),
                    ),
                    GainSeats::Waiting | GainSeats::Centred | GainSeats::Turn => {
                        let next = self.acting[(t + 1) * self.games + i] as usize;
                        self.held[i * p + next]
                            .filter(|_| next != acting)
                            .map(|held| self.phi[row(t + 1, next)] - held)
                    }
                };
            }
        }
        let paid: f64 = gains.iter().flatten().map(|&g| g as f64).sum();
        // Centred: per step of a game at the turn's first state, the handovers' mean gain.
        let step_after = |k: usize| self.steps[k + self.games] as usize;
        let mut means = Vec::<(f64, u32)>::new();
        if matches!(self.seats, GainSeats::Centred | GainSeats::Turn) {
            for (k, gain) in gains.iter().enumerate() {
                if let Some(gain) = gain {
                    if means.len() <= step_after(k) {
                        means.resize(step_after(k) + 1, (0.0, 0));
                    }
                    means[step_after(k)].0 += *gain as f64;
                    means[step_after(k)].1 += 1;
                }
            }
        }
        self.payments = (gains.iter().enumerate())
            .map(|(k, gain)| {
                let mean = (means.get(step_after(k))).map_or(0.0, |&(sum, n)| sum / n as f64);
                gain.map_or(0.0, |g| self.weight * (g - mean as f32))
            })
            .collect();
        if self.seats != GainSeats::Turn {
            for (k, payment) in self.payments.iter().enumerate() {
                let (t, i) = (k / self.games, k % self.games);
                rewards[t * rows + i * p..][..p]
                    .iter_mut()
                    .for_each(|r| *r += payment);
            }
        }
        paid
    }

    /// Advantages (`[T × rows]`, after [`Potentials::pay`]): with [`GainSeats::Turn`], adds
    /// each handover's weighted, centred gain to the advantages of the steps of the turn it
    /// ends, on the row of the seat that chose there, within the rollout and but the turn's
    /// first (where END is chosen). Other forms add nothing.
    pub fn credit(&self, adv: &mut [f32]) {
        if self.seats != GainSeats::Turn {
            return;
        }
        let p = adv.len() / (self.rollout_steps() * self.games);
        for (k, &payment) in self.payments.iter().enumerate() {
            if payment == 0.0 {
                continue;
            }
            let (t, i, acting) = (k / self.games, k % self.games, self.acting[k]);
            for u in (0..=t).rev() {
                let here = u * self.games + i;
                if self.acting[here] != acting || self.turn_first[here] {
                    break;
                }
                adv[u * self.games * p + i * p + acting as usize] += payment;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::MlpEncoder;
    use crate::trainer::Trainer;

    fn unit(seats: GainSeats) -> BeliefGain {
        BeliefGain {
            weight: 0.5,
            fraction: 1.0,
            baseline: GainBaseline::None,
            seats,
            held: Vec::new(),
        }
    }

    /// Hand-made potentials of `games` games of two seats: per step and row (`phi`,
    /// `[(T + 1) × rows]`) and the acting seats (`[(T + 1) × games]`), with `held` carried in.
    fn potentials(gain: &BeliefGain, games: usize, phi: &[f32], acting: &[u8]) -> Potentials {
        Potentials {
            weight: gain.weight,
            baseline: gain.baseline,
            seats: gain.seats,
            games,
            phi: phi.to_vec(),
            acting: acting.to_vec(),
            steps: (0..acting.len()).map(|k| (k / games) as u16).collect(),
            turn_first: vec![false; acting.len()],
            payments: Vec::new(),
            held: if gain.held.is_empty() {
                vec![None; 2 * games]
            } else {
                gain.held.clone()
            },
            truth: Vec::new(),
            left: Vec::new(),
        }
    }

    /// Two steps of two games. Game 0: seat 0 acts and gains 1 nat while seat 1 gains 2,
    /// then seat 1 acts and gains 3 while seat 0 loses 1. Game 1: seat 1 acts, seat 0 gains 4
    /// and seat 1 loses 5, then the game ends (its next potentials, a new deal's, are not
    /// paid).
    #[test]
    fn pays_each_step_its_weighted_gain_but_the_last_of_a_game() {
        #[rustfmt::skip]
        let phi = [
            -5.0, -6.0, -9.0, -4.0,
            -4.0, -4.0, -5.0, -9.0,
            -5.0, -1.0, -2.0, -2.0,
        ];
        let mut tally = potentials(&unit(GainSeats::All), 2, &phi, &[0, 1, 1, 0, 0, 0]);
        let mut rewards = vec![0.0; 8];
        let dones = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0];
        let paid = tally.pay(&mut rewards, &dones);
        assert_eq!(rewards, [1.5, 1.5, -0.5, -0.5, 1.0, 1.0, 0.0, 0.0]);
        assert_eq!(paid, 3.0 - 1.0 + 2.0);
        assert_eq!(tally.at(1, 0), -8.0);
    }

    /// With the waiting seats only, the step that hands a seat the turn pays its share at
    /// the turn's first state less its share at the last state it acted at, carried over a
    /// rollout's end and forgotten at a game's. One game: seat 0 acts at steps 0–1 (its
    /// share −9, −7), seat 1 at 2–3 (−5, −4), seat 0 again at 4 (−3): step 3 pays −3 − (−7).
    /// The next rollout (a new network's shares): seat 0 acts at step 0, seat 1 at step 1
    /// with −3 against the −4 it held, and the game ends at step 1.
    #[test]
    fn the_waiting_form_pays_what_a_seat_came_to_know_between_its_turns() {
        let mut gain = unit(GainSeats::Waiting);
        #[rustfmt::skip]
        let phi = [
            -9.0, -8.0,
            -7.0, -8.0,
            -6.0, -5.0,
            -6.0, -4.0,
            -3.0, -2.0,
        ];
        let mut tally = potentials(&gain, 1, &phi, &[0, 0, 1, 1, 0]);
        let mut rewards = vec![0.0; 8];
        let paid = tally.pay(&mut rewards, &[0.0; 8]);
        assert_eq!(rewards, [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 2.0]);
        assert_eq!(paid, 4.0);
        gain.keep(&tally);
        assert_eq!(gain.held, [Some(-7.0), Some(-4.0)]);

        let mut tally = potentials(&gain, 1, &[-1.0, -1.0, -1.0, -3.0, 0.0, 0.0], &[0, 1, 1]);
        let mut rewards = vec![0.0; 4];
        let paid = tally.pay(&mut rewards, &[0.0, 0.0, 1.0, 1.0]);
        assert_eq!(rewards, [0.5, 0.5, 0.0, 0.0]);
        assert_eq!(paid, 1.0);
        gain.keep(&tally);
        assert_eq!(gain.held, [None, None]);
    }

    /// The centred form pays each handover its waiting gain less the mean over the
    /// rollout's handovers at the same step of a game. Two games, their seats taking turns
    /// at every step: steps 1–3 hand seats the turn with gains 3, 1, 2 in game 0 and 1, 1, 4
    /// in game 1 (step 0 hands seat 1 its first turn: nothing held), so the means per step
    /// are 2, 1, 3 (one mean over all six, 2, would pay step 2 too).
    #[test]
    fn the_centred_form_pays_each_handover_its_gain_less_the_mean_at_its_step() {
        #[rustfmt::skip]
        let phi = [
            -9.0, -8.0, -9.0, -8.0,
            -9.0, -8.0, -9.0, -8.0,
            -6.0, -8.0, -8.0, -8.0,
            -6.0, -7.0, -8.0, -7.0,
            -4.0, -7.0, -4.0, -7.0,
        ];
        let acting = [0, 0, 1, 1, 0, 0, 1, 1, 0, 0];
        let pay = |seats| {
            let mut tally = potentials(&unit(seats), 2, &phi, &acting);
            let mut rewards = vec![0.0; 16];
            let paid = tally.pay(&mut rewards, &[0.0; 16]);
            (rewards, paid)
        };
        #[rustfmt::skip]
        let waiting = [
            0.0, 0.0, 0.0, 0.0,
            1.5, 1.5, 0.5, 0.5,
            0.5, 0.5, 0.5, 0.5,
            1.0, 1.0, 2.0, 2.0,
        ];
        assert_eq!(pay(GainSeats::Waiting), (waiting.to_vec(), 12.0));
        #[rustfmt::skip]
        let centred = [
            0.0, 0.0, 0.0, 0.0,
            0.5, 0.5, -0.5, -0.5,
            0.0, 0.0, 0.0, 0.0,
            -0.5, -0.5, 0.5, 0.5,
        ];
        assert_eq!(pay(GainSeats::Centred), (centred.to_vec(), 12.0));
    }

    /// The turn form credits each handover's centred gain to the advantages of the turn
    /// that earned it, on the chooser's row, but the turn's first step; the reward is left
    /// alone. Two games: seat 0's turn (steps 0–2) tells seat 1 3 nats in game 0 and 1 in
    /// game 1 (mean 2), seat 1's turn (steps 3–4) tells seat 0 2 nats in both (mean 2).
    #[test]
    fn the_turn_form_credits_the_turn_that_told_in_its_advantages() {
        #[rustfmt::skip]
        let phi = [
            -9.0, -8.0, -9.0, -8.0,
            -9.0, -8.0, -9.0, -8.0,
            -9.0, -8.0, -9.0, -8.0,
            -9.0, -5.0, -9.0, -7.0,
            -9.0, -5.0, -9.0, -7.0,
            -7.0, -5.0, -7.0, -7.0,
        ];
        let acting = [0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 0, 0];
        let run = |seats| {
            let mut gain = unit(seats);
            gain.held = vec![Some(-9.0), Some(-8.0), Some(-9.0), Some(-8.0)];
            let mut tally = potentials(&gain, 2, &phi, &acting);
            for t in [0, 3, 5] {
                tally.turn_first[t * 2..][..2].fill(true);
            }
            let mut rewards = vec![0.0; 20];
            let paid = tally.pay(&mut rewards, &[0.0; 20]);
            let mut adv = vec![0.0; 20];
            tally.credit(&mut adv);
            (rewards, adv, paid)
        };
        let (rewards, adv, paid) = run(GainSeats::Turn);
        assert_eq!(paid, 8.0);
        assert_eq!(rewards, [0.0; 20]);
        #[rustfmt::skip]
        let credited = [
            0.0, 0.0, 0.0, 0.0,
            0.5, 0.0, -0.5, 0.0,
            0.5, 0.0, -0.5, 0.0,
            0.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 0.0,
        ];
        assert_eq!(adv, credited);
        let (rewards, adv, paid) = run(GainSeats::Centred);
        assert_eq!(paid, 8.0);
        assert_eq!(&rewards[8..12], [0.5, 0.5, -0.5, -0.5]);
        assert_eq!(adv, [0.0; 20]);
    }

    /// A fresh Other-Play trainer of 3 games (6 rows), each seat naming colours its own way.
    fn other_play_trainer(rollout_steps: usize, seed: u64) -> Trainer<MlpEncoder> {
        let config = crate::TrainConfig::from_toml_str(
            &format!(
                "[algorithm]\nname = \"op\"\nsymmetries = \"both\"\n\
                 [network]\npreset = \"compact\"\nhidden = 8\n\
                 [ppo]\nnum_envs = 3\nrollout_steps = {rollout_steps}\nminibatches = 1\n\
                 [run]\nthreads = 1\n"
            ),
            "test",
        )
        .unwrap();
        Trainer::new(config, seed).unwrap()
    }

    /// Colour log-probabilities `[rows × 9 × 3]` in which row r gives −(r + 1) to each
    /// card's true colour (as the row's seat names it) and −50 to every other.
    fn true_colours_at_minus_row(actor: &Actor) -> Vec<f32> {
        let log_prob = |(i, &hot): (usize, &f32)| {
            if hot > 0.5 {
                -((i / 27) as f32 + 1.0)
            } else {
                -50.0
            }
        };
        actor
            .colour_one_hots()
            .iter()
            .enumerate()
            .map(log_prob)
            .collect()
    }

    /// Each game's potential sums its seats' rows, each row's log-probability of every
    /// card's true colour as the row's seat names colours (Other-Play relabels them per
    /// seat): row r gives −(r + 1) to each true colour and −50 to every other.
    #[test]
    fn a_games_potential_sums_its_seats_log_probabilities_of_the_true_colours() {
        let trainer = other_play_trainer(2, 1);
        let actor = trainer.actor();
        assert_eq!(actor.rows(), 6);
        let log_probs = true_colours_at_minus_row(actor);
        let unit = BeliefGain {
            weight: 1.0,
            fraction: 1.0,
            baseline: GainBaseline::None,
            seats: GainSeats::All,
            held: Vec::new(),
        };
        let mut tally = unit.column(0.0, 2, actor).unwrap();
        tally.record(1, &log_probs, actor);
        let y = 9.0;
        let at_1: Vec<f32> = (0..3).map(|i| tally.at(1, i)).collect();
        assert_eq!(at_1, [-3.0 * y, -7.0 * y, -11.0 * y]);
        assert_eq!(&tally.acting[3..6], actor.env().acting_seats());
        assert!((0..3).all(|i| tally.at(0, i) == 0.0 && tally.at(2, i) == 0.0));
    }

    /// With the counting baseline a seat's share counts its unopened cards only, each as
    /// log p − log(share of its colour among them): with log p = −(r + 1) on every true
    /// colour, row r gives n·(H − (r + 1)), n its unopened cards and H the entropy of their
    /// colours' shares (the same in every seat's colour names), after a rollout in which
    /// seats have opened cards.
    #[test]
    fn the_counting_baseline_counts_what_the_seat_infers_of_its_unopened_cards() {
        let mut trainer = other_play_trainer(5, 2);
        trainer.update().unwrap();
        let actor = trainer.actor();
        let y = 9;
        let log_probs = true_colours_at_minus_row(actor);
        let unit = BeliefGain {
            weight: 1.0,
            fraction: 1.0,
            baseline: GainBaseline::Counting,
            seats: GainSeats::All,
            held: Vec::new(),
        };
        let mut tally = unit.column(0.0, 5, actor).unwrap();
        tally.record(0, &log_probs, actor);
        let mut opened_any = false;
        for i in 0..3 {
            let phi = tally.at(0, i);
            let game = actor.game(i);
            let expected: f64 = (0..2)
                .map(|s| {
                    let opened = game.known_cards(Seat(s as u8));
                    opened_any |= !opened.is_empty();
                    let mut left = [0f64; 3];
                    for k in (0..y).filter(|&k| !opened.contains(Card(k as u8))) {
                        left[game.colour_of(Card(k as u8)).0 as usize] += 1.0;
                    }
                    let n: f64 = left.iter().sum();
                    let h: f64 = (left.iter().filter(|&&x| x > 0.0))
                        .map(|&x| -(x / n) * (x / n).ln())
                        .sum();
                    n * (h - (i * 2 + s + 1) as f64)
                })
                .sum();
            assert!(
                (phi as f64 - expected).abs() < 1e-4,
                "game {i}: {phi} against {expected}"
            );
        }
        assert!(opened_any, "the rollout opened cards");
    }

    #[test]
    fn the_weight_falls_to_zero_over_its_share_of_the_run() {
        let unit = BeliefGain {
            weight: 0.2,
            fraction: 0.5,
            baseline: GainBaseline::None,
            seats: GainSeats::All,
            held: Vec::new(),
        };
        assert_eq!(unit.weight_at(0.0), 0.2);
        assert!((unit.weight_at(0.25) - 0.1).abs() < 1e-7);
        assert_eq!(unit.weight_at(0.5), 0.0);
        assert_eq!(unit.weight_at(0.9), 0.0);
    }
}

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
//! its partner's moves can tell it.
//! Its column is the rollout's potentials; it adds to the reward only, no loss term.
//! On `cpu` at 40M steps neither form moved self-play (docs/results/cpu-belief-gain.md):
//! with a critic that keeps up, what lasts of a potential-based payment is its end term.

use crate::actor::Actor;
use crate::config::{GainBaseline, PpoConfig};
use yokai_engine::{Card, Seat};

#[derive(Clone, Debug)]
pub(in crate::trainer) struct BeliefGain {
    weight: f32,
    fraction: f32,
    baseline: GainBaseline,
}

/// One rollout's potentials: per step (the rollout's `T` and the state after its last) and
/// game, Φ of the game's state before that step is taken.
pub(in crate::trainer) struct Potentials {
    weight: f32,
    baseline: GainBaseline,
    games: usize,
    phi: Vec<f32>,
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
            games,
            phi: vec![0.0; (t_len + 1) * games],
            truth: Vec::new(),
            left: Vec::new(),
        })
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
            self.phi[t * self.games + r / p] += phi;
        }
    }

    /// The potential recorded for game `i` at step `t`.
    #[cfg(test)]
    pub fn at(&self, t: usize, i: usize) -> f32 {
        self.phi[t * self.games + i]
    }

    /// Value targets: adds each step's weighted gain to both rows of its game in `rewards`
    /// (`[T × rows]`), but at the step that ends a game (`dones`, same shape), whose next
    /// state is a new game's. Returns the gain paid before the weight, summed over steps and
    /// games (nats).
    pub fn pay(&self, rewards: &mut [f32], dones: &[f32]) -> f64 {
        let rows = rewards.len() / (self.phi.len() / self.games - 1);
        let p = rows / self.games;
        let mut paid = 0.0;
        for (t, step) in rewards.chunks_exact_mut(rows).enumerate() {
            for (i, game) in step.chunks_exact_mut(p).enumerate() {
                if dones[t * rows + i * p] > 0.5 {
                    continue;
                }
                let gain = self.phi[(t + 1) * self.games + i] - self.phi[t * self.games + i];
                paid += gain as f64;
                for reward in game {
                    *reward += self.weight * gain;
                }
            }
        }
        paid
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::MlpEncoder;
    use crate::trainer::Trainer;

    fn potentials(phi: Vec<f32>, games: usize) -> Potentials {
        Potentials {
            weight: 0.5,
            baseline: GainBaseline::None,
            games,
            phi,
            truth: Vec::new(),
            left: Vec::new(),
        }
    }

    /// Two steps of two games of two seats: game 0 gains 1 nat then 2, game 1 loses 1 nat
    /// then ends (its next potential, a new deal's, is not paid).
    #[test]
    fn pays_each_step_its_weighted_gain_but_the_last_of_a_game() {
        let tally = potentials(vec![-5.0, -4.0, -4.0, -5.0, -2.0, -9.0], 2);
        let mut rewards = vec![0.0; 8];
        let dones = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0];
        let paid = tally.pay(&mut rewards, &dones);
        assert_eq!(rewards, [0.5, 0.5, -0.5, -0.5, 1.0, 1.0, 0.0, 0.0]);
        assert_eq!(paid, 1.0 - 1.0 + 2.0);
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
        };
        let mut tally = unit.column(0.0, 2, actor).unwrap();
        tally.record(1, &log_probs, actor);
        let y = 9.0;
        assert_eq!(&tally.phi[3..6], [-3.0 * y, -7.0 * y, -11.0 * y]);
        assert!(tally.phi[..3]
            .iter()
            .chain(&tally.phi[6..])
            .all(|&x| x == 0.0));
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
        };
        let mut tally = unit.column(0.0, 5, actor).unwrap();
        tally.record(0, &log_probs, actor);
        let mut opened_any = false;
        for (i, &phi) in tally.phi[..3].iter().enumerate() {
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
        };
        assert_eq!(unit.weight_at(0.0), 0.2);
        assert!((unit.weight_at(0.25) - 0.1).abs() < 1e-7);
        assert_eq!(unit.weight_at(0.5), 0.0);
        assert_eq!(unit.weight_at(0.9), 0.0);
    }
}

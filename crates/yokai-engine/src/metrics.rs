//! Metrics of a set of finished games (RULES §7).

use crate::scoring::Outcome;
use serde::{Deserialize, Serialize};

/// Running sums over finished games; merge partial sums from several threads with `merge`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MetricsAccumulator {
    pub games: u64,
    pub reward_sum: f64,
    pub reward_sq_sum: f64,
    pub wins: u64,
    pub early_ends: u64,
    pub early_wins: u64,
    pub length_sum: u64,
    pub correct_sum: u64,
    pub wrong_sum: u64,
}

/// The paper's metrics of a set of games.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    pub games: u64,
    /// Mean terminal reward R (shaping excluded).
    pub reward: f64,
    /// Standard error of the mean reward.
    pub reward_se: f64,
    pub win_rate: f64,
    /// EE: share of games ended early.
    pub early_end: f64,
    /// SEE: share of games ended early and won.
    pub successful_early_end: f64,
    /// WEE: P(win | early end); `None` when no game ended early.
    pub win_given_early_end: Option<f64>,
    /// LEN: mean steps per game.
    pub length: f64,
    pub correct_hints: f64,
    pub wrong_hints: f64,
}

impl MetricsAccumulator {
    pub fn add(&mut self, o: &Outcome) {
        self.games += 1;
        self.reward_sum += o.reward as f64;
        self.reward_sq_sum += (o.reward as f64).powi(2);
        self.wins += o.won as u64;
        self.early_ends += o.early_end as u64;
        self.early_wins += (o.early_end && o.won) as u64;
        self.length_sum += o.length as u64;
        self.correct_sum += o.correct_hints as u64;
        self.wrong_sum += o.wrong_hints as u64;
    }

    pub fn merge(&mut self, other: &MetricsAccumulator) {
        self.games += other.games;
        self.reward_sum += other.reward_sum;
        self.reward_sq_sum += other.reward_sq_sum;
        self.wins += other.wins;
        self.early_ends += other.early_ends;
        self.early_wins += other.early_wins;
        self.length_sum += other.length_sum;
        self.correct_sum += other.correct_sum;
        self.wrong_sum += other.wrong_sum;
    }

    /// The metrics; `None` for an empty set of games.
    pub fn metrics(&self) -> Option<Metrics> {
        if self.games == 0 {
            return None;
        }
        let n = self.games as f64;
        let mean = self.reward_sum / n;
        let var = if self.games > 1 {
            ((self.reward_sq_sum - n * mean * mean) / (n - 1.0)).max(0.0)
        } else {
            0.0
        };
        Some(Metrics {
            games: self.games,
            reward: mean,
            reward_se: (var / n).sqrt(),
            win_rate: self.wins as f64 / n,
            early_end: self.early_ends as f64 / n,
            successful_early_end: self.early_wins as f64 / n,
            win_given_early_end: (self.early_ends > 0)
                .then(|| self.early_wins as f64 / self.early_ends as f64),
            length: self.length_sum as f64 / n,
            correct_hints: self.correct_sum as f64 / n,
            wrong_hints: self.wrong_sum as f64 / n,
        })
    }
}

impl<'a> FromIterator<&'a Outcome> for MetricsAccumulator {
    fn from_iter<I: IntoIterator<Item = &'a Outcome>>(iter: I) -> Self {
        let mut acc = MetricsAccumulator::default();
        iter.into_iter().for_each(|o| acc.add(o));
        acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(reward: i32, won: bool, early_end: bool, length: u16) -> Outcome {
        Outcome {
            reward,
            score: reward,
            won,
            early_end,
            length,
            correct_hints: 1,
            wrong_hints: 0,
            clustered: 0,
            face_down: 0,
            revealed_unplaced: 0,
        }
    }

    #[test]
    fn metrics_of_hand_made_games() {
        let games = [
            outcome(20, true, true, 1),
            outcome(-3, false, true, 9),
            outcome(4, true, false, 32),
            outcome(-2, false, false, 30),
        ];
        let m = games
            .iter()
            .collect::<MetricsAccumulator>()
            .metrics()
            .unwrap();
        assert_eq!(m.games, 4);
        assert!((m.reward - 19.0 / 4.0).abs() < 1e-12);
        assert_eq!(m.win_rate, 0.5);
        assert_eq!(m.early_end, 0.5);
        assert_eq!(m.successful_early_end, 0.25);
        assert_eq!(m.win_given_early_end, Some(0.5));
        assert_eq!(m.length, 18.0);
        // [20, -3, 4, -2]: mean 4.75, squared deviations sum to 338.75, sample var 112.916…
        assert!((m.reward_se - (338.75f64 / 3.0 / 4.0).sqrt()).abs() < 1e-9);
    }

    #[test]
    fn no_early_end_means_no_wee() {
        let m = [outcome(1, true, false, 32)]
            .iter()
            .collect::<MetricsAccumulator>()
            .metrics()
            .unwrap();
        assert_eq!(m.win_given_early_end, None);
        assert!(MetricsAccumulator::default().metrics().is_none());
    }
}

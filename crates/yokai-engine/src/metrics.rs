//! Metrics of a set of finished games (RULES §7).

use crate::action::Action;
use crate::config::Config;
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
    /// Card moves (MOVE actions) of the games whose actions were counted
    /// ([`MetricsAccumulator::add_moves`]), and those onto the grid's outer ring.
    #[serde(default)]
    pub card_moves: u64,
    #[serde(default)]
    pub border_moves: u64,
    /// Games whose actions were counted.
    #[serde(default)]
    pub games_with_moves: u64,
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
    /// Card moves per game, and of them how many land on the grid's outer ring (row or
    /// column 0 or g−1; the paper's border-usage diagnostic, its appendix "Playing Yōkai on
    /// a grid"); `None` where the games' actions were not counted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub card_moves: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub border_moves: Option<f64>,
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

    /// Count the card moves of one game from its action indices (an episode record's
    /// `actions`), and those onto the grid's border. Why the border: the grid is finite (9×9
    /// for 9 cards) while the real game's table is not, so a policy that used the border a
    /// lot would be playing a game the grid cuts short. Indices outside the action space
    /// are not moves.
    pub fn add_moves(&mut self, config: &Config, actions: &[u16]) {
        let edge = config.grid() - 1;
        self.games_with_moves += 1;
        for &a in actions {
            if let Ok(Action::Move(_, cell)) = config.decode(a as usize) {
                self.card_moves += 1;
                let on_border = |x: u8| x == 0 || x as usize == edge;
                self.border_moves += (on_border(cell.row) || on_border(cell.col)) as u64;
            }
        }
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
        self.card_moves += other.card_moves;
        self.border_moves += other.border_moves;
        self.games_with_moves += other.games_with_moves;
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
            card_moves: (self.games_with_moves > 0)
                .then(|| self.card_moves as f64 / self.games_with_moves as f64),
            border_moves: (self.games_with_moves > 0)
                .then(|| self.border_moves as f64 / self.games_with_moves as f64),
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

    #[test]
    fn card_moves_onto_the_grids_outer_ring_are_border_moves() {
        use crate::bitboard::Cell;
        use crate::types::Card;
        let config = Config::from_name("9c-2p-perfect").unwrap();
        assert_eq!(config.grid(), 9);
        let mv = |row, col| config.encode(Action::Move(Card(2), Cell::new(row, col))) as u16;
        let observe = config.encode(Action::Observe(Card(1))) as u16;
        let mut acc = MetricsAccumulator::default();
        // Top row, centre, right column, bottom-left corner; observing is no move.
        acc.add_moves(&config, &[observe, mv(0, 4), mv(4, 4), mv(4, 8), mv(8, 0)]);
        acc.add(&outcome(1, true, false, 5));
        let mut other = MetricsAccumulator::default();
        other.add_moves(&config, &[mv(1, 1), observe, u16::MAX]); // inside; out of range
        other.add(&outcome(1, true, false, 3));
        acc.merge(&other);
        assert_eq!(
            (acc.card_moves, acc.border_moves, acc.games_with_moves),
            (5, 3, 2)
        );
        let m = acc.metrics().unwrap();
        assert_eq!((m.card_moves, m.border_moves), (Some(2.5), Some(1.5)));
        // Games whose actions were not counted have no figure (and serialise without one).
        let uncounted = [outcome(1, true, false, 3)]
            .iter()
            .collect::<MetricsAccumulator>();
        let m = uncounted.metrics().unwrap();
        assert_eq!(m.border_moves, None);
        assert!(!serde_json::to_string(&m).unwrap().contains("border"));
    }
}

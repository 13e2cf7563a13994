//! The probe study `yokai probe` runs: for each trained run, probes fitted on its
//! self-play memories and scored on held-out self-play games, then on games with each
//! partner in both seatings, by the same probes. The CLI and any other front end report
//! the curves; this module owns which games are played and which rows fit and test.

use super::{evaluate, fit, record, StepAccuracy};
use crate::{TrainError, TrainedPolicy};
use yokai_engine::Config;

/// Steps with fewer seat states than this are left out of the curves: too few to say.
pub const MIN_ROWS: usize = 20;

/// Fewest self-play games per run: the held-out fifth must give a step [`MIN_ROWS`] rows.
pub const MIN_GAMES: usize = 50;

/// Why a study cannot run.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error(
        "{games} self-play games per run are too few: the held-out fifth of the self-play games must give each \
         game step at least {MIN_ROWS} seat states (use {MIN_GAMES} or more)"
    )]
    TooFewGames { games: usize },
    #[error("no run to probe")]
    NoRun,
    #[error("{path}: probes are built for 2-player games (its game has {players} players)")]
    NotTwoPlayers { path: String, players: usize },
    /// A run or partner trained on another game than the first run.
    #[error(transparent)]
    OtherGame(#[from] TrainError),
}

/// Where a curve's games were played: the run's held-out self-play, or with partner `k`
/// (an index into the study's partners), both seatings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    SelfPlay,
    With(usize),
}

/// One probed run in one setting: accuracy per game step.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Index of the run among the study's runs.
    pub run: usize,
    pub setting: Setting,
    pub steps: Vec<StepAccuracy>,
}

/// The study's plan, checked: `runs` probed, each in self-play (`games` games, 80 % fit,
/// 20 % test) and with each of `partners` (`games` per seating); deals and actions follow
/// `seed` (self-play `seed`, the two seatings `seed + 1` and `seed + 2`).
pub struct Study<'a> {
    runs: &'a [TrainedPolicy],
    partners: &'a [TrainedPolicy],
    games: usize,
    seed: u64,
    game: Config,
}

impl<'a> Study<'a> {
    /// Check the plan: enough games, at least one run, one 2-player game for all.
    pub fn new(
        runs: &'a [TrainedPolicy],
        partners: &'a [TrainedPolicy],
        games: usize,
        seed: u64,
    ) -> Result<Study<'a>, StudyError> {
        if games < MIN_GAMES {
            return Err(StudyError::TooFewGames { games });
        }
        let first = runs.first().ok_or(StudyError::NoRun)?;
        let game = *first.game();
        if game.players() != 2 {
            return Err(StudyError::NotTwoPlayers {
                path: first.path().display().to_string(),
                players: game.players(),
            });
        }
        for policy in runs.iter().chain(partners) {
            policy.check_game(&game)?;
        }
        Ok(Study {
            runs,
            partners,
            games,
            seed,
            game,
        })
    }

    /// The game every run and partner was trained on.
    pub fn game(&self) -> &Config {
        &self.game
    }

    /// Every curve: per run, self-play first, then each partner in order. `starting(k)` is
    /// called before run `k` is probed (for progress).
    pub fn run(&self, mut starting: impl FnMut(usize)) -> Vec<Curve> {
        let (game, games, seed) = (&self.game, self.games, self.seed);
        let mut curves = Vec::new();
        for (run, policy) in self.runs.iter().enumerate() {
            starting(run);
            let own = record(game, &[policy, policy], &[true, true], games, seed);
            let probes = fit(game, &own, |e| e % 5 != 0);
            curves.push(Curve {
                run,
                setting: Setting::SelfPlay,
                steps: evaluate(game, &probes, &own, |e| e % 5 == 0, MIN_ROWS),
            });
            for (k, partner) in self.partners.iter().enumerate() {
                let mut with = record(game, &[policy, partner], &[true, false], games, seed + 1);
                with.append(record(
                    game,
                    &[partner, policy],
                    &[false, true],
                    games,
                    seed + 2,
                ));
                curves.push(Curve {
                    run,
                    setting: Setting::With(k),
                    steps: evaluate(game, &probes, &with, |_| true, MIN_ROWS),
                });
            }
        }
        curves
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn policy() -> TrainedPolicy {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        TrainedPolicy::load(&dir.join("tests/golden/memory-named-gru/policy.ykp")).unwrap()
    }

    #[test]
    fn a_study_is_checked_then_gives_self_play_and_each_partner_per_run() {
        let runs = [policy(), policy()];
        let partners = [policy()];
        let e = Study::new(&runs, &partners, 49, 0).err().unwrap();
        assert!(e.to_string().contains("49 self-play games"), "{e}");
        assert!(matches!(
            Study::new(&[], &partners, 50, 0),
            Err(StudyError::NoRun)
        ));
        let curves = Study::new(&runs, &partners, 50, 3).unwrap().run(|_| {});
        let order: Vec<(usize, Setting)> = curves.iter().map(|c| (c.run, c.setting)).collect();
        use Setting::*;
        assert_eq!(
            order,
            [(0, SelfPlay), (0, With(0)), (1, SelfPlay), (1, With(0))]
        );
        // Two copies of one policy with one seed: the same curves.
        assert_eq!(curves[0].steps, curves[2].steps);
        assert_eq!(curves[1].steps, curves[3].steps);
        // Self-play tests on the held-out fifth (10 games, 2 seats a step); cross-play on
        // every game of both seatings, one seat probed (100 games).
        assert_eq!(curves[0].steps[0].rows, 20);
        assert_eq!(curves[1].steps[0].rows, 100);
    }
}

//! The probe study `yokai probe` runs: for each trained run, probes fitted on its
//! self-play memories and scored on held-out self-play games, then on games with each
//! partner in both seatings, by the same probes. The CLI and any other front end report
//! the curves; this module owns which games are played and which rows fit and test.

use super::{evaluate, fit, record, StepAccuracy, Target};
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
    /// The probe recorder steps seats from bare game states, which do not keep the
    /// colour names such a network reads (`network.colours` other than `dealt`).
    #[error(
        "{path}: its network reads its own colour names (network.colours = \"{names}\"), \
         which the probes do not support yet"
    )]
    ColourNames { path: String, names: String },
    /// A run or partner trained on another game than the first run.
    #[error(transparent)]
    OtherGame(#[from] TrainError),
}

/// Where a curve's games were played: the run's held-out self-play, or with partner `k`
/// (an index into the study's partners) in every other seat, the run in each seat in turn.
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

/// The study's plan, checked: `runs` probed, each in self-play (`games` games, every seat
/// recorded, 80 % of the games fit, 20 % test) and with each of `partners` (`games` per
/// seating: the run in seat i, the partner in every other, for each i); deals and actions
/// follow `seed` (self-play `seed`, seating i `seed + 1 + i`).
pub struct Study<'a> {
    runs: &'a [TrainedPolicy],
    partners: &'a [TrainedPolicy],
    games: usize,
    seed: u64,
    game: Config,
    target: Target,
}

impl<'a> Study<'a> {
    /// Check the plan: enough games, at least one run, one game for all; probes by
    /// `target` (board position, as the paper, or card id).
    pub fn new(
        runs: &'a [TrainedPolicy],
        partners: &'a [TrainedPolicy],
        games: usize,
        seed: u64,
        target: Target,
    ) -> Result<Study<'a>, StudyError> {
        if games < MIN_GAMES {
            return Err(StudyError::TooFewGames { games });
        }
        let first = runs.first().ok_or(StudyError::NoRun)?;
        let game = *first.game();
        for policy in runs.iter().chain(partners) {
            policy.check_game(&game)?;
            let names = policy.config().network.colours;
            if names != crate::config::ColourNames::Dealt {
                return Err(StudyError::ColourNames {
                    path: policy.path().display().to_string(),
                    names: names.to_string(),
                });
            }
        }
        Ok(Study {
            runs,
            partners,
            games,
            seed,
            game,
            target,
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
        let players = game.players();
        let mut curves = Vec::new();
        for (run, policy) in self.runs.iter().enumerate() {
            starting(run);
            let own = record(
                game,
                &vec![policy; players],
                &vec![true; players],
                games,
                seed,
            );
            let probes = fit(game, &own, |e| e % 5 != 0, self.target)
                .expect("records of played games have positions");
            curves.push(Curve {
                run,
                setting: Setting::SelfPlay,
                steps: evaluate(game, &probes, &own, |e| e % 5 == 0, MIN_ROWS),
            });
            for (k, partner) in self.partners.iter().enumerate() {
                let mut with = super::Records {
                    hidden: policy.hidden_size(),
                    ..Default::default()
                };
                for seat in 0..players {
                    let mut seats = vec![partner; players];
                    seats[seat] = policy;
                    let recorded: Vec<bool> = (0..players).map(|s| s == seat).collect();
                    with.append(record(
                        game,
                        &seats,
                        &recorded,
                        games,
                        seed + 1 + seat as u64,
                    ));
                }
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
        let e = Study::new(&runs, &partners, 49, 0, Target::Card)
            .err()
            .unwrap();
        assert!(e.to_string().contains("49 self-play games"), "{e}");
        assert!(matches!(
            Study::new(&[], &partners, 50, 0, Target::Card),
            Err(StudyError::NoRun)
        ));
        let curves = Study::new(&runs, &partners, 50, 3, Target::Card)
            .unwrap()
            .run(|_| {});
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

    /// A compact network of width 8 for `game`, as initialised, with `network` lines added
    /// to its `[network]` section, written to `path` and loaded back.
    fn untrained(game: &str, network: &str, path: &std::path::Path) -> TrainedPolicy {
        use crate::{MlpEncoder, TrainConfig, Trainer};
        let c = TrainConfig::from_toml_str(
            &format!(
                "game = \"{game}\"\n[network]\npreset = \"compact\"\nhidden = 8\n{network}\
                 [ppo]\nnum_envs = 4\nrollout_steps = 4\nminibatches = 1\n[run]\nthreads = 1\n"
            ),
            "test",
        )
        .unwrap();
        Trainer::<MlpEncoder>::new(c, 1)
            .unwrap()
            .policy()
            .write_atomic(path)
            .unwrap();
        TrainedPolicy::load(path).unwrap()
    }

    /// A network that reads first-seen colour names is refused, as run or as partner, with
    /// its path and the field named: the recorder steps seats from bare game states.
    #[test]
    fn first_seen_networks_are_refused_by_name() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("first-seen.ykp");
        let first_seen = [untrained(
            "9c-2p-perfect",
            "colours = \"first-seen\"\n",
            &path,
        )];
        for (runs, partners) in [
            (&first_seen[..], &[][..]),
            (&[policy()][..], &first_seen[..]),
        ] {
            let e = Study::new(runs, partners, 50, 0, Target::Card)
                .err()
                .unwrap();
            let text = e.to_string();
            assert!(matches!(e, StudyError::ColourNames { .. }), "{text}");
            assert!(
                text.contains("first-seen.ykp")
                    && text.contains("network.colours = \"first-seen\""),
                "{text}"
            );
        }
    }

    /// Three seats: self-play records every seat; with a partner, the run sits in each seat
    /// in turn with the partner in the other two, one seat recorded; positions are probed.
    #[test]
    fn three_players_are_probed_in_every_seat() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("p.ykp");
        let runs = [untrained("9c-3p-perfect", "", &path)];
        let partners = [TrainedPolicy::load(&path).unwrap()];
        let curves = Study::new(&runs, &partners, 50, 0, Target::Position)
            .unwrap()
            .run(|_| {});
        assert_eq!(curves.len(), 2);
        // Held-out fifth of 50 games × 3 seats; 3 seatings × 50 games × 1 seat.
        assert_eq!(curves[0].steps[0].rows, 30);
        assert_eq!(curves[1].steps[0].rows, 150);
        // Nine occupied positions at the first state, every card unseen: both shares exist.
        assert!(curves[0].steps[0].unseen.is_some());
    }
}

//! Replay files: one game as JSON lines, readable by people and by `yokai replay`.
//!
//! ```text
//! {"type":"header","format":1,"config":{…},"deal":{"seed":7},"seed":7,"seats":["human","belief"]}
//! {"type":"step","step":0,"seat":0,"substep":0,"action":5,"name":"observe card 3","reward":0,"shaping":1,"done":false}
//! …
//! {"type":"outcome","outcome":{…}}
//! ```
//!
//! The header and the action indices define the game ([`EpisodeRecord`]); the per-step
//! names, rewards and the outcome are metadata that reading checks against a replay of
//! the actions, so a hand-edited file that disagrees with the rules is refused with the
//! line that is wrong.

use crate::config::Config;
use crate::episode::{DealSource, EpisodeRecord, ReplayError};
use crate::scoring::Outcome;
use serde::{Deserialize, Serialize};

/// Version of the replay format this build writes and reads.
pub const REPLAY_FORMAT: u32 = 1;

/// Who sat where and how the game was started.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ReplayHeader {
    pub format: u32,
    pub config: Config,
    pub deal: DealSource,
    /// The seed the game (deal and policies) was started with, when there was one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// A name per seat: `human`, a built-in policy, or a trained policy's path.
    pub seats: Vec<String>,
}

/// One step as it was played.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReplayStep {
    pub step: usize,
    pub seat: u8,
    pub substep: u8,
    /// Action index (RULES §3).
    pub action: u16,
    /// The action in words.
    pub name: String,
    pub reward: i32,
    pub shaping: i32,
    pub done: bool,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
enum Line {
    Header(ReplayHeader),
    Step(ReplayStep),
    Outcome { outcome: Outcome },
}

/// A whole replay file in memory.
#[derive(Clone, Debug, PartialEq)]
pub struct Replay {
    pub header: ReplayHeader,
    pub steps: Vec<ReplayStep>,
    pub outcome: Option<Outcome>,
}

/// A replay file that cannot be read, with the line at fault.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReplayFileError {
    #[error("line {line}: {message}")]
    Line { line: usize, message: String },
    #[error("the file is empty (a replay starts with a header line)")]
    Empty,
    #[error("replay format {0} is not supported (this build reads format {REPLAY_FORMAT})")]
    Format(u32),
    #[error("the game does not replay: {0}")]
    Replay(#[from] ReplayError),
}

impl Replay {
    /// A replay of `record` with per-step metadata filled in by replaying it.
    pub fn from_record(
        record: &EpisodeRecord,
        seed: Option<u64>,
        seats: Vec<String>,
    ) -> Result<Replay, ReplayError> {
        let mut steps = Vec::with_capacity(record.actions.len());
        let game = record.replay_with(|before, action, step| {
            steps.push(ReplayStep {
                step: steps.len(),
                seat: before.current_seat().0,
                substep: before.substep().index() as u8,
                action: record.config.encode(action) as u16,
                name: action.to_string(),
                reward: step.reward,
                shaping: step.shaping,
                done: step.done,
            });
        })?;
        Ok(Replay {
            header: ReplayHeader {
                format: REPLAY_FORMAT,
                config: record.config,
                deal: record.deal.clone(),
                seed,
                seats,
            },
            steps,
            outcome: game.outcome(),
        })
    }

    /// The game record (config, deal, actions, outcome).
    pub fn record(&self) -> EpisodeRecord {
        EpisodeRecord {
            config: self.header.config,
            deal: self.header.deal.clone(),
            actions: self.steps.iter().map(|s| s.action).collect(),
            outcome: self.outcome,
        }
    }

    pub fn to_jsonl(&self) -> String {
        let mut out = String::new();
        let mut push = |line: &Line| {
            out += &serde_json::to_string(line).expect("replay lines serialise");
            out.push('\n');
        };
        push(&Line::Header(self.header.clone()));
        for s in &self.steps {
            push(&Line::Step(s.clone()));
        }
        if let Some(outcome) = self.outcome {
            push(&Line::Outcome { outcome });
        }
        out
    }

    /// Parse and check a replay: every line must parse, steps must be numbered in order,
    /// and replaying the actions must reproduce every step's metadata and the outcome.
    pub fn from_jsonl(text: &str) -> Result<Replay, ReplayFileError> {
        let mut header = None;
        let mut steps = Vec::new();
        let mut outcome = None;
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let err = |line: usize, message: String| ReplayFileError::Line {
            line: line + 1,
            message,
        };
        for (i, text) in &mut lines {
            let line: Line = serde_json::from_str(text).map_err(|e| err(i, e.to_string()))?;
            match (line, header.is_some()) {
                (Line::Header(h), false) => {
                    if h.format != REPLAY_FORMAT {
                        return Err(ReplayFileError::Format(h.format));
                    }
                    header = Some(h);
                }
                (Line::Header(_), true) => return Err(err(i, "a second header".into())),
                (_, false) => return Err(err(i, "the first line must be the header".into())),
                (Line::Step(s), true) => {
                    if s.step != steps.len() {
                        return Err(err(
                            i,
                            format!("expected step {}, got {}", steps.len(), s.step),
                        ));
                    }
                    if outcome.is_some() {
                        return Err(err(i, "a step after the outcome".into()));
                    }
                    steps.push((i, s));
                }
                (Line::Outcome { outcome: o }, true) => outcome = Some((i, o)),
            }
        }
        let header = header.ok_or(ReplayFileError::Empty)?;
        let replay = Replay {
            header: header.clone(),
            steps: steps.iter().map(|(_, s)| s.clone()).collect(),
            outcome: outcome.map(|(_, o)| o),
        };
        // Check the metadata against the rules.
        let mut record = replay.record();
        record.outcome = None;
        let checked = Replay::from_record(&record, header.seed, header.seats.clone())?;
        for ((line, written), truth) in steps.iter().zip(&checked.steps) {
            if written != truth {
                return Err(err(
                    *line,
                    format!(
                        "step {} says {written:?} but the game gives {truth:?}",
                        truth.step
                    ),
                ));
            }
        }
        if let Some((line, o)) = outcome {
            if Some(o) != checked.outcome {
                return Err(err(
                    line,
                    format!(
                        "the outcome does not match the replayed game ({:?})",
                        checked.outcome
                    ),
                ));
            }
        }
        Ok(replay)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::episode::RecordedGame;

    fn played(seed: u64) -> EpisodeRecord {
        let config = Config::from_name("9c-2p-perfect").unwrap();
        let mut game = RecordedGame::new(config, seed);
        let mut k = seed as usize;
        while !game.game().is_over() {
            let legal = game.game().legal_actions(game.game().current_seat());
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            game.apply(legal[(k >> 33) % legal.len()]).unwrap();
        }
        game.into_record()
    }

    #[test]
    fn round_trip_reproduces_the_game() {
        for seed in 0..20 {
            let record = played(seed);
            let replay =
                Replay::from_record(&record, Some(seed), vec!["a".into(), "b".into()]).unwrap();
            assert_eq!(replay.steps.len(), record.actions.len());
            let back = Replay::from_jsonl(&replay.to_jsonl()).unwrap();
            assert_eq!(back, replay);
            assert_eq!(
                back.record().replay().unwrap().outcome(),
                record.replay().unwrap().outcome()
            );
        }
    }

    #[test]
    fn edited_files_are_refused_with_the_line() {
        let replay =
            Replay::from_record(&played(3), Some(3), vec!["x".into(), "y".into()]).unwrap();
        let text = replay.to_jsonl();
        let lines: Vec<&str> = text.lines().collect();
        // A wrong reward on step 2 (line 4).
        let bad = text.replacen(
            lines[3],
            &lines[3].replace("\"reward\":0", "\"reward\":7"),
            1,
        );
        let e = Replay::from_jsonl(&bad).unwrap_err().to_string();
        assert!(e.starts_with("line 4:"), "{e}");
        // A step missing.
        let mut skipped: Vec<&str> = lines.clone();
        skipped.remove(2);
        let e = Replay::from_jsonl(&skipped.join("\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected step 1"), "{e}");
        // Not JSON.
        let e = Replay::from_jsonl("{\"type\":\"header\"")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("line 1:"), "{e}");
        assert_eq!(Replay::from_jsonl("\n"), Err(ReplayFileError::Empty));
    }
}

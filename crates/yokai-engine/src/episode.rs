//! Episode records: a game is fully determined by (config, deal, actions), so that is all a
//! record stores. Replaying re-applies the actions, which re-checks every one of them.

use crate::action::Action;
use crate::config::Config;
use crate::deal::{Deal, DealError};
use crate::game::{ActionError, Game, Step};
use crate::scoring::Outcome;
use serde::{Deserialize, Serialize};

/// Where a recorded game's deal came from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DealSource {
    Seed(u64),
    Explicit(Deal),
}

/// One recorded game: config, deal, and the acting seat's action at every step.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct EpisodeRecord {
    pub config: Config,
    pub deal: DealSource,
    /// Action indices (RULES §3), one per step, of the acting seat.
    pub actions: Vec<u16>,
    /// The outcome when the record was written, if the game had finished; a replay checks
    /// that it reproduces it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outcome: Option<Outcome>,
}

/// Why a record cannot be replayed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReplayError {
    #[error("the record's deal does not fit its config: {0}")]
    Deal(#[from] DealError),
    #[error("step {step}: {source}")]
    Action {
        step: usize,
        #[source]
        source: ActionError,
    },
    #[error("the replay ends with {replayed:?}, but the record says {recorded:?}")]
    OutcomeMismatch {
        recorded: Option<Outcome>,
        replayed: Option<Outcome>,
    },
    #[error("not a valid episode record: {0}")]
    Json(String),
}

/// A game that records its own actions as it is played.
#[derive(Clone, Debug)]
pub struct RecordedGame {
    game: Game,
    record: EpisodeRecord,
}

impl RecordedGame {
    pub fn new(config: Config, seed: u64) -> RecordedGame {
        RecordedGame {
            game: Game::new(config, seed),
            record: EpisodeRecord {
                config,
                deal: DealSource::Seed(seed),
                actions: Vec::new(),
                outcome: None,
            },
        }
    }

    pub fn from_deal(config: Config, deal: Deal) -> Result<RecordedGame, DealError> {
        Ok(RecordedGame {
            game: Game::from_deal(config, &deal)?,
            record: EpisodeRecord {
                config,
                deal: DealSource::Explicit(deal),
                actions: Vec::new(),
                outcome: None,
            },
        })
    }

    /// Continue a recorded game: replays `record` (checking every action and the recorded
    /// outcome) and keeps recording from where it ends.
    pub fn from_record(record: EpisodeRecord) -> Result<RecordedGame, ReplayError> {
        let game = record.replay()?;
        Ok(RecordedGame { game, record })
    }

    pub fn game(&self) -> &Game {
        &self.game
    }

    pub fn apply(&mut self, action: Action) -> Result<Step, ActionError> {
        let step = self.game.apply(action)?;
        self.record_applied(action, step);
        Ok(step)
    }

    fn record_applied(&mut self, action: Action, step: Step) {
        self.record
            .actions
            .push(self.game.config().encode(action) as u16);
        if step.done {
            self.record.outcome = self.game.outcome();
        }
    }

    /// [`Game::step_joint`] (one action per seat, all checked), recording the acting
    /// seat's action.
    pub fn step_joint(&mut self, actions: &[Action]) -> Result<Step, ActionError> {
        let acting = self.game.current_seat().index();
        let step = self.game.step_joint(actions)?;
        self.record_applied(actions[acting], step);
        Ok(step)
    }

    pub fn record(&self) -> &EpisodeRecord {
        &self.record
    }

    pub fn into_record(self) -> EpisodeRecord {
        self.record
    }
}

impl EpisodeRecord {
    /// The game at its start.
    pub fn initial_game(&self) -> Result<Game, ReplayError> {
        Ok(match &self.deal {
            DealSource::Seed(seed) => Game::new(self.config, *seed),
            DealSource::Explicit(deal) => Game::from_deal(self.config, deal)?,
        })
    }

    /// Replay every action, calling `visit(game_before, action, step)` on each; checks the
    /// recorded outcome at the end. Returns the final game.
    pub fn replay_with(
        &self,
        mut visit: impl FnMut(&Game, Action, &Step),
    ) -> Result<Game, ReplayError> {
        let mut game = self.initial_game()?;
        for (i, &index) in self.actions.iter().enumerate() {
            let before = game.clone();
            let step = game
                .apply_index(index as usize)
                .map_err(|source| ReplayError::Action { step: i, source })?;
            let action = self
                .config
                .decode(index as usize)
                .expect("applied, so it decodes");
            visit(&before, action, &step);
        }
        if self.outcome.is_some() && self.outcome != game.outcome() {
            return Err(ReplayError::OutcomeMismatch {
                recorded: self.outcome,
                replayed: game.outcome(),
            });
        }
        Ok(game)
    }

    /// Replay the whole record and return the final game.
    pub fn replay(&self) -> Result<Game, ReplayError> {
        self.replay_with(|_, _, _| {})
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("records always serialize")
    }

    pub fn from_json(text: &str) -> Result<EpisodeRecord, ReplayError> {
        serde_json::from_str(text).map_err(|e| ReplayError::Json(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Play the last legal action of the acting seat `steps` times (the first one is often
    /// END, which would finish the game at once).
    fn play_last_legal(game: &mut RecordedGame, steps: usize) {
        for _ in 0..steps {
            let seat = game.game().current_seat();
            let action = *game.game().legal_actions(seat).last().unwrap();
            game.apply(action).unwrap();
        }
    }

    #[test]
    fn from_record_continues_where_the_record_stops() {
        let config = Config::from_name("9c-2p-perfect").unwrap();
        let mut original = RecordedGame::new(config, 7);
        play_last_legal(&mut original, 9);
        let mut resumed = RecordedGame::from_record(original.record().clone()).unwrap();
        assert!(resumed.game() == original.game());
        play_last_legal(&mut original, 5);
        play_last_legal(&mut resumed, 5);
        assert!(resumed.game() == original.game());
        assert_eq!(resumed.record(), original.record());
    }

    #[test]
    fn from_record_refuses_an_illegal_action_and_names_its_step() {
        let config = Config::from_name("9c-2p-perfect").unwrap();
        let mut game = RecordedGame::new(config, 7);
        play_last_legal(&mut game, 3);
        let mut record = game.into_record();
        // Step 1 is the second OBSERVE; END is legal only at substep 0.
        record.actions[1] = config.encode(Action::End) as u16;
        match RecordedGame::from_record(record) {
            Err(ReplayError::Action { step: 1, .. }) => {}
            other => panic!("expected an error at step 1, got {:?}", other.map(|_| ())),
        }
    }
}

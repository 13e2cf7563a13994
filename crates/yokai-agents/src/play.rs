//! One game with one policy per seat.

use crate::Policy;
use yokai_engine::{
    derive_seed, Action, Config, EpisodeRecord, Illegal, Outcome, RecordedGame, Seat,
};

/// A finished game.
#[derive(Clone, Debug)]
pub struct Episode {
    pub outcome: Outcome,
    pub record: EpisodeRecord,
}

/// A policy broke the rules: a bug in that policy, reported with where it happened.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PlayError {
    #[error("policy `{policy}` at {seat}, step {step}, chose `{action}`: {reason}")]
    Illegal {
        policy: String,
        seat: Seat,
        step: usize,
        action: Action,
        reason: Illegal,
    },
    #[error("{got} policies for a {players}-player game")]
    SeatCount { players: usize, got: usize },
}

/// Play the game dealt from `deal_seed` with `policies[s]` in seat `s`; policy `s` is
/// reset with `derive_seed(policy_seed, s)`. Every seat is shown every action.
pub fn play_episode(
    config: Config,
    deal_seed: u64,
    policy_seed: u64,
    policies: &mut [Box<dyn Policy>],
) -> Result<Episode, PlayError> {
    if policies.len() != config.players() {
        return Err(PlayError::SeatCount {
            players: config.players(),
            got: policies.len(),
        });
    }
    for (s, policy) in policies.iter_mut().enumerate() {
        policy.reset(derive_seed(policy_seed, s as u64));
    }
    let mut game = RecordedGame::new(config, deal_seed);
    loop {
        let seat = game.game().current_seat();
        let action = policies[seat.index()].act(&game.game().view(seat));
        if let Err(reason) = game.game().check(seat, action) {
            return Err(PlayError::Illegal {
                policy: policies[seat.index()].name(),
                seat,
                step: game.game().steps(),
                action,
                reason,
            });
        }
        for (s, policy) in policies.iter_mut().enumerate() {
            policy.observe(&game.game().view(Seat(s as u8)), seat, action);
        }
        let step = game.apply(action).expect("checked above");
        if step.done {
            let outcome = game
                .game()
                .outcome()
                .expect("a finished game has an outcome");
            return Ok(Episode {
                outcome,
                record: game.into_record(),
            });
        }
    }
}

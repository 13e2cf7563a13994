//! Policies that play Yōkai from what one seat may know.
//!
//! A [`Policy`] acts on a [`SeatView`] — the public state and the seat's own colour
//! knowledge — never on a [`yokai_engine::Game`], so it cannot read hidden colours: the view
//! offers no method that returns one. Between its turns it is shown every action taken
//! ([`Policy::observe`]), which is public.
//!
//! Built-in policies, by name ([`PolicySpec`]): `random`, `greedy` ([`GreedyPolicy`]) and
//! `belief` ([`BeliefPolicy`]). [`play_episode`] plays one game with a policy per seat.

pub mod belief;
pub mod eval;
mod greedy;
mod play;
mod random;
mod seeds;
mod spec;

pub use belief::{BeliefParams, BeliefPolicy};
pub use greedy::GreedyPolicy;
pub use play::{play_episode, Episode, PlayError};
pub use random::RandomPolicy;
pub use seeds::{parse_seeds, SeedsError};
pub use spec::{PolicySpec, SpecError};

use yokai_engine::{Action, Seat, SeatView};

/// Something that chooses the acting seat's action.
pub trait Policy: Send {
    /// A short name, usable wherever a policy is accepted (e.g. `random`).
    fn name(&self) -> String;
    /// Start a new episode; `seed` makes any randomness of the policy reproducible.
    fn reset(&mut self, seed: u64);
    /// Choose a legal action for the seat of `view`, which is the acting seat.
    fn act(&mut self, view: &SeatView<'_>) -> Action;
    /// `actor` is about to play `action` in the state that `before` shows (this policy's
    /// own view of it). Called for every step, the policy's own actions included, so that
    /// it can follow the public history. The default ignores it.
    fn observe(&mut self, before: &SeatView<'_>, actor: Seat, action: Action) {
        let _ = (before, actor, action);
    }
}

//! Off-Belief Learning (Hu et al. 2021; docs/training.md "Off-Belief Learning").
//!
//! OBL grounds a seat's actions in what they do in a world drawn from the seat's *belief*
//! rather than in the real one: at each of its decisions the seat's action is applied to a
//! fictitious game (the real public state with card colours sampled from the belief) and
//! the partners play on (the level below, or with `obl.partner = "learner"` the policy being
//! learnt) until the seat is to act again. The reward and the value target of the action
//! come from that continuation, while the real game goes on with the real colours. The
//! belief is that of the previous level's play, so a convention the previous level does not
//! follow earns nothing: level 1 — whose previous level π₀ is uniformly random — learns
//! grounded play only.
//!
//! - [`belief`]: level 1's belief, exact: uniform over the colourings consistent with the
//!   seat's first-hand colours and the colour counts.
//! - [`continuation`]: one fictitious continuation, on plain [`yokai_engine::Game`]s.
//! - [`model`]: the belief model of the levels above 1 (recurrent encoder, autoregressive
//!   decoder that keeps the counts and first-hand colours), and [`learn`]: its training on
//!   the level below, measured against the exact belief of level 0.
//! - `previous`: the level below a level ≥ 2 run, its belief, and the belief's memory of
//!   the run's games.
//! - `targets`: the value targets of a PPO rollout's step, from one continuation per game;
//!   `partners` plays the partners in them (the level below or the learner), and `memory`
//!   steps memories along the fictitious states.
//!
//! - [`levels`]: a chain of levels, each trained on the one below (`yokai train --levels`).
//!
//! Everything here takes its inputs as arguments (the run's games as an
//! [`crate::actor::Actor`], the learner's network, the level below); the PPO trainer calls
//! [`targets::targets`] once per rollout step and knows nothing else of OBL.

pub mod belief;
pub mod continuation;
pub mod learn;
pub mod levels;
pub(crate) mod memory;
pub mod model;
pub(crate) mod partners;
pub(crate) mod previous;
pub(crate) mod targets;

pub use belief::{first_hand, first_hand_slots, sample_first_hand_consistent};
pub use continuation::{continue_all, continue_fictitiously, Continuation};
pub(crate) use previous::{PreviousLevel, SavedBelief, BELIEF_CURVE_SECTION, BELIEF_SECTION};
pub(crate) use targets::{targets, OblStep, StepInputs};

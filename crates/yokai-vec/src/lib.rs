//! # yokai-vec — many Yōkai games stepped at once
//!
//! A [`VecEnv`] holds N games of one configuration and steps all of them with one call,
//! split across threads in chunks with rayon. Everything a trainer reads lives in
//! preallocated, contiguous buffers that can be handed to a tensor library as they are:
//!
//! | buffer | shape | type |
//! |---|---|---|
//! | [`VecEnv::observations`] | `[N, P, …encoding shape]` | `T` (`f32` or `u8`) |
//! | [`VecEnv::legal_masks`] | `[N, P, N_a]` | `u8` (1 = legal) |
//! | [`VecEnv::adjacency`] | `[N, Y, Y]` (graph encodings only) | `T` |
//! | [`VecEnv::rewards`] | `[N]` game reward R on the terminal step, else 0 | `f32` |
//! | [`VecEnv::shaping`] | `[N]` shaping reward of the step | `f32` |
//! | [`VecEnv::dones`] | `[N]` 1 if the game ended on this step | `u8` |
//! | [`VecEnv::acting_seats`] | `[N]` the seat that acts next | `u8` |
//! | [`VecEnv::outcomes`] | `[N]` final metrics of a game that ended on this step | `Option<Outcome>` |
//!
//! ## Auto-reset: what a caller sees on the step a game ends
//! A game that ends during `step` is reset at once, in the same call. On that step
//! `rewards`, `shaping`, `dones = 1` and `outcomes = Some(..)` describe the *finished* game,
//! while `observations`, `legal_masks`, `adjacency` and `acting_seats` already show the
//! *first* state of the next game (the Gymnasium "same-step" convention, as in JaxMARL).
//! The final observation of a finished game is not kept: nothing in the game's reward
//! depends on it, and recurrent trainers reset their state on `dones` anyway.
//!
//! ## Determinism
//! Episode `e` of environment `i` is dealt from `episode_seed(seed, i, e)`. Each chunk of
//! games is stepped by one thread, and no game reads another, so every buffer is identical
//! whatever the number of threads (a test checks 1 and 2 threads against single games).
//!
//! ## Cost
//! No allocation in `step`. Actions are checked against the legal masks on the worker
//! threads. Each chunk then applies its actions and updates the buffers *in place*: a mask
//! clears the action groups of the old substep and marks the new ones, and an image writes
//! only the channels the action changed ([`yokai_engine::ImageChanges`]). A game that ends
//! is reset and written in full. The channels-first layout (`image-chw`) is the cheapest to
//! update, because its broadcast channels are two contiguous planes (`docs/performance.md`).

//!
//! ## Games the caller keeps: [`PackedGames`]
//! A JAX training loop keeps the environment's state itself, in a pytree, and calls out
//! once per step. [`PackedGames`] resets, steps and observes such batches: each game is
//! [`yokai_engine::PACKED_LEN`] bytes ([`yokai_engine::Game::pack`]), each call is a pure
//! function of its inputs, and stream `derive_seed(seed, i)` plays the games of env `i`
//! of a [`VecEnv`] seeded with `seed`. It writes every observation in full, so it is
//! several times slower per step than [`VecEnv`], which keeps its games and updates them
//! in place.

mod bits;
mod encoding;
mod env;
mod error;
mod options;
mod packed;

pub use encoding::Encoding;
pub use env::VecEnv;
pub use error::VecError;
pub use options::{episode_seed, VecEnvOptions};
pub use packed::{AutoReset, PackedBuffers, PackedGames, PackedOutputs};

//! # yokai-engine — the rules of Yōkai, exact and fast
//!
//! This crate is the contract of the Yōkai Learning Environment: `docs/spec/rules.md`
//! implemented completely, with no ML dependency. Everything else in the workspace (batched
//! environments, agents, training, the CLI, the Python package) stands on it.
//!
//! ## The model in ten minutes
//!
//! **Configuration** ([`Config`], RULES §1). Y cards in C colours on a g×g grid, P players,
//! a hint table (how many hints show 1, 2, … colours), and a memory mode. The paper's
//! presets are `9c` (9 cards, 3 colours, 9×9) and `16c` (16 cards, 4 colours, 10×10), with
//! 2–4 players: `Config::from_name("9c-2p-perfect")`. Custom games come from TOML
//! ([`ConfigSpec`] documents every key). A `Config` only exists validated — an unplayable
//! one is a [`ConfigError`] — and it is `Copy`, so every game carries its own.
//!
//! **Deal** ([`Deal`]). The hidden facts fixed at reset: each card's colour and each hint
//! slot's colours. From a seed (ChaCha8, portable, pinned by a test) or given explicitly.
//!
//! **State** ([`Game`]). Fixed-size arrays and bit sets, no heap: each card's cell, the
//! occupied cells as a [`Bitboard`] (one `u128`, cell `(r, c)` = bit `r·g + c`, g ≤ 11),
//! colour masks, hint slots (slots `0..revealed` are face up; each knows the card it is
//! placed on), and per seat the mask of cards it has ever observed. Card sets are `u32`
//! masks over card ids.
//!
//! **Turns** (RULES §2). One environment step is one *substep*. The acting seat plays
//! 0: OBSERVE or END, 1: OBSERVE another card, 2: MOVE (NOOP if nothing can move),
//! 3: REVEAL or PLACE; then the next seat acts. Other seats submit NOOP
//! ([`Game::step_joint`]) or are simply not asked ([`Game::apply`]). Every action is checked
//! first; an illegal one returns an [`ActionError`] that names seat, action and reason
//! ([`Illegal`]) and changes nothing. The game ends on END or when the last hint is placed.
//!
//! **Legal moves** (the hot path, `legal.rs`). A MOVE must keep all cards one 4-connected
//! group. Per card, not per (card, cell): lift the card, split the rest into connected
//! groups by bitboard flood fill, and the targets are the empty cells adjacent to every
//! group. A leaf card (one neighbour) skips the fill. [`Game::write_legal_mask`] writes the
//! N_a-long mask of a seat without allocating.
//!
//! **Actions** ([`Action`], RULES §3). A fixed index layout per config
//! ([`Config::encode`]/[`Config::decode`]), and readable names (`move card 4 to r2c6`) that
//! also parse back.
//!
//! **Scoring** (`scoring.rs`, RULES §4). Clusters by flood fill per colour; the terminal
//! reward R comes in [`Step::reward`] on the last step; the shaping reward comes separately
//! in [`Step::shaping`]; [`Game::outcome`] gives everything metrics need ([`Outcome`],
//! aggregated by [`MetricsAccumulator`]).
//!
//! **Observations** ([`observation`], RULES §5). Image `[g, g+1, 2C+8]`, graph (adjacency +
//! node features), the public/private split and the ground truth, each written into a
//! caller-provided `&mut [f32]` or `&mut [u8]` ([`Scalar`]). The channel table is in the
//! [`observation`] module docs.
//!
//! **Symmetries** ([`Symmetry`], RULES §6). Colour permutations × rotations (× reflections),
//! applied to observations, masks and actions, each with its inverse.
//!
//! **Records** ([`EpisodeRecord`]). A game is (config, deal, action indices): JSON in and
//! out, and a replay re-checks every action and the recorded outcome.
//!
//! **Views** ([`SeatView`]). What a policy receives instead of a `Game`: public facts and
//! the seat's own colour knowledge, with no way to reach a hidden colour.
//!
//! ```
//! use yokai_engine::{Config, Game, Seat};
//! let config = Config::from_name("9c-2p-perfect").unwrap();
//! let mut game = Game::new(config, 42);
//! while !game.is_over() {
//!     let action = game.legal_actions(game.current_seat())[0];
//!     let step = game.apply(action).unwrap();
//!     if step.done {
//!         println!("R = {}", step.reward);
//!     }
//! }
//! ```

pub mod action;
pub mod bitboard;
pub mod config;
pub mod deal;
pub mod digest;
pub mod episode;
pub mod fictitious;
pub mod game;
pub mod labels;
mod legal;
pub mod metrics;
pub mod observation;
pub mod packed;
pub mod playthrough;
pub mod reference;
pub mod render;
pub mod replay;
pub mod scoring;
pub mod symmetry;
pub mod types;
pub mod view;

pub use action::{Action, ActionLayout, IndexOutOfRange};
pub use bitboard::{Bitboard, Cell, Geometry, MAX_GRID};
pub use config::{Config, ConfigError, ConfigSpec, Memory, Preset};
pub use deal::{derive_seed, Deal, DealError};
pub use episode::{DealSource, EpisodeRecord, RecordedGame, ReplayError};
pub use game::{ActionError, Game, Illegal, LayoutError, Phase, Step, Substep};
pub use labels::{ColourLabels, ColourNaming};
pub use metrics::{Metrics, MetricsAccumulator};
pub use observation::{
    BufferError, ImageChanges, ImageChannels, ImageEncoder, ImageLayout, Part, Scalar,
};
pub use packed::{PackError, PACKED_FORMAT, PACKED_LEN};
pub use playthrough::{golden_set, playthrough, Chooser, GoldenGame, PLAYTHROUGH_FORMAT};
pub use render::{render_seat, render_truth};
pub use replay::{Replay, ReplayFileError, ReplayHeader, ReplayStep, REPLAY_FORMAT};
pub use scoring::Outcome;
pub use symmetry::{Symmetry, SymmetryError};
pub use types::{
    Card, CardSet, Colour, ColourSet, HintSlot, Seat, MAX_CARDS, MAX_COLOURS, MAX_HINTS,
    MAX_PLAYERS,
};
pub use view::{PublicView, SeatView};

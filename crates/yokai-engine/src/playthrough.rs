//! Golden playthroughs (after OpenSpiel's `playthroughs/` and shakmaty's perft files): one
//! game from a fixed seed, played by a seeded random legal player, written step by step as
//! text — the board, the legal actions, a digest of every observation encoding of every
//! seat, the action and what it paid. The files are committed (`tests/playthroughs/`) and a
//! test writes them again: a change to the rules, the action order or any encoding shows up
//! as a diff at the step where it happens.

use crate::action::Action;
use crate::config::Config;
use crate::deal::derive_seed;
use crate::digest::fnv1a;
use crate::game::Game;
use crate::observation::{ImageLayout, Part};
use crate::render::render_truth;
use crate::types::Seat;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write;

/// Version of the playthrough text; a change of layout bumps it (and rewrites the files).
pub const PLAYTHROUGH_FORMAT: u32 = 1;

/// How the acting seat chooses in a playthrough.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Chooser {
    /// Uniformly among the legal actions: most such games end early (RULES §4).
    Random,
    /// Uniformly among the legal actions other than END, so the game runs until the last
    /// hint is placed and every substep of every turn is played.
    NeverEnd,
}

/// The playthrough of the game dealt from `seed` in `config`, the acting seat choosing
/// with a generator seeded from `seed`.
pub fn playthrough(config: Config, seed: u64, chooser: Chooser) -> String {
    let mut game = Game::new(config, seed);
    let mut player = ChaCha8Rng::seed_from_u64(derive_seed(seed, 0x9_1A7));
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# playthrough format {PLAYTHROUGH_FORMAT}: {config}, seed {seed}, {chooser:?} player, \
         {} actions",
        config.num_actions()
    );
    while !game.is_over() {
        let seat = game.current_seat();
        let _ = writeln!(out, "\n## step {}", game.steps());
        out += &render_truth(&game);
        let legal = game.legal_actions(seat);
        let indices: Vec<usize> = legal.iter().map(|&a| config.encode(a)).collect();
        let _ = writeln!(
            out,
            "legal for {seat} ({}): {}",
            legal.len(),
            ranges(&indices)
        );
        for s in 0..config.players() {
            let _ = writeln!(out, "{}", digests(&game, Seat(s as u8)));
        }
        let choices: Vec<_> = match chooser {
            Chooser::Random => legal.clone(),
            Chooser::NeverEnd => legal
                .iter()
                .copied()
                .filter(|&a| a != Action::End)
                .collect(),
        };
        let action = choices[(player.next_u64() % choices.len() as u64) as usize];
        let result = game.apply(action).expect("a legal action applies");
        let _ = writeln!(
            out,
            "{seat}: {} ({action}) -> reward {}, shaping {}, done {}",
            config.encode(action),
            result.reward,
            result.shaping,
            result.done
        );
    }
    let _ = writeln!(out, "\n## end after {} steps", game.steps());
    out += &render_truth(&game);
    for s in 0..config.players() {
        let _ = writeln!(out, "{}", digests(&game, Seat(s as u8)));
    }
    let _ = writeln!(
        out,
        "outcome: {:?}",
        game.outcome().expect("the game is over")
    );
    out
}

/// One committed playthrough: the file it is kept in and how to play it again.
#[derive(Clone, Debug)]
pub struct GoldenGame {
    pub file_name: String,
    pub config: Config,
    pub seed: u64,
    pub chooser: Chooser,
}

/// The committed set (`crates/yokai-engine/tests/playthroughs/`): every preset config in
/// both memory modes, each with a random game (seed 1, which mostly ends early) and a game
/// that never ENDs (seed 2, every turn played to the last hint).
pub fn golden_set() -> Vec<GoldenGame> {
    let mut out = Vec::new();
    for config in Config::presets() {
        for (seed, chooser, kind) in [
            (1, Chooser::Random, "random"),
            (2, Chooser::NeverEnd, "never-end"),
        ] {
            out.push(GoldenGame {
                file_name: format!("{config}-seed{seed}-{kind}.txt"),
                config,
                seed,
                chooser,
            });
        }
    }
    out
}

/// `2-10, 13, 20-21`: sorted indices as runs.
fn ranges(indices: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let mut j = i;
        while j + 1 < indices.len() && indices[j + 1] == indices[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            indices[i].to_string()
        } else {
            format!("{}-{}", indices[i], indices[j])
        });
        i = j + 1;
    }
    parts.join(", ")
}

/// One line per seat: an FNV-1a digest (`digest::fnv1a`) of each encoding of its observation (image in both
/// memory orders and every part as u8, graph nodes as f32 in every part, adjacency).
fn digests(game: &Game, seat: Seat) -> String {
    let config = game.config();
    let view = game.view(seat);
    let mut line = format!("{seat}:");
    for (name, part) in [
        ("full", Part::Full),
        ("public", Part::Public),
        ("private", Part::Private),
    ] {
        for (layout_name, layout) in [("hwc", ImageLayout::Hwc), ("chw", ImageLayout::Chw)] {
            let mut image = vec![0u8; config.image_shape_in(part, layout).iter().product()];
            view.write_image_in(part, layout, &mut image)
                .expect("buffer of the image's size");
            let _ = write!(line, " image-{layout_name}-{name} {:016x}", fnv1a(&image));
        }
        let mut nodes = vec![0f32; config.node_shape(part).iter().product()];
        view.write_nodes(part, &mut nodes)
            .expect("buffer of the nodes' size");
        let bytes: Vec<u8> = nodes.iter().flat_map(|x| x.to_le_bytes()).collect();
        let _ = write!(line, " nodes-{name} {:016x}", fnv1a(&bytes));
    }
    let y = config.cards();
    let mut adjacency = vec![0u8; y * y];
    view.write_adjacency(&mut adjacency)
        .expect("buffer of the adjacency's size");
    let _ = write!(line, " adjacency {:016x}", fnv1a(&adjacency));
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_join_runs_of_consecutive_indices() {
        assert_eq!(ranges(&[2, 3, 4, 7, 9, 10]), "2-4, 7, 9-10");
        assert_eq!(ranges(&[0]), "0");
        assert_eq!(ranges(&[]), "");
    }
}

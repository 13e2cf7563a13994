//! Test support: the engine's slow reference implementations (`yokai_engine::reference`),
//! a seeded random player, and a random game checked against the rules at every step.
#![allow(dead_code, clippy::needless_range_loop)]

use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeSet;
use yokai_engine::*;

/// Every preset in both memory modes, plus two custom games (5 players; a 2×2 grid where
/// nothing can ever move).
pub fn all_configs() -> Vec<Config> {
    let mut out = Config::presets();
    out.push(
        Config::from_toml_str(
            "cards = 12\ncolours = 3\ngrid = 8\nplayers = 5\nhints = [2, 3]\n",
            "custom",
        )
        .unwrap(),
    );
    out.push(
        Config::from_toml_str(
            "cards = 4\ncolours = 2\ngrid = 2\nplayers = 3\nhints = [2]\n",
            "tiny",
        )
        .unwrap(),
    );
    out
}

pub use yokai_engine::reference::{
    check_state, reference_clustered, reference_moves, reference_reward,
};

/// A seeded random player: uniform over the legal actions of the acting seat.
pub struct RandomPlayer(ChaCha8Rng);

impl RandomPlayer {
    pub fn new(seed: u64) -> RandomPlayer {
        RandomPlayer(ChaCha8Rng::seed_from_u64(seed))
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.0.next_u64() % n as u64) as usize
    }
    pub fn pick(&mut self, game: &Game) -> Action {
        let legal = game.legal_actions(game.current_seat());
        legal[self.below(legal.len())]
    }
}

/// Parse a hand-drawn board: rows of space-separated tokens, `.` empty, a number a card id;
/// the drawing's top-left is at (row0, col0).
pub fn layout(row0: usize, col0: usize, rows: &[&str]) -> Vec<Cell> {
    let mut cells = Vec::new();
    for (r, line) in rows.iter().enumerate() {
        for (c, token) in line.split_whitespace().enumerate() {
            if let Ok(k) = token.parse::<usize>() {
                if cells.len() <= k {
                    cells.resize(k + 1, Cell::new(99, 99));
                }
                cells[k] = Cell::new(row0 + r, col0 + c);
            }
        }
    }
    cells
}

/// A 9c deal from colour digits and hint colour masks.
pub fn deal(config: &Config, colours: &[u8], hints: &[u8]) -> Deal {
    Deal::new(
        config,
        colours.iter().map(|&c| Colour(c)).collect(),
        hints.iter().map(|&h| ColourSet(h)).collect(),
    )
    .unwrap()
}

/// How much of the expensive checking to do at each step.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Depth {
    /// Everything at every step (property tests).
    Full,
    /// The cheap invariants at every step, the reference comparisons at one step in `n`
    /// (soak test).
    Sampled(u64),
}

/// The same game as seen through a symmetry: built from the mapped deal and layout, and fed
/// the mapped actions. Its observations must equal the mapped observations of the original.
fn transformed_game(game: &Game, sym: &Symmetry) -> Game {
    let config = *game.config();
    let d = game.deal();
    let mapped = Deal::new(
        &config,
        d.card_colours.iter().map(|&c| sym.map_colour(c)).collect(),
        d.hint_colours
            .iter()
            .map(|&h| sym.map_colour_set(h))
            .collect(),
    )
    .unwrap();
    let cells: Vec<Cell> = (0..config.cards())
        .map(|k| sym.map_cell(config.grid(), game.cell_of(Card(k as u8))))
        .collect();
    Game::from_layout(config, &mapped, &cells).unwrap()
}

/// Play one game with random legal actions and check every invariant of docs/spec/rules.md on
/// the way.
/// Returns the record and the number of steps.
pub fn play_checked(
    config: Config,
    deal_seed: u64,
    player_seed: u64,
    depth: Depth,
) -> (EpisodeRecord, usize) {
    let mut player = RandomPlayer::new(player_seed);
    let mut recorded = RecordedGame::new(config, deal_seed);
    let initial_deal = recorded.game().deal();
    let symmetries = Symmetry::all(&config, true);
    let sym = symmetries[player.below(symmetries.len())];
    let mut twin = transformed_game(recorded.game(), &sym);
    let p = config.players();
    let y = config.cards();
    let n_a = config.num_actions();
    let mut ever = vec![CardSet::EMPTY; p];
    let mut hinted_at: Vec<Option<Cell>> = vec![None; y];
    let mut states = Vec::new();
    let mut step_index = 0u64;
    loop {
        let game = recorded.game().clone();
        let deep = match depth {
            Depth::Full => true,
            Depth::Sampled(n) => step_index % n == 0,
        };
        // What END would pay here (a trainer's exact value of END) is what ending pays.
        if game.is_legal(Action::End) {
            let mut ended = game.clone();
            let step = ended.apply(Action::End).unwrap();
            assert_eq!(step.reward, game.end_reward(), "END at step {step_index}");
            assert_eq!(step.reward, reference_reward(&ended));
        }
        // The state's own invariants (distinct cells, one 4-connected group, colour
        // counts, placed hints revealed and on hinted cards), then hinted cards where they
        // were hinted.
        if let Err(fault) = check_state(&game) {
            panic!("step {step_index}: {fault}\n{game:?}");
        }
        assert_eq!(game.occupied().count() as usize, y);
        for k in 0..y {
            let card = Card(k as u8);
            match (hinted_at[k], game.is_hinted(card)) {
                (Some(cell), true) => assert_eq!(game.cell_of(card), cell, "a hinted card moved"),
                (None, true) => hinted_at[k] = Some(game.cell_of(card)),
                (Some(_), false) => panic!("a hint disappeared"),
                (None, false) => {}
            }
        }
        // Colours never change.
        assert_eq!(game.deal(), initial_deal);
        for colour in 0..config.colours() {
            assert_eq!(
                game.cards_of_colour(Colour(colour as u8)).len(),
                config.cards_per_colour()
            );
        }
        assert!(game.steps() <= config.max_episode_len());

        // Legal masks: the u8 and f32 masks agree, the list agrees, and (deep) every index's
        // mask bit equals what `check` says, and the fast moves equal the reference.
        for s in 0..p {
            let seat = Seat(s as u8);
            let mut mask = vec![0u8; n_a];
            game.write_legal_mask(seat, &mut mask);
            let mut maskf = vec![0f32; n_a];
            game.write_legal_mask(seat, &mut maskf);
            assert!(mask.iter().zip(&maskf).all(|(&a, &b)| a as f32 == b));
            let listed: Vec<usize> = game
                .legal_actions(seat)
                .iter()
                .map(|&a| config.encode(a))
                .collect();
            let masked: Vec<usize> = (0..n_a).filter(|&i| mask[i] == 1).collect();
            assert_eq!(listed, masked);
            if !game.is_over() {
                assert!(!masked.is_empty(), "{seat} has no legal action\n{game:?}");
            }
            if deep {
                for (i, &m) in mask.iter().enumerate() {
                    let action = config.decode(i).unwrap();
                    let ok = game.check(seat, action).is_ok();
                    assert_eq!(
                        m == 1,
                        ok,
                        "{seat} {action}: mask {m}, check {:?}\n{game:?}",
                        game.check(seat, action)
                    );
                }
            }
            // Observations: exactly the cards the seat may know show a colour, and the right one.
            let may_know = match config.memory() {
                Memory::Perfect => ever[s],
                Memory::Imperfect if s == game.current_seat().index() && !game.is_over() => {
                    game.turn_observed()
                }
                // A finished game has no turn in progress, whichever way it ended.
                Memory::Imperfect => CardSet::EMPTY,
            };
            assert_eq!(game.known_cards(seat), may_know, "{seat}");
            let mut private = vec![0u8; config.image_shape(Part::Private).iter().product()];
            game.write_image(seat, Part::Private, &mut private).unwrap();
            let c = config.colours();
            for k in 0..y {
                let cell = game.cell_of(Card(k as u8));
                let px = (cell.row as usize * (config.grid() + 1) + cell.col as usize) * c;
                let shown: Vec<u8> = private[px..px + c].to_vec();
                let mut expected = vec![0u8; c];
                if may_know.contains(Card(k as u8)) {
                    expected[game.colour_of(Card(k as u8)).index()] = 1;
                }
                assert_eq!(shown, expected, "{seat} card {k}");
            }
            if deep {
                check_observations(&game, &twin, &sym, seat);
            }
        }
        if deep && game.substep() == Substep::Move && !game.is_over() {
            let fast: BTreeSet<(u8, Cell)> = game
                .legal_actions(game.current_seat())
                .into_iter()
                .filter_map(|a| match a {
                    Action::Move(card, cell) => Some((card.0, cell)),
                    _ => None,
                })
                .collect();
            assert_eq!(fast, reference_moves(&game), "\n{game:?}");
        }
        states.push(game.clone());
        if game.is_over() {
            break;
        }
        // Deep: every legal action succeeds on a copy; a few illegal ones fail and change nothing.
        if deep {
            let seat = game.current_seat();
            let mut mask = vec![0u8; n_a];
            game.write_legal_mask(seat, &mut mask);
            for i in 0..n_a {
                if mask[i] == 1 || player.below(16) == 0 {
                    let mut copy = game.clone();
                    let result = copy.apply_index(i);
                    assert_eq!(
                        result.is_ok(),
                        mask[i] == 1,
                        "{}",
                        config.decode(i).unwrap()
                    );
                    if result.is_err() {
                        assert_eq!(copy, game, "a rejected action changed the game");
                    }
                }
            }
        }

        let action = player.pick(&game);
        let seat = game.current_seat().index();
        let step = recorded.apply(action).unwrap();
        if deep {
            check_incremental(&game, action, recorded.game());
        }
        let twin_step = twin.apply(sym.apply_action(&config, action)).unwrap();
        assert_eq!(step, twin_step, "the symmetric game scored differently");
        let expected_shaping = match action {
            Action::Observe(card) => !ever[seat].contains(card) as i32,
            Action::Place(slot, card) => recorded
                .game()
                .hint_colours(slot)
                .contains(recorded.game().colour_of(card))
                as i32,
            _ => 0,
        };
        assert_eq!(step.shaping, expected_shaping, "{action}");
        if let Action::Observe(card) = action {
            ever[seat].insert(card);
        }
        assert_eq!(step.done, recorded.game().is_over());
        if step.done {
            assert_eq!(step.reward, reference_reward(recorded.game()));
            assert!((config.min_reward()..=config.max_reward()).contains(&step.reward));
            let o = recorded.game().outcome().unwrap();
            assert_eq!(o.reward, step.reward);
            assert_eq!(o.clustered as usize, reference_clustered(recorded.game()));
            assert_eq!(o.won, o.clustered as usize == config.colours());
        } else {
            assert_eq!(step.reward, 0);
        }
        step_index += 1;
    }
    // The same deal and actions give the same trajectory, state by state.
    let record = recorded.into_record();
    let json = record.to_json();
    let back = EpisodeRecord::from_json(&json).unwrap();
    assert_eq!(back, record);
    let mut i = 0;
    let last = back
        .replay_with(|before, _, _| {
            assert!(*before == states[i], "replay diverged at step {i}");
            i += 1;
        })
        .unwrap();
    assert_eq!(last, *states.last().unwrap());
    let len = states.len() - 1;
    (record, len)
}

/// Updating the buffers of the state before `action` in place (what batched environments do)
/// gives exactly the full writes of the state after it: images in both layouts, every part
/// and element type, and legal masks.
fn check_incremental(before: &Game, action: Action, after: &Game) {
    fn images<T: Scalar + Default>(before: &Game, action: Action, after: &Game) {
        let config = *before.config();
        let changes = before.image_changes(action);
        for layout in [ImageLayout::Hwc, ImageLayout::Chw] {
            let encoder = ImageEncoder::<T>::new(&config, layout);
            for part in [Part::Full, Part::Public, Part::Private] {
                let n: usize = config.image_shape(part).iter().product();
                for s in 0..config.players() {
                    let seat = Seat(s as u8);
                    let (mut updated, mut full) = (vec![T::ZERO; n], vec![T::ZERO; n]);
                    encoder.write(before, seat, part, &mut updated).unwrap();
                    encoder
                        .update(after, seat, part, changes, &mut updated)
                        .unwrap();
                    after.write_image_in(seat, part, layout, &mut full).unwrap();
                    assert!(
                        updated == full,
                        "{layout:?} {part:?} image of {seat} after {action} differs when updated in place"
                    );
                }
            }
        }
    }
    images::<u8>(before, action, after);
    images::<f32>(before, action, after);
    let n_a = before.config().num_actions();
    for s in 0..before.config().players() {
        let seat = Seat(s as u8);
        let (mut updated, mut full) = (vec![0u8; n_a], vec![0u8; n_a]);
        before.write_legal_mask(seat, &mut updated);
        before.clear_legal_mask(seat, &mut updated);
        assert!(updated.iter().all(|&m| m == 0), "clear left a legal bit");
        after.mark_legal_mask(seat, &mut updated);
        after.write_legal_mask(seat, &mut full);
        assert_eq!(updated, full, "mask of {seat} after {action}");
    }
}

/// The observations of `game` mapped by `sym` equal the twin's observations (equivariance),
/// and mapping back gives the originals (inverse ∘ symmetry = identity); for every encoding.
fn check_observations(game: &Game, twin: &Game, sym: &Symmetry, seat: Seat) {
    let config = *game.config();
    let inv = sym.inverse();
    for part in [Part::Full, Part::Public, Part::Private] {
        let n: usize = config.image_shape(part).iter().product();
        let (mut a, mut b, mut t, mut back) =
            (vec![0f32; n], vec![0f32; n], vec![0f32; n], vec![0f32; n]);
        game.write_image(seat, part, &mut a).unwrap();
        twin.write_image(seat, part, &mut b).unwrap();
        sym.apply_image(&config, part, &a, &mut t).unwrap();
        assert_eq!(
            t, b,
            "image {part:?} of {seat} is not equivariant under {sym:?}"
        );
        inv.apply_image(&config, part, &t, &mut back).unwrap();
        assert_eq!(back, a);
        // The same in the channels-first layout.
        let (mut ac, mut bc, mut tc, mut backc) =
            (vec![0f32; n], vec![0f32; n], vec![0f32; n], vec![0f32; n]);
        game.write_image_in(seat, part, ImageLayout::Chw, &mut ac)
            .unwrap();
        twin.write_image_in(seat, part, ImageLayout::Chw, &mut bc)
            .unwrap();
        sym.apply_image_in(&config, part, ImageLayout::Chw, &ac, &mut tc)
            .unwrap();
        assert_eq!(
            tc, bc,
            "channels-first image {part:?} of {seat} under {sym:?}"
        );
        inv.apply_image_in(&config, part, ImageLayout::Chw, &tc, &mut backc)
            .unwrap();
        assert_eq!(backc, ac);
        let mut a8 = vec![0u8; n];
        game.write_image(seat, part, &mut a8).unwrap();
        let scales = config.image_channels().scales(&config);
        if part != Part::Private {
            for (i, (&u, &f)) in a8.iter().zip(&a).enumerate() {
                let s = scales[i % scales.len()] as f32;
                assert!(
                    (u as f32 / s - f).abs() < 1e-6,
                    "u8 and f32 images disagree at {i}"
                );
            }
        }
        let mut t8 = vec![0u8; n];
        let mut back8 = vec![0u8; n];
        sym.apply_image(&config, part, &a8, &mut t8).unwrap();
        inv.apply_image(&config, part, &t8, &mut back8).unwrap();
        assert_eq!(back8, a8);

        let n: usize = config.node_shape(part).iter().product();
        let (mut a, mut b, mut t, mut back) =
            (vec![0f32; n], vec![0f32; n], vec![0f32; n], vec![0f32; n]);
        game.write_nodes(seat, part, &mut a).unwrap();
        twin.write_nodes(seat, part, &mut b).unwrap();
        sym.apply_nodes(&config, part, &a, &mut t).unwrap();
        assert_eq!(t, b, "nodes {part:?} not equivariant");
        inv.apply_nodes(&config, part, &t, &mut back).unwrap();
        assert_eq!(back, a);
    }
    // Channels-first holds the same values as the spec's [g, g+1, F], transposed.
    for part in [Part::Full, Part::Public, Part::Private] {
        let [h, w, f] = config.image_shape(part);
        assert_eq!(config.image_shape_in(part, ImageLayout::Chw), [f, h, w]);
        let (mut hwc, mut chw) = (vec![0f32; h * w * f], vec![0f32; h * w * f]);
        game.write_image(seat, part, &mut hwc).unwrap();
        game.write_image_in(seat, part, ImageLayout::Chw, &mut chw)
            .unwrap();
        for r in 0..h {
            for c in 0..w {
                for k in 0..f {
                    assert_eq!(chw[(k * h + r) * w + c], hwc[(r * w + c) * f + k]);
                }
            }
        }
    }
    // Public = Full with the known-colour channels zeroed.
    let n: usize = config.image_shape(Part::Full).iter().product();
    let (mut full, mut public) = (vec![0u8; n], vec![0u8; n]);
    game.write_image(seat, Part::Full, &mut full).unwrap();
    game.write_image(seat, Part::Public, &mut public).unwrap();
    let ch = config.image_channels();
    for (i, (&f, &p)) in full.iter().zip(&public).enumerate() {
        let channel = i % ch.len;
        let expected = if channel < ch.hint { 0 } else { f };
        assert_eq!(p, expected);
    }
    let yy = config.cards() * config.cards();
    let (mut adj, mut adj_twin) = (vec![0u8; yy], vec![0u8; yy]);
    game.write_adjacency(&mut adj).unwrap();
    twin.write_adjacency(&mut adj_twin).unwrap();
    assert_eq!(
        adj, adj_twin,
        "adjacency must be invariant under grid symmetries"
    );
    for a in 0..config.cards() {
        for b in 0..config.cards() {
            let (ca, cb) = (game.cell_of(Card(a as u8)), game.cell_of(Card(b as u8)));
            let d = (ca.row as i32 - cb.row as i32).abs() + (ca.col as i32 - cb.col as i32).abs();
            assert_eq!(adj[a * config.cards() + b] == 1, d == 1);
        }
    }
    let (mut gt, mut gt_twin, mut gt_t) = (
        vec![0u8; config.cards()],
        vec![0u8; config.cards()],
        vec![0u8; config.cards()],
    );
    game.write_ground_truth(&mut gt).unwrap();
    twin.write_ground_truth(&mut gt_twin).unwrap();
    sym.apply_ground_truth(&gt, &mut gt_t);
    assert_eq!(gt_t, gt_twin);
    // Masks and actions.
    let n_a = config.num_actions();
    let (mut m, mut mt, mut m_twin, mut m_back) = (
        vec![0u8; n_a],
        vec![0u8; n_a],
        vec![0u8; n_a],
        vec![0u8; n_a],
    );
    game.write_legal_mask(seat, &mut m);
    twin.write_legal_mask(seat, &mut m_twin);
    sym.apply_mask(&config, &m, &mut mt).unwrap();
    assert_eq!(mt, m_twin, "legal mask not equivariant");
    inv.apply_mask(&config, &mt, &mut m_back).unwrap();
    assert_eq!(m_back, m);
    for i in (0..n_a).step_by(7) {
        assert_eq!(
            inv.apply_action_index(&config, sym.apply_action_index(&config, i)),
            i
        );
    }
}

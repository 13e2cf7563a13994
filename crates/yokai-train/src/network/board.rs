//! The board read back from the graph node features: where each card lies, which cards
//! touch, which hint lies on which card.
//!
//! Why from the features rather than from the environment's adjacency buffer: every
//! network reads one flat observation per row, and the features already say where each
//! card is (row and column channels) and which card a placed hint covers (its id channel).
//! Reading the board from them keeps one input for every encoder and head, and it follows
//! Other-Play's rotated views for free (the rotated features give the rotated board). The
//! tests below check the result against the engine on random play.

use burn::prelude::*;
use burn::tensor::TensorData;
use yokai_engine::{Config, Part};

/// What a network needs to know to read the board from node features `[B, Y+H, F]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Board {
    pub cards: usize,
    pub hints: usize,
    pub features: usize,
    pub grid: usize,
    /// Feature channels: row and column (scaled by 1 / (g − 1)), card id ((id + 1) / Y),
    /// and "hinted" (on a hint slot: placed on a card).
    row: usize,
    col: usize,
    id: usize,
    hinted: usize,
    /// The substep channel (substep / 3, on every node).
    substep: usize,
}

impl Board {
    pub fn new(game: &Config) -> Board {
        let [_, features] = game.node_shape(Part::Full);
        let ch = game.image_channels();
        Board {
            cards: game.cards(),
            hints: game.hints(),
            features,
            grid: game.grid(),
            row: ch.row,
            col: ch.col,
            id: ch.id,
            hinted: ch.hinted,
            substep: ch.substep,
        }
    }

    /// Whether the node features `[(Y+H)·F]` of one row say its seat is at the MOVE
    /// substep: the only substep at which any MOVE is legal (the engine's rules; checked
    /// against its legal actions by the tests below). Read from the first card's node on
    /// the CPU, before any tensor is made, so a head can leave the other rows' MOVE
    /// scores uncomputed.
    pub fn at_move_substep(&self, nodes: &[f32]) -> bool {
        (nodes[self.substep] * 3.0).round() as u8 == yokai_engine::Substep::Move as u8
    }

    /// Each card's row and column `[B, Y, 1]`, whole numbers read back from the scaled
    /// position channels of the cards' node features `[B, Y, F]`. [`Board::near`] and
    /// [`Board::card_adjacency`] both start from them, so a head that needs both reads the
    /// positions once.
    pub fn positions(&self, card_x: Tensor<3>) -> Positions {
        let scale = (self.grid - 1) as f32;
        Positions {
            rows: (card_x.clone().narrow(2, self.row, 1) * scale).round(),
            cols: (card_x.narrow(2, self.col, 1) * scale).round(),
        }
    }

    /// `[B, Y, g²]`: 1 where card y lies on a 4-neighbour of cell x.
    ///
    /// From the Manhattan distance d between the card's cell and cell x (d = 1), a few
    /// elementwise ops. Why not the cards' one-hot cells times the cells' adjacency matrix:
    /// that product costs Y·g⁴ multiply-adds per row (59k on 9c, as much as the GRU's input
    /// map) for a result that is mostly zeros.
    pub fn near(&self, at: &Positions) -> Tensor<3> {
        is_one(self.cell_distance(at))
    }

    /// `[B, Y, g²]`: the Manhattan distance from each card's cell to every cell.
    fn cell_distance(&self, at: &Positions) -> Tensor<3> {
        let g = self.grid;
        let [b, y, _] = at.rows.dims();
        let cells = g * g;
        let device = at.rows.device();
        let cell_rows = index_row(cells, |x| (x / g) as f32, &device).expand([b, y, cells]);
        let cell_cols = index_row(cells, |x| (x % g) as f32, &device).expand([b, y, cells]);
        (at.rows.clone().expand([b, y, cells]) - cell_rows).abs()
            + (at.cols.clone().expand([b, y, cells]) - cell_cols).abs()
    }

    /// `[B, Y, Y]`: 1 where two cards lie on 4-neighbouring cells (the engine's adjacency),
    /// from the Manhattan distance between every pair of cards.
    pub fn card_adjacency(&self, at: &Positions) -> Tensor<3> {
        let [b, y, _] = at.rows.dims();
        let across = |v: &Tensor<3>| {
            (v.clone().expand([b, y, y]) - v.clone().swap_dims(1, 2).expand([b, y, y])).abs()
        };
        is_one(across(&at.rows) + across(&at.cols))
    }

    /// `[B, H, Y]`: 1 where hint slot h is placed on card y, from the hint slots' and the
    /// cards' node features. A placed hint carries its card's id channel; an unplaced one
    /// carries 0, which no card has.
    pub fn hint_on_card(&self, hint_x: Tensor<3>, card_x: Tensor<3>) -> Tensor<3> {
        let [b, h, _] = hint_x.dims();
        let y = self.cards;
        let scale = y as f32;
        let placed = hint_x.clone().narrow(2, self.hinted, 1);
        let hint_id = (hint_x.narrow(2, self.id, 1) * scale).round();
        let card_id = (card_x.narrow(2, self.id, 1) * scale)
            .round()
            .swap_dims(1, 2);
        let same =
            (-(hint_id.expand([b, h, y]) - card_id.expand([b, h, y])).abs() + 1.0).clamp_min(0.0);
        same * placed.expand([b, h, y])
    }
}

/// The cards' cells, as [`Board::positions`] reads them from node features.
pub(crate) struct Positions {
    rows: Tensor<3>,
    cols: Tensor<3>,
}

impl Positions {
    /// The positions of some rows of the batch, in the order of `rows`.
    pub fn select(&self, rows: Tensor<1, Int>) -> Positions {
        Positions {
            rows: self.rows.clone().select(0, rows.clone()),
            cols: self.cols.clone().select(0, rows),
        }
    }
}

/// `[1, 1, n]` holding `value(0), …, value(n − 1)`.
fn index_row(n: usize, value: impl Fn(usize) -> f32, device: &Device) -> Tensor<3> {
    Tensor::from_data(
        TensorData::new((0..n).map(value).collect::<Vec<_>>(), [1, 1, n]),
        device,
    )
}

/// 1 where a whole-numbered distance is 0, else 0.
fn is_zero(d: Tensor<3>) -> Tensor<3> {
    (-d + 1.0).clamp_min(0.0)
}

/// 1 where a whole-numbered distance is 1, else 0.
fn is_one(d: Tensor<3>) -> Tensor<3> {
    is_zero((d - 1.0).abs())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use rand_chacha::rand_core::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use yokai_engine::{Card, Game, HintSlot, Seat};

    pub(crate) fn to_vec<const D: usize>(t: Tensor<D>) -> Vec<f32> {
        t.into_data()
            .convert::<f32>()
            .try_into_vec::<f32>()
            .unwrap()
    }

    /// Random legal play on 9c and 16c: the positions read from the node features are the
    /// engine's, `near` is the 4-neighbourhood of every card's cell, the card adjacency is
    /// the engine's `write_adjacency`, and each placed hint is found on its card.
    #[test]
    fn the_board_read_from_node_features_is_the_engines_through_random_play() {
        let device = Device::flex();
        for name in ["9c-2p-perfect", "16c-3p-perfect"] {
            let game_config = Config::from_name(name).unwrap();
            let board = Board::new(&game_config);
            let [nodes, f] = game_config.node_shape(Part::Full);
            let (y, g, nh) = (game_config.cards(), game_config.grid(), game_config.hints());
            let mut rng = ChaCha8Rng::seed_from_u64(7);
            let (mut checked, mut placed_seen) = (0, 0);
            for deal in 0..6 {
                let mut game = Game::new(game_config, deal);
                while !game.is_over() {
                    let mut x = vec![0f32; nodes * f];
                    game.view(Seat(0)).write_nodes(Part::Full, &mut x).unwrap();
                    let x: Tensor<3> =
                        Tensor::from_data(TensorData::new(x, [1, nodes, f]), &device);
                    let cards = x.clone().narrow(1, 0, y);
                    let at = board.positions(cards.clone());
                    let on = to_vec(is_zero(board.cell_distance(&at)));
                    let near = to_vec(board.near(&at));
                    for k in 0..y {
                        let cell = game.cell_of(Card(k as u8));
                        let (r, c) = (cell.row as usize, cell.col as usize);
                        for i in 0..g * g {
                            let (ri, ci) = (i / g, i % g);
                            let here = (ri, ci) == (r, c);
                            let beside = ri.abs_diff(r) + ci.abs_diff(c) == 1;
                            assert_eq!(on[k * g * g + i], here as u8 as f32, "{name} card {k}");
                            assert_eq!(near[k * g * g + i], beside as u8 as f32, "{name} card {k}");
                        }
                    }
                    let mut adjacency = vec![0f32; y * y];
                    game.write_adjacency(&mut adjacency).unwrap();
                    assert_eq!(to_vec(board.card_adjacency(&at)), adjacency, "{name}");
                    let hint_on = to_vec(board.hint_on_card(x.narrow(1, y, nh), cards));
                    for slot in 0..nh {
                        let on_card = game.hint_card(HintSlot(slot as u8));
                        placed_seen += on_card.is_some() as usize;
                        for k in 0..y {
                            let expected = on_card == Some(Card(k as u8));
                            assert_eq!(hint_on[slot * y + k], expected as u8 as f32, "{name}");
                        }
                    }
                    checked += 1;
                    let legal = game.legal_actions(game.current_seat());
                    let pick = legal[(rng.next_u64() % legal.len() as u64) as usize];
                    game.apply(pick).unwrap();
                }
            }
            assert!(checked > 50, "{name}: {checked} states");
            assert!(
                placed_seen > 20,
                "{name}: only {placed_seen} placed hints seen"
            );
        }
    }

    /// Random legal play on 9c and 16c: every seat's node features say "MOVE substep"
    /// exactly when the game is at it, and every state where the acting seat has a legal
    /// MOVE is one of them (what lets the pointer head skip the other rows' MOVE scores).
    #[test]
    fn the_move_substep_read_from_node_features_covers_every_legal_move() {
        for name in ["9c-2p-perfect", "16c-3p-perfect"] {
            let game_config = Config::from_name(name).unwrap();
            let board = Board::new(&game_config);
            let [nodes, f] = game_config.node_shape(Part::Full);
            let mut rng = ChaCha8Rng::seed_from_u64(3);
            let (mut at_move, mut other) = (0, 0);
            for deal in 0..6 {
                let mut game = Game::new(game_config, deal);
                while !game.is_over() {
                    let is_move = game.substep() == yokai_engine::Substep::Move;
                    let mut x = vec![0f32; nodes * f];
                    for seat in 0..game_config.players() {
                        game.view(Seat(seat as u8))
                            .write_nodes(Part::Full, &mut x)
                            .unwrap();
                        assert_eq!(board.at_move_substep(&x), is_move, "{name} seat {seat}");
                    }
                    let legal = game.legal_actions(game.current_seat());
                    let can_move = legal
                        .iter()
                        .any(|a| matches!(a, yokai_engine::Action::Move(..)));
                    assert!(
                        !can_move || is_move,
                        "{name}: a MOVE legal at {:?}",
                        game.substep()
                    );
                    (at_move, other) = if is_move {
                        (at_move + 1, other)
                    } else {
                        (at_move, other + 1)
                    };
                    let pick = legal[(rng.next_u64() % legal.len() as u64) as usize];
                    game.apply(pick).unwrap();
                }
            }
            assert!(
                at_move > 20 && other > 50,
                "{name}: {at_move} at MOVE, {other} not"
            );
        }
    }
}

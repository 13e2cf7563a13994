//! The pointer-style actor head (`network.head = "pointer"`): action logits computed from
//! per-card and per-hint embeddings instead of one dense `hidden × N_a` layer.
//!
//! Why: the actions of Yōkai are relations between things on the table. "Move card y to
//! cell x" is good when x touches cards of y's colour; "place hint h on card y" is good
//! when h's colours include y's. A dense layer must learn each of the Y·g² moves and H·Y
//! placements separately, from a GRU state that has squeezed the board into one vector. Here
//! one set of weights scores every (card, cell) and (hint, card) pair, so what is learnt
//! about one card or cell holds for all of them:
//!
//! - every node (card or hint slot) gets an embedding `z = relu(W x + U h)` from its own
//!   features `x` and the GRU state `h` (what the seat remembers);
//! - cards add what their 4-neighbours look like (one message-passing step over the
//!   board): `r_y = relu(z_y + M Σ_{y' next to y} z_{y'})`;
//! - MOVE y→x: `q_y · (e_x + Σ_{y' next to cell x, y' ≠ y} k_{y'})`, a bilinear score of
//!   the card against the cards that would become its neighbours (and a learnt embedding of
//!   the cell);
//! - OBSERVE y: a linear score of `r_y`; PLACE h on y: `a_h · b_y`;
//! - NOOP, END and REVEAL: a linear map of the GRU state, and with `network.pointer_pool`
//!   of the mean and maximum of the card embeddings `r` too (whether every colour is
//!   clustered is a question about all cards at once, which END needs answered).
//!
//! The card positions are read from the graph node features (row and column channels), so
//! the head follows Other-Play's rotated views without knowing about them.

use super::board::{Board, Positions};
use crate::init::Init;
use crate::tensor::{rows_tensor, FoldedLinear};
use burn::module::{Module, Param};
use burn::nn::Linear;
use burn::prelude::*;
use burn::tensor::activation::relu;
use burn::tensor::{IndexingUpdateOp, TensorData};
use yokai_engine::Config;

/// Width of the head's node embeddings.
const WIDTH: usize = 32;

#[derive(Module, Debug)]
pub struct PointerHead {
    /// Node features → embedding (shared by every card and hint slot).
    node: Linear,
    /// GRU state → embedding, added to every node.
    context: Linear,
    /// Sum of a card's neighbours' embeddings → added to its own.
    message: Linear,
    /// MOVE: query of the moving card, key of each card around the target cell.
    move_query: Linear,
    move_key: Linear,
    /// A learnt embedding per cell, `[g², WIDTH]`.
    cell: Param<Tensor<2>>,
    /// OBSERVE: one score per card.
    observe: Linear,
    /// PLACE: query of the hint slot, key of the card.
    hint_query: Linear,
    hint_key: Linear,
    /// NOOP, END, REVEAL from the GRU state (and the pooled card embeddings with `pool`).
    other: Linear,
    /// With `ppo.belief_aux`: each card's colour logits from its embedding.
    colour: Option<Linear>,
    #[module(skip)]
    shape: HeadShape,
}

/// The sizes the head needs from the game config.
#[derive(Clone, Copy, Debug)]
struct HeadShape {
    board: Board,
    /// NOOP, END and REVEAL also read the mean and maximum of the card embeddings.
    pool: bool,
}

impl PointerHead {
    pub fn new(
        game: &Config,
        hidden: usize,
        pool: bool,
        colour_head: bool,
        gain: f64,
        init: &mut Init,
        device: &Device,
    ) -> Self {
        let board = Board::new(game);
        let (features, g) = (board.features, board.grid);
        let sqrt2 = std::f64::consts::SQRT_2;
        PointerHead {
            node: init.linear(features, WIDTH, sqrt2, device),
            context: init.linear(hidden, WIDTH, sqrt2, device),
            message: init.linear(WIDTH, WIDTH, 1.0, device),
            move_query: init.linear(WIDTH, WIDTH, gain, device),
            move_key: init.linear(WIDTH, WIDTH, 1.0, device),
            cell: Param::from_tensor(Tensor::from_data(
                TensorData::new(init.orthogonal(g * g, WIDTH, 1.0), [g * g, WIDTH]),
                device,
            )),
            observe: init.linear(WIDTH, 1, gain, device),
            hint_query: init.linear(WIDTH, WIDTH, gain, device),
            hint_key: init.linear(WIDTH, WIDTH, 1.0, device),
            other: init.linear(hidden + if pool { 2 * WIDTH } else { 0 }, 3, gain, device),
            colour: colour_head.then(|| init.linear(WIDTH, game.colours(), 1.0, device)),
            shape: HeadShape { board, pool },
        }
    }

    /// Logits `[B, N_a]` in the game's action order, from the graph node features `[B,
    /// (Y+H)·F]` and the GRU states `[B, H]` of the same rows.
    pub fn forward(&self, nodes: Tensor<2>, h: Tensor<2>) -> Tensor<2> {
        self.forward_with_colours(nodes, h, MoveRows::Every).0
    }

    /// The positions `k` of `rows` (row indices into `nodes`, flat `[B, (Y+H)·F]` node
    /// features) whose seat is at the MOVE substep: the rows [`MoveRows::Only`] needs.
    pub fn rows_at_move<R: Copy + TryInto<usize>>(&self, nodes: &[f32], rows: &[R]) -> Vec<usize> {
        let board = self.shape.board;
        let l = (board.cards + board.hints) * board.features;
        (0..rows.len())
            .filter(|&k| {
                let r = rows[k]
                    .try_into()
                    .ok()
                    .expect("row indices are not negative");
                board.at_move_substep(&nodes[r * l..][..l])
            })
            .collect()
    }

    /// The action logits and, with the colour layer, each card's colour logits `[B, Y, C]`
    /// from the same card embeddings. `moving` says which rows get MOVE scores.
    pub fn forward_with_colours(
        &self,
        nodes: Tensor<2>,
        h: Tensor<2>,
        moving: MoveRows,
    ) -> (Tensor<2>, Option<Tensor<3>>) {
        let parts = self.parts(nodes, h);
        let moves = self.moves_of(parts.cards.clone(), &parts.at, moving);
        let logits = parts.in_action_order(Some(moves));
        (logits, parts.colours)
    }

    /// The logits the learner reads, split where MOVE can be legal: every row's logits of
    /// the actions other than MOVE `[B, N_a − Y·g²]` (in action order, the MOVE block cut
    /// out), the MOVE logits `[m, Y·g²]` of the rows `moving` names (positions, in its
    /// order), and with the colour layer the colour logits `[B, Y, C]`.
    ///
    /// Why: a row off the MOVE substep has 48 logits that can be legal (9c), not 777.
    /// Handing the learner its MOVE block as zeros made every masked softmax, entropy and
    /// their gradients run over the 729 columns no such row can choose.
    pub fn forward_split(
        &self,
        nodes: Tensor<2>,
        h: Tensor<2>,
        moving: &[usize],
    ) -> (Tensor<2>, Tensor<2>, Option<Tensor<3>>) {
        let parts = self.parts(nodes, h);
        let moves = self.moves_of_rows(parts.cards.clone(), &parts.at, moving);
        (parts.in_action_order(None), moves, parts.colours)
    }

    /// Everything the head computes from its inputs except the MOVE scores.
    fn parts(&self, nodes: Tensor<2>, h: Tensor<2>) -> HeadParts {
        let Board {
            cards: y,
            hints: nh,
            features: f,
            ..
        } = self.shape.board;
        let [b, _] = nodes.dims();
        let x: Tensor<3> = nodes.reshape([b, y + nh, f]);
        let context: Tensor<3> = self.context.forward(h.clone()).unsqueeze_dim(1);
        let z = relu(self.node.forward_folded(x.clone()) + context.expand([b, y + nh, WIDTH]));
        let z_cards = z.clone().narrow(1, 0, y);
        let z_hints = z.narrow(1, y, nh);

        let at = self.shape.board.positions(x.clone().narrow(1, 0, y));
        // Card adjacency `[B, Y, Y]`, then one message-passing step.
        let touching = self.shape.board.card_adjacency(&at);
        let gathered = touching.matmul(z_cards.clone());
        let cards = relu(z_cards + self.message.forward_folded(gathered));

        let observe = self.observe.forward_folded(cards.clone()).reshape([b, y]);
        let place = self
            .hint_query
            .forward_folded(z_hints)
            .matmul(self.hint_key.forward_folded(cards.clone()).swap_dims(1, 2))
            .reshape([b, nh * y]);
        let colours = self
            .colour
            .as_ref()
            .map(|c| c.forward_folded(cards.clone()));
        let other = if self.shape.pool {
            let mean = cards.clone().mean_dim(1).reshape([b, WIDTH]);
            let max = cards.clone().max_dim(1).reshape([b, WIDTH]);
            self.other.forward(Tensor::cat(vec![h, mean, max], 1))
        } else {
            self.other.forward(h)
        };
        HeadParts {
            other,
            observe,
            place,
            colours,
            cards,
            at,
        }
    }

    /// The MOVE logits `[B, Y·g²]` of the rows `moving` names, 0 in the others.
    fn moves_of(&self, cards: Tensor<3>, at: &Positions, moving: MoveRows) -> Tensor<2> {
        let [b, y, _] = cards.dims();
        let g = self.shape.board.grid;
        let board = &self.shape.board;
        match moving {
            MoveRows::Only(rows) if rows.len() < b => {
                let device = cards.device();
                let all = Tensor::zeros([b, y * g * g], &device);
                if rows.is_empty() {
                    return all;
                }
                let idx = rows_tensor(rows.iter().map(|&r| r as i64).collect(), &device);
                let scores = self.moves_of_rows(cards, at, rows);
                all.select_assign(0, idx, scores, IndexingUpdateOp::Add)
            }
            _ => self
                .move_scores(cards, board.near(at))
                .reshape([b, y * g * g]),
        }
    }

    /// The MOVE logits `[rows.len(), Y·g²]` of the rows `rows` (positions, in its order).
    fn moves_of_rows(&self, cards: Tensor<3>, at: &Positions, rows: &[usize]) -> Tensor<2> {
        let [_, y, _] = cards.dims();
        let g = self.shape.board.grid;
        let device = cards.device();
        if rows.is_empty() {
            return Tensor::zeros([0, y * g * g], &device);
        }
        let idx = rows_tensor(rows.iter().map(|&r| r as i64).collect(), &device);
        let near = self.shape.board.near(&at.select(idx.clone()));
        self.move_scores(cards.select(0, idx), near)
            .reshape([rows.len(), y * g * g])
    }
}

/// Which rows of a batch the pointer head computes MOVE scores for.
///
/// Why: MOVE is legal only at the MOVE substep, a quarter of a seat's decisions, and its
/// Y·g² scores (729 of the 777 logits on 9c) are most of the head's work. Where every
/// logit is masked before it is read (acting with a legal mask, the learner's masked
/// softmax), the other rows' MOVE logits change nothing, so they are left at 0.
#[derive(Clone, Copy, Debug)]
pub enum MoveRows<'a> {
    /// Every row: for callers that hand the logits on unmasked.
    Every,
    /// Only these rows (positions in the batch, ascending, from
    /// [`PointerHead::rows_at_move`]); the others' MOVE logits are 0.
    Only(&'a [usize]),
}

/// What [`PointerHead::parts`] computes: the logits of every action but MOVE, the colour
/// logits, and what the MOVE scores read (card embeddings `[B, Y, WIDTH]`, positions).
struct HeadParts {
    /// NOOP, END, REVEAL `[B, 3]`.
    other: Tensor<2>,
    observe: Tensor<2>,
    place: Tensor<2>,
    colours: Option<Tensor<3>>,
    cards: Tensor<3>,
    at: Positions,
}

impl HeadParts {
    /// The logits in the game's action order, with `moves` as the MOVE block, or without
    /// the MOVE block (`None`).
    fn in_action_order(&self, moves: Option<Tensor<2>>) -> Tensor<2> {
        let mut blocks = vec![self.other.clone().narrow(1, 0, 2), self.observe.clone()];
        blocks.extend(moves);
        blocks.push(self.other.clone().narrow(1, 2, 1));
        blocks.push(self.place.clone());
        Tensor::cat(blocks, 1)
    }
}

impl PointerHead {
    /// MOVE y→x scores `[B, Y, g²]` from the card embeddings `[B, Y, WIDTH]` and `near`
    /// (`Board::near`): q_y · (e_x + Σ_{y' next to x, y' ≠ y} k_{y'}). The card itself is
    /// left out: moved next to its old cell, it would count itself as a neighbour.
    ///
    /// Computed as q_y · e_x + Σ_{y'} (q_y · k_{y'}) near[y', x] − (q_y · k_y) near[y, x]:
    /// the card pairs' scores `[B, Y, Y]` times `near`, instead of building every cell's
    /// key `[B, g², WIDTH]` first: the same sum for two thirds of the multiply-adds, and
    /// without those tensors (5 MB each for a minibatch's 512 choosing rows on 9c) and
    /// their gradients. With the board's cheaper layout this made the `cpu` preset's
    /// updates 11 % faster (docs/training.md, "Speed").
    fn move_scores(&self, cards: Tensor<3>, near: Tensor<3>) -> Tensor<3> {
        let [b, y, cells] = near.dims();
        let q = self.move_query.forward_folded(cards.clone());
        let k = self.move_key.forward_folded(cards);
        let own = (q.clone() * k.clone()).sum_dim(2);
        let pairs = q.clone().matmul(k.swap_dims(1, 2));
        let to_cells = q
            .reshape([b * y, WIDTH])
            .matmul(self.cell.val().transpose())
            .reshape([b, y, cells]);
        to_cells + pairs.matmul(near.clone()) - near * own.expand([b, y, cells])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{ActionHead, NetworkPreset, TrainConfig};
    use crate::network::board::tests::to_vec;
    use crate::network::{ActorCritic, GruCell, MlpEncoder};
    use rand_chacha::rand_core::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use yokai_engine::{Action, Card, Cell, Game, Part, Seat};

    /// A head for a GRU state of width 8, without the colour layer.
    fn small_head(game: &Config, pool: bool, gain: f64, seed: u64) -> PointerHead {
        let device = Device::flex();
        PointerHead::new(game, 8, pool, false, gain, &mut Init::new(seed), &device)
    }

    /// The head scores every action of the game, in the engine's order: a MOVE logit
    /// changes when a card next to its target cell changes, and not when a card far away
    /// from the target does.
    #[test]
    fn move_logits_read_the_cards_around_the_target_cell() {
        let device = Device::flex();
        let mut config = TrainConfig::from_toml_str("", "test").unwrap();
        config.network.preset = NetworkPreset::Compact;
        config.network.head = ActionHead::Pointer;
        config.network.hidden = 16;
        config.network.actor_gain = 1.0;
        let game_config = Config::from_name("9c-2p-perfect").unwrap();
        let net = ActorCritic::<MlpEncoder, GruCell>::new(&config, &game_config, 3, &device);
        let [nodes, f] = game_config.node_shape(Part::Full);
        let game = Game::new(game_config, 0);
        let mut x = vec![0f32; nodes * f];
        game.view(Seat(0)).write_nodes(Part::Full, &mut x).unwrap();
        let logits = |x: &[f32]| {
            let obs = Tensor::from_data(TensorData::new(x.to_vec(), [1, nodes * f]), &device);
            to_vec(net.policy_logits(obs, Tensor::zeros([1, 16], &device)))
        };
        let base = logits(&x);
        assert_eq!(base.len(), game_config.num_actions());
        // Card 0 starts at the start square's top-left corner (3, 3); card 8 at (5, 5).
        // Give card 8 a known colour: the move of card 0 to (5, 6), next to card 8, changes;
        // its move to (2, 3), far from card 8, does not.
        let ch = game_config.image_channels();
        let mut changed = x.clone();
        changed[8 * f + ch.known] = 1.0 - changed[8 * f + ch.known];
        let after = logits(&changed);
        let mv = |card: u8, r: usize, c: usize| {
            game_config.encode(Action::Move(Card(card), Cell::new(r, c)))
        };
        assert_ne!(base[mv(0, 5, 6)], after[mv(0, 5, 6)]);
        assert_eq!(base[mv(0, 2, 3)], after[mv(0, 2, 3)]);
    }

    /// With `pointer_pool`, END reads the cards: it changes when a card's known colour
    /// does, at the same GRU state; without it, END depends on the GRU state alone.
    #[test]
    fn pooled_end_reads_the_cards_and_plain_end_does_not() {
        let device = Device::flex();
        let game_config = Config::from_name("9c-2p-perfect").unwrap();
        let [nodes, f] = game_config.node_shape(Part::Full);
        let mut x = vec![0f32; nodes * f];
        Game::new(game_config, 0)
            .view(Seat(0))
            .write_nodes(Part::Full, &mut x)
            .unwrap();
        let mut changed = x.clone();
        let known = game_config.image_channels().known;
        changed[4 * f + known] = 1.0 - changed[4 * f + known];
        let end = game_config.encode(Action::End);
        for pool in [false, true] {
            let head = small_head(&game_config, pool, 1.0, 2);
            let h: Tensor<2> = Tensor::ones([1, 8], &device);
            let end_logit = |x: &[f32]| {
                let obs = Tensor::from_data(TensorData::new(x.to_vec(), [1, nodes * f]), &device);
                to_vec(head.forward(obs, h.clone()))[end]
            };
            let (before, after) = (end_logit(&x), end_logit(&changed));
            assert_eq!(before != after, pool, "pool {pool}: {before} → {after}");
        }
    }

    /// MOVE scores for the rows at the MOVE substep only ([`MoveRows::Only`]), on rows of
    /// random play at every substep: every logit that can be legal is the one
    /// [`MoveRows::Every`] gives, the other rows' MOVE logits are 0, and a loss that reads
    /// only logits that can be legal has the same gradients (with respect to the GRU
    /// states and the node features, which every weight's gradient passes through).
    #[test]
    fn move_scores_of_the_moving_rows_leave_every_logit_that_can_be_legal_as_it_was() {
        let device = Device::flex().autodiff();
        let game_config = Config::from_name("9c-2p-perfect").unwrap();
        let head = PointerHead::new(&game_config, 8, true, true, 1.0, &mut Init::new(4), &device);
        let [nodes, f] = game_config.node_shape(Part::Full);
        let l = nodes * f;
        let (y, g) = (game_config.cards(), game_config.grid());
        let moves = 2 + y..2 + y + y * g * g;
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let (mut x, mut at_move) = (Vec::new(), Vec::new());
        let mut game = Game::new(game_config, 1);
        for k in 0..24 {
            if game.is_over() {
                game = Game::new(game_config, rng.next_u64());
            }
            let mut row = vec![0f32; l];
            game.view(game.current_seat())
                .write_nodes(Part::Full, &mut row)
                .unwrap();
            x.extend(row);
            if game.substep() == yokai_engine::Substep::Move {
                at_move.push(k);
            }
            let legal = game.legal_actions(game.current_seat());
            game.apply(legal[(rng.next_u64() % legal.len() as u64) as usize])
                .unwrap();
        }
        let b = x.len() / l;
        let rows: Vec<usize> = (0..b).collect();
        let moving = head.rows_at_move(&x, &rows);
        assert_eq!(moving, at_move);
        // Positions in `rows`, whatever the rows' indices into the batch are.
        assert_eq!(head.rows_at_move(&x, &[at_move[0] as i64, 0]), [0]);
        assert!(
            !moving.is_empty() && moving.len() < b,
            "{} of {b} rows move",
            moving.len()
        );
        let na = game_config.num_actions();
        // A weight for every logit that can be legal: all of a moving row's, the non-MOVE
        // logits of the others.
        let weights: Vec<f32> = (0..b * na)
            .map(|i| {
                let can_be_legal = moving.contains(&(i / na)) || !moves.contains(&(i % na));
                if can_be_legal {
                    (i % 7) as f32 - 3.0
                } else {
                    0.0
                }
            })
            .collect();
        let run = |which: MoveRows| {
            let nodes =
                Tensor::<2>::from_data(TensorData::new(x.clone(), [b, l]), &device).require_grad();
            let h = Tensor::<2>::from_data(
                TensorData::new(
                    (0..b * 8).map(|i| (i % 5) as f32 * 0.3 - 0.6).collect(),
                    [b, 8],
                ),
                &device,
            )
            .require_grad();
            let (logits, colours) = head.forward_with_colours(nodes.clone(), h.clone(), which);
            let w = Tensor::<2>::from_data(TensorData::new(weights.clone(), [b, na]), &device);
            let loss = (logits.clone() * w).sum() + colours.unwrap().sum();
            let grads = loss.backward();
            let grad = |t: Tensor<2>| to_vec(t.grad(&grads).unwrap());
            (to_vec(logits), grad(h), grad(nodes))
        };
        let (every, h_every, x_every) = run(MoveRows::Every);
        let (only, h_only, x_only) = run(MoveRows::Only(&moving));
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * (1.0 + a.abs());
        for i in 0..b * na {
            if moving.contains(&(i / na)) || !moves.contains(&(i % na)) {
                assert!(
                    close(every[i], only[i]),
                    "logit {i}: {} vs {}",
                    every[i],
                    only[i]
                );
            } else {
                assert_eq!(only[i], 0.0, "row {}'s MOVE logit", i / na);
            }
        }
        for (name, a, c) in [("h", &h_every, &h_only), ("nodes", &x_every, &x_only)] {
            for (k, (&p, &q)) in a.iter().zip(c.iter()).enumerate() {
                assert!(close(p, q), "d loss / d {name}[{k}]: {p} vs {q}");
            }
        }
        assert!(h_every.iter().any(|&v| v != 0.0));
    }

    /// The learner's split ([`PointerHead::forward_split`]) holds the logits the whole
    /// head gives: every row's non-MOVE logits in action order, and the MOVE block of each
    /// row it names, in the order named; with none named, no MOVE rows.
    #[test]
    fn the_split_logits_are_the_whole_heads_columns() {
        let device = Device::flex();
        let game_config = Config::from_name("9c-2p-perfect").unwrap();
        let head = PointerHead::new(&game_config, 8, true, true, 1.0, &mut Init::new(6), &device);
        let [nodes, f] = game_config.node_shape(Part::Full);
        let l = nodes * f;
        let layout = game_config.action_layout();
        let (na, moves) = (game_config.num_actions(), layout.reveal - layout.movement);
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let mut game = Game::new(game_config, 3);
        let mut x = Vec::new();
        for _ in 0..10 {
            let mut row = vec![0f32; l];
            game.view(game.current_seat())
                .write_nodes(Part::Full, &mut row)
                .unwrap();
            x.extend(row);
            let legal = game.legal_actions(game.current_seat());
            game.apply(legal[(rng.next_u64() % legal.len() as u64) as usize])
                .unwrap();
        }
        let b = x.len() / l;
        let nodes_t = || Tensor::<2>::from_data(TensorData::new(x.clone(), [b, l]), &device);
        let h = || {
            let v = (0..b * 8).map(|i| (i % 7) as f32 * 0.2 - 0.5).collect();
            Tensor::<2>::from_data(TensorData::new(v, [b, 8]), &device)
        };
        let (whole, colours) = head.forward_with_colours(nodes_t(), h(), MoveRows::Every);
        let whole = to_vec(whole);
        let named = [7usize, 2, 4];
        let (others, moving, split_colours) = head.forward_split(nodes_t(), h(), &named);
        let (others, moving) = (to_vec(others), to_vec(moving));
        assert_eq!(others.len(), b * (na - moves));
        assert_eq!(moving.len(), named.len() * moves);
        let close = |a: f32, c: f32| (a - c).abs() <= 1e-5 * (1.0 + a.abs());
        for r in 0..b {
            let rest = (0..layout.movement).chain(layout.reveal..na);
            for (j, a) in rest.enumerate() {
                let (w, o) = (whole[r * na + a], others[r * (na - moves) + j]);
                assert!(close(w, o), "row {r} action {a}: {w} vs {o}");
            }
        }
        for (k, &r) in named.iter().enumerate() {
            for m in 0..moves {
                let (w, o) = (whole[r * na + layout.movement + m], moving[k * moves + m]);
                assert!(close(w, o), "row {r} MOVE {m}: {w} vs {o}");
            }
        }
        assert_eq!(to_vec(colours.unwrap()), to_vec(split_colours.unwrap()));
        let (_, none, _) = head.forward_split(nodes_t(), h(), &[]);
        assert_eq!(none.dims(), [0, moves]);
    }

    /// The factored MOVE scores equal their definition, summed card by card over each
    /// target cell's neighbours, on boards from random play.
    #[test]
    fn move_scores_are_the_query_against_the_cell_and_its_other_neighbours() {
        let device = Device::flex();
        let game_config = Config::from_name("9c-2p-perfect").unwrap();
        let head = small_head(&game_config, false, 1.0, 5);
        let board = Board::new(&game_config);
        let [nodes, f] = game_config.node_shape(Part::Full);
        let (y, g) = (game_config.cards(), game_config.grid());
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut boards = 0;
        for deal in 0..4 {
            let mut game = Game::new(game_config, deal);
            while !game.is_over() {
                let mut x = vec![0f32; nodes * f];
                game.view(Seat(0)).write_nodes(Part::Full, &mut x).unwrap();
                let x: Tensor<3> = Tensor::from_data(TensorData::new(x, [1, nodes, f]), &device);
                let near = board.near(&board.positions(x.narrow(1, 0, y)));
                let cards: Tensor<3> = Tensor::random(
                    [1, y, WIDTH],
                    burn::tensor::Distribution::Normal(0.0, 1.0),
                    &device,
                );
                let got = to_vec(head.move_scores(cards.clone(), near.clone()));
                let q = to_vec(head.move_query.forward(cards.clone()));
                let k = to_vec(head.move_key.forward(cards));
                let (e, near) = (to_vec(head.cell.val()), to_vec(near));
                let dot = |a: &[f32], b: &[f32]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f32>();
                for card in 0..y {
                    let q_y = &q[card * WIDTH..][..WIDTH];
                    for cell in 0..g * g {
                        let mut key = e[cell * WIDTH..][..WIDTH].to_vec();
                        for other in (0..y).filter(|&o| o != card && near[o * g * g + cell] == 1.0)
                        {
                            for (kv, ko) in key.iter_mut().zip(&k[other * WIDTH..][..WIDTH]) {
                                *kv += ko;
                            }
                        }
                        let want = dot(q_y, &key);
                        let have = got[card * g * g + cell];
                        assert!(
                            (want - have).abs() <= 1e-4 * (1.0 + want.abs()),
                            "{want} vs {have}"
                        );
                    }
                }
                boards += 1;
                let legal = game.legal_actions(game.current_seat());
                game.apply(legal[(rng.next_u64() % legal.len() as u64) as usize])
                    .unwrap();
            }
        }
        assert!(boards > 20, "{boards} boards");
    }
}

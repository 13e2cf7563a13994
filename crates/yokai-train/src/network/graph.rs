//! The paper's graph encoders (`network.encoder = "gcn" | "gatv2" | "relation"`): message
//! passing over the cards, the hint slots and one virtual node, then a readout that does not
//! depend on the order of the nodes.
//!
//! The graph of one observation:
//! - a node per card and per hint slot, with the graph observation's features, and one
//!   virtual node (an extra "virtual" feature, 1 on it and 0 elsewhere) joined to every
//!   other node, so that a few layers carry news across the whole table;
//! - edges between cards on 4-neighbouring cells (the engine's adjacency) and between a
//!   placed hint and its card, both read from the features ([`Board`]), so rotated
//!   Other-Play views give rotated graphs;
//! - every node is its own neighbour (self-loops).
//!
//! Layers (`network.graph_layers` of width `network.graph_width`, 4 × 64 in the paper):
//! - `gcn`: `h ← h + relu(D^-½ (A + I) D^-½ h W)` (Kipf & Welling, with a residual);
//! - `gatv2`: `h ← h + relu(Σ_j α_ij W_s h_j)` with `α_ij = softmax_j aᵀ LeakyReLU(W_t h_i +
//!   W_s h_j)` over i's neighbours, 4 heads (Brody et al.'s GATv2);
//! - `relation`: a Transformer block, multi-head self-attention between every pair of
//!   nodes (edges ignored: positions are in the features) then an MLP, each with a
//!   residual and a layer norm (Zambaldi et al.'s relational module).
//!
//! Pre-embedding (`network.graph_preembed`, the paper's appendix after Bortoletto et al.):
//! each node-feature modality gets its own dense layer before message passing — known
//! colour, hint colours, position, locks (present and hinted), seen this turn and id to 4
//! values each, my turn to 2, substep to 4: 30 values per node (the paper's 26 has no
//! separate hint-colour modality) — and the virtual node is the zero vector (with its flag).
//!
//! Readout (`network.graph_readout`): `pooled`, the virtual node's embedding and the mean of
//! the other nodes' embeddings, both invariant to relabelling cards (permuting card nodes,
//! with the hints that point at them) and to permuting hint slots (the tests check it); or
//! `concat`, every node's embedding side by side, as the paper's appendix. The pointer head
//! still reads each card from the observation itself, so nothing is lost for the actor.

use super::board::Board;
use super::Encoder;
use crate::config::{EncoderKind, GraphReadout, TrainConfig, GRAPH_HEADS};
use crate::init::Init;
use crate::tensor::FoldedLinear;
use burn::module::{Module, Param};
use burn::nn::{LayerNorm, LayerNormConfig, Linear};
use burn::prelude::*;
use burn::tensor::activation::{leaky_relu, relu, softmax};
use burn::tensor::TensorData;
use yokai_engine::{Config, Part};
use yokai_vec::Encoding;

/// A graph encoder: (pre-embedding,) input layer, message-passing layers, readout.
#[derive(Module, Debug)]
pub struct GraphEncoder {
    /// One dense layer per node-feature modality (empty without pre-embedding).
    preembed: Vec<Linear>,
    /// Node features (or their pre-embeddings) plus the "virtual" flag → width.
    input: Linear,
    layers: Vec<GraphLayer>,
    #[module(skip)]
    board: Board,
    #[module(skip)]
    width: usize,
    /// Each pre-embedded modality's first feature channel and channel count.
    #[module(skip)]
    modalities: Vec<(usize, usize)>,
    #[module(skip)]
    concat: bool,
}

/// The node-feature modalities and their pre-embedding sizes: `(first channel, channels,
/// embedding size)`. The sizes are the paper's (4, and 2 for the current player).
pub fn modalities(game: &Config) -> Vec<(usize, usize, usize)> {
    let ch = game.image_channels();
    let c = game.colours();
    vec![
        (ch.known, c, 4),
        (ch.hint, c, 4),
        (ch.row, 2, 4),
        (ch.present, 2, 4),
        (ch.observed, 1, 4),
        (ch.id, 1, 4),
        (ch.my_turn, 1, 2),
        (ch.substep, 1, 4),
    ]
}

/// One message-passing layer of any of the three kinds. (A network holds a handful, built
/// once: the size of the largest variant does not matter.)
#[allow(clippy::large_enum_variant)]
#[derive(Module, Debug)]
pub enum GraphLayer {
    Gcn(GcnLayer),
    Gatv2(GatLayer),
    Relation(RelationLayer),
}

#[derive(Module, Debug)]
pub struct GcnLayer {
    weight: Linear,
}

#[derive(Module, Debug)]
pub struct GatLayer {
    /// W_s: the message a node sends (and its key).
    source: Linear,
    /// W_t: the receiving node's query.
    target: Linear,
    /// a: one attention vector per head, `[heads · width/heads]`.
    attention: Param<Tensor<1>>,
}

#[derive(Module, Debug)]
pub struct RelationLayer {
    query: Linear,
    key: Linear,
    value: Linear,
    output: Linear,
    norm_attention: LayerNorm,
    hidden: Linear,
    back: Linear,
    norm_mlp: LayerNorm,
}

impl Encoder for GraphEncoder {
    const KINDS: &'static [EncoderKind] =
        &[EncoderKind::Gcn, EncoderKind::Gatv2, EncoderKind::Relation];

    fn encoding() -> Encoding {
        Encoding::Graph(Part::Full)
    }

    fn new(config: &TrainConfig, game: &Config, init: &mut Init, device: &Device) -> Self {
        let board = Board::new(game);
        let d = config.network.graph_width;
        let sqrt2 = std::f64::consts::SQRT_2;
        let kind = config.network.encoder();
        let layers = (0..config.network.graph_layers)
            .map(|_| match kind {
                EncoderKind::Gcn => GraphLayer::Gcn(GcnLayer {
                    weight: init.linear(d, d, sqrt2, device),
                }),
                EncoderKind::Gatv2 => GraphLayer::Gatv2(GatLayer {
                    source: init.linear(d, d, sqrt2, device),
                    target: init.linear(d, d, 1.0, device),
                    attention: Param::from_tensor(Tensor::from_data(
                        TensorData::new(init.orthogonal(GRAPH_HEADS, d / GRAPH_HEADS, 1.0), [d]),
                        device,
                    )),
                }),
                EncoderKind::Relation => GraphLayer::Relation(RelationLayer {
                    query: init.linear(d, d, 1.0, device),
                    key: init.linear(d, d, 1.0, device),
                    value: init.linear(d, d, 1.0, device),
                    output: init.linear(d, d, 1.0, device),
                    norm_attention: LayerNormConfig::new(d).init(device),
                    hidden: init.linear(d, d, sqrt2, device),
                    back: init.linear(d, d, 1.0, device),
                    norm_mlp: LayerNormConfig::new(d).init(device),
                }),
                EncoderKind::Cnn | EncoderKind::Mlp | EncoderKind::PublicPrivate => {
                    unreachable!(
                        "train_run and TrainedPolicy build GraphEncoder for graph kinds only"
                    )
                }
            })
            .collect();
        let (preembed, modalities, inputs) = if config.network.graph_preembed {
            let m = modalities(game);
            let layers = m
                .iter()
                .map(|&(_, n, out)| init.linear(n, out, sqrt2, device))
                .collect();
            let width = m.iter().map(|&(_, _, out)| out).sum();
            (layers, m.iter().map(|&(at, n, _)| (at, n)).collect(), width)
        } else {
            (Vec::new(), Vec::new(), board.features)
        };
        GraphEncoder {
            preembed,
            input: init.linear(inputs + 1, d, sqrt2, device),
            layers,
            board,
            width: d,
            modalities,
            concat: config.network.graph_readout == GraphReadout::Concat,
        }
    }

    fn output_size(&self) -> usize {
        if self.concat {
            (self.board.cards + self.board.hints + 1) * self.width
        } else {
            2 * self.width
        }
    }

    fn forward(&self, obs: Tensor<2>) -> Tensor<2> {
        let h = self.node_embeddings(obs);
        let [b, v, d] = h.dims();
        if self.concat {
            return h.reshape([b, v * d]);
        }
        let virtual_node = h.clone().narrow(1, v - 1, 1).reshape([b, d]);
        let mean = h.narrow(1, 0, v - 1).mean_dim(1).reshape([b, d]);
        Tensor::cat(vec![virtual_node, mean], 1)
    }
}

impl GraphEncoder {
    /// Every node's embedding after the last layer, `[B, Y+H+1, width]` (cards, hint slots,
    /// then the virtual node).
    pub fn node_embeddings(&self, obs: Tensor<2>) -> Tensor<3> {
        let Board {
            cards: y,
            hints: nh,
            features: f,
            ..
        } = self.board;
        let n = y + nh;
        let [b, _] = obs.dims();
        let device = obs.device();
        let x: Tensor<3> = obs.reshape([b, n, f]);
        // What the layers read of the edges, computed once for all of them: the normalised
        // adjacency (GCN) or the attention mask (GATv2); the relation module reads none.
        let structure = match self.layers.first() {
            Some(GraphLayer::Gcn(_)) => Some(GcnLayer::normalise(self.edges(x.clone()))),
            Some(GraphLayer::Gatv2(_)) => Some(GatLayer::mask(self.edges(x.clone()))),
            _ => None,
        };
        let x = self.preembedded(x);
        let f = x.dims()[2];
        let real = Tensor::cat(vec![x, Tensor::zeros([b, n, 1], &device)], 2);
        let virtual_node = Tensor::cat(
            vec![
                Tensor::zeros([b, 1, f], &device),
                Tensor::ones([b, 1, 1], &device),
            ],
            2,
        );
        let mut h = relu(
            self.input
                .forward_folded(Tensor::cat(vec![real, virtual_node], 1)),
        );
        for layer in &self.layers {
            h = match (layer, &structure) {
                (GraphLayer::Gcn(l), Some(a)) => h.clone() + l.forward(h, a.clone()),
                (GraphLayer::Gatv2(l), Some(m)) => h.clone() + l.forward(h, m.clone()),
                (GraphLayer::Relation(l), _) => l.forward(h),
                _ => unreachable!("every layer of an encoder is of one kind"),
            };
        }
        h
    }

    /// The node features with each modality embedded by its own dense layer, side by side
    /// (`[B, N, 30]` for three colours); the features themselves without pre-embedding.
    pub fn preembedded(&self, x: Tensor<3>) -> Tensor<3> {
        if self.preembed.is_empty() {
            return x;
        }
        let parts = self
            .preembed
            .iter()
            .zip(&self.modalities)
            .map(|(layer, &(at, n))| layer.forward_folded(x.clone().narrow(2, at, n)))
            .collect();
        Tensor::cat(parts, 2)
    }

    /// The graph's edges with self-loops, `[B, V, V]` with V = Y + H + 1 (0 or 1).
    pub fn edges(&self, x: Tensor<3>) -> Tensor<3> {
        let (y, nh) = (self.board.cards, self.board.hints);
        let [b, n, _] = x.dims();
        let v = n + 1;
        let device = x.device();
        let cards = x.clone().narrow(1, 0, y);
        let card_card = self
            .board
            .card_adjacency(&self.board.positions(cards.clone()));
        let hint_card = self.board.hint_on_card(x.narrow(1, y, nh), cards);
        let ones = |rows: usize, cols: usize| Tensor::<3>::ones([b, rows, cols], &device);
        let top = Tensor::cat(
            vec![card_card, hint_card.clone().swap_dims(1, 2), ones(y, 1)],
            2,
        );
        let middle = Tensor::cat(
            vec![hint_card, Tensor::zeros([b, nh, nh], &device), ones(nh, 1)],
            2,
        );
        let bottom = Tensor::cat(vec![ones(1, n), Tensor::zeros([b, 1, 1], &device)], 2);
        let mut eye = vec![0f32; v * v];
        for i in 0..v {
            eye[i * v + i] = 1.0;
        }
        let eye: Tensor<3> = Tensor::from_data(TensorData::new(eye, [1, v, v]), &device);
        Tensor::cat(vec![top, middle, bottom], 1) + eye.expand([b, v, v])
    }
}

impl GcnLayer {
    /// `D^-½ (A + I) D^-½` from the edges with self-loops.
    fn normalise(edges: Tensor<3>) -> Tensor<3> {
        let [b, v, _] = edges.dims();
        let scale = edges.clone().sum_dim(2).powf_scalar(-0.5);
        edges * scale.clone().expand([b, v, v]) * scale.swap_dims(1, 2).expand([b, v, v])
    }

    fn forward(&self, h: Tensor<3>, normalised: Tensor<3>) -> Tensor<3> {
        relu(normalised.matmul(self.weight.forward_folded(h)))
    }
}

impl GatLayer {
    /// `[B, V, V]`: 0 on the edges, −10⁹ elsewhere (nothing after the softmax).
    fn mask(edges: Tensor<3>) -> Tensor<3> {
        (edges - 1.0).mul_scalar(1e9)
    }

    fn forward(&self, h: Tensor<3>, blocked: Tensor<3>) -> Tensor<3> {
        let [b, v, d] = h.dims();
        let (heads, dh) = (GRAPH_HEADS, d / GRAPH_HEADS);
        let source = self.source.forward_folded(h.clone());
        let target = self.target.forward_folded(h);
        // s[b, i, j] = W_t h_i + W_s h_j for every pair, then the score per head.
        let pairs = target.reshape([b, v, 1, d]).expand([b, v, v, d])
            + source.clone().reshape([b, 1, v, d]).expand([b, v, v, d]);
        let a: Tensor<4> = self.attention.val().reshape([1, 1, 1, d]);
        let scores: Tensor<4> = (leaky_relu(pairs, 0.2) * a.expand([b, v, v, d]))
            .reshape([b, v, v, heads, dh])
            .sum_dim(4)
            .reshape([b, v, v, heads]);
        let alpha = softmax(
            scores + blocked.reshape([b, v, v, 1]).expand([b, v, v, heads]),
            2,
        )
        .permute([0, 3, 1, 2]);
        let messages = source.reshape([b, v, heads, dh]).permute([0, 2, 1, 3]);
        relu(
            alpha
                .matmul(messages)
                .permute([0, 2, 1, 3])
                .reshape([b, v, d]),
        )
    }
}

impl RelationLayer {
    fn forward(&self, h: Tensor<3>) -> Tensor<3> {
        let [b, v, d] = h.dims();
        let (heads, dh) = (GRAPH_HEADS, d / GRAPH_HEADS);
        let split = |t: Tensor<3>| t.reshape([b, v, heads, dh]).swap_dims(1, 2);
        let q = split(self.query.forward_folded(h.clone()));
        let k = split(self.key.forward_folded(h.clone()));
        let values = split(self.value.forward_folded(h.clone()));
        let scores = q.matmul(k.swap_dims(2, 3)).div_scalar((dh as f32).sqrt());
        let attended = softmax(scores, 3)
            .matmul(values)
            .swap_dims(1, 2)
            .reshape([b, v, d]);
        let h = self
            .norm_attention
            .forward(h + self.output.forward_folded(attended));
        let mlp = self
            .back
            .forward_folded(relu(self.hidden.forward_folded(h.clone())));
        self.norm_mlp.forward(h + mlp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::board::tests::to_vec;
    use rand_chacha::rand_core::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use yokai_engine::{Card, Game, Seat};

    fn encoder(kind: EncoderKind, game: &Config, seed: u64) -> GraphEncoder {
        encoder_with(kind, game, seed, false, GraphReadout::Pooled)
    }

    fn encoder_with(
        kind: EncoderKind,
        game: &Config,
        seed: u64,
        preembed: bool,
        readout: GraphReadout,
    ) -> GraphEncoder {
        let mut config = TrainConfig::from_toml_str("", "test").unwrap();
        config.network.encoder = Some(kind);
        config.network.graph_preembed = preembed;
        config.network.graph_readout = readout;
        GraphEncoder::new(&config, game, &mut Init::new(seed), &Device::flex())
    }

    /// Node features of seat 0 after `steps` random legal actions from deal `deal`.
    fn features_after(game_config: Config, deal: u64, steps: usize) -> Vec<f32> {
        features(&play(game_config, deal, steps))
    }

    /// The game after `steps` random legal actions from deal `deal` (or its end).
    fn play(game_config: Config, deal: u64, steps: usize) -> Game {
        let mut game = Game::new(game_config, deal);
        let mut rng = ChaCha8Rng::seed_from_u64(deal);
        for _ in 0..steps {
            if game.is_over() {
                break;
            }
            let legal = game.legal_actions(game.current_seat());
            game.apply(legal[(rng.next_u64() % legal.len() as u64) as usize])
                .unwrap();
        }
        game
    }

    fn features(game: &Game) -> Vec<f32> {
        let [n, f] = game.config().node_shape(Part::Full);
        let mut x = vec![0f32; n * f];
        game.view(Seat(0)).write_nodes(Part::Full, &mut x).unwrap();
        x
    }

    /// The largest difference between the two rows of a 2-row output, flattened.
    fn halves_gap(out: Vec<f32>) -> f32 {
        let (a, b) = out.split_at(out.len() / 2);
        a.iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f32::max)
    }

    fn batch(rows: &[Vec<f32>]) -> Tensor<2> {
        let width = rows[0].len();
        Tensor::from_data(
            TensorData::new(rows.concat(), [rows.len(), width]),
            &Device::flex(),
        )
    }

    /// Relabelling cards (their node rows permuted; the hints that point at them follow,
    /// since a placed hint names its card by the id channel, which moves with the row) and
    /// permuting hint slots leave every graph encoder's output unchanged, while each node's
    /// own embedding moves with its node (equivariance). Checked on states of random play,
    /// with hints placed, in 9c and 16c.
    #[test]
    fn graph_encoders_are_invariant_to_relabelling_cards_and_hint_slots() {
        for name in ["9c-2p-perfect", "16c-2p-perfect"] {
            let game = Config::from_name(name).unwrap();
            let [n, f] = game.node_shape(Part::Full);
            let (y, nh) = (game.cards(), game.hints());
            let mut rng = ChaCha8Rng::seed_from_u64(11);
            let kinds = [EncoderKind::Gcn, EncoderKind::Gatv2, EncoderKind::Relation];
            for (kind, preembed) in kinds.into_iter().flat_map(|k| [(k, false), (k, true)]) {
                let net = encoder_with(kind, &game, 5, preembed, GraphReadout::Pooled);
                for deal in 0..3 {
                    let x = features_after(game, deal, 25 + 10 * deal as usize);
                    // A random permutation of the cards and one of the hint slots.
                    let mut order: Vec<usize> = (0..y).collect();
                    let mut slots: Vec<usize> = (y..n).collect();
                    for i in (1..y).rev() {
                        order.swap(i, (rng.next_u64() % (i as u64 + 1)) as usize);
                    }
                    for i in (1..nh).rev() {
                        slots.swap(i, (rng.next_u64() % (i as u64 + 1)) as usize);
                    }
                    order.extend(slots);
                    let permuted: Vec<f32> = order
                        .iter()
                        .flat_map(|&i| x[i * f..][..f].to_vec())
                        .collect();
                    let gap =
                        halves_gap(to_vec(net.forward(batch(&[x.clone(), permuted.clone()]))));
                    assert!(gap < 1e-4, "{name} {kind:?}: output moved by {gap}");
                    let nodes = to_vec(net.node_embeddings(batch(&[x, permuted])));
                    let d = nodes.len() / 2 / (n + 1);
                    let (first, second) = nodes.split_at(nodes.len() / 2);
                    for (to, &from) in order.iter().enumerate() {
                        for c in 0..d {
                            let (p, q) = (first[from * d + c], second[to * d + c]);
                            assert!((p - q).abs() < 1e-4, "{name} {kind:?} node {from}");
                        }
                    }
                }
            }
        }
    }

    /// Pre-embedding gives every feature channel to exactly one modality, and each
    /// modality's block of the embedding reads only its own channels. The concatenating
    /// readout hands on every node's embedding, in node order.
    #[test]
    fn preembedding_reads_each_modality_apart_and_concat_hands_on_every_node() {
        for name in ["9c-2p-perfect", "16c-4p-perfect"] {
            let game = Config::from_name(name).unwrap();
            let [n, f] = game.node_shape(Part::Full);
            let m = modalities(&game);
            let mut channels: Vec<usize> = m.iter().flat_map(|&(at, k, _)| at..at + k).collect();
            channels.sort();
            assert_eq!(channels, (0..f).collect::<Vec<_>>(), "{name}");
            let widths: usize = m.iter().map(|&(_, _, out)| out).sum();
            assert_eq!(
                widths,
                2 * 4 + 4 * 4 + 2 + 4,
                "the paper's sizes, and hint colours"
            );
            let net = encoder_with(EncoderKind::Gcn, &game, 3, true, GraphReadout::Concat);
            let x = features_after(game, 1, 30);
            let base = to_vec(net.preembedded(batch(std::slice::from_ref(&x)).reshape([1, n, f])));
            let mut block = 0;
            for &(at, k, out) in &m {
                let mut changed = x.clone();
                for node in 0..n {
                    for c in at..at + k {
                        changed[node * f + c] += 0.5;
                    }
                }
                let moved = to_vec(net.preembedded(batch(&[changed]).reshape([1, n, f])));
                for node in 0..n {
                    for j in 0..widths {
                        let gap = (base[node * widths + j] - moved[node * widths + j]).abs();
                        let inside = (block..block + out).contains(&j);
                        assert_eq!(gap > 1e-6, inside, "{name}: channels {at}.. and value {j}");
                    }
                }
                block += out;
            }
            let nodes = to_vec(net.node_embeddings(batch(std::slice::from_ref(&x))));
            assert_eq!(net.output_size(), (n + 1) * 64);
            assert_eq!(to_vec(net.forward(batch(&[x]))), nodes);
        }
    }

    /// The graph carries the board: moving one card to another cell changes the graph
    /// encoders' output (and the graph's edges), and so does a different observation.
    #[test]
    fn graph_encoders_read_the_board() {
        let game = Config::from_name("9c-2p-perfect").unwrap();
        let [_, f] = game.node_shape(Part::Full);
        let ch = game.image_channels();
        let x = features_after(game, 3, 30);
        // Card 0 to the far corner (row 0, column 0): its edges change.
        let mut moved = x.clone();
        moved[ch.row] = 0.0;
        moved[ch.col] = 0.0;
        assert_ne!(moved, x, "card 0 was already in the corner");
        for kind in [EncoderKind::Gcn, EncoderKind::Gatv2, EncoderKind::Relation] {
            let net = encoder(kind, &game, 2);
            let [n, _] = game.node_shape(Part::Full);
            let edges = |x: &[f32]| to_vec(net.edges(batch(&[x.to_vec()]).reshape([1, n, f])));
            assert_ne!(edges(&x), edges(&moved));
            let gap = halves_gap(to_vec(net.forward(batch(&[x.clone(), moved.clone()]))));
            assert!(
                gap > 1e-3,
                "{kind:?}: moving a card changed nothing ({gap})"
            );
        }
    }

    /// Edges: symmetric, self-loops everywhere, the virtual node joined to every node, and
    /// each card's degree (without the self-loop and the virtual node) equal to its number
    /// of 4-neighbours plus its hint.
    #[test]
    fn graph_edges_are_symmetric_with_a_virtual_node() {
        let game = Config::from_name("9c-2p-perfect").unwrap();
        let [n, f] = game.node_shape(Part::Full);
        let net = encoder(EncoderKind::Gcn, &game, 1);
        let v = n + 1;
        let y = game.cards();
        let mut hinted = 0;
        for deal in 0..4 {
            let state = play(game, deal, 40);
            let e = to_vec(net.edges(batch(&[features(&state)]).reshape([1, n, f])));
            for i in 0..v {
                assert_eq!(e[i * v + i], 1.0, "self-loop of {i}");
                assert_eq!(e[i * v + n], 1.0, "{i} joined to the virtual node");
                for j in 0..v {
                    assert_eq!(e[i * v + j], e[j * v + i], "({i}, {j})");
                }
            }
            for k in 0..y {
                let card = Card(k as u8);
                let cell = state.cell_of(card);
                let beside = (0..y)
                    .filter(|&j| {
                        let other = state.cell_of(Card(j as u8));
                        other.row.abs_diff(cell.row) + other.col.abs_diff(cell.col) == 1
                    })
                    .count();
                let hint = state.hint_on(card).is_some() as usize;
                hinted += hint;
                let degree: f32 = (0..n).filter(|&j| j != k).map(|j| e[k * v + j]).sum();
                assert_eq!(degree, (beside + hint) as f32, "deal {deal} card {k}");
            }
        }
        assert!(hinted > 0, "no hint placed in the states checked");
    }
}

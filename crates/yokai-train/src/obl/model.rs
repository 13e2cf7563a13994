//! The belief model B of OBL levels above 1: what a seat's history says about every card's
//! colour, as a distribution it can sample colourings from.
//!
//! - **Encoder**: the compact network's per-card MLP and a GRU over the seat's observations
//!   (its own memory, separate from the policy's).
//! - **Autoregressive decoder** over card ids 0..Y−1: slot k's colour logits read the GRU
//!   state, card k's node features, the colours of its 4-neighbours as far as the decoder
//!   knows them (drawn before it, or seen first-hand), and how many cards of each colour are
//!   still *available* to it — the colour count Y/C minus the colours of the cards before it
//!   (sampled, or the true ones when training) minus the first-hand colours of the cards
//!   after it. The neighbours' colours carry what a clustering convention says ("my partner
//!   put this card next to that one"), which one summary state reads poorly. Colours
//!   with none available are masked, and a card the seat has seen first-hand takes its
//!   colour, so every sample holds the colour counts and the seat's own knowledge exactly.
//!   Hints are read as features, not as constraints: a placed hint may be wrong.
//!
//! Under uniformly random play the exact belief is uniform over the consistent colourings,
//! whose conditional at slot k is available_c / Σ available: the model can represent it
//! from its inputs, and `obl::learn` measures how close it gets (KL in nats).

use crate::config::{NetworkPreset, TrainConfig};
use crate::distribution::{masked_log_softmax, sample_row, unit_draw};
use crate::init::Init;
use crate::network::{Encoder, GruCell, MlpEncoder, Recurrent};
use burn::module::Module;
use burn::nn::Linear;
use burn::prelude::*;
use burn::tensor::activation::relu;
use burn::tensor::TensorData;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{Colour, Config, Part};

/// Width of the decoder's hidden layer.
const SLOT_WIDTH: usize = 64;

/// A seat's colour knowledge per card: `Some(colour)` where it has seen the card itself.
pub type FirstHand = [Option<u8>];

#[derive(Module, Debug)]
pub struct BeliefModel {
    encoder: MlpEncoder,
    embed: Linear,
    gru: GruCell,
    slot: Linear,
    out: Linear,
    /// ln(available count) → logits, added to the decoder's output: with it the exact
    /// belief of uncommitted play (colour ∝ available count) is one identity matrix away,
    /// and what the history adds is learnt on top.
    count_prior: Linear,
    /// Cards, colours, node features, hidden size.
    #[module(skip)]
    shape: [usize; 4],
    /// Cards of each colour (scales the available counts to [0, 1]).
    #[module(skip)]
    per_colour: usize,
}

/// How many of card `k`'s 4-neighbours (`adjacency` `[Y, Y]`, 1 for neighbours) have each
/// colour as far as slot `k` knows: drawn before it (`before`) or seen first-hand.
fn neighbour_colours(
    colours: usize,
    adjacency: &[f32],
    before: &[u8],
    first_hand: &FirstHand,
    k: usize,
) -> Vec<usize> {
    let y = first_hand.len();
    let mut counts = vec![0; colours];
    for j in (0..y).filter(|&j| adjacency[k * y + j] > 0.5) {
        let known = if j < k {
            Some(before[j])
        } else {
            first_hand[j]
        };
        if let Some(c) = known {
            counts[c as usize] += 1;
        }
    }
    counts
}

/// The decoder's inputs for a batch of (seat, card slot) pairs, gathered on the CPU: the
/// card's node features, its neighbours' known colours and the colours available to it.
#[derive(Clone, Debug, Default)]
pub struct SlotInputs {
    card: Vec<f32>,
    around: Vec<f32>,
    /// Per pair, per colour: the available count (also the sampling mask: > 0).
    pub avail: Vec<f32>,
}

impl SlotInputs {
    /// Add card `k`'s slot of one seat: its graph observation `obs` (cards first, `features`
    /// values per node), the card adjacency `[Y, Y]`, the colours of the slots before `k`
    /// and the seat's first-hand colours. Returns the counts available to the slot.
    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        game: &Config,
        features: usize,
        obs: &[f32],
        adjacency: &[f32],
        before: &[u8],
        first_hand: &FirstHand,
        k: usize,
    ) -> Vec<usize> {
        self.card
            .extend_from_slice(&obs[k * features..][..features]);
        let around = neighbour_colours(game.colours(), adjacency, before, first_hand, k);
        self.around.extend(around.iter().map(|&x| x as f32));
        let avail = available(game, before, first_hand, k);
        self.avail.extend(avail.iter().map(|&x| x as f32));
        avail
    }
}

/// The colours still available to slot `k` (see the module docs), given the colours of the
/// slots before it and the first-hand colours of those after it.
fn available(config: &Config, before: &[u8], first_hand: &FirstHand, k: usize) -> Vec<usize> {
    let mut left = vec![config.cards_per_colour(); config.colours()];
    for &c in before {
        left[c as usize] -= 1;
    }
    for c in first_hand[k + 1..].iter().flatten() {
        left[*c as usize] -= 1;
    }
    left
}

impl BeliefModel {
    /// A freshly initialised model of width `hidden` for `game`; a pure function of `seed`.
    pub fn new(game: &Config, hidden: usize, seed: u64, device: &Device) -> BeliefModel {
        let mut init = Init::new(seed);
        let mut config = TrainConfig::default();
        config.network.preset = NetworkPreset::Compact;
        config.network.hidden = hidden;
        let encoder = MlpEncoder::new(&config, game, &mut init, device);
        let [_, features] = game.node_shape(Part::Full);
        let (y, c) = (game.cards(), game.colours());
        let sqrt2 = std::f64::consts::SQRT_2;
        BeliefModel {
            embed: init.linear(encoder.output_size(), hidden, sqrt2, device),
            encoder,
            gru: GruCell::new(hidden, hidden, &mut init, device),
            slot: init.linear(hidden + features + 2 * c, SLOT_WIDTH, sqrt2, device),
            out: init.linear(SLOT_WIDTH, c, 0.01, device),
            count_prior: init.linear(c, c, 0.01, device),
            shape: [y, c, features, hidden],
            per_colour: game.cards_per_colour(),
        }
    }

    pub fn hidden_size(&self) -> usize {
        self.shape[3]
    }

    /// One step of the memory for `B` rows: observations `[B, L]` (graph, full), states
    /// `[B, H]`, `keep` `[B, 1]` (0 where an episode starts). The new states.
    pub fn step(&self, obs: Tensor<2>, h: Tensor<2>, keep: Tensor<2>) -> Tensor<2> {
        let x = relu(self.embed.forward(self.encoder.forward(obs)));
        self.gru.step(self.gru.project(x), h * keep)
    }

    /// Unroll `T` steps for `B` sequences (`obs` `[B, T, L]`, `h0` `[B, H]`, `keep`
    /// `[B, T]`): the state after every step, `[B·T, H]` in `(b, t)` order.
    pub fn unroll(&self, obs: Tensor<3>, h0: Tensor<2>, keep: Tensor<2>) -> Tensor<2> {
        let [b, t, l] = obs.dims();
        let x = relu(
            self.embed
                .forward(self.encoder.forward(obs.reshape([b * t, l]))),
        );
        let gx = self
            .gru
            .project(x)
            .reshape([b, t, self.gru.projected_size()]);
        self.gru
            .unroll(gx, h0, keep)
            .reshape([b * t, self.hidden_size()])
    }

    /// Width of a node's features in the graph observation.
    pub fn features(&self) -> usize {
        self.shape[2]
    }

    /// Log-probabilities `[R, C]` of the colours of `R` (seat, slot) pairs: their states
    /// `[R, H]` and their [`SlotInputs`].
    pub fn log_probs(&self, states: Tensor<2>, inputs: &SlotInputs) -> Tensor<2> {
        let [_, c, f, _] = self.shape;
        let rows = inputs.avail.len() / c;
        let device = states.device();
        let t = |v: &[f32], w: usize| {
            Tensor::from_data(TensorData::new(v.to_vec(), [rows, w]), &device)
        };
        self.slot_log_probs(
            states,
            t(&inputs.card, f),
            t(&inputs.around, c),
            t(&inputs.avail, c),
        )
    }

    /// Log-probabilities `[R, C]` of one slot's colour for `R` (row, slot) pairs: their
    /// states `[R, H]`, the slot's card features `[R, F]`, its neighbours' known colours
    /// `[R, C]` and available counts `[R, C]`.
    fn slot_log_probs(
        &self,
        states: Tensor<2>,
        card: Tensor<2>,
        neighbours: Tensor<2>,
        avail: Tensor<2>,
    ) -> Tensor<2> {
        let per = self.per_colour as f32;
        let mask = avail.clone().greater_elem(0.0).float();
        let log_count = avail.clone().clamp_min(1.0).log();
        let x = Tensor::cat(vec![states, card, neighbours / 4.0, avail / per], 1);
        let logits =
            self.out.forward(relu(self.slot.forward(x))) + self.count_prior.forward(log_count);
        masked_log_softmax(logits, mask)
    }

    /// Draw one colouring for each of `n` seats: their states `[n, H]`, graph observations
    /// (`obs`, `[n × L]`, cards first), card adjacencies (`[n × Y × Y]`) and first-hand
    /// colours (`[n × Y]`). Slots go in card order, each conditioned on the colours drawn
    /// before it; each slot is one batched pass over the seats that have not seen the card.
    pub fn sample(
        &self,
        game: &Config,
        states: Tensor<2>,
        obs: &[f32],
        adjacency: &[f32],
        first_hand: &FirstHand,
        rng: &mut ChaCha8Rng,
    ) -> Vec<Vec<Colour>> {
        let [y, c, f, _] = self.shape;
        let n = states.dims()[0];
        let l = obs.len() / n.max(1);
        let device = states.device();
        let mut drawn: Vec<Vec<u8>> = vec![Vec::with_capacity(y); n];
        for k in 0..y {
            let open: Vec<usize> = (0..n)
                .filter(|&i| first_hand[i * y + k].is_none())
                .collect();
            let mut inputs = SlotInputs::default();
            for &i in &open {
                let (obs, adjacency) = (&obs[i * l..][..l], &adjacency[i * y * y..][..y * y]);
                inputs.push(
                    game,
                    f,
                    obs,
                    adjacency,
                    &drawn[i],
                    &first_hand[i * y..][..y],
                    k,
                );
            }
            let log_p = if open.is_empty() {
                Vec::new()
            } else {
                let idx: Vec<i64> = open.iter().map(|&i| i as i64).collect();
                let rows = Tensor::<1, Int>::from_data(TensorData::new(idx, [open.len()]), &device);
                crate::tensor::to_vec(self.log_probs(states.clone().select(0, rows), &inputs))
            };
            let mut next = 0;
            for (i, colours) in drawn.iter_mut().enumerate() {
                if let Some(colour) = first_hand[i * y + k] {
                    colours.push(colour);
                    continue;
                }
                // The available counts mask the colours none of which is left.
                let (lp, avail) = (&log_p[next * c..][..c], &inputs.avail[next * c..][..c]);
                next += 1;
                let (colour, _, _) = sample_row(lp, avail, unit_draw(rng), false);
                colours.push(colour as u8);
            }
        }
        drawn
            .into_iter()
            .map(|x| x.into_iter().map(Colour).collect())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::obl::first_hand_slots;
    use rand_chacha::rand_core::{Rng, SeedableRng};
    use yokai_engine::{Game, Seat};

    /// Whatever its weights, the model's samples keep the colour counts and the seat's
    /// first-hand colours: over random histories in 9c and 16c, from random states, drawn
    /// one seat at a time and all 30 seats in one batch.
    #[test]
    fn samples_keep_first_hand_colours_and_the_counts() {
        let device = Device::flex();
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for name in ["9c-2p-perfect", "16c-2p-perfect", "9c-3p-imperfect"] {
            let config = Config::from_name(name).unwrap();
            let y = config.cards();
            let model = BeliefModel::new(&config, 16, 7, &device);
            let l: usize = config.node_shape(Part::Full).iter().product();
            let (mut games, mut states, mut obs, mut adjacency, mut first) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for case in 0..30u64 {
                let mut game = Game::new(config, case);
                for _ in 0..(case as usize * 3) % config.max_episode_len() {
                    if game.is_over() {
                        break;
                    }
                    let legal = game.legal_actions(game.current_seat());
                    game.apply(legal[(rng.next_u64() % legal.len() as u64) as usize])
                        .unwrap();
                }
                let seat = Seat((case % config.players() as u64) as u8);
                first.extend(first_hand_slots(&game, seat));
                let at = obs.len();
                obs.resize(at + l, 0f32);
                game.write_nodes(seat, Part::Full, &mut obs[at..]).unwrap();
                let at = adjacency.len();
                adjacency.resize(at + y * y, 0f32);
                game.write_adjacency(&mut adjacency[at..]).unwrap();
                states.extend((0..16).map(|_| (rng.next_u64() % 200) as f32 / 100.0 - 1.0));
                games.push(game);
            }
            let n = games.len();
            let tensor = |rows: std::ops::Range<usize>| {
                let v = states[rows.start * 16..rows.end * 16].to_vec();
                Tensor::from_data(TensorData::new(v, [rows.len(), 16]), &device)
            };
            let batch = model.sample(&config, tensor(0..n), &obs, &adjacency, &first, &mut rng);
            for (i, game) in games.iter().enumerate() {
                let one = model
                    .sample(
                        &config,
                        tensor(i..i + 1),
                        &obs[i * l..][..l],
                        &adjacency[i * y * y..][..y * y],
                        &first[i * y..][..y],
                        &mut rng,
                    )
                    .remove(0);
                for sample in [&batch[i], &one] {
                    for (k, known) in first[i * y..][..y].iter().enumerate() {
                        if let Some(c) = known {
                            assert_eq!(sample[k].0, *c, "{name} case {i}: card {k}");
                        }
                    }
                    let mut counts = vec![0; config.colours()];
                    for c in sample {
                        counts[c.index()] += 1;
                    }
                    assert!(
                        counts.iter().all(|&n| n == config.cards_per_colour()),
                        "{name}: {counts:?}"
                    );
                    game.with_card_colours(sample).unwrap();
                }
            }
        }
    }
}

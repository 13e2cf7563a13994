//! The recurrent actor-critic: an observation encoder, a GRU memory, and actor and critic
//! heads, with parameters shared by every seat.
//!
//! Encoders are swappable behind [`Encoder`]; the trainer and the policy loader are generic
//! over it. The GRU is our own cell built from two linear maps, because burn's `Gru` cannot
//! reset its state inside a sequence and PPO rollouts contain episode starts anywhere.

mod board;
mod graph;
pub mod gru_sequence;
mod pointer;
mod public_private;
mod trxl;

pub use graph::GraphEncoder;
pub use pointer::{MoveRows, PointerHead};
pub use public_private::PublicPrivateEncoder;
pub use trxl::TransformerXl;

use crate::config::{ActionHead, CriticInput, EncoderKind, MemoryKind, NetworkConfig, TrainConfig};
use crate::init::Init;
use crate::seen::SeenSeat;
use burn::module::Module;
use burn::nn::conv::Conv2d;
use burn::nn::Linear;
use burn::prelude::*;
use burn::tensor::activation::{relu, sigmoid, tanh};
use yokai_engine::{Config, ImageLayout, Part};
use yokai_vec::Encoding;

/// A batch of rows' action logits as the learner reads them.
// One value per shard and minibatch, moved once: the size of its handles does not matter.
#[allow(clippy::large_enum_variant)]
pub enum ActionLogits {
    /// Every row's logit of every action, `[rows, N_a]` (the dense head).
    Every(Tensor<2>),
    /// The pointer head's, where MOVE can be legal only at the MOVE substep: every row's
    /// logits of the other actions `[rows, N_a − Y·g²]` (action order, the MOVE block cut
    /// out) and the MOVE logits `[m, Y·g²]` of the `m` rows at the MOVE substep, in the
    /// order the caller named them.
    Split { others: Tensor<2>, moves: Tensor<2> },
}

/// Work to do with the network types a config names, whichever they are: [`for_network`]
/// calls `run` with the encoder and memory types of a `NetworkConfig`. Training a run and
/// loading a policy file are both such jobs.
pub trait NetworkJob {
    type Output;
    fn run<E: Encoder + 'static, M: Recurrent + 'static>(self) -> Self::Output;
}

/// Run `job` with the encoder and memory types `network` names: the one place that maps a
/// config's `network.encoder` × `network.memory` to Rust types, so a new encoder or memory
/// is one line here.
pub fn for_network<J: NetworkJob>(network: &NetworkConfig, job: J) -> J::Output {
    use EncoderKind::*;
    match (network.encoder(), network.memory) {
        (Cnn, MemoryKind::Gru) => job.run::<CnnEncoder, GruCell>(),
        (PublicPrivate, MemoryKind::Gru) => job.run::<PublicPrivateEncoder, GruCell>(),
        (Mlp, MemoryKind::Gru) => job.run::<MlpEncoder, GruCell>(),
        (Gcn | Gatv2 | Relation, MemoryKind::Gru) => job.run::<GraphEncoder, GruCell>(),
        (Cnn, MemoryKind::Trxl) => job.run::<CnnEncoder, TransformerXl>(),
        (PublicPrivate, MemoryKind::Trxl) => job.run::<PublicPrivateEncoder, TransformerXl>(),
        (Mlp, MemoryKind::Trxl) => job.run::<MlpEncoder, TransformerXl>(),
        (Gcn | Gatv2 | Relation, MemoryKind::Trxl) => job.run::<GraphEncoder, TransformerXl>(),
    }
}

/// The observation encoding the encoder `network` names reads (what a trainer outside Rust
/// must show it).
pub fn encoding_of(network: &NetworkConfig) -> Encoding {
    struct Reads;
    impl NetworkJob for Reads {
        type Output = Encoding;
        fn run<E: Encoder + 'static, M: Recurrent + 'static>(self) -> Encoding {
            E::encoding()
        }
    }
    for_network(network, Reads)
}

/// Maps a batch of flattened observations `[B, L]` to embeddings `[B, output_size]`.
pub trait Encoder: Module + burn::module::ModuleDisplay + Sized + Sync {
    /// The `network.encoder` kinds this type implements (a checkpoint's config names one).
    const KINDS: &'static [EncoderKind];
    /// The observation encoding the encoder reads.
    fn encoding() -> Encoding;
    fn new(config: &TrainConfig, game: &Config, init: &mut Init, device: &Device) -> Self;
    fn output_size(&self) -> usize;
    fn forward(&self, obs: Tensor<2>) -> Tensor<2>;
}

/// The paper's encoder: 4 × Conv2d(filters, 3×3, stride 1, valid) with ReLU over the image
/// `[g, g+1, F]`, flattened.
#[derive(Module, Debug)]
pub struct CnnEncoder {
    convs: Vec<Conv2d>,
    /// Image rows, columns and channels.
    #[module(skip)]
    shape: [usize; 3],
    #[module(skip)]
    out: usize,
}

impl Encoder for CnnEncoder {
    const KINDS: &'static [EncoderKind] = &[EncoderKind::Cnn];
    fn encoding() -> Encoding {
        Encoding::Image(Part::Full, ImageLayout::Hwc)
    }
    fn new(config: &TrainConfig, game: &Config, init: &mut Init, device: &Device) -> Self {
        let shape = game.image_shape(Part::Full);
        let f = config.network.filters;
        let convs = conv_layers(init, shape[2], f, device);
        let out = (shape[0] - 8) * (shape[1] - 8) * f;
        CnnEncoder { convs, shape, out }
    }
    fn output_size(&self) -> usize {
        self.out
    }
    fn forward(&self, obs: Tensor<2>) -> Tensor<2> {
        let [b, _] = obs.dims();
        let [h, w, c] = self.shape;
        conv_stack(&self.convs, obs.reshape([b, h, w, c]))
    }
}

/// The paper's four 3×3 convolutions (`filters` each, valid padding) over `c_in` channels.
fn conv_layers(init: &mut Init, c_in: usize, filters: usize, device: &Device) -> Vec<Conv2d> {
    let gain = std::f64::consts::SQRT_2;
    (0..4)
        .map(|i| init.conv3x3(if i == 0 { c_in } else { filters }, filters, gain, device))
        .collect()
}

/// `x` `[B, H, W, C]` (channels last, as the image observation is laid out) through
/// `convs`, each followed by a ReLU, flattened channels first to `[B, F·H'·W']`: what
/// `Conv2d::forward` on the channels-first image gives, in the same order, so policy files
/// read the same.
fn conv_stack(convs: &[Conv2d], mut x: Tensor<4>) -> Tensor<2> {
    let [b, ..] = x.dims();
    for conv in convs {
        x = relu(conv3x3_by_patches(conv, x));
    }
    x.permute([0, 3, 1, 2]).reshape([b as i64, -1])
}

/// One 3×3 valid convolution of stride 1 (what [`conv_layers`] makes) on a channels-last
/// `x` `[B, H, W, C]`, computed as one matrix product: the nine shifted views of `x`
/// side by side along the channels are each output cell's 3×3 patch, `[B·H'·W', 9·C]`, and
/// the kernel `[F, C, 3, 3]` is read as a `[9·C, F]` matrix; the bias is the matrix's last
/// row, against a column of ones beside the patches.
///
/// Why not `Conv2d::forward`: the GPU build (no CubeCL autotune) runs it with burn's direct
/// convolution kernel, which took 72 % of an update's GPU time at the paper's batch on an
/// H200. Why the bias inside the product: added after it, its gradient is a sum over the
/// B·H'·W' rows, and the reduction that (by its four launches per gradient step) makes it
/// took 56 % of the GPU time; inside, the product's own backward makes it
/// (docs/results/gpu-h200-3.md).
fn conv3x3_by_patches(conv: &Conv2d, x: Tensor<4>) -> Tensor<4> {
    let [b, h, w, c] = x.dims();
    let (h_out, w_out) = (h - 2, w - 2);
    let shifts = (0..3).flat_map(|i| (0..3).map(move |j| (i, j)));
    let mut views: Vec<Tensor<4>> = shifts
        .map(|(i, j)| x.clone().slice([0..b, i..i + h_out, j..j + w_out, 0..c]))
        .collect();
    let weight = conv.weight.val();
    let [f, ..] = weight.dims();
    // kernel[(i·3 + j)·C + c, f] = weight[f, c, i, j], the patches' feature order.
    let mut kernel = weight.permute([2, 3, 1, 0]).reshape([9 * c, f]);
    if let Some(bias) = &conv.bias {
        views.push(Tensor::ones([b, h_out, w_out, 1], &x.device()));
        kernel = Tensor::cat(vec![kernel, bias.val().unsqueeze_dim(0)], 0);
    }
    let [rows, _] = kernel.dims();
    let patches = Tensor::cat(views, 3).reshape([b * h_out * w_out, rows]);
    patches.matmul(kernel).reshape([b, h_out, w_out, f])
}

/// The compact encoder: one small MLP shared by every node (card or hint slot) of the
/// graph observation, then a linear layer over all node embeddings in order. Sharing the
/// per-node layer means what it learns about one card (its colour, its hint) holds for all
/// of them. Cheap enough to learn on a CPU.
#[derive(Module, Debug)]
pub struct MlpEncoder {
    node: Linear,
    mix: Linear,
    #[module(skip)]
    nodes: usize,
    #[module(skip)]
    features: usize,
    #[module(skip)]
    width: usize,
    #[module(skip)]
    out: usize,
}

/// Width of a node embedding.
const NODE_WIDTH: usize = 32;

impl Encoder for MlpEncoder {
    const KINDS: &'static [EncoderKind] = &[EncoderKind::Mlp];
    fn encoding() -> Encoding {
        Encoding::Graph(Part::Full)
    }
    fn new(config: &TrainConfig, game: &Config, init: &mut Init, device: &Device) -> Self {
        let [nodes, features] = game.node_shape(Part::Full);
        let out = config.network.hidden;
        let sqrt2 = std::f64::consts::SQRT_2;
        MlpEncoder {
            node: init.linear(features, NODE_WIDTH, sqrt2, device),
            mix: init.linear(nodes * NODE_WIDTH, out, sqrt2, device),
            nodes,
            features,
            width: NODE_WIDTH,
            out,
        }
    }
    fn output_size(&self) -> usize {
        self.out
    }
    fn forward(&self, obs: Tensor<2>) -> Tensor<2> {
        let [b, _] = obs.dims();
        let per_node = relu(
            self.node
                .forward(obs.reshape([b * self.nodes, self.features])),
        );
        relu(
            self.mix
                .forward(per_node.reshape([b, self.nodes * self.width])),
        )
    }
}

/// The network's recurrent memory, stepped one time step at a time (the caller zeroes a
/// row's state where an episode starts). Named `Recurrent`, not `Memory`, because the
/// engine's `Memory` is the game's memory mode (perfect or imperfect). A step is split in
/// two so that BPTT computes the part that depends only on the input for a whole sequence in
/// one matrix product.
///
/// The state is one flat vector per row, whatever the memory keeps in it (a GRU its hidden
/// vector; a Transformer-XL its output and its window of past inputs): the trainer stores,
/// resets and checkpoints it without knowing its layout, and the heads read
/// [`Recurrent::output`] of it.
pub trait Recurrent: Module + burn::module::ModuleDisplay + Sized + Sync {
    /// The `network.memory` this type implements (a checkpoint's config names one).
    const KIND: MemoryKind;
    /// A memory reading inputs of width `d_in`, sized by the network config.
    fn build(d_in: usize, network: &NetworkConfig, init: &mut Init, device: &Device) -> Self;
    /// Width of the state.
    fn size(&self) -> usize;
    /// Width of what the heads read from a state.
    fn output_size(&self) -> usize {
        self.size()
    }
    /// What the heads read from states `[rows, size]`: `[rows, output_size]`.
    fn output(&self, state: Tensor<2>) -> Tensor<2> {
        state
    }
    /// The input-dependent part of a step: `[rows, d_in]` → `[rows, projected_size]`.
    fn project(&self, x: Tensor<2>) -> Tensor<2>;
    fn projected_size(&self) -> usize;
    /// One step from a projected input and the state `[rows, size]`; the new state.
    fn step(&self, projected: Tensor<2>, state: Tensor<2>) -> Tensor<2>;
    /// Every step of sequences: projected inputs `[B, T, projected_size]`, the states before
    /// the first step `[B, size]` and `keep` `[B, T]` (0 clears a row's state before that
    /// step); the states after every step `[B, T, size]`.
    fn unroll(&self, projected: Tensor<3>, state: Tensor<2>, keep: Tensor<2>) -> Tensor<3> {
        unroll_by_steps(self, projected, state, keep)
    }
}

/// [`Recurrent::unroll`] one [`Recurrent::step`] at a time.
fn unroll_by_steps<M: Recurrent>(
    memory: &M,
    gx: Tensor<3>,
    mut h: Tensor<2>,
    keep: Tensor<2>,
) -> Tensor<3> {
    let t = gx.dims()[1];
    let mut states = Vec::with_capacity(t);
    // The steps read `gx` a chunk of about √T steps at a time. Autodiff's backward of a
    // slice writes the slice's gradient into zeros of the whole sliced tensor, so T
    // one-step slices of `gx` would fill and add T tensors of its full size (32 at the
    // presets' T = 32); chunks first cut that to T/c + c of them (12).
    let chunk = (t as f64).sqrt().round().max(1.0) as usize;
    for start in (0..t).step_by(chunk) {
        let len = chunk.min(t - start);
        let gx_chunk = gx.clone().narrow(1, start, len);
        for s in 0..len {
            let gx_s: Tensor<2> = gx_chunk.clone().narrow(1, s, 1).squeeze_dim(1);
            let keep_s = keep.clone().narrow(1, start + s, 1);
            h = memory.step(gx_s, h * keep_s);
            states.push(h.clone());
        }
    }
    Tensor::stack(states, 1)
}

/// A GRU cell (PyTorch's equations).
#[derive(Module, Debug)]
pub struct GruCell {
    input: Linear,
    hidden: Linear,
    #[module(skip)]
    size: usize,
}

impl GruCell {
    pub fn new(d_in: usize, size: usize, init: &mut Init, device: &Device) -> GruCell {
        GruCell {
            input: init.linear(d_in, 3 * size, 1.0, device),
            hidden: init.linear(size, 3 * size, 1.0, device),
            size,
        }
    }
}

impl Recurrent for GruCell {
    const KIND: MemoryKind = MemoryKind::Gru;

    fn build(d_in: usize, network: &NetworkConfig, init: &mut Init, device: &Device) -> Self {
        GruCell::new(d_in, network.hidden, init, device)
    }

    fn size(&self) -> usize {
        self.size
    }

    /// `gx = W_i x + b_i` for the reset, update and candidate gates.
    fn project(&self, x: Tensor<2>) -> Tensor<2> {
        self.input.forward(x)
    }

    fn projected_size(&self) -> usize {
        3 * self.size
    }

    fn step(&self, gx: Tensor<2>, h: Tensor<2>) -> Tensor<2> {
        let n = self.size;
        if std::env::var_os("YOKAI_CHEAP_GRU").is_some() {
            return tanh(gx.narrow(1, 2 * n, n)) + h;
        }
        let gh = self.hidden.forward(h.clone());
        let r = sigmoid(gx.clone().narrow(1, 0, n) + gh.clone().narrow(1, 0, n));
        let z = sigmoid(gx.clone().narrow(1, n, n) + gh.clone().narrow(1, n, n));
        let cand = tanh(gx.narrow(1, 2 * n, n) + r * gh.narrow(1, 2 * n, n));
        cand.clone() + z * (h - cand)
    }

    /// On the CPU, sequences of more than one step (the learner's) run as one fused
    /// operation with its own backward pass ([`gru_sequence`]): the same equations without
    /// a graph node per gate. Acting's single steps stay step by step: measured, the fused
    /// call's reads and writes of its inputs cost them more than it saves.
    fn unroll(&self, gx: Tensor<3>, h0: Tensor<2>, keep: Tensor<2>) -> Tensor<3> {
        match &self.hidden.bias {
            Some(bias) if gx.dims()[1] > 1 && gru_sequence::fused_on(&gx.device()) => {
                let w = self.hidden.weight.val();
                gru_sequence::gru_sequence(gx, h0, keep, w, bias.val())
            }
            _ => unroll_by_steps(self, gx, h0, keep),
        }
    }
}

/// Encoder → Linear → ReLU → memory (a GRU by default) → actor and critic heads.
///
/// The actor is one of two heads (`network.head`): `actor`, a dense layer over the state
/// (the paper's), or `pointer`, which also reads the observation's per-card features
/// ([`PointerHead`]). Exactly one of them is present.
///
/// The critic reads the memory's output, and with `network.critic = "central"` also every
/// card's true colour through the `central` layer first ([`CriticInput`]).
#[derive(Module, Debug)]
pub struct ActorCritic<E: Encoder, M: Recurrent> {
    encoder: E,
    embed: Linear,
    /// The recurrent memory (`network.memory`: a GRU or a Transformer-XL). Files written
    /// before 2026-11-25 name its tensors `gru.…`; [`crate::artifact`] reads them too.
    memory: M,
    /// `network.head_layers` layers (width of the memory's output, ReLU) between the memory
    /// and every head: the paper's +1HL / +2HL ablations. Empty in every other network.
    head_layers: Vec<Linear>,
    actor: Option<Linear>,
    pointer: Option<PointerHead>,
    central: Option<Linear>,
    critic: Linear,
    #[module(skip)]
    hidden: usize,
}

/// How many parts a batch of rows is cut into on `device`, acting ([`ActorCritic::act`])
/// and learning: one per worker thread on the CPU, where a batch's small matrices would
/// otherwise run on one core; one on a GPU, whose kernels already fill the device.
pub fn shards_on(device: &Device) -> usize {
    if *device == crate::device::default_device() {
        rayon::current_num_threads()
    } else {
        1
    }
}

/// What [`ActorCritic::step_seats`] returns: every seat's new memory state, and the action
/// logits of the seats whose turn it is.
#[derive(Clone, Debug, Default)]
pub struct SeatStep {
    /// The new states `[rows × H]`, in the order of the rows.
    pub states: Vec<f32>,
    /// The acting rows' logits `[acting × N_a]`.
    logits: Vec<f32>,
    /// The rows whose seat acts, ascending.
    acting: Vec<usize>,
    num_actions: usize,
}

impl SeatStep {
    /// Row `k`'s action logits (unmasked), if its seat is the one to act. Its MOVE logits
    /// are 0 unless it is at the MOVE substep, where alone a MOVE can be legal
    /// ([`MoveRows`]); `TrainedPolicy::step_seat_every_logit` computes them all.
    pub fn logits(&self, k: usize) -> Option<&[f32]> {
        let i = self.acting.binary_search(&k).ok()?;
        Some(&self.logits[i * self.num_actions..][..self.num_actions])
    }
}

/// What [`ActorCritic::act`] gives for a batch of rows: every row's value `[B]` and new
/// state `[B, H]`, and the choosing rows' action logits `[choosing, N_a]`, in row order.
/// [`ActorCritic::act_with`] adds every row's colour log-probabilities.
#[derive(Clone, Debug, Default)]
pub struct Acted {
    pub values: Vec<f32>,
    pub states: Vec<f32>,
    pub logits: Vec<f32>,
    /// Every row's colour layer, log-softmaxed: `[B × Y × C]` (empty unless asked for).
    pub colour_log_probs: Vec<f32>,
}

/// The rows of one acting step, as [`ActorCritic::act`] takes them.
#[derive(Clone, Copy)]
pub struct ActBatch<'a> {
    obs: &'a [f32],
    states: &'a [f32],
    keep: &'a [f32],
    choosing: &'a [usize],
}

impl<'a> ActBatch<'a> {
    pub fn new(obs: &'a [f32], states: &'a [f32], keep: &'a [f32], choosing: &'a [usize]) -> Self {
        ActBatch {
            obs,
            states,
            keep,
            choosing,
        }
    }
}

impl<E: Encoder, M: Recurrent> ActorCritic<E, M> {
    /// A freshly initialised network; a pure function of `seed`.
    pub fn new(config: &TrainConfig, game: &Config, seed: u64, device: &Device) -> Self {
        let mut init = Init::new(seed);
        let encoder = E::new(config, game, &mut init, device);
        let h = config.network.hidden;
        let sqrt2 = std::f64::consts::SQRT_2;
        let embed = init.linear(encoder.output_size(), h, sqrt2, device);
        let memory = M::build(h, &config.network, &mut init, device);
        let out = memory.output_size();
        // Drawn only when asked for, so that every other network's weights stay the same
        // function of the seed.
        let head_layers = (0..config.network.head_layers)
            .map(|_| init.linear(out, out, sqrt2, device))
            .collect();
        ActorCritic {
            head_layers,
            embed,
            encoder,
            actor: (config.network.head == ActionHead::Dense)
                .then(|| init.linear(out, game.num_actions(), config.network.actor_gain, device)),
            pointer: (config.network.head == ActionHead::Pointer).then(|| {
                PointerHead::new(
                    game,
                    out,
                    config.network.pointer_pool,
                    config.ppo.belief_aux > 0.0,
                    config.network.actor_gain,
                    &mut init,
                    device,
                )
            }),
            central: (config.network.critic == CriticInput::Central).then(|| {
                let truth = game.cards() * game.colours();
                init.linear(out + truth, out, sqrt2, device)
            }),
            critic: init.linear(out, 1, config.network.critic_gain, device),
            hidden: memory.size(),
            memory,
        }
    }

    /// Size of the recurrent state (what the trainer stores per row; for a GRU its hidden
    /// vector, for a Transformer-XL its output and window of past inputs).
    pub fn hidden_size(&self) -> usize {
        self.hidden
    }

    fn input_projection(&self, obs: Tensor<2>) -> Tensor<2> {
        let x = relu(self.embed.forward(self.encoder.forward(obs)));
        self.memory.project(x)
    }

    /// One step for `B` rows: observations `[B, L]`, states `[B, H]`, and `keep` `[B, 1]`
    /// (0 where an episode starts at this step, which zeroes that row's state first).
    /// Returns the unmasked action logits `[B, N_a]` and the new states. (Values come from
    /// [`ActorCritic::values`] of the states, where a caller needs them.)
    pub fn step(&self, obs: Tensor<2>, h: Tensor<2>, keep: Tensor<2>) -> (Tensor<2>, Tensor<2>) {
        let h = self.recur(obs.clone(), h, keep);
        (self.policy_logits(obs, h.clone()), h)
    }

    /// The memory's step alone: the new states `[B, H]` from observations `[B, L]`, states
    /// and `keep` as in [`ActorCritic::step`], without the heads, for callers that need the
    /// actor on some rows only (a waiting seat's only action is NOOP).
    pub fn recur(&self, obs: Tensor<2>, h: Tensor<2>, keep: Tensor<2>) -> Tensor<2> {
        let gx: Tensor<3> = self.input_projection(obs).unsqueeze_dim(1);
        self.memory.unroll(gx, h, keep).squeeze_dim(1)
    }

    /// Action logits `[rows, N_a]` from the rows' observations `[rows, L]` (read by the
    /// pointer head only) and the GRU states after them.
    pub fn policy_logits(&self, obs: Tensor<2>, states: Tensor<2>) -> Tensor<2> {
        self.policy_logits_of_head(obs, self.head_input(states))
    }

    /// [`ActorCritic::policy_logits`] from what the heads read ([`ActorCritic::head_input`]),
    /// for callers that also need the values of the same rows: the head layers run once.
    pub fn policy_logits_of_head(&self, obs: Tensor<2>, head_input: Tensor<2>) -> Tensor<2> {
        match (&self.actor, &self.pointer) {
            (Some(actor), _) => actor.forward(head_input),
            (None, Some(pointer)) => pointer.forward(obs, head_input),
            (None, None) => unreachable!("ActorCritic::new builds one actor head"),
        }
    }

    /// Action logits `[rows.len(), N_a]`, in the order of `rows`, for some rows of a step:
    /// `obs` holds every row's observation (`[B, L]`, flat) and `head_input` what the heads
    /// read of every row's state after the step ([`ActorCritic::head_input`], `[B, ·]`).
    /// The actor runs on those rows alone: in a step most rows have one legal action (a
    /// waiting seat's NOOP), and the pointer head costs as much as the rest of the network.
    /// For the same reason the pointer head scores MOVEs only for rows at the MOVE substep
    /// ([`MoveRows`]): the others' MOVE logits are 0, so callers mask the logits with the
    /// legal actions before reading them, as every sampler does. Empty when `rows` is.
    pub fn logits_of_rows(&self, obs: &[f32], head_input: Tensor<2>, rows: &[usize]) -> Vec<f32> {
        if rows.is_empty() {
            return Vec::new();
        }
        let device = head_input.device();
        let l = obs.len() / head_input.dims()[0];
        let chosen_obs = rows.iter().flat_map(|&r| &obs[r * l..][..l]).copied();
        let idx = rows.iter().map(|&r| r as i64).collect();
        let chosen_obs = crate::tensor::tensor2(chosen_obs.collect(), [rows.len(), l], &device);
        let head_input = head_input.select(0, crate::tensor::rows_tensor(idx, &device));
        let moving = self.rows_at_move(obs, rows);
        let (logits, _) =
            self.policy_and_colour_logits_of_head(chosen_obs, head_input, MoveRows::Only(&moving));
        crate::tensor::to_vec(logits)
    }

    /// One step of acting for `B` rows, on flat buffers: observations `[B, L]`, states
    /// `[B, H]`, `keep` `[B]` as in [`ActorCritic::step`]. Returns every row's value (none
    /// with a central critic, which reads what the caller holds: [`ActorCritic::values`])
    /// and new state, and the action logits of the rows `choosing` (ascending), as
    /// [`ActorCritic::logits_of_rows`] gives them.
    ///
    /// The rows are cut into `shards` contiguous parts that run side by side on rayon's
    /// threads ([`shards_on`] says how many a device wants): an acting step's matrices are a
    /// few rows wide, too small for burn's kernels to split, so one part per core is what
    /// uses the cores. Every row gets what it gets alone, so the result does not depend on
    /// `shards` beyond float rounding.
    pub fn act(
        &self,
        obs: &[f32],
        states: &[f32],
        keep: &[f32],
        choosing: &[usize],
        device: &Device,
        shards: usize,
    ) -> Acted {
        self.act_with(
            ActBatch::new(obs, states, keep, choosing),
            false,
            device,
            shards,
        )
    }

    /// [`ActorCritic::act`] on `batch`, and with `colours` every row's colour
    /// log-probabilities from the colour layer (`ppo.belief_aux`; empty without it),
    /// waiting rows included: what the belief-gain reward (`ppo.belief_gain`) reads. The
    /// pointer head then runs on every row instead of the choosing rows alone, about twice
    /// its work.
    pub fn act_with(
        &self,
        batch: ActBatch,
        colours: bool,
        device: &Device,
        shards: usize,
    ) -> Acted {
        use rayon::prelude::*;
        let ActBatch {
            obs,
            states,
            keep,
            choosing,
        } = batch;
        let rows = keep.len();
        let per = rows.div_ceil(shards.max(1)).max(1);
        if per >= rows {
            return self.act_part(batch, colours, device);
        }
        let (l, h) = (obs.len() / rows, states.len() / rows);
        let parts: Vec<Acted> = (0..rows)
            .step_by(per)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|start| {
                let end = (start + per).min(rows);
                let mine: Vec<usize> = choosing
                    .iter()
                    .filter(|&&r| (start..end).contains(&r))
                    .map(|&r| r - start)
                    .collect();
                let (obs, states) = (&obs[start * l..end * l], &states[start * h..end * h]);
                let part = ActBatch::new(obs, states, &keep[start..end], &mine);
                self.act_part(part, colours, device)
            })
            .collect();
        let mut all = Acted::default();
        for part in parts {
            all.values.extend(part.values);
            all.states.extend(part.states);
            all.logits.extend(part.logits);
            all.colour_log_probs.extend(part.colour_log_probs);
        }
        all
    }

    /// One step of the network for the seats `rows` (a game and a seat each, whose
    /// observations it writes itself), states `[rows × H]` and `keep` `[rows]` as in
    /// [`ActorCritic::step`]: every seat's memory steps, and the actor runs for the seats
    /// whose turn it is (the others only wait). For callers that drive seats of games outside
    /// the batched environment: the probe recorder, OBL's belief data,
    /// [`crate::TrainedPolicy::step_seats`].
    pub fn step_seats(
        &self,
        rows: &[(&yokai_engine::Game, yokai_engine::Seat)],
        states: Vec<f32>,
        keep: Vec<f32>,
        device: &Device,
    ) -> SeatStep {
        let views: Vec<SeenSeat> = rows.iter().map(|&(g, s)| SeenSeat::plain(g, s)).collect();
        self.step_views(&views, states, keep, device)
    }

    /// [`ActorCritic::step_seats`] for seats that see their games through a symmetry each
    /// (OBL's partners under Other-Play): the acting rows' logits are in the seat's view,
    /// so a caller samples there and maps the action back ([`crate::distribution::sample_seen`]).
    pub fn step_views(
        &self,
        rows: &[SeenSeat],
        states: Vec<f32>,
        keep: Vec<f32>,
        device: &Device,
    ) -> SeatStep {
        let Some(first) = rows.first() else {
            return SeatStep::default();
        };
        let obs = Self::observations(rows);
        let acting: Vec<usize> = (0..rows.len()).filter(|&k| rows[k].acts()).collect();
        let acted = self.act(&obs, &states, &keep, &acting, device, shards_on(device));
        SeatStep {
            states: acted.states,
            logits: acted.logits,
            acting,
            num_actions: first.game.config().num_actions(),
        }
    }

    /// The seats' observations `[rows × L]` in this network's encoding.
    fn observations(rows: &[SeenSeat]) -> Vec<f32> {
        let Some(first) = rows.first() else {
            return Vec::new();
        };
        let encoding = E::encoding();
        let l: usize = encoding.shape(first.game.config()).iter().product();
        let mut obs = vec![0f32; rows.len() * l];
        for (k, view) in rows.iter().enumerate() {
            view.write(encoding, &mut obs[k * l..][..l]);
        }
        obs
    }

    /// The colour layer's guess for every card, `[rows × Y]` (the colour of highest
    /// logit, in the seat's view), at the seats `rows` (at least one) whose memories after
    /// reading their state are `states` (`[rows × H]`, as [`ActorCritic::step_views`]
    /// returns them). `None` for a network without a colour layer (`ppo.belief_aux` = 0).
    /// For reading what the belief head learned on states of any kind (`yokai probe`).
    pub fn colour_guesses(
        &self,
        rows: &[SeenSeat],
        states: &[f32],
        device: &Device,
    ) -> Option<Vec<u8>> {
        let (log_probs, c) = self.colour_log_probs(rows, states, device)?;
        let guess = |card: &[f32]| crate::distribution::first_max(card) as u8;
        Some(log_probs.chunks_exact(c).map(guess).collect())
    }

    /// The colour layer's log-probabilities of every card's colours, `[rows × Y × C]` (in
    /// the seat's view), and C, at the seats `rows` (at least one) whose memories after
    /// reading their state are `states`, as for [`ActorCritic::colour_guesses`]. `None`
    /// without a colour layer.
    pub fn colour_log_probs(
        &self,
        rows: &[SeenSeat],
        states: &[f32],
        device: &Device,
    ) -> Option<(Vec<f32>, usize)> {
        use crate::tensor::{tensor2, to_vec};
        let n = rows.len();
        assert!(n > 0, "colour log-probabilities for at least one seat");
        let obs = Self::observations(rows);
        let l = obs.len() / n;
        let x = self.head_input(tensor2(states.to_vec(), [n, self.hidden_size()], device));
        let obs = tensor2(obs, [n, l], device);
        let (_, colours) = self.policy_and_colour_logits_of_head(obs, x, MoveRows::Only(&[]));
        let colours = colours?;
        let c = colours.dims()[2];
        Some((to_vec(burn::tensor::activation::log_softmax(colours, 2)), c))
    }

    /// [`ActorCritic::act`] on one thread, for one part of the rows.
    fn act_part(&self, batch: ActBatch, colours: bool, device: &Device) -> Acted {
        use crate::tensor::{tensor2, to_vec};
        let ActBatch {
            obs,
            states,
            keep,
            choosing,
        } = batch;
        let rows = keep.len();
        let h = self.recur(
            tensor2(obs.to_vec(), [rows, obs.len() / rows.max(1)], device),
            tensor2(states.to_vec(), [rows, states.len() / rows.max(1)], device),
            tensor2(keep.to_vec(), [rows, 1], device),
        );
        // The head layers run once for the values and the logits.
        let x = self.head_input(h.clone());
        let (logits, colour_log_probs) = if colours {
            self.logits_and_colours(obs, x.clone(), choosing)
        } else {
            (self.logits_of_rows(obs, x.clone(), choosing), Vec::new())
        };
        Acted {
            values: match self.central {
                None => to_vec(self.values_of_head(x.clone(), None)),
                Some(_) => Vec::new(),
            },
            logits,
            states: to_vec(h),
            colour_log_probs,
        }
    }

    /// [`ActorCritic::logits_of_rows`] for the rows `choosing`, and every row's colour
    /// log-probabilities `[B × Y × C]` (empty without a colour layer), from one run of the
    /// head over every row.
    fn logits_and_colours(
        &self,
        obs: &[f32],
        head_input: Tensor<2>,
        choosing: &[usize],
    ) -> (Vec<f32>, Vec<f32>) {
        use crate::tensor::{rows_tensor, tensor2, to_vec};
        let device = head_input.device();
        let rows = head_input.dims()[0];
        let moving: Vec<usize> = (self.rows_at_move(obs, choosing).into_iter())
            .map(|k| choosing[k])
            .collect();
        let all_obs = tensor2(obs.to_vec(), [rows, obs.len() / rows.max(1)], &device);
        let (logits, colours) =
            self.policy_and_colour_logits_of_head(all_obs, head_input, MoveRows::Only(&moving));
        let logits = if choosing.is_empty() {
            Vec::new()
        } else {
            let idx = choosing.iter().map(|&r| r as i64).collect();
            to_vec(logits.select(0, rows_tensor(idx, &device)))
        };
        let colours = colours.map_or_else(Vec::new, |c| {
            to_vec(burn::tensor::activation::log_softmax(c, 2))
        });
        (logits, colours)
    }

    /// The action logits and, where the network has a colour layer (`ppo.belief_aux`),
    /// every card's colour logits `[rows, Y, C]`, from what the heads read
    /// ([`ActorCritic::head_input`]). The pointer head scores MOVEs for the rows `moving`
    /// names (the dense head for every row).
    pub fn policy_and_colour_logits_of_head(
        &self,
        obs: Tensor<2>,
        head_input: Tensor<2>,
        moving: MoveRows,
    ) -> (Tensor<2>, Option<Tensor<3>>) {
        match &self.pointer {
            Some(pointer) => pointer.forward_with_colours(obs, head_input, moving),
            None => (self.policy_logits_of_head(obs, head_input), None),
        }
    }

    /// The action logits as the learner reads them ([`ActionLogits`]) and, with a colour
    /// layer, the colour logits `[rows, Y, C]`: the pointer head's split at the rows
    /// `moving` (positions from [`ActorCritic::rows_at_move`]), the dense head's whole.
    pub fn action_logits_of_head(
        &self,
        obs: Tensor<2>,
        head_input: Tensor<2>,
        moving: &[usize],
    ) -> (ActionLogits, Option<Tensor<3>>) {
        match &self.pointer {
            Some(pointer) => {
                let (others, moves, colours) = pointer.forward_split(obs, head_input, moving);
                (ActionLogits::Split { others, moves }, colours)
            }
            None => (
                ActionLogits::Every(self.policy_logits_of_head(obs, head_input)),
                None,
            ),
        }
    }

    /// For [`MoveRows::Only`]: the positions `k` of `rows` (row indices into `obs`, flat
    /// `[B, L]`) whose seat is at the MOVE substep; empty for a network without the
    /// pointer head, which reads no observation in its head.
    pub fn rows_at_move<R: Copy + TryInto<usize>>(&self, obs: &[f32], rows: &[R]) -> Vec<usize> {
        self.pointer
            .as_ref()
            .map(|p| p.rows_at_move(obs, rows))
            .unwrap_or_default()
    }

    /// What the heads read of memory states `[rows, H]`: the memory's output through the
    /// `network.head_layers` layers. Callers that need both heads on the same rows compute
    /// it once and pass it to the `…_of_head` forms.
    pub fn head_input(&self, states: Tensor<2>) -> Tensor<2> {
        self.head_layers
            .iter()
            .fold(self.memory.output(states), |x, layer| {
                relu(layer.forward(x))
            })
    }

    /// Whether the actor reads the observations (the pointer head) besides the states.
    pub fn actor_reads_observations(&self) -> bool {
        self.pointer.is_some()
    }

    /// Whether the critic reads the true colours ([`CriticInput::Central`]).
    pub fn critic_is_central(&self) -> bool {
        self.central.is_some()
    }

    /// State values `[rows]` from memory states `[rows, H]`, and with a central critic
    /// every row's true colours `truth` (`[rows, Y·C]` one-hot, as
    /// [`crate::actor::Actor::colour_one_hots`] writes them; `None` for a local critic,
    /// which ignores it).
    ///
    /// # Panics
    /// With a central critic and no `truth`: the trainer always passes it.
    pub fn values(&self, states: Tensor<2>, truth: Option<Tensor<2>>) -> Tensor<1> {
        self.values_of_head(self.head_input(states), truth)
    }

    /// [`ActorCritic::values`] from what the heads read ([`ActorCritic::head_input`]).
    pub fn values_of_head(&self, x: Tensor<2>, truth: Option<Tensor<2>>) -> Tensor<1> {
        let x = match &self.central {
            None => x,
            Some(central) => {
                let truth = truth.expect("a central critic reads the true colours");
                relu(central.forward(Tensor::cat(vec![x, truth], 1)))
            }
        };
        self.critic.forward(x).squeeze_dim(1)
    }

    /// [`ActorCritic::values`] on flat buffers: states `[rows × H]`, truth `[rows × Y·C]`.
    pub fn values_of(&self, states: &[f32], truth: &[f32], device: &Device) -> Vec<f32> {
        use crate::tensor::{tensor2, to_vec};
        let rows = states.len() / self.hidden;
        let truth = tensor2(truth.to_vec(), [rows, truth.len() / rows.max(1)], device);
        let states = tensor2(states.to_vec(), [rows, self.hidden], device);
        to_vec(self.values(states, self.central.as_ref().map(|_| truth)))
    }

    /// Unroll `T` steps for `B` sequences: observations `[B, T, L]`, initial states
    /// `[B, H]`, `keep` `[B, T]`. Returns the GRU state after every step, `[B·T, H]` in
    /// `(b, t)` row-major order; the heads are applied by the caller, so that the actor
    /// head can skip rows with a single legal action.
    pub fn unroll(&self, obs: Tensor<3>, h0: Tensor<2>, keep: Tensor<2>) -> Tensor<2> {
        let [b, t, l] = obs.dims();
        let gx = self.input_projection(obs.reshape([b * t, l])).reshape([
            b,
            t,
            self.memory.projected_size(),
        ]);
        let all = self.memory.unroll(gx, h0, keep);
        all.reshape([b * t, self.hidden])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tensor::parameters;

    /// The patch-product convolutions give what burn's `Conv2d::forward` gives on the
    /// channels-first image, flattened in the same order (a non-square image, channels in
    /// ≠ out, non-zero bias), and the same gradients for every kernel and bias.
    #[test]
    fn convolution_by_patches_is_burns_conv2d() {
        use burn::tensor::Distribution;
        let device = Device::flex().autodiff();
        let normal = Distribution::Normal(0.0, 1.0);
        let mut convs = conv_layers(&mut Init::new(5), 5, 6, &device);
        for conv in &mut convs {
            let bias = Tensor::random([6], normal, &device).require_grad();
            conv.bias = Some(burn::module::Param::from_tensor(bias));
        }
        let x: Tensor<4> = Tensor::random([3, 11, 12, 5], normal, &device);
        let by_patches = conv_stack(&convs, x.clone());
        let mut y = x.permute([0, 3, 1, 2]);
        for conv in &convs {
            y = relu(conv.forward(y));
        }
        let by_burn = y.reshape([3i64, -1]);
        assert_eq!(by_patches.dims(), [3, 6 * 3 * 4]);
        let most = |t: Tensor<2>| t.abs().max().into_scalar::<f32>();
        let diff = most(by_patches.clone() - by_burn.clone());
        assert!(diff < 1e-4, "largest difference {diff}");
        // Gradients of one weighted sum of the outputs, by each path.
        let r: Tensor<2> = Tensor::random(by_burn.dims(), normal, &device);
        let (g_patches, g_burn) = (
            (by_patches * r.clone()).sum().backward(),
            (by_burn * r).sum().backward(),
        );
        for (k, conv) in convs.iter().enumerate() {
            let (weight, bias) = (conv.weight.val(), conv.bias.as_ref().unwrap().val());
            let grads = |g| {
                let w = weight.grad(g).unwrap().reshape([6, -1]);
                let b = bias.grad(g).unwrap().reshape([1, 6]);
                (w, b)
            };
            let ((w1, b1), (w2, b2)) = (grads(&g_patches), grads(&g_burn));
            let (w, b) = (most(w1 - w2), most(b1 - b2));
            assert!(w < 1e-3 && b < 1e-3, "layer {k}: kernel {w}, bias {b}");
        }
    }

    fn network(head_layers: usize) -> ActorCritic<MlpEncoder, GruCell> {
        let text =
            format!("[network]\npreset = \"compact\"\nhidden = 16\nhead_layers = {head_layers}\n");
        let config = TrainConfig::from_toml_str(&text, "t").unwrap();
        let game = config.game_config().unwrap();
        ActorCritic::new(&config, &game, 3, &Device::flex())
    }

    /// `network.head_layers` adds that many 16 × 16 layers before the heads (the paper's
    /// +1HL / +2HL); more than 4 is refused. What they compute is checked against the
    /// PyTorch network in python/tests/test_torch_train.py.
    #[test]
    fn head_layers_sit_between_the_memory_and_the_heads() {
        let sizes: Vec<usize> = (0..3).map(|n| parameters(&network(n)).len()).collect();
        assert_eq!(sizes[1] - sizes[0], 16 * 16 + 16);
        assert_eq!(sizes[2] - sizes[0], 2 * (16 * 16 + 16));
        // Drawn after the memory: every layer before them keeps its weights.
        let (plain, deeper) = (
            parameters(&network(0).memory),
            parameters(&network(2).memory),
        );
        assert_eq!(plain, deeper);
        let e = TrainConfig::from_toml_str("[network]\nhead_layers = 5\n", "t")
            .unwrap_err()
            .to_string();
        assert!(e.contains("network.head_layers"), "{e}");
    }
}

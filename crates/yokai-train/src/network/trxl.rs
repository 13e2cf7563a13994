//! A gated Transformer-XL memory (`network.memory = "trxl"`), the paper's memory ablation:
//! 1 layer, 8 heads, width 64, a window of 32 past steps, gates biased by 2, sinusoidal
//! positions (all `network.trxl_*` fields).
//!
//! Each step the layer attends from the current input to itself and to the inputs of the
//! last `M` steps of the same episode, then applies a position-wise MLP. Both sub-layers
//! are pre-norm and joined to their input by a GRU-type gate instead of a sum (Parisotto et
//! al.'s GTrXL); the gate's update bias starts it near the identity, which is what lets RL
//! train a transformer at all.
//!
//! **The state is the window itself**, flat per row: `[output (d) | inputs (M·d) | valid
//! (M)]`, oldest first. So the trainer keeps it across rollout boundaries, zeroes it where
//! an episode starts (every slot then invalid: nothing before the start is seen), and
//! checkpoints it like a GRU's hidden vector — exact resume comes for free. Positions are
//! the ages of the slots (0 for the current step, k for k steps ago), as sinusoids added to
//! the keys and values: with one query per step, absolute ages are Transformer-XL's relative
//! positions. Within a BPTT sequence the gradient flows through the window; the window
//! handed over from the previous rollout is a constant, as in Transformer-XL's cached
//! segment.

use super::Recurrent;
use crate::config::{MemoryKind, NetworkConfig};
use crate::init::Init;
use crate::tensor::FoldedLinear;
use burn::module::Module;
use burn::nn::{LayerNorm, LayerNormConfig, Linear};
use burn::prelude::*;
use burn::tensor::activation::{relu, sigmoid, softmax, tanh};
use burn::tensor::TensorData;

#[derive(Module, Debug)]
pub struct TransformerXl {
    /// Input → model width (the part of a step BPTT batches over the whole sequence).
    input: Linear,
    norm_attention: LayerNorm,
    query: Linear,
    key: Linear,
    value: Linear,
    output: Linear,
    gate_attention: Gate,
    norm_mlp: LayerNorm,
    hidden: Linear,
    back: Linear,
    gate_mlp: Gate,
    #[module(skip)]
    shape: Shape,
}

#[derive(Clone, Debug)]
struct Shape {
    width: usize,
    heads: usize,
    window: usize,
    gate_bias: f32,
    /// The sinusoids of the slots' ages, `(window + 1) × width`, computed once: a step
    /// only copies them to the device.
    ages: Vec<f32>,
}

/// GTrXL's GRU-type gate joining a sub-layer's output `y` to its input `x`:
/// `r = σ(W_r y + U_r x)`, `z = σ(W_z y + U_z x − b)`, `ĥ = tanh(W_g y + U_g (r ⊙ x))`,
/// result `(1 − z) ⊙ x + z ⊙ ĥ`. With b = 2, z starts near 0.12: the layer starts close to
/// passing its input through.
#[derive(Module, Debug)]
pub struct Gate {
    /// `W_r, W_z, W_g` stacked: `y` → 3·d.
    from_output: Linear,
    /// `U_r, U_z` stacked: `x` → 2·d.
    from_input: Linear,
    /// `U_g`: `r ⊙ x` → d.
    candidate: Linear,
}

impl Gate {
    fn new(d: usize, init: &mut Init, device: &Device) -> Gate {
        Gate {
            from_output: init.linear(d, 3 * d, 1.0, device),
            from_input: init.linear(d, 2 * d, 1.0, device),
            candidate: init.linear(d, d, 1.0, device),
        }
    }

    fn forward(&self, x: Tensor<2>, y: Tensor<2>, bias: f32) -> Tensor<2> {
        let [_, d] = x.dims();
        let wy = self.from_output.forward(y);
        let ux = self.from_input.forward(x.clone());
        let r = sigmoid(wy.clone().narrow(1, 0, d) + ux.clone().narrow(1, 0, d));
        let z = sigmoid(wy.clone().narrow(1, d, d) + ux.narrow(1, d, d) - bias);
        let candidate = tanh(wy.narrow(1, 2 * d, d) + self.candidate.forward(r * x.clone()));
        x.clone() + z * (candidate - x)
    }
}

impl Recurrent for TransformerXl {
    const KIND: MemoryKind = MemoryKind::Trxl;

    fn build(d_in: usize, network: &NetworkConfig, init: &mut Init, device: &Device) -> Self {
        let d = network.trxl_width;
        let sqrt2 = std::f64::consts::SQRT_2;
        TransformerXl {
            input: init.linear(d_in, d, 1.0, device),
            norm_attention: LayerNormConfig::new(d).init(device),
            query: init.linear(d, d, 1.0, device),
            key: init.linear(d, d, 1.0, device),
            value: init.linear(d, d, 1.0, device),
            output: init.linear(d, d, 1.0, device),
            gate_attention: Gate::new(d, init, device),
            norm_mlp: LayerNormConfig::new(d).init(device),
            hidden: init.linear(d, d, sqrt2, device),
            back: init.linear(d, d, 1.0, device),
            gate_mlp: Gate::new(d, init, device),
            shape: Shape {
                width: d,
                heads: network.trxl_heads,
                window: network.trxl_memory,
                gate_bias: network.trxl_gate_bias as f32,
                ages: ages(network.trxl_memory, d),
            },
        }
    }

    fn size(&self) -> usize {
        let Shape { width, window, .. } = self.shape;
        width + window * width + window
    }

    fn output_size(&self) -> usize {
        self.shape.width
    }

    fn output(&self, state: Tensor<2>) -> Tensor<2> {
        state.narrow(1, 0, self.shape.width)
    }

    fn project(&self, x: Tensor<2>) -> Tensor<2> {
        self.input.forward(x)
    }

    fn projected_size(&self) -> usize {
        self.shape.width
    }

    fn step(&self, x: Tensor<2>, state: Tensor<2>) -> Tensor<2> {
        let Shape {
            width: d,
            heads,
            window: m,
            gate_bias,
            ref ages,
        } = self.shape;
        let dh = d / heads;
        let [b, _] = x.dims();
        let device = x.device();
        let past: Tensor<3> = state.clone().narrow(1, d, m * d).reshape([b, m, d]);
        let valid = state.narrow(1, d + m * d, m);
        // The window and the current input, oldest first, each normalised, plus its age.
        let sequence = Tensor::cat(vec![past.clone(), x.clone().reshape([b, 1, d])], 1);
        let ages: Tensor<3> =
            Tensor::from_data(TensorData::new(ages.clone(), [1, m + 1, d]), &device);
        let normed = self.norm_attention.forward(sequence) + ages.expand([b, m + 1, d]);
        let current = normed.clone().narrow(1, m, 1).reshape([b, d]);
        let q = self.query.forward(current).reshape([b, heads, 1, dh]);
        let split = |t: Tensor<3>| t.reshape([b, m + 1, heads, dh]).swap_dims(1, 2);
        let k = split(self.key.forward_folded(normed.clone()));
        let v = split(self.value.forward_folded(normed));
        // Empty slots (before the episode's start, or not filled yet) get −10⁹.
        let seen = Tensor::cat(vec![valid.clone(), Tensor::ones([b, 1], &device)], 1);
        let blocked = (seen - 1.0).mul_scalar(1e9).reshape([b, 1, 1, m + 1]);
        let scores = q.matmul(k.swap_dims(2, 3)).div_scalar((dh as f32).sqrt())
            + blocked.expand([b, heads, 1, m + 1]);
        let attended = softmax(scores, 3).matmul(v).reshape([b, d]);
        let y =
            self.gate_attention
                .forward(x.clone(), relu(self.output.forward(attended)), gate_bias);
        let mlp = self
            .back
            .forward(relu(self.hidden.forward(self.norm_mlp.forward(y.clone()))));
        let out = self.gate_mlp.forward(y, relu(mlp), gate_bias);
        // Slide the window: drop the oldest input, append this one.
        let past = Tensor::cat(vec![past.narrow(1, 1, m - 1), x.reshape([b, 1, d])], 1);
        let valid = Tensor::cat(
            vec![valid.narrow(1, 1, m - 1), Tensor::ones([b, 1], &device)],
            1,
        );
        Tensor::cat(vec![out, past.reshape([b, m * d]), valid], 1)
    }
}

/// Sinusoidal embeddings `(m + 1) × d` of the ages m, m − 1, …, 0 of the window's slots
/// (oldest first) and the current step (Vaswani et al.'s frequencies).
fn ages(m: usize, d: usize) -> Vec<f32> {
    let mut table = vec![0f32; (m + 1) * d];
    for slot in 0..=m {
        let age = (m - slot) as f64;
        for i in 0..d / 2 {
            let angle = age / 10_000f64.powf(2.0 * i as f64 / d as f64);
            table[slot * d + 2 * i] = angle.sin() as f32;
            table[slot * d + 2 * i + 1] = angle.cos() as f32;
        }
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::board::tests::to_vec;

    fn memory(window: usize) -> TransformerXl {
        let mut network = crate::config::TrainConfig::from_toml_str("", "t")
            .unwrap()
            .network;
        network.trxl_width = 16;
        network.trxl_heads = 4;
        network.trxl_memory = window;
        TransformerXl::build(8, &network, &mut Init::new(3), &Device::flex())
    }

    fn row(values: Vec<f32>) -> Tensor<2> {
        let n = values.len();
        Tensor::from_data(TensorData::new(values, [1, n]), &Device::flex())
    }

    /// Steps a sequence of inputs from a zero state; the outputs after each step.
    fn outputs(net: &TransformerXl, inputs: &[Vec<f32>]) -> Vec<Vec<f32>> {
        let mut state = Tensor::zeros([1, net.size()], &Device::flex());
        let mut out = Vec::new();
        for x in inputs {
            state = net.step(net.project(row(x.clone())), state);
            out.push(to_vec(net.output(state.clone())));
        }
        out
    }

    fn input(k: usize) -> Vec<f32> {
        (0..8).map(|i| ((k * 8 + i) as f32 * 0.37).sin()).collect()
    }

    /// The output at step t depends on the inputs of the last `window` steps and on
    /// nothing older: changing the first input changes the outputs while it is in the
    /// window, and not once it has slid out.
    #[test]
    fn the_window_remembers_exactly_its_last_steps() {
        let window = 3;
        let net = memory(window);
        let seq: Vec<Vec<f32>> = (0..7).map(input).collect();
        let mut changed = seq.clone();
        changed[0] = input(100);
        let (a, b) = (outputs(&net, &seq), outputs(&net, &changed));
        for t in 0..seq.len() {
            let differs = a[t].iter().zip(&b[t]).any(|(p, q)| (p - q).abs() > 1e-6);
            // Step 0 is the input itself; steps 1..=window still hold it in the window.
            assert_eq!(differs, t <= window, "step {t}");
        }
    }

    /// A zeroed state (an episode start) forgets everything: the steps after it equal a
    /// fresh start on the same inputs. The layout is output, window, valid flags.
    #[test]
    fn a_zeroed_state_is_a_fresh_start() {
        let net = memory(4);
        assert_eq!(net.size(), 16 + 4 * 16 + 4);
        assert_eq!(net.output_size(), 16);
        let mut state = Tensor::zeros([1, net.size()], &Device::flex());
        for k in 0..6 {
            state = net.step(net.project(row(input(k))), state);
        }
        let flags = to_vec(state.clone().narrow(1, 16 + 64, 4));
        assert_eq!(flags, vec![1.0; 4]);
        let later: Vec<Vec<f32>> = (10..14).map(input).collect();
        let mut reset = state * 0.0;
        let mut after_reset = Vec::new();
        for x in &later {
            reset = net.step(net.project(row(x.clone())), reset);
            after_reset.push(to_vec(net.output(reset.clone())));
        }
        assert_eq!(after_reset, outputs(&net, &later));
    }

    /// Slots flagged invalid are not attended to: a window full of arbitrary values with
    /// every flag 0 gives the same output as an empty one, and setting one flag changes it.
    #[test]
    fn invalid_slots_are_masked() {
        let net = memory(4);
        let x = net.project(row(input(1)));
        let fresh = to_vec(
            net.output(net.step(x.clone(), Tensor::zeros([1, net.size()], &Device::flex()))),
        );
        let mut junk: Vec<f32> = (0..net.size()).map(|i| (i as f32 * 1.3).cos()).collect();
        let flags = 16 + 4 * 16;
        junk[flags..].fill(0.0);
        let masked = to_vec(net.output(net.step(x.clone(), row(junk.clone()))));
        let gap = fresh
            .iter()
            .zip(&masked)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(gap < 1e-5, "{gap}");
        junk[flags + 3] = 1.0;
        let seen = to_vec(net.output(net.step(x, row(junk))));
        assert_ne!(seen, masked);
    }
}

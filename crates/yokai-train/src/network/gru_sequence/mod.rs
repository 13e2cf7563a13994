//! The GRU over a whole sequence as one operation on the CPU, with a hand-written backward
//! pass ([`host`]).
//!
//! Why: built from burn's tensor operations, one GRU step is about twenty small operations
//! (slices of the gates, sigmoid, tanh, products), each an allocation and, while learning, a
//! node of the autodiff graph whose backward pass allocates again; a slice's backward even
//! fills a zero tensor of the whole sliced input. At the CPU presets' width (64, shards of
//! 16–32 sequences) that bookkeeping, not the arithmetic, was most of the GRU's time:
//! replacing the step with a near-empty one made `cpu-fast` 21 % faster. Here the forward
//! pass is one loop over the steps with one matrix product each, and the backward pass
//! (back-propagation through time) one loop back plus one product for the weights.
//!
//! Only burn's `flex` CPU backend (and autodiff over it) runs it; on a GPU the step-by-step
//! GRU stays ([`fused_on`]), where a loop on the host would mean reading the device.

pub mod host;

pub use crate::host_kernel::fused_on;
use crate::host_kernel::{read, write};
use burn::backend::autodiff::checkpoint::base::Checkpointer;
use burn::backend::autodiff::checkpoint::strategy::CheckpointStrategy;
use burn::backend::autodiff::grads::Gradients;
use burn::backend::autodiff::ops::{Backward, Ops, OpsKind};
use burn::backend::autodiff::Autodiff;
use burn::backend::tensor::FloatTensor;
use burn::backend::{backend_extension, Backend, Dispatch, Flex, TensorMetadata};
use burn::prelude::*;
use host::Dims;

/// The GRU's states after every step `[B, T, H]` from the input map `gx` `[B, T, 3H]`, the
/// states before the first step `h0` `[B, H]`, `keep` `[B, T]` (0 clears a row's memory
/// before that step) and the hidden map's weights `w` `[H, 3H]` and `bias` `[3H]`
/// (formulas in [`host`]). Differentiable in every input but `keep`. Only where
/// [`fused_on`] holds.
pub fn gru_sequence(
    gx: Tensor<3>,
    h0: Tensor<2>,
    keep: Tensor<2>,
    w: Tensor<2>,
    bias: Tensor<1>,
) -> Tensor<3> {
    Tensor::from_dispatch(<Dispatch as GruSequenceOps>::gru_sequence(
        gx.into_dispatch(),
        h0.into_dispatch(),
        keep.into_dispatch(),
        w.into_dispatch(),
        bias.into_dispatch(),
    ))
}

/// The operation as a burn backend extension: computed on the host for the CPU backend
/// (the trait's own body), with the backward pass of [`host::backward`] under autodiff.
#[backend_extension(Flex, Autodiff)]
pub trait GruSequenceOps: Backend {
    fn gru_sequence(
        gx: FloatTensor<Self>,
        h0: FloatTensor<Self>,
        keep: FloatTensor<Self>,
        w: FloatTensor<Self>,
        bias: FloatTensor<Self>,
    ) -> FloatTensor<Self> {
        forward_on::<Self>(gx, h0, keep, w, bias).0
    }
}

/// The forward pass on the host: the states as a tensor of `B`, and what the backward
/// pass needs.
fn forward_on<B: Backend>(
    gx: FloatTensor<B>,
    h0: FloatTensor<B>,
    keep: FloatTensor<B>,
    w: FloatTensor<B>,
    bias: FloatTensor<B>,
) -> (FloatTensor<B>, Saved) {
    let (device, d) = (gx.device(), dims(&gx));
    let (keep, w) = (read::<B>(keep), read::<B>(w));
    let (hs, cache) = host::forward(
        d,
        &read::<B>(gx),
        &read::<B>(h0),
        &keep,
        &w,
        &read::<B>(bias),
    );
    let saved = Saved { d, keep, w, cache };
    (write::<B, 3>(hs, [d.b, d.t, d.h], &device), saved)
}

impl GruSequenceOps for Flex {}

/// `[B, T, 3H]` → the call's sizes.
fn dims<T: TensorMetadata>(gx: &T) -> Dims {
    let shape = gx.shape();
    Dims {
        b: shape[0],
        t: shape[1],
        h: shape[2] / 3,
    }
}

/// What the backward pass needs of the forward one (see [`host::backward`]).
#[derive(Clone, Debug)]
struct Saved {
    d: Dims,
    keep: Vec<f32>,
    w: Vec<f32>,
    cache: host::Cache,
}

#[derive(Debug)]
struct GruBackward;

impl<B: Backend> Backward<B, 4> for GruBackward {
    type State = Saved;

    fn backward(self, ops: Ops<Saved, 4>, grads: &mut Gradients, _: &mut Checkpointer) {
        let [gx, h0, w, bias] = ops.parents;
        let grad = grads.consume::<B>(&ops.node);
        let device = grad.device();
        let s = ops.state;
        let g = host::backward(s.d, &s.keep, &s.w, &s.cache, &read::<B>(grad));
        let Dims { b, t, h } = s.d;
        if let Some(node) = gx {
            grads.register::<B>(node.id, write::<B, 3>(g.gx, [b, t, 3 * h], &device));
        }
        if let Some(node) = h0 {
            grads.register::<B>(node.id, write::<B, 2>(g.h0, [b, h], &device));
        }
        if let Some(node) = w {
            grads.register::<B>(node.id, write::<B, 2>(g.w, [h, 3 * h], &device));
        }
        if let Some(node) = bias {
            grads.register::<B>(node.id, write::<B, 1>(g.bias, [3 * h], &device));
        }
    }
}

impl<B: Backend + GruSequenceOps, C: CheckpointStrategy> GruSequenceOps for Autodiff<B, C> {
    fn gru_sequence(
        gx: FloatTensor<Self>,
        h0: FloatTensor<Self>,
        keep: FloatTensor<Self>,
        w: FloatTensor<Self>,
        bias: FloatTensor<Self>,
    ) -> FloatTensor<Self> {
        let parents = [gx.node(), h0.node(), w.node(), bias.node()];
        let (out, saved) = forward_on::<B>(
            gx.into_primitive(),
            h0.into_primitive(),
            keep.into_primitive(),
            w.into_primitive(),
            bias.into_primitive(),
        );
        match GruBackward.prepare::<C>(parents).compute_bound().stateful() {
            OpsKind::Tracked(prep) => prep.finish(saved, out),
            OpsKind::UnTracked(prep) => prep.finish(out),
        }
    }
}

#[cfg(test)]
mod tests;

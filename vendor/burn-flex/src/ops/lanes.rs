//! YLE patch (see PATCHED.md): `exp`, `tanh` and `sigmoid` of f32 tensors evaluated eight
//! lanes at a time with `wide`'s `f32x8` instead of one element at a time through libm.
//!
//! libm's scalar `expf` and `tanhf` were 13 % of the CPU time of a small recurrent
//! network's training step (softmaxes, GRU gates). Every element goes through the same
//! eight-lane function (the tail is padded), so a result does not depend on where an
//! element sits in its tensor. The workspace's tests check the functions' accuracy and
//! that independence through burn's tensor API (crates/yokai-train/tests/cpu_math.rs).

use crate::ops::unary::unary_op;
use crate::FlexTensor;
use burn_backend::DType;
use wide::f32x8;

/// `f` over every element of a float tensor: eight lanes at a time for f32, through one
/// lane of the same function for f16 / bf16, `f64_op` for f64.
pub fn map_lanes(tensor: FlexTensor, f: fn(f32x8) -> f32x8, f64_op: fn(f64) -> f64) -> FlexTensor {
    if tensor.dtype() != DType::F32 {
        return unary_op(tensor, move |x: f32| f(f32x8::splat(x)).to_array()[0], f64_op);
    }
    // A unique, contiguous tensor at offset 0 is changed in place; any other is first
    // copied into one (the identity through `unary_op`'s allocating paths).
    let mut tensor = if tensor.is_unique()
        && tensor.layout().is_contiguous()
        && tensor.layout().start_offset() == 0
    {
        tensor
    } else {
        unary_op(tensor, |x: f32| x, |x: f64| x)
    };
    let n = tensor.layout().num_elements();
    let storage: &mut [f32] = tensor.storage_mut();
    apply(&mut storage[..n], f);
    tensor
}

fn apply(values: &mut [f32], f: fn(f32x8) -> f32x8) {
    let mut chunks = values.chunks_exact_mut(8);
    for chunk in &mut chunks {
        let lanes: [f32; 8] = (&*chunk).try_into().expect("chunks of 8");
        chunk.copy_from_slice(&f(f32x8::from(lanes)).to_array());
    }
    let rest = chunks.into_remainder();
    if !rest.is_empty() {
        let mut lanes = [0f32; 8];
        lanes[..rest.len()].copy_from_slice(rest);
        let out = f(f32x8::from(lanes)).to_array();
        rest.copy_from_slice(&out[..rest.len()]);
    }
}

pub fn exp(x: f32x8) -> f32x8 {
    x.exp()
}

pub fn tanh(x: f32x8) -> f32x8 {
    x.tanh()
}

/// 1 / (1 + e^−x) for x ≥ 0 and e^x / (1 + e^x) below, as the published scalar form, with
/// e = e^−|x| never overflowing.
pub fn sigmoid(x: f32x8) -> f32x8 {
    let e = (-x.abs()).exp();
    let one = f32x8::splat(1.0);
    let denominator = one + e;
    x.simd_ge(f32x8::splat(0.0))
        .select(one / denominator, e / denominator)
}

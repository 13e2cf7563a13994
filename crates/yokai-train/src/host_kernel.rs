//! What the operations computed on the host share: burn's `flex` CPU backend runs them as
//! plain loops over the tensors' elements, with a hand-written backward pass under
//! autodiff (the GRU over a sequence, `network::gru_sequence`; the learner's masked
//! softmax terms, `trainer::choice_terms`). On any other device their burn-built forms run
//! ([`fused_on`]), where a loop on the host would mean reading the device.

use burn::backend::tensor::FloatTensor;
use burn::backend::Backend;
use burn::prelude::*;
use burn::tensor::{try_read_sync, TensorData};
use wide::f32x8;

/// Whether the host operations can run on `device`: burn's `flex` CPU backend, with or
/// without autodiff.
pub fn fused_on(device: &Device) -> bool {
    let cpu = crate::device::default_device();
    *device == cpu || *device == cpu.autodiff()
}

/// A tensor's elements as `f32`s (on the CPU backend a copy out of its buffer).
pub(crate) fn read<B: Backend>(tensor: FloatTensor<B>) -> Vec<f32> {
    let data = try_read_sync(B::float_into_data(tensor))
        .expect("the CPU backend reads synchronously")
        .expect("a tensor of the CPU backend can be read");
    data.try_into_vec::<f32>()
        .expect("the host operations' tensors hold f32 elements")
}

/// `values` as a tensor of `shape` on `device`.
pub(crate) fn write<B: Backend, const D: usize>(
    values: Vec<f32>,
    shape: [usize; D],
    device: &B::Device,
) -> FloatTensor<B> {
    B::float_from_data(TensorData::new(values, shape), device)
}

/// `n` ≤ 8 values of `s` from `at` (the rest 0), as eight lanes.
///
/// Whole lanes take a fixed-length copy the compiler turns into one vector load; the copy
/// of a variable length `n` is a call to `memcpy`, which perf measured as 4 % of a
/// `cpu-fast` update's time when the GRU used it for every lane.
pub(crate) fn load(s: &[f32], at: usize, n: usize) -> f32x8 {
    if n == 8 {
        let lanes: [f32; 8] = s[at..at + 8].try_into().expect("8 lanes");
        return f32x8::from(lanes);
    }
    let mut lanes = [0.0; 8];
    lanes[..n].copy_from_slice(&s[at..at + n]);
    f32x8::from(lanes)
}

/// The first `n` lanes of `v` into `s` from `at`.
pub(crate) fn store(s: &mut [f32], at: usize, n: usize, v: f32x8) {
    if n == 8 {
        let out: &mut [f32; 8] = (&mut s[at..at + 8]).try_into().expect("8 lanes");
        *out = v.to_array();
        return;
    }
    s[at..at + n].copy_from_slice(&v.to_array()[..n]);
}

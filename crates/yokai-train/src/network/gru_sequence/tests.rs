//! The fused GRU against the step-by-step one built from burn's operations: the same
//! states and the same gradients, with memories cleared inside the sequences.

use super::*;
use crate::network::{unroll_by_steps, GruCell, Recurrent};
use burn::tensor::Distribution;

/// `[B, T]` keep flags: some rows cleared at some steps (never all, never none).
fn keep(b: usize, t: usize, device: &Device) -> Tensor<2> {
    let flags: Vec<f32> = (0..b * t)
        .map(|i| if i % 7 == 3 || i % 11 == 5 { 0.0 } else { 1.0 })
        .collect();
    Tensor::from_data(TensorData::new(flags, [b, t]), device)
}

fn close(a: &Tensor<3>, b: &Tensor<3>) -> f32 {
    (a.clone() - b.clone()).abs().max().into_scalar::<f32>()
}

#[test]
fn the_fused_gru_computes_the_steps_states_and_gradients() {
    let device = crate::device::default_device().autodiff();
    let (b, t, h, d_in) = (5, 9, 8, 6);
    let mut init = crate::init::Init::new(3);
    let cell = GruCell::new(d_in, h, &mut init, &device);
    let x: Tensor<3> =
        Tensor::random([b, t, d_in], Distribution::Normal(0.0, 1.0), &device).require_grad();
    let h0: Tensor<2> =
        Tensor::random([b, h], Distribution::Normal(0.0, 1.0), &device).require_grad();
    let keep = keep(b, t, &device);
    // A loss that weighs every state differently, so that every gradient path counts.
    let weights: Tensor<3> = Tensor::random([b, t, h], Distribution::Normal(0.0, 1.0), &device);
    let run = |fused: bool| {
        let gx = cell
            .project(x.clone().reshape([b * t, d_in]))
            .reshape([b, t, 3 * h]);
        let states = if fused {
            cell.unroll(gx, h0.clone(), keep.clone())
        } else {
            unroll_by_steps(&cell, gx, h0.clone(), keep.clone())
        };
        let grads = (states.clone() * weights.clone()).sum().backward();
        let grad_x = x.grad(&grads).expect("x has a gradient");
        let grad_h0 = h0.grad(&grads).expect("h0 has a gradient");
        let grad_w = cell
            .hidden
            .weight
            .val()
            .grad(&grads)
            .expect("w has a gradient");
        let grad_wi = cell
            .input
            .weight
            .val()
            .grad(&grads)
            .expect("w_i has a gradient");
        let grad_b = cell
            .hidden
            .bias
            .as_ref()
            .unwrap()
            .val()
            .grad(&grads)
            .unwrap();
        (states.inner(), grad_x, grad_h0, grad_w, grad_wi, grad_b)
    };
    let (fused, steps) = (run(true), run(false));
    assert!(fused_on(&device), "the test runs the fused operation");
    assert!(
        close(&fused.0, &steps.0) < 1e-5,
        "states {}",
        close(&fused.0, &steps.0)
    );
    assert!(
        close(&fused.1, &steps.1) < 1e-4,
        "d x {}",
        close(&fused.1, &steps.1)
    );
    let two = |a: Tensor<2>, b: Tensor<2>| (a - b).abs().max().into_scalar::<f32>();
    let (dh0, dw, dwi) = (
        two(fused.2.clone(), steps.2.clone()),
        two(fused.3.clone(), steps.3.clone()),
        two(fused.4.clone(), steps.4.clone()),
    );
    assert!(dh0 < 1e-4 && dw < 1e-4 && dwi < 1e-4, "{dh0} {dw} {dwi}");
    let db: f32 = (fused.5 - steps.5).abs().max().into_scalar();
    assert!(db < 1e-4, "d bias {db}");
    // The gradients are not all zero (a cleared memory cuts h0's path, not every path).
    assert!(steps.2.abs().sum().into_scalar::<f32>() > 1e-3);
}

#[test]
fn without_autodiff_the_fused_gru_gives_the_same_states() {
    let device = crate::device::default_device();
    let (b, t, h) = (4, 6, 5);
    let mut init = crate::init::Init::new(8);
    let cell = GruCell::new(3, h, &mut init, &device);
    let gx: Tensor<3> = Tensor::random([b, t, 3 * h], Distribution::Normal(0.0, 1.0), &device);
    let h0: Tensor<2> = Tensor::random([b, h], Distribution::Normal(0.0, 1.0), &device);
    let keep = keep(b, t, &device);
    let fused = cell.unroll(gx.clone(), h0.clone(), keep.clone());
    let steps = unroll_by_steps(&cell, gx, h0, keep);
    assert!(close(&fused, &steps) < 1e-5);
}

//! Each choosing row's log π(chosen action), entropy and log π(END) from its group's
//! logits ([`super::row_groups`]) as one operation on the CPU, with a hand-written backward
//! pass.
//!
//! Why: built from burn's operations (`distribution::masked_log_softmax`, `entropy`,
//! `chosen_log_prob`), the three terms are about twenty passes over `[k, w]` (w = 777 at
//! the MOVE substep) each way, each an allocation and, forward, an autodiff node: 7 % of
//! a `cpu-fast` update's samples in a profile with call stacks (2026-11-28), and a share
//! of the backward nodes other terms use too (docs/results/choice-terms.md). Here
//! the forward pass reads a row twice (its best legal logit, then the exponentials and
//! their sums, eight lanes at a time) and the backward pass once.
//!
//! The formulas, over a row's legal columns L with logits l, best legal logit m, x = l − m
//! and s = Σ_L eˣ:
//! - log π(j) = x_j − ln s at a legal column j; at an illegal one m − 60 − (m + ln s),
//!   the value of the burn form, which floors illegal logits 60 below m
//!   (`distribution::ILLEGAL_GAP`) and detaches the floor;
//! - H = −Σ_L π log π = ln s − Σ_L eˣ·x / s.
//!
//! Gradients, with g_a, g_H, g_e flowing into log π(chosen), H and log π(END):
//! ∂/∂l_j = −π_j (g_a + g_e + g_H (log π(j) + H)) at every legal j, plus g_a at the chosen
//! column and g_e at END's where they are legal, and 0 at illegal columns. Illegal columns
//! get probability exactly 0 here (e⁻⁶⁰ of the best one in the burn form: below f32's
//! rounding of the sums), so both forms agree to rounding.

use crate::distribution::{chosen_log_prob, entropy, masked_log_softmax, ILLEGAL_GAP};
use crate::host_kernel::{fused_on, load, read, store, write};
use crate::tensor::tensor2;
use burn::backend::autodiff::checkpoint::base::Checkpointer;
use burn::backend::autodiff::checkpoint::strategy::CheckpointStrategy;
use burn::backend::autodiff::grads::Gradients;
use burn::backend::autodiff::ops::{Backward, Ops, OpsKind};
use burn::backend::autodiff::Autodiff;
use burn::backend::tensor::FloatTensor;
use burn::backend::{backend_extension, Backend, Dispatch, Flex, TensorMetadata};
use burn::prelude::*;
use rayon::prelude::*;
use wide::f32x8;

/// Rows per task when the rows are split over threads: each row is one softmax, and a
/// task of fewer would cost more to hand out than to compute.
const ROWS_PER_TASK: usize = 32;

/// log π(chosen), H and log π(END) of each of `k` rows, from `logits` `[k, w]`, the rows'
/// legal masks `mask` (`k × w`, 1 where legal), each row's chosen column `chosen` and
/// END's column `end`. Differentiable in `logits`. The host operation on burn's CPU
/// backend, the burn form elsewhere: the same values to rounding.
pub fn choice_terms(
    logits: Tensor<2>,
    mask: Vec<f32>,
    chosen: Vec<usize>,
    end: usize,
) -> [Tensor<1>; 3] {
    let [k, w] = logits.dims();
    debug_assert_eq!(mask.len(), k * w);
    debug_assert_eq!(chosen.len(), k);
    let terms = if fused_on(&logits.device()) {
        Tensor::from_dispatch(<Dispatch as ChoiceTermsOps>::choice_terms(
            logits.into_dispatch(),
            mask,
            chosen,
            end,
        ))
    } else {
        burn_form(logits, &mask, &chosen, end)
    };
    let term = |i: usize| terms.clone().narrow(0, i, 1).reshape([k]);
    [term(0), term(1), term(2)]
}

/// The three terms `[3, k]` from burn's operations: the reference the host operation is
/// tested against, and what runs off the CPU backend.
fn burn_form(logits: Tensor<2>, mask: &[f32], chosen: &[usize], end: usize) -> Tensor<2> {
    let [k, w] = logits.dims();
    let device = logits.device();
    let mut one_hot = vec![0f32; k * w];
    for (row, &a) in chosen.iter().enumerate() {
        one_hot[row * w + a] = 1.0;
    }
    let mask = tensor2(mask.to_vec(), [k, w], &device);
    let log_probs = masked_log_softmax(logits, mask.clone());
    let logp = chosen_log_prob(log_probs.clone(), tensor2(one_hot, [k, w], &device));
    let h = entropy(log_probs.clone(), mask);
    let end = log_probs.narrow(1, end, 1).reshape([k]);
    Tensor::stack(vec![logp, h, end], 0)
}

/// The operation as a burn backend extension: computed on the host for the CPU backend
/// (the trait's own body), with the backward pass of [`backward`] under autodiff.
#[backend_extension(Flex, Autodiff)]
pub trait ChoiceTermsOps: Backend {
    /// `[3, k]` from logits `[k, w]` and, on the host, the mask (`k × w`), each row's
    /// chosen column and END's column (see [`choice_terms`]).
    fn choice_terms(
        logits: FloatTensor<Self>,
        mask: Vec<f32>,
        chosen: Vec<usize>,
        end: usize,
    ) -> FloatTensor<Self> {
        forward_on::<Self>(logits, mask, chosen, end).0
    }
}

impl ChoiceTermsOps for Flex {}

/// What the backward pass needs of the forward one.
#[derive(Clone, Debug)]
struct Saved {
    w: usize,
    logits: Vec<f32>,
    mask: Vec<f32>,
    chosen: Vec<usize>,
    end: usize,
    /// eˣ at legal columns, 0 at the others (`k × w`).
    exps: Vec<f32>,
    /// Per row: m, ln s, H.
    rows: Vec<RowSums>,
}

/// One row's best legal logit, the log of its sum of exponentials and its entropy.
#[derive(Clone, Copy, Debug, Default)]
struct RowSums {
    best: f32,
    ln_sum: f32,
    entropy: f32,
}

impl RowSums {
    /// log π at column `j` of a row with logits `l` and mask `mask`.
    fn log_prob(&self, l: &[f32], mask: &[f32], j: usize) -> f32 {
        if mask[j] > 0.5 {
            l[j] - self.best - self.ln_sum
        } else {
            -ILLEGAL_GAP - self.ln_sum
        }
    }
}

fn forward_on<B: Backend>(
    logits: FloatTensor<B>,
    mask: Vec<f32>,
    chosen: Vec<usize>,
    end: usize,
) -> (FloatTensor<B>, Saved) {
    let device = logits.device();
    let w = logits.shape()[1];
    let logits = read::<B>(logits);
    let k = logits.len() / w.max(1);
    let mut exps = vec![0f32; k * w];
    let rows: Vec<RowSums> = exps
        .par_chunks_mut(w.max(1))
        .with_min_len(ROWS_PER_TASK)
        .enumerate()
        .map(|(r, e)| row_forward(&logits[r * w..][..w], &mask[r * w..][..w], e))
        .collect();
    let mut out = vec![0f32; 3 * k];
    for (r, sums) in rows.iter().enumerate() {
        let (l, m) = (&logits[r * w..][..w], &mask[r * w..][..w]);
        out[r] = sums.log_prob(l, m, chosen[r]);
        out[k + r] = sums.entropy;
        out[2 * k + r] = sums.log_prob(l, m, end);
    }
    let saved = Saved {
        w,
        logits,
        mask,
        chosen,
        end,
        exps,
        rows,
    };
    (write::<B, 2>(out, [3, k], &device), saved)
}

/// One row's sums, writing eˣ at its legal columns into `exps` (0 elsewhere).
fn row_forward(l: &[f32], mask: &[f32], exps: &mut [f32]) -> RowSums {
    let w = l.len();
    let half = f32x8::splat(0.5);
    // 1. The best legal logit.
    let mut best = f32x8::splat(f32::NEG_INFINITY);
    for at in (0..w).step_by(8) {
        let n = (w - at).min(8);
        let legal = load(mask, at, n).simd_gt(half);
        best = best.max(legal.select(load(l, at, n), f32x8::splat(f32::NEG_INFINITY)));
    }
    let best = best
        .to_array()
        .into_iter()
        .fold(f32::NEG_INFINITY, f32::max);
    if best == f32::NEG_INFINITY {
        // No legal column: never in a rollout (every seat has a legal move). All zero.
        return RowSums::default();
    }
    // 2. s = Σ eˣ and Σ eˣ·x over the legal columns (x ≤ 0 there).
    let (mut sum, mut weighted) = (f32x8::splat(0.0), f32x8::splat(0.0));
    let zero = f32x8::splat(0.0);
    for at in (0..w).step_by(8) {
        let n = (w - at).min(8);
        let legal = load(mask, at, n).simd_gt(half);
        let x = legal.select(load(l, at, n) - best, zero);
        let e = legal.select(x.exp(), zero);
        store(exps, at, n, e);
        sum += e;
        weighted += e * x;
    }
    let (sum, weighted) = (sum.reduce_add(), weighted.reduce_add());
    let ln_sum = sum.ln();
    RowSums {
        best,
        ln_sum,
        entropy: ln_sum - weighted / sum,
    }
}

/// ∂/∂logits `[k × w]` from the gradients `grad` `[3 × k]` of the three terms.
fn backward(s: &Saved, grad: &[f32]) -> Vec<f32> {
    let (w, k) = (s.w, s.rows.len());
    let mut out = vec![0f32; k * w];
    out.par_chunks_mut(w.max(1))
        .with_min_len(ROWS_PER_TASK)
        .enumerate()
        .for_each(|(r, g)| {
            let sums = s.rows[r];
            let (g_a, g_h, g_e) = (grad[r], grad[k + r], grad[2 * k + r]);
            let at_row = r * w;
            let (l, mask, exps) = (
                &s.logits[at_row..][..w],
                &s.mask[at_row..][..w],
                &s.exps[at_row..][..w],
            );
            // −π_j (C + g_H·x_j) with C = g_a + g_e + g_H (H − ln s); π_j = eˣ/s is 0 at
            // illegal columns, so they get 0.
            let inv_sum = f32x8::splat((-sums.ln_sum).exp());
            let c = f32x8::splat(g_a + g_e + g_h * (sums.entropy - sums.ln_sum));
            let (g_h, best) = (f32x8::splat(g_h), f32x8::splat(sums.best));
            for at in (0..w).step_by(8) {
                let n = (w - at).min(8);
                let p = load(exps, at, n) * inv_sum;
                let x = load(l, at, n) - best;
                store(g, at, n, -(p * (c + g_h * x)));
            }
            let (a, e) = (s.chosen[r], s.end);
            if mask[a] > 0.5 {
                g[a] += g_a;
            }
            if mask[e] > 0.5 {
                g[e] += g_e;
            }
        });
    out
}

#[derive(Debug)]
struct ChoiceTermsBackward;

impl<B: Backend> Backward<B, 1> for ChoiceTermsBackward {
    type State = Saved;

    fn backward(self, ops: Ops<Saved, 1>, grads: &mut Gradients, _: &mut Checkpointer) {
        let [logits] = ops.parents;
        let grad = grads.consume::<B>(&ops.node);
        let device = grad.device();
        let s = ops.state;
        if let Some(node) = logits {
            let g = backward(&s, &read::<B>(grad));
            let k = s.rows.len();
            grads.register::<B>(node.id, write::<B, 2>(g, [k, s.w], &device));
        }
    }
}

impl<B: Backend + ChoiceTermsOps, C: CheckpointStrategy> ChoiceTermsOps for Autodiff<B, C> {
    fn choice_terms(
        logits: FloatTensor<Self>,
        mask: Vec<f32>,
        chosen: Vec<usize>,
        end: usize,
    ) -> FloatTensor<Self> {
        let parents = [logits.node()];
        let (out, saved) = forward_on::<B>(logits.into_primitive(), mask, chosen, end);
        match ChoiceTermsBackward
            .prepare::<C>(parents)
            .compute_bound()
            .stateful()
        {
            OpsKind::Tracked(prep) => prep.finish(saved, out),
            OpsKind::UnTracked(prep) => prep.finish(out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tensor::to_vec;
    use rand_chacha::rand_core::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Random rows of width `w`: logits spread over ±`spread`, masks with 1 to w legal
    /// columns (some rows with a single one), chosen columns legal, END legal in some
    /// rows and not in others.
    fn rows(k: usize, w: usize, spread: f32, seed: u64) -> (Vec<f32>, Vec<f32>, Vec<usize>) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut unit = move || (rng.next_u32() % 100_000) as f32 / 100_000.0;
        let logits = (0..k * w).map(|_| (unit() * 2.0 - 1.0) * spread).collect();
        let mut mask = vec![0f32; k * w];
        let mut chosen = vec![];
        for r in 0..k {
            let share = [0.0, 0.1, 0.5, 1.0][r % 4];
            for j in 0..w {
                mask[r * w + j] = (unit() < share) as u8 as f32;
            }
            // At least one legal column; the chosen one is legal.
            let a = ((unit() * w as f32) as usize).min(w - 1);
            mask[r * w + a] = 1.0;
            chosen.push(a);
        }
        (logits, mask, chosen)
    }

    /// The host operation gives the burn form's three terms and, for a loss weighing them
    /// differently in every row, its gradient with respect to every logit, on widths with
    /// and without a tail of lanes (48 and 777 are the pointer head's groups), logits
    /// spread from ±1 to ±80, rows with one legal column, END legal or not.
    #[test]
    fn the_host_operation_matches_the_burn_form_values_and_gradients() {
        let device = crate::device::default_device().autodiff();
        assert!(fused_on(&device), "the test runs the host operation");
        for (case, (k, w, spread)) in [(70, 48, 4.0), (40, 777, 8.0), (33, 13, 80.0), (9, 8, 1.0)]
            .into_iter()
            .enumerate()
        {
            let (values, mask, chosen) = rows(k, w, spread, case as u64);
            let end = case % w;
            let weights: Vec<f32> = (0..3 * k).map(|i| (i % 7) as f32 - 3.0).collect();
            let run = |host: bool| {
                let leaf = tensor2(values.clone(), [k, w], &device).require_grad();
                let terms = if host {
                    choice_terms(leaf.clone(), mask.clone(), chosen.clone(), end)
                } else {
                    let t = burn_form(leaf.clone(), &mask, &chosen, end);
                    [0, 1, 2].map(|i| t.clone().narrow(0, i, 1).reshape([k]))
                };
                let joined = Tensor::cat(terms.to_vec(), 0);
                let weights = crate::tensor::tensor1(weights.clone(), &device);
                let loss = (joined.clone() * weights).sum();
                let grad = to_vec(leaf.grad(&loss.backward()).expect("a gradient"));
                (to_vec(joined), grad)
            };
            let ((host, host_grad), (reference, reference_grad)) = (run(true), run(false));
            let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * (1.0 + a.abs().max(b.abs()));
            for (i, (&a, &b)) in host.iter().zip(&reference).enumerate() {
                let what = ["log π(chosen)", "H", "log π(END)"][i / k];
                assert!(close(a, b), "case {case} {what} row {}: {a} vs {b}", i % k);
            }
            for (i, (&a, &b)) in host_grad.iter().zip(&reference_grad).enumerate() {
                let (r, j) = (i / w, i % w);
                if mask[i] > 0.5 {
                    assert!(close(a, b), "case {case} ∂/∂l({r}, {j}): {a} vs {b}");
                } else {
                    assert!(
                        a == 0.0 && b.abs() < 1e-20,
                        "case {case} illegal ({r}, {j}): {a} {b}"
                    );
                }
            }
            // A row with a single legal column: its action has probability 1, entropy 0.
            let single = (0..k).filter(|&r| mask[r * w..][..w].iter().sum::<f32>() == 1.0);
            for r in single {
                assert!(
                    host[r].abs() < 1e-6 && host[k + r].abs() < 1e-6,
                    "case {case} row {r}"
                );
            }
        }
    }
}

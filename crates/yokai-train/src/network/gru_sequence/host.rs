//! The GRU over a whole sequence and its backward pass, on plain `f32` buffers in the CPU's
//! memory: the arithmetic behind [`super::gru_sequence`].
//!
//! The layouts are burn's row-major ones: `gx` `[B, T, 3H]` (the input map of every step,
//! gates in the order reset, update, candidate), `h0` `[B, H]`, `keep` `[B, T]` (0 where the
//! memory is cleared before step t, else 1), `w` `[H, 3H]` and `bias` `[3H]` (the hidden
//! map, `gh = (h·keep) w + bias`), `hs` `[B, T, H]` (the state after every step). One step:
//!
//! ```text
//! p = h_{t−1}·keep_t    gh = p w + bias
//! r = σ(gx_r + gh_r)    z = σ(gx_z + gh_z)    c = tanh(gx_c + r ⊙ gh_c)
//! h_t = c + z ⊙ (p − c)
//! ```

use crate::host_kernel::{load, store};
use gemm::{gemm, Parallelism};
use wide::f32x8;

/// The sizes of one call: sequences, steps, state width.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dims {
    pub b: usize,
    pub t: usize,
    pub h: usize,
}

/// What the forward pass keeps for the backward one, per row and step: the reset gate, the
/// update gate, the candidate state, the candidate's hidden map `gh_c` and the state the
/// step read, `p = h_{t−1}·keep_t` (`[B, T, CACHED·H]`, in that order).
pub type Cache = Vec<f32>;

/// Values the [`Cache`] keeps per hidden unit and step.
const CACHED: usize = 5;

/// `dst[m×n] (+)= lhs[m×k] · rhs[k×n]`, each given by its pointer, row stride and column
/// stride (elements); one thread (the learner's shards already use every core).
///
/// # Safety
/// Every index the strides reach lies inside the slice it was taken from.
#[allow(clippy::too_many_arguments)]
unsafe fn product(
    (m, n, k): (usize, usize, usize),
    dst: *mut f32,
    (dst_rs, dst_cs): (usize, usize),
    accumulate: bool,
    lhs: *const f32,
    (lhs_rs, lhs_cs): (usize, usize),
    rhs: *const f32,
    (rhs_rs, rhs_cs): (usize, usize),
) {
    unsafe {
        gemm(
            m,
            n,
            k,
            dst,
            dst_cs as isize,
            dst_rs as isize,
            accumulate,
            lhs,
            lhs_cs as isize,
            lhs_rs as isize,
            rhs,
            rhs_cs as isize,
            rhs_rs as isize,
            1.0,
            1.0,
            false,
            false,
            false,
            Parallelism::None,
        );
    }
}

/// 1 / (1 + e^−x) for x ≥ 0 and e^x / (1 + e^x) below, e = e^−|x| never overflowing (the
/// form of burn-flex's lanes).
fn sigmoid(x: f32x8) -> f32x8 {
    let e = (-x.abs()).exp();
    let one = f32x8::splat(1.0);
    let denominator = one + e;
    x.simd_ge(f32x8::splat(0.0))
        .select(one / denominator, e / denominator)
}

/// `p = h_{t−1}·keep_t` for every row: `h0` at t = 0, else the previous step's output.
fn reset_states(d: Dims, t: usize, h0: &[f32], keep: &[f32], hs: &[f32], p: &mut [f32]) {
    let Dims { t: len, h, .. } = d;
    for (row, p) in p.chunks_exact_mut(h).enumerate() {
        let k = keep[row * len + t];
        let prev = if t == 0 {
            &h0[row * h..][..h]
        } else {
            &hs[(row * len + t - 1) * h..][..h]
        };
        for (p, &x) in p.iter_mut().zip(prev) {
            *p = x * k;
        }
    }
}

/// The states after every step `[B, T, H]` and the [`Cache`] for [`backward`].
pub fn forward(
    d: Dims,
    gx: &[f32],
    h0: &[f32],
    keep: &[f32],
    w: &[f32],
    bias: &[f32],
) -> (Vec<f32>, Cache) {
    let Dims { b, t: len, h } = d;
    let (g, stride) = (3 * h, CACHED * h);
    debug_assert_eq!(
        (gx.len(), h0.len(), keep.len(), w.len(), bias.len()),
        (b * len * g, b * h, b * len, h * g, g)
    );
    let mut hs = vec![0.0; b * len * h];
    let mut cache = vec![0.0; b * len * stride];
    let (mut p, mut gh) = (vec![0.0; b * h], vec![0.0; b * g]);
    for t in 0..len {
        reset_states(d, t, h0, keep, &hs, &mut p);
        // SAFETY: p is [b, h], w [h, g], gh [b, g], all row-major.
        unsafe {
            product(
                (b, g, h),
                gh.as_mut_ptr(),
                (g, 1),
                false,
                p.as_ptr(),
                (h, 1),
                w.as_ptr(),
                (g, 1),
            );
        }
        for row in 0..b {
            let at = row * len + t;
            let (x, a) = (&gx[at * g..][..g], &gh[row * g..][..g]);
            let (cached, p) = (&mut cache[at * stride..][..stride], &p[row * h..][..h]);
            let out = &mut hs[at * h..][..h];
            // Eight units at a time: the gates' exp and tanh in `wide`'s lanes, as burn's CPU
            // backend (vendor/burn-flex) computes them for the step-by-step GRU.
            for j in (0..h).step_by(8) {
                let n = 8.min(h - j);
                let at = |s: &[f32], k: usize| load(s, k * h + j, n);
                let r = sigmoid(at(x, 0) + at(a, 0) + at(bias, 0));
                let z = sigmoid(at(x, 1) + at(a, 1) + at(bias, 1));
                let ghc = at(a, 2) + at(bias, 2);
                let c = (at(x, 2) + r * ghc).tanh();
                store(out, j, n, c + z * (load(p, j, n) - c));
                for (k, v) in [r, z, c, ghc, load(p, j, n)].into_iter().enumerate() {
                    store(cached, k * h + j, n, v);
                }
            }
        }
    }
    (hs, cache)
}

/// The gradients of a loss with respect to `gx`, `h0`, `w` and `bias`, from its gradient
/// `dhs` with respect to every step's state `[B, T, H]`: back-propagation through time over
/// the forward pass's [`Cache`].
pub fn backward(d: Dims, keep: &[f32], w: &[f32], cache: &[f32], dhs: &[f32]) -> Grads {
    let Dims { b, t: len, h } = d;
    let (g, stride) = (3 * h, CACHED * h);
    let mut dgx = vec![0.0; b * len * g];
    // The gradient of the hidden map's output `gh` at every step, `[B, T, 3H]`: the
    // weights' gradient is one product over all steps at the end.
    let mut dgh = vec![0.0; b * len * g];
    // The gradient flowing into h_{t−1} from later steps.
    let mut carry = vec![0.0; b * h];
    for t in (0..len).rev() {
        // dp = dh ⊙ z here; the hidden map's part is added by the product below.
        for row in 0..b {
            let at = row * len + t;
            let cached = &cache[at * stride..][..stride];
            let (dx, da) = (&mut dgx[at * g..][..g], &mut dgh[at * g..][..g]);
            for j in 0..h {
                let dh = dhs[at * h + j] + carry[row * h + j];
                let (r, z, c, ghc, p) = (
                    cached[j],
                    cached[h + j],
                    cached[2 * h + j],
                    cached[3 * h + j],
                    cached[4 * h + j],
                );
                let dc = dh * (1.0 - z) * (1.0 - c * c);
                let dz = dh * (p - c) * z * (1.0 - z);
                let dr = dc * ghc * r * (1.0 - r);
                dx[j] = dr;
                dx[h + j] = dz;
                dx[2 * h + j] = dc;
                da[j] = dr;
                da[h + j] = dz;
                da[2 * h + j] = dc * r;
                carry[row * h + j] = dh * z;
            }
        }
        // carry += dgh_t · wᵀ, then through the reset: carry ⊙ keep_t.
        // SAFETY: dgh's step-t rows are [b, g] with row stride len·g; w [h, g] read as
        // wᵀ [g, h]; carry [b, h].
        unsafe {
            product(
                (b, h, g),
                carry.as_mut_ptr(),
                (h, 1),
                true,
                dgh.as_ptr().add(t * g),
                (len * g, 1),
                w.as_ptr(),
                (1, g),
            );
        }
        for (row, carry) in carry.chunks_exact_mut(h).enumerate() {
            let k = keep[row * len + t];
            carry.iter_mut().for_each(|x| *x *= k);
        }
    }
    let mut dw = vec![0.0; h * g];
    // SAFETY: the cached p are rows [B·T, h] of stride CACHED·h from offset 4h, read as pᵀ
    // [h, B·T]; dgh [B·T, g]; dw [h, g].
    unsafe {
        product(
            (h, g, b * len),
            dw.as_mut_ptr(),
            (g, 1),
            false,
            cache.as_ptr().add(4 * h),
            (1, stride),
            dgh.as_ptr(),
            (g, 1),
        );
    }
    let mut dbias = vec![0.0; g];
    for row in dgh.chunks_exact(g) {
        dbias.iter_mut().zip(row).for_each(|(s, x)| *s += x);
    }
    Grads {
        gx: dgx,
        h0: carry,
        w: dw,
        bias: dbias,
    }
}

/// What [`backward`] gives, each in its input's layout.
#[derive(Clone, Debug)]
pub struct Grads {
    pub gx: Vec<f32>,
    pub h0: Vec<f32>,
    pub w: Vec<f32>,
    pub bias: Vec<f32>,
}

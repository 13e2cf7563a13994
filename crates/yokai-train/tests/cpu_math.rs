//! burn's CPU backend as this workspace builds it (`vendor/burn-flex`, PATCHED.md) computes
//! `exp`, `tanh` and `sigmoid` of f32 tensors eight lanes at a time instead of through
//! libm. These tests hold those functions to f64's values within a few units in the last
//! place, on contiguous and on strided tensors, and check that an element's result does
//! not depend on where it sits in its tensor. Its maxima and minima along a dimension
//! that is not the last one walk each block's slices in order (PATCHED.md, 4); a test holds
//! them, and the index of each, to a plain loop's, ties and NaNs included.

use burn::prelude::*;
use burn::tensor::activation::sigmoid;
use burn::tensor::TensorData;

fn tensor(xs: &[f32]) -> Tensor<1> {
    Tensor::from_data(TensorData::new(xs.to_vec(), [xs.len()]), &Device::flex())
}

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .unwrap()
}

type Case = (
    &'static str,
    fn(Tensor<1>) -> Tensor<1>,
    fn(f64) -> f64,
    f32,
    f32,
);

const CASES: [Case; 3] = [
    ("exp", |t| t.exp(), f64::exp, -100.0, 88.0),
    ("tanh", |t| t.tanh(), f64::tanh, -12.0, 12.0),
    (
        "sigmoid",
        sigmoid,
        |x| 1.0 / (1.0 + (-x).exp()),
        -100.0,
        100.0,
    ),
];

#[test]
fn exp_tanh_and_sigmoid_agree_with_f64_within_a_few_ulps() {
    for (name, f, reference, lo, hi) in CASES {
        let n = 100_003;
        let mut xs: Vec<f32> = (0..n)
            .map(|i| lo + (hi - lo) * i as f32 / (n - 1) as f32)
            .collect();
        xs.extend([0.0, -0.0, 1e-6, -1e-6, 1e-30, -3e-4, 2.5e-4]);
        let ys = values(f(tensor(&xs)));
        let mut worst = 0.0f64;
        for (&x, &y) in xs.iter().zip(&ys) {
            let want = reference(x as f64);
            let ulp = ((want.abs() as f32).max(f32::MIN_POSITIVE) * f32::EPSILON) as f64;
            let err = (y as f64 - want).abs();
            assert!(
                err <= 4.0 * ulp + 1e-38,
                "{name}({x}) = {y}, f64 gives {want}"
            );
            worst = worst.max(err / ulp);
        }
        // A sweep this dense finds rounding somewhere: a test that compared f64 with itself
        // would not get here.
        assert!(worst > 0.0, "{name}: exact everywhere?");
    }
}

#[test]
fn an_elements_result_does_not_depend_on_its_position() {
    let xs: Vec<f32> = (0..6 * 7).map(|i| i as f32 * 0.41 - 8.0).collect();
    for (name, f, _, _, _) in CASES {
        let whole = values(f(tensor(&xs)));
        // Views from an offset (narrowed) go through the backend's copying path; the
        // whole tensor is changed in place with a different split into lanes.
        for start in 0..9 {
            let part = values(f(tensor(&xs).narrow(0, start, xs.len() - start)));
            assert_eq!(part, whole[start..], "{name} from {start}");
        }
    }
}

/// max / min along `dim` of a `[a, b, c]` tensor, by a plain loop with burn's rules: the
/// first index of the extremum wins a tie, and a NaN wins over any number (the first NaN).
fn extremum_by_loop(xs: &[f32], dims: [usize; 3], dim: usize, max: bool) -> (Vec<f32>, Vec<i64>) {
    let better =
        |v: f32, best: f32| !best.is_nan() && (v.is_nan() || if max { v > best } else { v < best });
    let strides = [dims[1] * dims[2], dims[2], 1];
    let mut out_dims = dims;
    out_dims[dim] = 1;
    let (mut values, mut indices) = (Vec::new(), Vec::new());
    for i in 0..out_dims[0] {
        for j in 0..out_dims[1] {
            for k in 0..out_dims[2] {
                let base = i * strides[0] + j * strides[1] + k * strides[2];
                let (mut best, mut at) = (xs[base], 0);
                for d in 1..dims[dim] {
                    let v = xs[base + d * strides[dim]];
                    if better(v, best) {
                        (best, at) = (v, d as i64);
                    }
                }
                values.push(best);
                indices.push(at);
            }
        }
    }
    (values, indices)
}

#[test]
fn maxima_and_minima_along_any_dimension_match_a_plain_loop() {
    use rand_chacha::rand_core::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    // Small blocks, the pointer head's `[B, 9, 64]` (above the crate's threshold for
    // splitting the work over threads), and odd sizes.
    for shape in [[2, 3, 4], [64, 9, 64], [5, 7, 3], [3, 1, 9], [1, 6, 1]] {
        let n: usize = shape.iter().product();
        // Few distinct values, so ties are common; now and then a NaN.
        let xs: Vec<f32> = (0..n)
            .map(|_| match rng.next_u32() % 50 {
                0 => f32::NAN,
                r => (r % 7) as f32 - 3.0,
            })
            .collect();
        let t: Tensor<3> = Tensor::from_data(TensorData::new(xs.clone(), shape), &Device::flex());
        for dim in 0..3 {
            for max in [true, false] {
                let (want, want_at) = extremum_by_loop(&xs, shape, dim, max);
                let (got, got_at) = if max {
                    t.clone().max_dim_with_indices(dim)
                } else {
                    t.clone().min_dim_with_indices(dim)
                };
                let alone = if max {
                    t.clone().max_dim(dim)
                } else {
                    t.clone().min_dim(dim)
                };
                let same = |a: &[f32], b: &[f32]| {
                    a.len() == b.len()
                        && a.iter()
                            .zip(b)
                            .all(|(x, y)| x == y || (x.is_nan() && y.is_nan()))
                };
                let what = format!(
                    "{} along {dim} of {shape:?}",
                    if max { "max" } else { "min" }
                );
                assert!(same(&values(got), &want), "{what}: values");
                assert!(
                    same(&values(alone), &want),
                    "{what}: values without indices"
                );
                let got_at = got_at
                    .into_data()
                    .convert::<i64>()
                    .try_into_vec::<i64>()
                    .unwrap();
                assert_eq!(got_at, want_at, "{what}: indices");
            }
        }
    }
}

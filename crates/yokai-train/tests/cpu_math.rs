//! burn's CPU backend as this workspace builds it (`vendor/burn-flex`, PATCHED.md) computes
//! `exp`, `tanh` and `sigmoid` of f32 tensors eight lanes at a time instead of through
//! libm. These tests hold those functions to f64's values within a few units in the last
//! place, on contiguous and on strided tensors, and check that an element's result does
//! not depend on where it sits in its tensor.

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

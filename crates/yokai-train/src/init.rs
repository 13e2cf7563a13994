//! Orthogonal initialisation drawn from our own seeded generator.
//!
//! burn's initialisers draw from a per-device global generator, which concurrent runs (or
//! tests) share; drawing here makes a network a pure function of its seed.

use burn::module::Param;
use burn::nn::conv::{Conv2d, Conv2dConfig};
use burn::nn::{Linear, LinearConfig};
use burn::prelude::*;
use burn::tensor::TensorData;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A generator of initial weights.
pub struct Init {
    rng: ChaCha8Rng,
}

impl Init {
    pub fn new(seed: u64) -> Init {
        Init {
            rng: ChaCha8Rng::seed_from_u64(seed),
        }
    }

    fn normal(&mut self) -> f64 {
        // Box-Muller; u1 in (0, 1] so the log is finite.
        let u1 = 1.0 - crate::distribution::unit_draw(&mut self.rng);
        let u2 = crate::distribution::unit_draw(&mut self.rng);
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    /// A `rows × cols` matrix (row-major) whose rows are orthonormal when `rows ≤ cols` and
    /// whose columns are orthonormal otherwise, times `gain` (as torch's `orthogonal_`).
    pub fn orthogonal(&mut self, rows: usize, cols: usize, gain: f64) -> Vec<f32> {
        let (n, m) = (rows.min(cols), rows.max(cols));
        // n orthonormal vectors of length m by modified Gram-Schmidt on Gaussian draws.
        let mut vecs: Vec<Vec<f64>> = Vec::with_capacity(n);
        while vecs.len() < n {
            let mut v: Vec<f64> = (0..m).map(|_| self.normal()).collect();
            for u in &vecs {
                let dot: f64 = v.iter().zip(u).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(u).for_each(|(a, b)| *a -= dot * b);
            }
            let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
            if norm > 1e-6 {
                v.iter_mut().for_each(|a| *a /= norm);
                vecs.push(v);
            }
        }
        let mut out = vec![0f32; rows * cols];
        for r in 0..rows {
            for c in 0..cols {
                let x = if rows <= cols { vecs[r][c] } else { vecs[c][r] };
                out[r * cols + c] = (x * gain) as f32;
            }
        }
        out
    }

    /// A linear layer `d_in → d_out` with orthogonal weights and zero bias.
    pub fn linear(&mut self, d_in: usize, d_out: usize, gain: f64, device: &Device) -> Linear {
        let mut layer = LinearConfig::new(d_in, d_out).init(device);
        // burn stores the weight as [d_in, d_out] (row layout).
        let w = self.orthogonal(d_in, d_out, gain);
        layer.weight =
            Param::from_tensor(Tensor::from_data(TensorData::new(w, [d_in, d_out]), device));
        layer.bias = Some(Param::from_tensor(Tensor::zeros([d_out], device)));
        layer
    }

    /// A 3×3 valid convolution with orthogonal weights (flattened per output filter).
    pub fn conv3x3(&mut self, c_in: usize, c_out: usize, gain: f64, device: &Device) -> Conv2d {
        let mut conv = Conv2dConfig::new([c_in, c_out], [3, 3]).init(device);
        let w = self.orthogonal(c_out, c_in * 9, gain);
        conv.weight = Param::from_tensor(Tensor::from_data(
            TensorData::new(w, [c_out, c_in, 3, 3]),
            device,
        ));
        conv.bias = Some(Param::from_tensor(Tensor::zeros([c_out], device)));
        conv
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orthogonal_rows_or_columns_are_orthonormal() {
        let mut init = Init::new(3);
        for (rows, cols) in [(4, 10), (10, 4), (6, 6)] {
            let w = init.orthogonal(rows, cols, 2.0);
            let (n, by_row) = if rows <= cols {
                (rows, true)
            } else {
                (cols, false)
            };
            let get = |i: usize, k: usize| {
                if by_row {
                    w[i * cols + k] as f64
                } else {
                    w[k * cols + i] as f64
                }
            };
            let len = rows.max(cols);
            for i in 0..n {
                for j in 0..n {
                    let dot: f64 = (0..len).map(|k| get(i, k) * get(j, k)).sum();
                    let want = if i == j { 4.0 } else { 0.0 };
                    assert!((dot - want).abs() < 1e-4, "{rows}x{cols} ({i},{j}) {dot}");
                }
            }
        }
    }

    #[test]
    fn same_seed_same_weights() {
        assert_eq!(
            Init::new(7).orthogonal(5, 9, 1.0),
            Init::new(7).orthogonal(5, 9, 1.0)
        );
        assert_ne!(
            Init::new(7).orthogonal(5, 9, 1.0),
            Init::new(8).orthogonal(5, 9, 1.0)
        );
    }
}

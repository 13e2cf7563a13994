//! Multinomial logistic regression: the linear probe. Features are standardised (mean 0,
//! variance 1 on the training rows), then the weights are fitted by full-batch gradient
//! descent on the cross-entropy with a small L2 penalty. Small and exact enough for a few
//! hundred features and tens of thousands of rows, with no dependency.
//!
//! The step size comes from the data: recurrent states are strongly correlated, so the
//! largest eigenvalue λ of the standardised features' covariance can be near the number of
//! features, and a fixed step would diverge there. The cross-entropy's curvature is at most
//! λ/2 along any direction, so a step of 1/(λ/2) never overshoots.

/// A fitted linear classifier over `features` inputs and `classes` outputs.
#[derive(Clone, Debug)]
pub struct LinearProbe {
    features: usize,
    classes: usize,
    mean: Vec<f32>,
    scale: Vec<f32>,
    /// `[classes × (features + 1)]`, the bias last.
    weights: Vec<f32>,
}

/// Gradient steps of a fit.
const STEPS: usize = 400;
const L2: f32 = 1e-4;

/// The largest eigenvalue of `zᵀz / rows` (`z` is `rows × features`, with a column of ones
/// for the bias), by power iteration.
fn largest_eigenvalue(z: &[f32], rows: usize, features: usize) -> f32 {
    let width = features + 1;
    let mut v = vec![1f32 / (width as f32).sqrt(); width];
    let mut lambda = 1f32;
    for _ in 0..30 {
        let mut next = vec![0f32; width];
        for r in 0..rows {
            let row = &z[r * features..][..features];
            let dot = row.iter().zip(&v).map(|(a, b)| a * b).sum::<f32>() + v[features];
            for (n, &a) in next.iter_mut().zip(row) {
                *n += dot * a;
            }
            next[features] += dot;
        }
        let norm = next.iter().map(|x| x * x).sum::<f32>().sqrt() / rows.max(1) as f32;
        if norm <= 0.0 {
            break;
        }
        lambda = norm;
        let scale = 1.0 / (norm * rows.max(1) as f32);
        v = next.into_iter().map(|x| x * scale).collect();
    }
    lambda.max(1e-3)
}

impl LinearProbe {
    /// Fit on `x` (`rows × features`, row-major) with labels `y` (`0..classes`).
    pub fn fit(x: &[f32], y: &[u8], features: usize, classes: usize) -> LinearProbe {
        let rows = y.len();
        assert_eq!(x.len(), rows * features, "x holds rows × features values");
        let mut mean = vec![0f32; features];
        let mut scale = vec![1f32; features];
        if rows > 0 {
            for r in 0..rows {
                for (m, &v) in mean.iter_mut().zip(&x[r * features..][..features]) {
                    *m += v / rows as f32;
                }
            }
            let mut var = vec![0f32; features];
            for r in 0..rows {
                for f in 0..features {
                    var[f] += (x[r * features + f] - mean[f]).powi(2) / rows as f32;
                }
            }
            for (s, v) in scale.iter_mut().zip(var) {
                *s = if v > 1e-12 { 1.0 / v.sqrt() } else { 0.0 };
            }
        }
        let mut probe = LinearProbe {
            features,
            classes,
            mean,
            scale,
            weights: vec![0f32; classes * (features + 1)],
        };
        let z: Vec<f32> = (0..rows * features)
            .map(|i| (x[i] - probe.mean[i % features]) * probe.scale[i % features])
            .collect();
        let width = features + 1;
        let step = 1.0 / (0.5 * largest_eigenvalue(&z, rows, features) + L2);
        let mut grad = vec![0f32; classes * width];
        let mut p = vec![0f32; classes];
        for _ in 0..STEPS {
            grad.iter_mut().for_each(|g| *g = 0.0);
            for r in 0..rows {
                let row = &z[r * features..][..features];
                probe.probabilities_standardised(row, &mut p);
                p[y[r] as usize] -= 1.0;
                for (c, &err) in p.iter().enumerate() {
                    let g = &mut grad[c * width..][..width];
                    for (gf, &v) in g.iter_mut().zip(row) {
                        *gf += err * v;
                    }
                    g[features] += err;
                }
            }
            let n = rows.max(1) as f32;
            for (w, g) in probe.weights.iter_mut().zip(&grad) {
                *w -= step * (g / n + L2 * *w);
            }
        }
        probe
    }

    fn probabilities_standardised(&self, z: &[f32], out: &mut [f32]) {
        let width = self.features + 1;
        for (c, o) in out.iter_mut().enumerate() {
            let w = &self.weights[c * width..][..width];
            *o = w[self.features] + w.iter().zip(z).map(|(a, b)| a * b).sum::<f32>();
        }
        let max = out.iter().cloned().fold(f32::MIN, f32::max);
        let mut total = 0.0;
        for o in out.iter_mut() {
            *o = (*o - max).exp();
            total += *o;
        }
        out.iter_mut().for_each(|o| *o /= total);
    }

    /// The most likely class of one row of features.
    pub fn predict(&self, x: &[f32]) -> u8 {
        let z: Vec<f32> = x
            .iter()
            .enumerate()
            .map(|(f, &v)| (v - self.mean[f]) * self.scale[f])
            .collect();
        let mut p = vec![0f32; self.classes];
        self.probabilities_standardised(&z, &mut p);
        crate::distribution::first_max(&p) as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_chacha::rand_core::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// Rows of `features` values: the class's one-hot through a random projection plus
    /// `noise`, or noise alone.
    fn data(rows: usize, features: usize, signal: bool, seed: u64) -> (Vec<f32>, Vec<u8>) {
        let uniform = |rng: &mut ChaCha8Rng| crate::distribution::unit_draw(rng) as f32 - 0.5;
        // One projection for every call; the noise (and so the rows) differ by `seed`.
        let mut fixed = ChaCha8Rng::seed_from_u64(99);
        let projection: Vec<f32> = (0..3 * features).map(|_| uniform(&mut fixed)).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut uniform = move || uniform(&mut rng);
        let (mut x, mut y) = (Vec::new(), Vec::new());
        for r in 0..rows {
            let class = (r * 7 + r / 3) % 3;
            y.push(class as u8);
            for f in 0..features {
                let s = if signal {
                    projection[class * features + f]
                } else {
                    0.0
                };
                x.push(s + 0.1 * uniform());
            }
        }
        (x, y)
    }

    fn accuracy(probe: &LinearProbe, x: &[f32], y: &[u8], features: usize) -> f64 {
        let hits = (0..y.len())
            .filter(|&r| probe.predict(&x[r * features..][..features]) == y[r])
            .count();
        hits as f64 / y.len() as f64
    }

    /// A state that holds the colour linearly is read back almost perfectly on held-out
    /// rows; pure noise is read at chance (1/3).
    #[test]
    fn a_linear_code_is_read_and_noise_is_not() {
        let features = 32;
        let (x, y) = data(2000, features, true, 1);
        let (tx, ty) = data(1000, features, true, 4);
        let probe = LinearProbe::fit(&x, &y, features, 3);
        let acc = accuracy(&probe, &tx, &ty, features);
        assert!(acc > 0.98, "linear code: {acc}");
        let (x, y) = data(2000, features, false, 2);
        let (tx, ty) = data(3000, features, false, 3);
        let probe = LinearProbe::fit(&x, &y, features, 3);
        let acc = accuracy(&probe, &tx, &ty, features);
        assert!((acc - 1.0 / 3.0).abs() < 0.04, "noise: {acc}");
    }
}

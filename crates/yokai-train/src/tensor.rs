//! Moving numbers between plain vectors and burn tensors: the few conversions every layer
//! of the crate needs (networks, the learner, beliefs, policies), in one leaf module.

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::nn::Linear;
use burn::prelude::*;
use burn::tensor::TensorData;

pub(crate) fn tensor2(v: Vec<f32>, shape: [usize; 2], device: &Device) -> Tensor<2> {
    Tensor::from_data(TensorData::new(v, shape), device)
}

pub(crate) fn tensor1(v: Vec<f32>, device: &Device) -> Tensor<1> {
    let n = v.len();
    Tensor::from_data(TensorData::new(v, [n]), device)
}

/// Row indices for `Tensor::select`.
pub(crate) fn rows_tensor(rows: Vec<i64>, device: &Device) -> Tensor<1, Int> {
    let n = rows.len();
    Tensor::from_data(TensorData::new(rows, [n]), device)
}

pub(crate) fn to_vec<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .expect("f32 tensor data")
}

/// Every float parameter of a module, flattened in visiting order.
pub fn parameters<M: Module>(model: &M) -> Vec<f32> {
    struct Collect(Vec<f32>);
    impl ModuleVisitor for Collect {
        fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
            self.0.extend(to_vec(param.val()));
        }
    }
    let mut c = Collect(Vec::new());
    model.visit(&mut c);
    c.0
}

/// `model` with its float parameters replaced by `values`, read in the order
/// [`parameters`] writes them (its inverse): for weights computed outside the module, as
/// averaged ones. `values` must hold exactly as many numbers as the module has.
pub fn with_parameters<M: Module>(model: M, values: &[f32], device: &Device) -> M {
    struct Fill<'a> {
        values: &'a [f32],
        at: usize,
        device: &'a Device,
    }
    impl ModuleMapper for Fill<'_> {
        fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
            param.map(|t| {
                let shape = t.dims();
                let n = shape.iter().product::<usize>();
                let own = self.values[self.at..self.at + n].to_vec();
                self.at += n;
                Tensor::from_data(TensorData::new(own, shape), self.device)
            })
        }
    }
    let mut fill = Fill {
        values,
        at: 0,
        device,
    };
    let model = model.map(&mut fill);
    assert_eq!(
        fill.at,
        values.len(),
        "as many values as the module has parameters"
    );
    model
}

/// A linear layer applied to every item of a batch of sets (nodes, cards, time steps):
/// `[..., d_in]` → `[..., d_out]` as one `[rows, d_in] @ [d_in, d_out]` product.
///
/// Why: burn 0.22 (`burn-dispatch`, the backend the trainer runs on) builds `Linear::forward`
/// of a 3-D input from a batched product against the broadcast weight whenever folding the
/// batch into the rows would make the output "less square" — `[512, 9, 32]` through a
/// `32 × 32` layer became 512 gemm calls, each with its own packing buffers, and a weight
/// gradient summed over a `[512, 32, 32]` tensor. perf put 17 % of a `cpu-op` update's CPU
/// time in those products (`docs/results/folded-linear.md`). Folding gives the same values
/// up to the order of the weight gradient's sums.
pub(crate) trait FoldedLinear {
    fn forward_folded<const D: usize>(&self, x: Tensor<D>) -> Tensor<D>;
}

impl FoldedLinear for Linear {
    fn forward_folded<const D: usize>(&self, x: Tensor<D>) -> Tensor<D> {
        if D <= 2 {
            return self.forward(x);
        }
        let mut dims = x.dims();
        let d_in = dims[D - 1];
        let rows = dims[..D - 1].iter().product();
        let y = self.forward(x.reshape([rows, d_in]));
        dims[D - 1] = y.dims()[1];
        y.reshape(dims)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::init::Init;

    /// `with_parameters` reads values in the order `parameters` writes them: a module
    /// filled with 0, 1, 2, … gives them back, and a weight and a bias get their own runs.
    #[test]
    fn with_parameters_inverts_parameters() {
        let device = crate::device::default_device();
        let layer = burn::nn::LinearConfig::new(3, 2).init(&device);
        let n = parameters(&layer).len();
        assert_eq!(n, 3 * 2 + 2);
        let values: Vec<f32> = (0..n).map(|i| i as f32).collect();
        let filled = with_parameters(layer, &values, &device);
        assert_eq!(parameters(&filled), values);
        assert_eq!(to_vec(filled.weight.val()), values[..6]);
    }

    /// A folded 3-D linear layer gives `Linear::forward`'s values, and the same gradients
    /// with respect to its input, weight and bias (within the sums' rounding).
    #[test]
    fn a_folded_linear_layer_equals_the_plain_one() {
        let device = Device::flex().autodiff();
        let layer = Init::new(3).linear(5, 4, 1.0, &device);
        let x: Vec<f32> = (0..6 * 7 * 5)
            .map(|i| ((i * 37) % 23) as f32 / 11.0 - 1.0)
            .collect();
        let run = |folded: bool| {
            let input = Tensor::<3>::from_data(TensorData::new(x.clone(), [6, 7, 5]), &device)
                .require_grad();
            let y = if folded {
                layer.forward_folded(input.clone())
            } else {
                layer.forward(input.clone())
            };
            assert_eq!(y.dims(), [6, 7, 4]);
            let w: Tensor<3> = Tensor::from_data(
                TensorData::new(
                    (0..6 * 7 * 4).map(|i| (i % 5) as f32 - 2.0).collect(),
                    [6, 7, 4],
                ),
                &device,
            );
            let grads = (y.clone() * w).sum().backward();
            let bias = layer.bias.as_ref().unwrap().val();
            (
                to_vec(y),
                to_vec(input.grad(&grads).unwrap()),
                to_vec(layer.weight.val().grad(&grads).unwrap()),
                to_vec(bias.grad(&grads).unwrap()),
            )
        };
        let (plain, folded) = (run(false), run(true));
        let pairs = [
            ("output", &plain.0, &folded.0),
            ("input gradient", &plain.1, &folded.1),
            ("weight gradient", &plain.2, &folded.2),
            ("bias gradient", &plain.3, &folded.3),
        ];
        for (name, a, b) in pairs {
            assert_eq!(a.len(), b.len(), "{name}");
            for (i, (&p, &q)) in a.iter().zip(b.iter()).enumerate() {
                assert!(
                    (p - q).abs() <= 1e-5 * (1.0 + p.abs()),
                    "{name}[{i}]: {p} vs {q}"
                );
            }
        }
        assert!(plain.2.iter().any(|&g| g != 0.0));
    }
}

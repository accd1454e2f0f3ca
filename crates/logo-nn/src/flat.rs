//! A module's parameters (and gradients) as one flat `f64` vector, in the module's own
//! visiting order (fields in declaration order; a `Linear` is weight `[in, out]` row-major,
//! then bias). TRPO's conjugate gradient and line search work on these vectors.

use burn::module::{AutodiffModule, Module, ModuleMapper, ModuleVisitor, Param};
use burn::tensor::backend::{AutodiffBackend, Backend};
use burn::tensor::{Tensor, TensorCreationOptions, TensorData};

use crate::mlp::{LayerTensors, Mlp};

/// A tensor's values as `f64`, whatever the backend's float type.
pub fn to_f64<B: Backend, const D: usize>(t: Tensor<B, D>) -> Vec<f64> {
    t.into_data()
        .convert::<f64>()
        .into_vec::<f64>()
        .expect("a float tensor converts to f64")
}

/// A tensor of `shape` from `f64` values, in the backend's float type.
pub fn from_f64<B: Backend, const D: usize>(
    values: &[f64],
    shape: [usize; D],
    device: &B::Device,
) -> Tensor<B, D> {
    from_vec_f64(values.to_vec(), shape, device)
}

/// As [`from_f64`], taking the values without copying them first.
///
/// The tensor gets the backend's own float type explicitly: burn 0.21 otherwise takes a
/// device's default dtype from the first backend that used the device, so an
/// `NdArray<f32>` tensor made after any `NdArray<f64>` one (the same CPU device) would
/// silently hold f64.
pub fn from_vec_f64<B: Backend, const D: usize>(
    values: Vec<f64>,
    shape: [usize; D],
    device: &B::Device,
) -> Tensor<B, D> {
    let options = TensorCreationOptions::new(device.clone())
        .with_dtype(<B::FloatElem as burn::tensor::Element>::dtype());
    Tensor::from_data(TensorData::new(values, shape), options)
}

/// Σ aᵢ bᵢ of two flat vectors, in order.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

struct Collect(Vec<f64>);

impl<B: Backend> ModuleVisitor<B> for Collect {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<B, D>>) {
        self.0.extend(to_f64(param.val()));
    }
}

/// Every float parameter of `module`, flattened.
pub fn params_to_vec<B: Backend, M: Module<B>>(module: &M) -> Vec<f64> {
    let mut collect = Collect(Vec::with_capacity(module.num_params()));
    module.visit(&mut collect);
    collect.0
}

struct Load<'a> {
    flat: &'a [f64],
    pos: usize,
}

impl<B: Backend> ModuleMapper<B> for Load<'_> {
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<B, D>>) -> Param<Tensor<B, D>> {
        param.map(|t| {
            let shape = t.shape();
            let n = shape.num_elements();
            let values = &self.flat[self.pos..self.pos + n];
            self.pos += n;
            let new = Tensor::from_data(TensorData::new(values.to_vec(), shape), &t.device());
            if t.is_require_grad() {
                new.require_grad()
            } else {
                new
            }
        })
    }
}

/// `module` with its parameters replaced by `flat` (as from [`params_to_vec`]).
///
/// # Panics
/// If `flat.len()` is not `module.num_params()`: a caller's bug, not a user input.
pub fn vec_to_params<B: Backend, M: Module<B>>(module: M, flat: &[f64]) -> M {
    assert_eq!(
        flat.len(),
        module.num_params(),
        "flat parameter vector of the wrong length"
    );
    module.map(&mut Load { flat, pos: 0 })
}

struct CollectGrads<'a, B: AutodiffBackend> {
    grads: &'a B::Gradients,
    out: Vec<f64>,
}

impl<B: AutodiffBackend> ModuleVisitor<B> for CollectGrads<'_, B> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<B, D>>) {
        let value = param.val();
        match value.grad(self.grads) {
            Some(g) => self.out.extend(to_f64(g)),
            None => self
                .out
                .extend(std::iter::repeat_n(0.0, value.shape().num_elements())),
        }
    }
}

/// The gradient of every float parameter of `module`, flattened like [`params_to_vec`]
/// (zeros where the loss does not depend on a parameter).
pub fn grads_to_vec<B: AutodiffBackend, M: AutodiffModule<B>>(
    module: &M,
    grads: &B::Gradients,
) -> Vec<f64> {
    let mut collect = CollectGrads {
        grads,
        out: Vec::with_capacity(module.num_params()),
    };
    module.visit(&mut collect);
    collect.out
}

/// Splits a flat vector laid out like an [`Mlp`]'s parameters into per-layer tensors.
pub fn split_layers<B: Backend>(mlp: &Mlp<B>, flat: &[f64], device: &B::Device) -> LayerTensors<B> {
    let mut pos = 0;
    mlp.layers
        .iter()
        .map(|layer| {
            let [i, o] = layer.weight.shape().dims();
            let w = from_f64(&flat[pos..pos + i * o], [i, o], device);
            let b = from_f64(&flat[pos + i * o..pos + i * o + o], [o], device);
            pos += i * o + o;
            (w, b)
        })
        .collect()
}

/// The inverse of [`split_layers`].
pub fn flatten_layers<B: Backend>(layers: LayerTensors<B>) -> Vec<f64> {
    layers
        .into_iter()
        .flat_map(|(w, b)| to_f64(w).into_iter().chain(to_f64(b)))
        .collect()
}

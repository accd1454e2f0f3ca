//! The [`Engine`] trait itself, apart from its two implementations (see the module
//! doc of `engine`).

use burn::tensor::backend::Backend;
use burn::tensor::{Int, Tensor, TensorCreationOptions, TensorData};

/// The device of an engine's backend.
pub type Device<E> = burn::tensor::Device<<E as Engine>::B>;

/// What the algorithms need from a network, wherever it runs. See the module doc.
pub trait Engine: Send + Sync + 'static {
    /// The backend holding batch columns and network outputs, on which losses run.
    type B: Backend;
    /// An MLP with its parameters, in this engine's form.
    type Net: Clone + Send + Sync;
    /// Rows of network inputs, uploaded once and reused by every pass over them.
    type Rows: Clone + Send + Sync;
    /// The activations of one forward pass.
    type Trace: Send + Sync;
    /// What the Gauss–Newton product needs besides the trace, computed once per trace.
    type Curvature: Send + Sync;

    /// `values` as a tensor of `shape` on the engine's device: a host → device transfer
    /// (batch columns, targets, log σ).
    fn upload<const D: usize>(&self, values: &[f64], shape: [usize; D]) -> Tensor<Self::B, D> {
        crate::flat::from_f64(values, shape, &self.device())
    }
    /// A tensor's values on the host: a device → host transfer (values for GAE, rewards,
    /// loss values).
    fn download<const D: usize>(&self, t: Tensor<Self::B, D>) -> Vec<f64> {
        crate::flat::to_f64(t)
    }

    /// What this engine is, for logs and checkpoint metadata ("kernels f64", …).
    fn describe(&self) -> String;
    fn device(&self) -> Device<Self>;

    /// `values` (row-major, `width` per row) as network inputs.
    fn rows(&self, values: &[f64], width: usize) -> Self::Rows;
    /// The rows at `indices`, in that order (minibatches, subsamples).
    fn select(&self, rows: &Self::Rows, indices: &[usize]) -> Self::Rows;
    fn num_rows(&self, rows: &Self::Rows) -> usize;

    /// An MLP with layer sizes `dims` (`[input, hidden..., output]`) and parameters laid
    /// out as [`crate::flat::params_to_vec`] lays out a [`crate::Mlp`].
    fn net(&self, dims: &[usize], params: &[f64]) -> Self::Net;
    fn params(&self, net: &Self::Net) -> Vec<f64>;

    fn trace(&self, net: &Self::Net, x: &Self::Rows) -> Self::Trace;
    /// The network's output for every row of the trace, `[rows, output]`.
    fn output(&self, trace: &Self::Trace) -> Tensor<Self::B, 2>;
    /// The output for every row of `x`, without keeping the activations.
    fn forward(&self, net: &Self::Net, x: &Self::Rows) -> Tensor<Self::B, 2> {
        self.output(&self.trace(net, x))
    }
    /// Jᵀ·u: the parameter gradient of Σ output ⊙ `upstream` at the trace's rows.
    fn vjp(&self, net: &Self::Net, trace: &Self::Trace, upstream: Tensor<Self::B, 2>) -> Vec<f64>;
    fn curvature(&self, net: &Self::Net, trace: &Self::Trace) -> Self::Curvature;
    /// Σ_rows J_rᵀ diag(`output_weights`) J_r `tangent`: the Gauss–Newton matrix of the
    /// trace's rows times a parameter-shaped vector.
    fn gauss_newton(
        &self,
        net: &Self::Net,
        trace: &Self::Trace,
        curvature: &Self::Curvature,
        tangent: &[f64],
        output_weights: &[f64],
    ) -> Vec<f64>;
}

/// The rows of `t` at `indices` (dimension 0).
///
/// The index tensor names its dtype: made without one, it would fix the CPU device's
/// default dtypes from `B`, and a float32 engine's minibatch would turn the float64
/// modules made after it into float32 ones (tests/dtype_order.rs).
pub fn select_rows<B: Backend, const D: usize>(
    t: &Tensor<B, D>,
    indices: &[usize],
) -> Tensor<B, D> {
    let idx: Vec<i64> = indices.iter().map(|&i| i as i64).collect();
    let options = TensorCreationOptions::new(t.device())
        .with_dtype(<B::IntElem as burn::tensor::Element>::dtype());
    let idx = Tensor::<B, 1, Int>::from_data(TensorData::new(idx, [indices.len()]), options);
    t.clone().select(0, idx)
}

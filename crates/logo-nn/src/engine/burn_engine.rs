//! The burn engine: the MLP of `crate::mlp` as burn tensor ops on any backend `B`
//! (ndarray, wgpu, …). Its passes are the definition's own: the forward trace, the
//! forward-mode J·v and the reverse-mode Jᵀ·u of [`Mlp`]; the Gauss–Newton product is the
//! one followed by the other. Parameters stay on the device; only flat vectors cross.

use burn::module::Param;
use burn::nn::Linear;
use burn::tensor::Tensor;
use burn::tensor::backend::Backend;

use super::Engine;
use crate::flat::{flatten_layers, from_f64, params_to_vec, split_layers};
use crate::mlp::Mlp;

/// Burn tensor ops on the backend `B` and its `device`.
#[derive(Debug, Clone)]
pub struct BurnEngine<B: Backend> {
    pub device: B::Device,
    /// The backend's name and float type, as the user chose them ("ndarray f32").
    pub name: String,
}

impl<B: Backend> BurnEngine<B> {
    pub fn new(device: B::Device, name: &str) -> Self {
        Self {
            device,
            name: name.to_string(),
        }
    }
}

/// The inputs of every layer (`[x, h1, ...]`) and the output.
pub struct BurnTrace<B: Backend> {
    inputs: Vec<Tensor<B, 2>>,
    output: Tensor<B, 2>,
}

impl<B: Backend> Engine for BurnEngine<B> {
    type B = B;
    type Net = Mlp<B>;
    type Rows = Tensor<B, 2>;
    type Trace = BurnTrace<B>;
    type Curvature = ();

    fn describe(&self) -> String {
        format!("burn {}", self.name)
    }

    fn device(&self) -> B::Device {
        self.device.clone()
    }

    fn rows(&self, values: &[f64], width: usize) -> Tensor<B, 2> {
        assert!(
            width > 0 && values.len().is_multiple_of(width),
            "rows of the wrong width"
        );
        from_f64(values, [values.len() / width, width], &self.device)
    }

    fn select(&self, rows: &Tensor<B, 2>, indices: &[usize]) -> Tensor<B, 2> {
        super::select_rows(rows, indices)
    }

    fn num_rows(&self, rows: &Tensor<B, 2>) -> usize {
        rows.dims()[0]
    }

    fn net(&self, dims: &[usize], params: &[f64]) -> Mlp<B> {
        assert_eq!(
            params.len(),
            crate::mlp::num_params(dims),
            "parameters of the wrong length"
        );
        let mut at = 0;
        let layers = dims
            .windows(2)
            .map(|w| {
                let (fan_in, fan_out) = (w[0], w[1]);
                let weight = from_f64(
                    &params[at..at + fan_in * fan_out],
                    [fan_in, fan_out],
                    &self.device,
                );
                at += fan_in * fan_out;
                let bias = from_f64(&params[at..at + fan_out], [fan_out], &self.device);
                at += fan_out;
                Linear {
                    weight: Param::from_tensor(weight),
                    bias: Some(Param::from_tensor(bias)),
                }
            })
            .collect();
        Mlp { layers }
    }

    fn params(&self, net: &Mlp<B>) -> Vec<f64> {
        params_to_vec(net)
    }

    fn trace(&self, net: &Mlp<B>, x: &Tensor<B, 2>) -> BurnTrace<B> {
        let (inputs, output) = net.forward_trace(x.clone());
        BurnTrace { inputs, output }
    }

    fn output(&self, trace: &BurnTrace<B>) -> Tensor<B, 2> {
        trace.output.clone()
    }

    fn forward(&self, net: &Mlp<B>, x: &Tensor<B, 2>) -> Tensor<B, 2> {
        net.forward(x.clone())
    }

    fn vjp(&self, net: &Mlp<B>, trace: &BurnTrace<B>, upstream: Tensor<B, 2>) -> Vec<f64> {
        flatten_layers(net.vjp(&trace.inputs, upstream))
    }

    fn curvature(&self, _net: &Mlp<B>, _trace: &BurnTrace<B>) {}

    fn gauss_newton(
        &self,
        net: &Mlp<B>,
        trace: &BurnTrace<B>,
        _curvature: &(),
        tangent: &[f64],
        output_weights: &[f64],
    ) -> Vec<f64> {
        let tangent = split_layers(net, tangent, &self.device);
        let jv = net.jvp(&trace.inputs, &tangent);
        let weights = from_f64::<B, 2>(output_weights, [1, output_weights.len()], &self.device);
        flatten_layers(net.vjp(&trace.inputs, jv * weights))
    }
}

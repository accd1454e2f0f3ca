//! The tanh MLP every network here is made of: its definition (layer sizes, the
//! reference's initialisation), and its forward- and reverse-mode derivatives over cached
//! activations, written with burn tensor ops for any backend (the burn engine's trace,
//! J·v and Jᵀ·u; burn's `Linear` cannot be differentiated twice, and these need no second
//! forward pass).

use burn::module::{Module, Param};
use burn::nn::{Linear, LinearConfig};
use burn::tensor::{Tensor, backend::Backend};
use serde::{Deserialize, Serialize};

/// Sizes and output scaling of an MLP.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MlpConfig {
    pub input: usize,
    pub hidden: Vec<usize>,
    pub output: usize,
    /// The output layer's initial weights are multiplied by this and its bias zeroed
    /// (0.1 in the LOGO reference, for the policy mean and the critics).
    pub output_scale: Option<f64>,
}

/// Linear layers with tanh between them; the output layer is linear.
#[derive(Module, Debug)]
pub struct Mlp<B: Backend> {
    pub layers: Vec<Linear<B>>,
}

/// One parameter-shaped value per layer: (weight `[in, out]`, bias `[out]`).
pub type LayerTensors<B> = Vec<(Tensor<B, 2>, Tensor<B, 1>)>;

impl MlpConfig {
    /// `[input, hidden..., output]`.
    pub fn dims(&self) -> Vec<usize> {
        std::iter::once(self.input)
            .chain(self.hidden.iter().copied())
            .chain([self.output])
            .collect()
    }

    pub fn init<B: Backend>(&self, device: &B::Device) -> Mlp<B> {
        let dims = self.dims();
        let last = dims.len() - 2;
        let layers = dims
            .windows(2)
            .enumerate()
            .map(|(i, w)| {
                // burn's default initialiser is PyTorch's: weight and bias ~ U(±1/sqrt(fan_in)).
                let mut layer = LinearConfig::new(w[0], w[1]).init::<B>(device);
                if let (true, Some(scale)) = (i == last, self.output_scale) {
                    // detach + require_grad: the scaled weight must be a leaf of the autodiff
                    // graph, or it would never receive a gradient.
                    layer.weight = layer
                        .weight
                        .map(|w| w.mul_scalar(scale).detach().require_grad());
                    layer.bias = Some(Param::from_tensor(Tensor::zeros([w[1]], device)));
                }
                layer
            })
            .collect();
        Mlp { layers }
    }

    /// Number of scalar parameters.
    pub fn num_params(&self) -> usize {
        num_params(&self.dims())
    }
}

/// Parameters of an MLP with layer sizes `dims`: a weight and a bias per layer.
pub fn num_params(dims: &[usize]) -> usize {
    dims.windows(2).map(|w| w[0] * w[1] + w[1]).sum()
}

impl<B: Backend> Mlp<B> {
    /// `[input, hidden..., output]`.
    pub fn dims(&self) -> Vec<usize> {
        std::iter::once(self.layers[0].weight.dims()[0])
            .chain(self.layers.iter().map(|l| l.weight.dims()[1]))
            .collect()
    }

    pub fn forward(&self, x: Tensor<B, 2>) -> Tensor<B, 2> {
        let last = self.layers.len() - 1;
        self.layers.iter().enumerate().fold(x, |h, (i, layer)| {
            let z = layer.forward(h);
            if i < last { z.tanh() } else { z }
        })
    }

    /// The input of every layer (`[x, h1, h2, ...]`), then the output.
    pub fn forward_trace(&self, x: Tensor<B, 2>) -> (Vec<Tensor<B, 2>>, Tensor<B, 2>) {
        let last = self.layers.len() - 1;
        let mut inputs = Vec::with_capacity(self.layers.len());
        let mut h = x;
        for (i, layer) in self.layers.iter().enumerate() {
            inputs.push(h.clone());
            let z = layer.forward(h);
            h = if i < last { z.tanh() } else { z };
        }
        (inputs, h)
    }

    fn weight(&self, i: usize) -> Tensor<B, 2> {
        self.layers[i].weight.val()
    }

    /// Forward-mode derivative of the output along a parameter direction `tangent`
    /// (one `(dW, db)` per layer), at the activations `inputs` of [`Self::forward_trace`]:
    /// dz = x·dW + db + dx·W, and through tanh dh = (1 − h²) ⊙ dz.
    pub fn jvp(&self, inputs: &[Tensor<B, 2>], tangent: &LayerTensors<B>) -> Tensor<B, 2> {
        let last = self.layers.len() - 1;
        let mut d_input: Option<Tensor<B, 2>> = None; // the data x has no tangent
        for (i, (dw, db)) in tangent.iter().enumerate() {
            let mut dz = inputs[i].clone().matmul(dw.clone()) + db.clone().unsqueeze_dim(0);
            if let Some(dx) = d_input {
                dz = dz + dx.matmul(self.weight(i));
            }
            if i == last {
                return dz;
            }
            let h = inputs[i + 1].clone();
            d_input = Some(dz * (h.clone() * h).neg().add_scalar(1.0));
        }
        unreachable!("an MLP has at least one layer")
    }

    /// Reverse-mode: the parameter gradient of `sum(output ⊙ upstream)` at `inputs`.
    pub fn vjp(&self, inputs: &[Tensor<B, 2>], upstream: Tensor<B, 2>) -> LayerTensors<B> {
        let mut grads = Vec::with_capacity(self.layers.len());
        let mut dz = upstream;
        for i in (0..self.layers.len()).rev() {
            let x = inputs[i].clone();
            grads.push((
                x.clone().transpose().matmul(dz.clone()),
                dz.clone().sum_dim(0).squeeze_dim(0),
            ));
            if i > 0 {
                dz = dz.matmul(self.weight(i).transpose()) * (x.clone() * x).neg().add_scalar(1.0);
            }
        }
        grads.reverse();
        grads
    }
}

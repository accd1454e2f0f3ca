//! A critic for one reward stream: one value net, or two with baseline min(V1, V2)
//! (clipped double-Q, the seed paper's "CDQ"), each fitted to the GAE returns by L-BFGS
//! on MSE + l2·‖θ‖² (the reference: 25 iterations, l2 = 1e-3).

use burn::module::AutodiffModule;
use burn::tensor::Tensor;
use burn::tensor::backend::AutodiffBackend;
use logo_nn::flat::{from_f64, grads_to_vec, params_to_vec, to_f64, vec_to_params};
use logo_nn::{ValueNet, ValueNetConfig};
use serde::{Deserialize, Serialize};

use crate::lbfgs;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CriticKind {
    /// One value net (LOGO).
    Single,
    /// Two value nets fitted to the same returns; the baseline is their minimum.
    TwinMin,
}

pub struct Critic<B: AutodiffBackend> {
    /// One net, or two for `TwinMin`.
    pub nets: Vec<ValueNet<B>>,
}

impl<B: AutodiffBackend> Critic<B> {
    pub fn new(kind: CriticKind, obs_dim: usize, hidden: &[usize], device: &B::Device) -> Self {
        let config = ValueNetConfig { obs_dim, hidden: hidden.to_vec() };
        let count = match kind {
            CriticKind::Single => 1,
            CriticKind::TwinMin => 2,
        };
        Self { nets: (0..count).map(|_| config.init(device)).collect() }
    }

    /// The baseline V(s) for each row: the (minimum over the) value net(s).
    pub fn values(&self, obs: Tensor<B::InnerBackend, 2>) -> Vec<f64> {
        self.nets
            .iter()
            .map(|net| to_f64(net.valid().forward(obs.clone())))
            .reduce(|a, b| a.iter().zip(&b).map(|(x, y)| x.min(*y)).collect())
            .expect("a critic has at least one net")
    }

    /// Fits every net to `returns`; returns the final loss of each.
    pub fn fit(&mut self, obs: &Tensor<B, 2>, returns: &[f64], l2: f64, iterations: usize) -> Vec<f64> {
        let device = obs.device();
        let target = from_f64::<B, 1>(returns, [returns.len()], &device);
        let mut losses = Vec::new();
        for net in &mut self.nets {
            let template = net.clone();
            let objective = |theta: &[f64]| {
                let candidate = vec_to_params(template.clone(), theta);
                let diff = candidate.forward(obs.clone()) - target.clone();
                let mse = (diff.clone() * diff).mean();
                let mut grad = grads_to_vec(&candidate, &mse.backward());
                let reg: f64 = theta.iter().map(|t| t * t).sum();
                grad.iter_mut().zip(theta).for_each(|(g, t)| *g += 2.0 * l2 * t);
                (to_f64(mse.inner())[0] + l2 * reg, grad)
            };
            let result = lbfgs::minimize(objective, params_to_vec(&template), iterations);
            *net = vec_to_params(template, &result.x);
            losses.push(result.loss);
        }
        losses
    }
}

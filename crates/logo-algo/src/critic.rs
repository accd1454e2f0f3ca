//! A critic for one reward stream: one value net, or two with baseline min(V1, V2)
//! (clipped double-Q, the seed paper's "CDQ"), each fitted to the GAE returns by L-BFGS
//! on MSE + l2·‖θ‖² (the reference: 25 iterations, l2 = 1e-3).
//!
//! The gradient is the MLP's hand-written reverse pass over one forward trace, on a plain
//! (no-autodiff) backend: no graph to build, and the fast tanh of the ndarray backend.
//! A test checks it against burn's autodiff.

use burn::tensor::Tensor;
use burn::tensor::backend::Backend;
use logo_nn::flat::{flatten_layers, from_f64, to_f64, vec_to_params};
use logo_nn::host::is_host_backend;
use logo_nn::{HostMlp, HostTrace, ValueNet, ValueNetConfig};
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

pub struct Critic<B: Backend> {
    /// One net, or two for `TwinMin`.
    pub nets: Vec<ValueNet<B>>,
}

/// MSE(V(obs), target) + l2·‖θ‖² and its gradient, for `net` with parameters `theta`.
pub fn value_loss_and_grad<B: Backend>(
    net: &ValueNet<B>,
    obs: Tensor<B, 2>,
    target: Tensor<B, 2>,
    theta: &[f64],
    l2: f64,
) -> (f64, Vec<f64>) {
    let n = obs.dims()[0] as f64;
    let (inputs, out) = net.net.forward_trace(obs);
    let diff = out - target;
    let mse = to_f64((diff.clone() * diff.clone()).sum())[0] / n;
    let mut grad = flatten_layers(net.net.vjp(&inputs, diff.mul_scalar(2.0 / n)));
    grad.iter_mut()
        .zip(theta)
        .for_each(|(g, t)| *g += 2.0 * l2 * t);
    (mse + l2 * theta.iter().map(|t| t * t).sum::<f64>(), grad)
}

/// [`value_loss_and_grad`] on host buffers (see `logo_nn::host`), as an L-BFGS
/// objective: the loss is a forward pass, the gradient a reverse pass over its trace.
pub struct HostValueObjective<'a> {
    pub dims: Vec<usize>,
    pub obs: &'a [f64],
    pub target: &'a [f64],
    pub l2: f64,
    /// The net, trace and residuals of the latest loss.
    last: Option<(HostMlp, HostTrace, Vec<f64>)>,
}

impl<'a> HostValueObjective<'a> {
    pub fn new(dims: Vec<usize>, obs: &'a [f64], target: &'a [f64], l2: f64) -> Self {
        Self {
            dims,
            obs,
            target,
            l2,
            last: None,
        }
    }
}

impl lbfgs::Objective for HostValueObjective<'_> {
    fn loss(&mut self, theta: &[f64]) -> f64 {
        let net = HostMlp::new(self.dims.clone(), theta.to_vec());
        let trace = net.trace(self.obs);
        let diff: Vec<f64> = trace
            .output()
            .iter()
            .zip(self.target)
            .map(|(v, t)| v - t)
            .collect();
        let mse = diff.iter().map(|d| d * d).sum::<f64>() / diff.len() as f64;
        let l2 = self.l2 * theta.iter().map(|t| t * t).sum::<f64>();
        self.last = Some((net, trace, diff));
        mse + l2
    }

    fn gradient(&mut self) -> Vec<f64> {
        let (net, trace, diff) = self.last.as_ref().expect("gradient() follows loss()");
        let n = diff.len() as f64;
        let upstream: Vec<f64> = diff.iter().map(|d| d * 2.0 / n).collect();
        let mut grad = net.vjp(trace, &upstream);
        grad.iter_mut()
            .zip(&net.params)
            .for_each(|(g, t)| *g += 2.0 * self.l2 * t);
        grad
    }
}

impl<B: Backend> Critic<B> {
    pub fn new(kind: CriticKind, obs_dim: usize, hidden: &[usize], device: &B::Device) -> Self {
        let config = ValueNetConfig {
            obs_dim,
            hidden: hidden.to_vec(),
        };
        let count = match kind {
            CriticKind::Single => 1,
            CriticKind::TwinMin => 2,
        };
        Self {
            nets: (0..count).map(|_| config.init(device)).collect(),
        }
    }

    /// The baseline V(s) for each row: the (minimum over the) value net(s).
    pub fn values(&self, obs: Tensor<B, 2>) -> Vec<f64> {
        let host_obs = is_host_backend::<B>().then(|| to_f64(obs.clone()));
        self.nets
            .iter()
            .map(|net| match &host_obs {
                Some(x) => HostMlp::from_mlp(&net.net).forward(x),
                None => to_f64(net.forward(obs.clone())),
            })
            .reduce(|a, b| a.iter().zip(&b).map(|(x, y)| x.min(*y)).collect())
            .expect("a critic has at least one net")
    }

    /// Fits every net to `returns`; returns the final loss of each.
    pub fn fit(
        &mut self,
        obs: &Tensor<B, 2>,
        returns: &[f64],
        l2: f64,
        iterations: usize,
    ) -> Vec<f64> {
        let target = from_f64::<B, 2>(returns, [returns.len(), 1], &obs.device());
        let host_obs = is_host_backend::<B>().then(|| to_f64(obs.clone()));
        let mut losses = Vec::new();
        for net in &mut self.nets {
            let template = net.clone();
            // A value net's parameters are its MLP's, in the same order.
            let HostMlp { dims, params: x0 } = HostMlp::from_mlp(&template.net);
            let result = match &host_obs {
                Some(x) => {
                    let mut objective = HostValueObjective::new(dims, x, returns, l2);
                    lbfgs::minimize(&mut objective, x0, iterations)
                }
                None => {
                    let mut objective = lbfgs::Eager::new(|theta: &[f64]| {
                        let candidate = vec_to_params(template.clone(), theta);
                        value_loss_and_grad(&candidate, obs.clone(), target.clone(), theta, l2)
                    });
                    lbfgs::minimize(&mut objective, x0, iterations)
                }
            };
            *net = vec_to_params(template, &result.x);
            losses.push(result.loss);
        }
        losses
    }
}

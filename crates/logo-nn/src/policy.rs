//! The Gaussian MLP policy: a tanh MLP for the action mean and a state-independent,
//! learned log standard deviation.

use burn::module::{Module, Param};
use burn::tensor::{Tensor, backend::Backend};
use rand::Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::flat::{from_f64, to_f64};
use crate::host::{HostMlp, is_host_backend};
use crate::mlp::{Mlp, MlpConfig};

/// ln(2π), of the Gaussian log-density.
pub const LOG_2PI: f64 = 1.837_877_066_409_345_5;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PolicyConfig {
    pub obs_dim: usize,
    pub act_dim: usize,
    /// Hidden sizes of the mean MLP (tanh). The reference: 128-128.
    pub hidden: Vec<usize>,
    /// Initial log standard deviation of every action dimension. The reference: 0.
    pub log_std_init: f64,
}

impl PolicyConfig {
    pub fn new(obs_dim: usize, act_dim: usize) -> Self {
        Self {
            obs_dim,
            act_dim,
            hidden: vec![128, 128],
            log_std_init: 0.0,
        }
    }

    pub fn mean_net(&self) -> MlpConfig {
        MlpConfig {
            input: self.obs_dim,
            hidden: self.hidden.clone(),
            output: self.act_dim,
            output_scale: Some(0.1),
        }
    }

    pub fn init<B: Backend>(&self, device: &B::Device) -> GaussianPolicy<B> {
        GaussianPolicy {
            mean: self.mean_net().init(device),
            log_std: Param::from_tensor(Tensor::full([self.act_dim], self.log_std_init, device)),
        }
    }
}

/// π(a|s) = N(μ(s), diag(exp(log_std))²).
#[derive(Module, Debug)]
pub struct GaussianPolicy<B: Backend> {
    pub mean: Mlp<B>,
    pub log_std: Param<Tensor<B, 1>>,
}

/// log N(a; μ, σ²) summed over action dimensions: one value per row.
pub fn gaussian_log_prob<B: Backend>(
    mean: Tensor<B, 2>,
    log_std: Tensor<B, 1>,
    actions: Tensor<B, 2>,
) -> Tensor<B, 1> {
    let act_dim = log_std.dims()[0] as f64;
    let log_std = log_std.unsqueeze_dim::<2>(0);
    let z = (actions - mean) / log_std.clone().exp();
    let per_row = (z.clone() * z).mul_scalar(-0.5) - log_std;
    per_row
        .sum_dim(1)
        .squeeze_dim::<1>(1)
        .sub_scalar(0.5 * LOG_2PI * act_dim)
}

impl<B: Backend> GaussianPolicy<B> {
    pub fn obs_dim(&self) -> usize {
        self.mean.layers[0].weight.dims()[0]
    }

    pub fn act_dim(&self) -> usize {
        self.log_std.dims()[0]
    }

    /// The mean action μ(s): the deterministic action used for evaluation.
    pub fn mean_action(&self, obs: Tensor<B, 2>) -> Tensor<B, 2> {
        self.mean.forward(obs)
    }

    /// log π(a|s), one value per row.
    pub fn log_prob(&self, obs: Tensor<B, 2>, actions: Tensor<B, 2>) -> Tensor<B, 1> {
        gaussian_log_prob(self.mean.forward(obs), self.log_std.val(), actions)
    }

    /// Entropy of π(·|s) (the same for every state): Σ log σ + ½ d (1 + ln 2π).
    pub fn entropy(&self) -> Tensor<B, 1> {
        let d = self.act_dim() as f64;
        self.log_std
            .val()
            .sum()
            .add_scalar(0.5 * d * (1.0 + LOG_2PI))
    }

    /// A frozen copy for acting (rollouts, evaluation, recording): observations in, actions
    /// out, as host vectors. On the default CPU backend the mean net runs on host buffers
    /// (`crate::host`): a batch-1 forward through burn-ndarray costs tens of µs in
    /// allocations, more than the physics step it drives.
    pub fn acting(&self) -> ActingPolicy<B> {
        let mean = if is_host_backend::<B>() {
            MeanNet::Host(HostMlp::from_mlp(&self.mean))
        } else {
            MeanNet::Burn(self.mean.clone())
        };
        ActingPolicy {
            mean,
            std: to_f64(self.log_std.val().exp()),
            obs_dim: self.obs_dim(),
        }
    }
}

enum MeanNet<B: Backend> {
    Host(HostMlp),
    Burn(Mlp<B>),
}

/// See [`GaussianPolicy::acting`].
pub struct ActingPolicy<B: Backend> {
    mean: MeanNet<B>,
    std: Vec<f64>,
    obs_dim: usize,
}

impl<B: Backend> ActingPolicy<B> {
    /// μ(s) for every row of `obs` (`rows * obs_dim` values, row-major).
    pub fn mean(&self, obs: &[f64]) -> Vec<f64> {
        match &self.mean {
            MeanNet::Host(net) => net.forward(obs),
            MeanNet::Burn(net) => {
                let rows = obs.len() / self.obs_dim;
                let device = net.layers[0].weight.device();
                to_f64(net.forward(from_f64(obs, [rows, self.obs_dim], &device)))
            }
        }
    }

    /// a ~ π(·|s) for every row of `obs`, with the caller's generator (so a seed fixes the
    /// rollout); `rows * act_dim` values, row-major. Unclipped, as the reference stores
    /// them (MuJoCo clamps to the control range).
    pub fn sample<R: Rng>(&self, obs: &[f64], rng: &mut R) -> Vec<f64> {
        let mut actions = self.mean(obs);
        for (i, a) in actions.iter_mut().enumerate() {
            let noise: f64 = rng.sample(StandardNormal);
            *a += self.std[i % self.std.len()] * noise;
        }
        actions
    }
}

//! The Gaussian MLP policy: a tanh MLP for the action mean and a state-independent,
//! learned log standard deviation.
//!
//! - [`GaussianPolicy`]: its definition as a burn module (initialisation, checkpoints,
//!   the reference's BC import);
//! - [`Policy`]: the same policy as training holds it, on an [`Engine`];
//! - [`ActingPolicy`]: a frozen host copy that rollouts, evaluation and recording act with.

use burn::module::{Module, Param};
use burn::tensor::{Tensor, backend::Backend};
use rand::Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::engine::Engine;
use crate::flat::{params_to_vec, to_f64, vec_to_params};
use crate::kernels::HostMlp;
use crate::loss::{gaussian_entropy, gaussian_log_prob};
use crate::mlp::{Mlp, MlpConfig};
use crate::observation_norm::ObservationStats;

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

    /// Entropy of π(·|s) (the same for every state).
    pub fn entropy(&self) -> Tensor<B, 1> {
        gaussian_entropy(self.log_std.val())
    }

    /// A frozen host copy for acting.
    pub fn acting(&self) -> ActingPolicy {
        ActingPolicy::new(
            HostMlp::new(self.mean.dims(), params_to_vec(&self.mean)),
            to_f64(self.log_std.val()),
        )
    }
}

/// The policy being trained, on an engine: the mean network in the engine's form and
/// log σ as host values (a handful of numbers). Its flat parameters are the mean net's
/// then log σ, as [`params_to_vec`] lays out a [`GaussianPolicy`].
pub struct Policy<E: Engine> {
    /// The mean network's layer sizes.
    pub dims: Vec<usize>,
    pub mean: E::Net,
    pub log_std: Vec<f64>,
}

impl<E: Engine> Clone for Policy<E> {
    fn clone(&self) -> Self {
        Self {
            dims: self.dims.clone(),
            mean: self.mean.clone(),
            log_std: self.log_std.clone(),
        }
    }
}

impl<E: Engine> Policy<E> {
    /// The module's parameters on `engine`.
    pub fn from_module<B: Backend>(engine: &E, module: &GaussianPolicy<B>) -> Self {
        let dims = module.mean.dims();
        Self {
            mean: engine.net(&dims, &params_to_vec(&module.mean)),
            dims,
            log_std: to_f64(module.log_std.val()),
        }
    }

    /// `template` with this policy's parameters (for checkpoints).
    pub fn to_module<B: Backend>(
        &self,
        engine: &E,
        template: GaussianPolicy<B>,
    ) -> GaussianPolicy<B> {
        vec_to_params(template, &self.params(engine))
    }

    pub fn num_params(&self) -> usize {
        crate::mlp::num_params(&self.dims) + self.log_std.len()
    }

    pub fn act_dim(&self) -> usize {
        self.log_std.len()
    }

    /// The mean net's parameters, then log σ.
    pub fn params(&self, engine: &E) -> Vec<f64> {
        let mut theta = engine.params(&self.mean);
        theta.extend(&self.log_std);
        theta
    }

    /// The same policy with parameters `theta` (laid out as [`Self::params`]).
    pub fn with_params(&self, engine: &E, theta: &[f64]) -> Self {
        assert_eq!(
            theta.len(),
            self.num_params(),
            "policy parameters of the wrong length"
        );
        let (mean, log_std) = theta.split_at(theta.len() - self.log_std.len());
        Self {
            dims: self.dims.clone(),
            mean: engine.net(&self.dims, mean),
            log_std: log_std.to_vec(),
        }
    }

    pub fn log_std_tensor(&self, engine: &E) -> Tensor<E::B, 1> {
        engine.upload(&self.log_std, [self.log_std.len()])
    }

    /// μ(s) for every row of `obs`.
    pub fn means(&self, engine: &E, obs: &E::Rows) -> Tensor<E::B, 2> {
        engine.forward(&self.mean, obs)
    }

    /// log π(a|s) for every row.
    pub fn log_prob(
        &self,
        engine: &E,
        obs: &E::Rows,
        actions: &Tensor<E::B, 2>,
    ) -> Tensor<E::B, 1> {
        gaussian_log_prob(
            self.means(engine, obs),
            self.log_std_tensor(engine),
            actions.clone(),
        )
    }

    /// A frozen host copy for acting, refreshed by the trainer once per iteration.
    /// Whether every parameter (mean network and log σ) is finite.
    pub fn is_finite(&self, engine: &E) -> bool {
        let finite = |v: &f64| v.is_finite();
        self.log_std.iter().all(finite) && engine.params(&self.mean).iter().all(finite)
    }

    pub fn acting(&self, engine: &E) -> ActingPolicy {
        ActingPolicy::new(
            HostMlp::new(self.dims.clone(), engine.params(&self.mean)),
            self.log_std.clone(),
        )
    }
}

/// A frozen policy on the host, for acting: observations in, actions out. The mean net
/// runs on the kernels' host MLP whatever engine trained it (a batch-1 forward through a
/// tensor library costs more than the physics step it drives).
pub struct ActingPolicy {
    mean: HostMlp,
    log_std: Vec<f64>,
    std: Vec<f64>,
    /// The statistics the run standardised observations with when it made this copy
    /// (None: the networks see them as the env gives them).
    observation_norm: Option<ObservationStats>,
}

impl ActingPolicy {
    pub fn new(mean: HostMlp, log_std: Vec<f64>) -> Self {
        assert_eq!(mean.output_dim(), log_std.len(), "one log σ per action");
        Self {
            mean,
            std: log_std.iter().map(|l| l.exp()).collect(),
            log_std,
            observation_norm: None,
        }
    }

    /// The same policy, seeing each observation through `norm` first.
    pub fn with_observation_norm(self, norm: Option<ObservationStats>) -> Self {
        if let Some(n) = &norm {
            assert_eq!(
                n.obs_dim(),
                self.mean.dims[0],
                "one statistic per observation"
            );
        }
        Self {
            observation_norm: norm,
            ..self
        }
    }

    pub fn observation_norm(&self) -> Option<&ObservationStats> {
        self.observation_norm.as_ref()
    }

    /// The mean net's layer sizes and parameters (the Python package's weights).
    pub fn mean_net(&self) -> &HostMlp {
        &self.mean
    }

    /// log σ, one per action.
    pub fn log_std(&self) -> &[f64] {
        &self.log_std
    }

    /// μ(s) for every row of `obs` (`rows * obs_dim` values, row-major).
    pub fn mean(&self, obs: &[f64]) -> Vec<f64> {
        match &self.observation_norm {
            None => self.mean.forward(obs),
            Some(norm) => {
                let mut seen = obs.to_vec();
                norm.normalise(&mut seen);
                self.mean.forward(&seen)
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

//! The natural-gradient policy step, used for both of LOGO's steps (LOGO-FACTS):
//! maximise the surrogate mean(exp(log π_θ − log π_old) · Â) within KL ≤ δ:
//! s = CG(F, g, 10 iterations), full step s·sqrt(2δ / sᵀFs), backtracking over
//! fractions 0.5^i (i < 10) until actual / expected improvement > 0.1, else no step.

use burn::module::AutodiffModule;
use burn::tensor::Tensor;
use burn::tensor::backend::AutodiffBackend;
use logo_nn::flat::{grads_to_vec, params_to_vec, to_f64, vec_to_params};
use logo_nn::{FisherVectorProduct, GaussianPolicy, conjugate_gradient, mean_kl};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolicyStepConfig {
    #[serde(default = "default_damping")]
    pub damping: f64,
    #[serde(default = "default_cg_iters")]
    pub cg_iters: usize,
    #[serde(default = "default_backtracks")]
    pub backtracks: usize,
    #[serde(default = "default_accept_ratio")]
    pub accept_ratio: f64,
}

fn default_damping() -> f64 {
    0.01
}
fn default_cg_iters() -> usize {
    10
}
fn default_backtracks() -> usize {
    10
}
fn default_accept_ratio() -> f64 {
    0.1
}

impl Default for PolicyStepConfig {
    fn default() -> Self {
        Self { damping: 0.01, cg_iters: 10, backtracks: 10, accept_ratio: 0.1 }
    }
}

/// The batch a step works on (autodiff-backend tensors; forward-only passes use `.inner()`).
pub struct StepData<B: AutodiffBackend> {
    pub obs: Tensor<B, 2>,
    pub actions: Tensor<B, 2>,
    /// log π_k(a|s): the policy that collected the batch.
    pub logp_old: Tensor<B, 1>,
}

#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepStats {
    /// Mean KL(π_before ‖ π_after) on the batch.
    pub kl: f64,
    pub expected_improvement: f64,
    pub actual_improvement: f64,
    /// Fraction of the full step taken; 0 when the line search kept the old parameters.
    pub step_fraction: f64,
}

fn surrogate<B: AutodiffBackend>(
    policy: &GaussianPolicy<B::InnerBackend>,
    data: &StepData<B>,
    advantages: &Tensor<B::InnerBackend, 1>,
) -> f64 {
    let logp = policy.log_prob(data.obs.clone().inner(), data.actions.clone().inner());
    to_f64(((logp - data.logp_old.clone().inner()).exp() * advantages.clone()).mean())[0]
}

pub fn trpo_step<B: AutodiffBackend>(
    policy: GaussianPolicy<B>,
    data: &StepData<B>,
    advantages: &[f64],
    max_kl: f64,
    config: &PolicyStepConfig,
) -> (GaussianPolicy<B>, StepStats) {
    let device = data.obs.device();
    let adv = logo_nn::flat::from_f64::<B, 1>(advantages, [advantages.len()], &device);
    let adv_inner = adv.clone().inner();

    // g = ∇ surrogate (autodiff); the loss is its negative, as in the reference.
    let logp = policy.log_prob(data.obs.clone(), data.actions.clone());
    let surr = ((logp - data.logp_old.clone()).exp() * adv).mean();
    let grad = grads_to_vec(&policy, &surr.backward());

    let inner = policy.valid();
    let fvp = FisherVectorProduct::new(&inner, data.obs.clone().inner(), config.damping);
    let direction = conjugate_gradient(|v| fvp.apply(v), &grad, config.cg_iters, 1e-10);
    let shs: f64 = 0.5 * direction.iter().zip(fvp.apply(&direction)).map(|(a, b)| a * b).sum::<f64>();
    let theta = params_to_vec(&inner);
    if !(shs > 0.0 && shs.is_finite()) {
        return (policy, StepStats::default());
    }
    let scale = (shs / max_kl).sqrt();
    let full_step: Vec<f64> = direction.iter().map(|d| d / scale).collect();
    let expected_full: f64 = grad.iter().zip(&full_step).map(|(g, s)| g * s).sum();

    let before = surrogate::<B>(&inner, data, &adv_inner);
    let mut fraction = 1.0;
    for _ in 0..config.backtracks {
        let candidate: Vec<f64> = theta.iter().zip(&full_step).map(|(t, s)| t + fraction * s).collect();
        let new_inner = vec_to_params(inner.clone(), &candidate);
        let actual = surrogate::<B>(&new_inner, data, &adv_inner) - before;
        let expected = expected_full * fraction;
        if actual / expected > config.accept_ratio {
            let old_mean = inner.mean_action(data.obs.clone().inner());
            let kl = mean_kl(
                old_mean,
                inner.log_std.val(),
                new_inner.mean_action(data.obs.clone().inner()),
                new_inner.log_std.val(),
            );
            let stats = StepStats {
                kl: to_f64(kl)[0],
                expected_improvement: expected,
                actual_improvement: actual,
                step_fraction: fraction,
            };
            return (vec_to_params(policy, &candidate), stats);
        }
        fraction *= 0.5;
    }
    (policy, StepStats { expected_improvement: expected_full, ..StepStats::default() })
}

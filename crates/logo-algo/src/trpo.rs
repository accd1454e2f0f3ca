//! The natural-gradient policy step, used for both of LOGO's steps (LOGO-FACTS):
//! maximise the surrogate mean(exp(log π_θ − log π_old) · Â) within KL ≤ δ:
//! s = CG(F, g, 10 iterations), full step s·sqrt(2δ / sᵀFs), backtracking over
//! fractions 0.5^i (i < 10) until actual / expected improvement > 0.1, else no step.

use burn::tensor::Tensor;
use burn::tensor::backend::Backend;
use logo_nn::flat::{flatten_layers, from_f64, params_to_vec, to_f64, vec_to_params};
use logo_nn::policy::gaussian_log_prob;
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
        Self {
            damping: 0.01,
            cg_iters: 10,
            backtracks: 10,
            accept_ratio: 0.1,
        }
    }
}

/// The batch a step works on.
pub struct StepData<B: Backend> {
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

/// The surrogate mean(exp(log π − log π_old) · Â).
pub fn surrogate<B: Backend>(
    policy: &GaussianPolicy<B>,
    data: &StepData<B>,
    advantages: &Tensor<B, 1>,
) -> f64 {
    let logp = policy.log_prob(data.obs.clone(), data.actions.clone());
    to_f64(((logp - data.logp_old.clone()).exp() * advantages.clone()).mean())[0]
}

/// ∇θ of [`surrogate`], by hand: with w_i = ratio_i Â_i / N and z = (a − μ)/σ,
/// ∂/∂μ = w z/σ (through the mean net's reverse pass) and ∂/∂log σ = Σ_i w_i (z² − 1).
/// Laid out like `params_to_vec(policy)`; a test checks it against burn's autodiff.
pub fn surrogate_gradient<B: Backend>(
    policy: &GaussianPolicy<B>,
    data: &StepData<B>,
    advantages: &Tensor<B, 1>,
) -> Vec<f64> {
    let n = data.obs.dims()[0] as f64;
    let (inputs, mean) = policy.mean.forward_trace(data.obs.clone());
    let log_std = policy.log_std.val();
    let logp = gaussian_log_prob(mean.clone(), log_std.clone(), data.actions.clone());
    let w = ((logp - data.logp_old.clone()).exp() * advantages.clone())
        .div_scalar(n)
        .unsqueeze_dim::<2>(1);
    let inv_std = log_std.neg().exp().unsqueeze_dim::<2>(0);
    let z = (data.actions.clone() - mean) * inv_std.clone();
    let mut grad = flatten_layers(policy.mean.vjp(&inputs, z.clone() * inv_std * w.clone()));
    grad.extend(to_f64(((z.clone() * z).sub_scalar(1.0) * w).sum_dim(0)));
    grad
}

pub fn trpo_step<B: Backend>(
    policy: GaussianPolicy<B>,
    data: &StepData<B>,
    advantages: &[f64],
    max_kl: f64,
    config: &PolicyStepConfig,
) -> (GaussianPolicy<B>, StepStats) {
    let adv = from_f64::<B, 1>(advantages, [advantages.len()], &data.obs.device());
    let grad = surrogate_gradient(&policy, data, &adv);
    let fvp = FisherVectorProduct::new(&policy, data.obs.clone(), config.damping);
    let direction = conjugate_gradient(|v| fvp.apply(v), &grad, config.cg_iters, 1e-10);
    let shs: f64 = 0.5
        * direction
            .iter()
            .zip(fvp.apply(&direction))
            .map(|(a, b)| a * b)
            .sum::<f64>();
    if !(shs > 0.0 && shs.is_finite()) {
        return (policy, StepStats::default());
    }
    let scale = (shs / max_kl).sqrt();
    let full_step: Vec<f64> = direction.iter().map(|d| d / scale).collect();
    let expected_full: f64 = grad.iter().zip(&full_step).map(|(g, s)| g * s).sum();

    let theta = params_to_vec(&policy);
    let before = surrogate(&policy, data, &adv);
    let mut fraction = 1.0;
    for _ in 0..config.backtracks {
        let candidate: Vec<f64> = theta
            .iter()
            .zip(&full_step)
            .map(|(t, s)| t + fraction * s)
            .collect();
        let new_policy = vec_to_params(policy.clone(), &candidate);
        let actual = surrogate(&new_policy, data, &adv) - before;
        let expected = expected_full * fraction;
        if actual / expected > config.accept_ratio {
            let kl = mean_kl(
                policy.mean_action(data.obs.clone()),
                policy.log_std.val(),
                new_policy.mean_action(data.obs.clone()),
                new_policy.log_std.val(),
            );
            let stats = StepStats {
                kl: to_f64(kl)[0],
                expected_improvement: expected,
                actual_improvement: actual,
                step_fraction: fraction,
            };
            return (new_policy, stats);
        }
        fraction *= 0.5;
    }
    (
        policy,
        StepStats {
            expected_improvement: expected_full,
            ..StepStats::default()
        },
    )
}

//! The natural-gradient policy step, used for both of LOGO's steps (LOGO-FACTS):
//! maximise the surrogate mean(exp(log π_θ − log π_old) · Â) within KL ≤ δ:
//! s = CG(F, g, 10 iterations), full step s·sqrt(2δ / sᵀFs), backtracking over
//! fractions 0.5^i (i < 10) until actual / expected improvement > 0.1, else no step.

use burn::tensor::Tensor;
use burn::tensor::backend::Backend;
use logo_nn::flat::{flatten_layers, from_f64, params_to_vec, to_f64, vec_to_params};
use logo_nn::host::is_host_backend;
use logo_nn::policy::{LOG_2PI, gaussian_log_prob};
use logo_nn::{
    FisherVectorProduct, GaussianPolicy, HostMlp, HostTrace, OutputSensitivities,
    conjugate_gradient, mean_kl,
};
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
    /// Also require the measured KL to be at most `kl_limit`·δ before accepting a step
    /// (backtracking further otherwise). Off by default: the reference's line search checks
    /// only the improvement, and its guidance steps often overshoot δ_k.
    #[serde(default)]
    pub kl_limit: Option<f64>,
    /// F·v on this fraction of the batch (rows spread evenly over it, see
    /// [`fisher_rows`]) instead of all of it: a cheaper, approximate curvature for the
    /// conjugate gradient and the step size. 1 (the default) is exact, as the reference.
    #[serde(default = "default_fisher_fraction")]
    pub fisher_fraction: f64,
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
fn default_fisher_fraction() -> f64 {
    1.0
}

impl PolicyStepConfig {
    /// What a config file cannot be trusted to hold; the message names the key.
    pub fn validate(&self) -> Result<(), String> {
        let fraction = self.fisher_fraction;
        if !(fraction > 0.0 && fraction <= 1.0) {
            return Err(format!(
                "policy_step.fisher_fraction must be in (0, 1], got {fraction}"
            ));
        }
        if !(self.damping >= 0.0 && self.damping.is_finite()) {
            return Err(format!(
                "policy_step.damping must be >= 0, got {}",
                self.damping
            ));
        }
        Ok(())
    }
}

/// The rows F·v is computed on: `None` for all of them (`fraction` 1), else
/// round(fraction · rows) (at least one) spread evenly, row ⌊j · rows / count⌋ for the
/// j-th, so that every part of the batch (its episodes come one after another) is seen.
pub fn fisher_rows(rows: usize, fraction: f64) -> Option<Vec<usize>> {
    if fraction >= 1.0 {
        return None;
    }
    let count = ((rows as f64 * fraction).round() as usize).clamp(1, rows.max(1));
    Some((0..count).map(|j| j * rows / count).collect())
}

impl Default for PolicyStepConfig {
    fn default() -> Self {
        Self {
            damping: 0.01,
            cg_iters: 10,
            backtracks: 10,
            accept_ratio: 0.1,
            kl_limit: None,
            fisher_fraction: 1.0,
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

/// What the natural-gradient step needs of the policy at parameters θ (flat, laid out like
/// `params_to_vec(policy)`), on the step's fixed batch. Two implementations: burn tensors
/// for any backend, and host buffers for the default CPU backend (`logo_nn::host`).
trait StepObjective {
    /// The surrogate at the old parameters.
    fn old_surrogate(&self) -> f64;
    /// ∇θ of the surrogate at the old parameters.
    fn gradient(&self) -> Vec<f64>;
    /// F·v at the old parameters (damped).
    fn fisher_vector_product(&self, v: &[f64]) -> Vec<f64>;
    /// The surrogate at θ and the mean KL(π_old ‖ π_θ) on the batch: a line-search
    /// candidate needs both, and they share the policy's forward pass.
    fn surrogate_and_kl(&self, theta: &[f64]) -> (f64, f64);
}

pub fn trpo_step<B: Backend>(
    policy: GaussianPolicy<B>,
    data: &StepData<B>,
    advantages: &[f64],
    max_kl: f64,
    config: &PolicyStepConfig,
) -> (GaussianPolicy<B>, StepStats) {
    let theta = params_to_vec(&policy);
    let objective: Box<dyn StepObjective + '_> = if is_host_backend::<B>() {
        Box::new(HostObjective::new(&policy, data, advantages, config))
    } else {
        Box::new(BurnObjective::new(&policy, data, advantages, config))
    };
    let result = natural_gradient_step(&*objective, &theta, max_kl, config);
    drop(objective);
    match result {
        Some((new_theta, stats)) => (vec_to_params(policy, &new_theta), stats),
        None => (policy, StepStats::default()),
    }
}

/// s = CG(F, g), full step s·sqrt(2δ / sᵀFs), then the backtracking line search.
/// `None` when no step could be made (a degenerate direction).
fn natural_gradient_step(
    objective: &dyn StepObjective,
    theta: &[f64],
    max_kl: f64,
    config: &PolicyStepConfig,
) -> Option<(Vec<f64>, StepStats)> {
    let grad = objective.gradient();
    let direction = conjugate_gradient(
        |v| objective.fisher_vector_product(v),
        &grad,
        config.cg_iters,
        1e-10,
    );
    let shs: f64 = 0.5
        * direction
            .iter()
            .zip(objective.fisher_vector_product(&direction))
            .map(|(a, b)| a * b)
            .sum::<f64>();
    if !(shs > 0.0 && shs.is_finite()) {
        return None;
    }
    let scale = (shs / max_kl).sqrt();
    let full_step: Vec<f64> = direction.iter().map(|d| d / scale).collect();
    let expected_full: f64 = grad.iter().zip(&full_step).map(|(g, s)| g * s).sum();

    let before = objective.old_surrogate();
    let mut fraction = 1.0;
    for _ in 0..config.backtracks {
        let candidate: Vec<f64> = theta
            .iter()
            .zip(&full_step)
            .map(|(t, s)| t + fraction * s)
            .collect();
        let (value, kl) = objective.surrogate_and_kl(&candidate);
        let actual = value - before;
        let expected = expected_full * fraction;
        if actual / expected > config.accept_ratio {
            if config.kl_limit.is_some_and(|limit| kl > limit * max_kl) {
                fraction *= 0.5;
                continue;
            }
            let stats = StepStats {
                kl,
                expected_improvement: expected,
                actual_improvement: actual,
                step_fraction: fraction,
            };
            return Some((candidate, stats));
        }
        fraction *= 0.5;
    }
    let stats = StepStats {
        expected_improvement: expected_full,
        ..StepStats::default()
    };
    Some((theta.to_vec(), stats))
}

/// The step's objective on burn tensors (any backend).
struct BurnObjective<'a, B: Backend> {
    policy: &'a GaussianPolicy<B>,
    data: &'a StepData<B>,
    advantages: Tensor<B, 1>,
    fvp: FisherVectorProduct<B>,
}

impl<'a, B: Backend> BurnObjective<'a, B> {
    fn new(
        policy: &'a GaussianPolicy<B>,
        data: &'a StepData<B>,
        advantages: &[f64],
        config: &PolicyStepConfig,
    ) -> Self {
        let device = data.obs.device();
        let fisher_obs = match fisher_rows(advantages.len(), config.fisher_fraction) {
            None => data.obs.clone(),
            Some(rows) => {
                let rows: Vec<i64> = rows.iter().map(|&r| r as i64).collect();
                let len = rows.len();
                let indices = Tensor::<B, 1, burn::tensor::Int>::from_data(
                    burn::tensor::TensorData::new(rows, [len]),
                    &device,
                );
                data.obs.clone().select(0, indices)
            }
        };
        let advantages = from_f64::<B, 1>(advantages, [advantages.len()], &device);
        let fvp = FisherVectorProduct::new(policy, fisher_obs, config.damping);
        Self {
            policy,
            data,
            advantages,
            fvp,
        }
    }
}

impl<B: Backend> StepObjective for BurnObjective<'_, B> {
    fn old_surrogate(&self) -> f64 {
        surrogate(self.policy, self.data, &self.advantages)
    }

    fn gradient(&self) -> Vec<f64> {
        surrogate_gradient(self.policy, self.data, &self.advantages)
    }

    fn fisher_vector_product(&self, v: &[f64]) -> Vec<f64> {
        self.fvp.apply(v)
    }

    fn surrogate_and_kl(&self, theta: &[f64]) -> (f64, f64) {
        let new = vec_to_params(self.policy.clone(), theta);
        let kl = mean_kl(
            self.policy.mean_action(self.data.obs.clone()),
            self.policy.log_std.val(),
            new.mean_action(self.data.obs.clone()),
            new.log_std.val(),
        );
        (surrogate(&new, self.data, &self.advantages), to_f64(kl)[0])
    }
}

/// The same objective on host buffers: the batch is copied out of its tensors once, the
/// old policy's activations are cached once for the gradient and every F·v.
struct HostObjective {
    mean_net: HostMlp,
    log_std: Vec<f64>,
    obs: Vec<f64>,
    actions: Vec<f64>,
    logp_old: Vec<f64>,
    advantages: Vec<f64>,
    trace: HostTrace,
    /// The old policy's means, `trace`'s output, copied out once.
    old_mean: Vec<f64>,
    /// The trace F·v runs on when it uses a subsample of the batch (`fisher_fraction`).
    fisher_trace: Option<HostTrace>,
    sensitivities: OutputSensitivities,
    damping: f64,
}

impl HostObjective {
    fn new<B: Backend>(
        policy: &GaussianPolicy<B>,
        data: &StepData<B>,
        advantages: &[f64],
        config: &PolicyStepConfig,
    ) -> Self {
        let mean_net = HostMlp::from_mlp(&policy.mean);
        let obs = to_f64(data.obs.clone());
        let trace = mean_net.trace(&obs);
        let obs_dim = mean_net.input_dim();
        let fisher_trace = fisher_rows(advantages.len(), config.fisher_fraction).map(|rows| {
            let subset: Vec<f64> = rows
                .iter()
                .flat_map(|&r| obs[r * obs_dim..(r + 1) * obs_dim].iter().copied())
                .collect();
            mean_net.trace(&subset)
        });
        let sensitivities = mean_net.output_sensitivities(fisher_trace.as_ref().unwrap_or(&trace));
        Self {
            old_mean: trace.output(),
            mean_net,
            log_std: to_f64(policy.log_std.val()),
            obs,
            actions: to_f64(data.actions.clone()),
            logp_old: to_f64(data.logp_old.clone()),
            advantages: advantages.to_vec(),
            trace,
            fisher_trace,
            sensitivities,
            damping: config.damping,
        }
    }

    /// (mean net, log σ) of a flat parameter vector.
    fn split(&self, theta: &[f64]) -> (HostMlp, Vec<f64>) {
        let (mean, log_std) = theta.split_at(self.mean_net.num_params());
        (
            HostMlp::new(self.mean_net.dims.clone(), mean.to_vec()),
            log_std.to_vec(),
        )
    }

    /// Per-row weights ratio_i · Â_i / N of the surrogate at means `mean` and `log_std`.
    fn weights(&self, mean: &[f64], log_std: &[f64]) -> Vec<f64> {
        let act_dim = log_std.len();
        let n = self.advantages.len() as f64;
        mean.chunks_exact(act_dim)
            .zip(self.actions.chunks_exact(act_dim))
            .zip(self.logp_old.iter().zip(&self.advantages))
            .map(|((mu, a), (logp_old, adv))| {
                let logp = host_log_prob(mu, log_std, a);
                (logp - logp_old).exp() * adv / n
            })
            .collect()
    }
}

/// log N(a; μ, σ²) summed over the action dimensions, as `gaussian_log_prob`.
fn host_log_prob(mean: &[f64], log_std: &[f64], action: &[f64]) -> f64 {
    mean.iter()
        .zip(log_std)
        .zip(action)
        .map(|((mu, ls), a)| {
            let z = (a - mu) / ls.exp();
            -0.5 * z * z - ls - 0.5 * LOG_2PI
        })
        .sum()
}

impl StepObjective for HostObjective {
    /// From the cached trace: the same forward pass a fresh one would repeat.
    fn old_surrogate(&self) -> f64 {
        self.weights(&self.old_mean, &self.log_std).iter().sum()
    }

    /// As [`surrogate_gradient`]: ∂/∂μ = w z/σ through the reverse pass, ∂/∂log σ = Σ w (z² − 1).
    fn gradient(&self) -> Vec<f64> {
        let act_dim = self.log_std.len();
        let mean = &self.old_mean;
        let w = self.weights(mean, &self.log_std);
        let inv_std: Vec<f64> = self.log_std.iter().map(|l| (-l).exp()).collect();
        let mut upstream = vec![0.0; mean.len()];
        let mut grad_log_std = vec![0.0; act_dim];
        for (i, wi) in w.iter().enumerate() {
            for j in 0..act_dim {
                let k = i * act_dim + j;
                let z = (self.actions[k] - mean[k]) * inv_std[j];
                upstream[k] = wi * z * inv_std[j];
                grad_log_std[j] += wi * (z * z - 1.0);
            }
        }
        let mut grad = self.mean_net.vjp(&self.trace, &upstream);
        grad.extend(grad_log_std);
        grad
    }

    /// As [`FisherVectorProduct::apply`]: [Jᵀ M J v_μ / N ; 2 v_logσ] + damping · v.
    fn fisher_vector_product(&self, v: &[f64]) -> Vec<f64> {
        let (v_mean, v_log_std) = v.split_at(self.mean_net.num_params());
        let trace = self.fisher_trace.as_ref().unwrap_or(&self.trace);
        let n = trace.rows() as f64;
        let scale: Vec<f64> = self.log_std.iter().map(|l| (-2.0 * l).exp() / n).collect();
        let mut out =
            self.mean_net
                .gauss_newton_product(trace, &self.sensitivities, v_mean, &scale);
        out.extend(v_log_std.iter().map(|x| 2.0 * x));
        out.iter_mut()
            .zip(v)
            .for_each(|(o, x)| *o += self.damping * x);
        out
    }

    /// The surrogate as [`surrogate`], and the KL as
    /// Σ_j [log σ_new − log σ_old + (σ_old² + (μ_old − μ_new)²) / (2σ_new²) − ½], averaged,
    /// both from one forward pass at θ.
    fn surrogate_and_kl(&self, theta: &[f64]) -> (f64, f64) {
        let act_dim = self.log_std.len();
        let (mean_net, log_std) = self.split(theta);
        let new_mean = mean_net.forward(&self.obs);
        let value = self.weights(&new_mean, &log_std).iter().sum();
        let total: f64 = self
            .old_mean
            .chunks_exact(act_dim)
            .zip(new_mean.chunks_exact(act_dim))
            .map(|(old, new)| {
                (0..act_dim)
                    .map(|j| {
                        let (lo, ln) = (self.log_std[j], log_std[j]);
                        let d = old[j] - new[j];
                        ln - lo + ((2.0 * lo).exp() + d * d) / (2.0 * (2.0 * ln).exp()) - 0.5
                    })
                    .sum::<f64>()
            })
            .sum();
        (value, total / self.trace.rows() as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use logo_nn::{Cpu, PolicyConfig};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random(rng: &mut ChaCha8Rng, n: usize, scale: f64) -> Vec<f64> {
        (0..n).map(|_| rng.random_range(-scale..scale)).collect()
    }

    /// A policy with random parameters θ (away from its initialisation) and random
    /// observations and actions, drawn in that order.
    fn random_policy_and_pairs(
        rng: &mut ChaCha8Rng,
        config: PolicyConfig,
        rows: usize,
    ) -> (
        GaussianPolicy<Cpu>,
        Vec<f64>,
        Tensor<Cpu, 2>,
        Tensor<Cpu, 2>,
    ) {
        let device = Default::default();
        let (obs_dim, act_dim) = (config.obs_dim, config.act_dim);
        let policy = config.init::<Cpu>(&device);
        let theta = random(rng, params_to_vec(&policy).len(), 0.5);
        let policy = vec_to_params(policy, &theta);
        let obs = random(rng, rows * obs_dim, 2.0);
        let actions = random(rng, rows * act_dim, 1.5);
        (
            policy,
            theta,
            from_f64(&obs, [rows, obs_dim], &device),
            from_f64(&actions, [rows, act_dim], &device),
        )
    }

    /// With `kl_limit`, the line search backtracks past steps whose KL exceeds the limit.
    #[test]
    fn the_kl_limit_keeps_accepted_steps_within_it() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let rows = 500;
        let config = PolicyConfig {
            obs_dim: 3,
            act_dim: 2,
            hidden: vec![8, 8],
            log_std_init: -0.5,
        };
        let (policy, theta, obs, actions) = random_policy_and_pairs(&mut rng, config, rows);
        let data = StepData::<Cpu> {
            logp_old: policy.log_prob(obs.clone(), actions.clone()),
            obs,
            actions,
        };
        let advantages = random(&mut rng, rows, 1.0);
        let objective =
            HostObjective::new(&policy, &data, &advantages, &PolicyStepConfig::default());
        let max_kl = 0.05;
        let free = PolicyStepConfig::default();
        let (_, unlimited) = natural_gradient_step(&objective, &theta, max_kl, &free).unwrap();
        let limited_config = PolicyStepConfig {
            kl_limit: Some(0.25),
            ..free
        };
        let (_, limited) =
            natural_gradient_step(&objective, &theta, max_kl, &limited_config).unwrap();
        assert!(
            unlimited.kl > 0.25 * max_kl,
            "the test needs a step beyond the limit: {unlimited:?}"
        );
        assert!(
            limited.kl <= 0.25 * max_kl && limited.step_fraction < unlimited.step_fraction,
            "{limited:?}"
        );
    }

    /// The host objective (the default CPU path) against the burn one, term by term, on a
    /// batch of 2100 rows (three host blocks) and a policy away from its initialisation.
    #[test]
    fn host_and_burn_objectives_agree() {
        let device = Default::default();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let rows = 2100;
        let config = PolicyConfig {
            obs_dim: 4,
            act_dim: 2,
            hidden: vec![8, 6],
            log_std_init: -0.4,
        };
        let (policy, theta, obs, actions) = random_policy_and_pairs(&mut rng, config, rows);
        let logp_old = random(&mut rng, rows, 1.0)
            .iter()
            .map(|x| x - 2.0)
            .collect::<Vec<_>>();
        let advantages = random(&mut rng, rows, 1.0);
        let data = StepData::<Cpu> {
            obs,
            actions,
            logp_old: from_f64(&logp_old, [rows], &device),
        };
        let exact = PolicyStepConfig::default();
        let burn = BurnObjective::new(&policy, &data, &advantages, &exact);
        let host = HostObjective::new(&policy, &data, &advantages, &exact);
        let close = |a: &[f64], b: &[f64], what: &str| {
            let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let err = a
                .iter()
                .zip(b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                err <= 1e-12 * scale,
                "{what}: max error {err:e} at scale {scale:e}"
            );
        };
        let moved: Vec<f64> = theta.iter().map(|t| t + 0.01 * t.signum()).collect();
        let (host_value, host_kl) = host.surrogate_and_kl(&moved);
        let (burn_value, burn_kl) = burn.surrogate_and_kl(&moved);
        close(&[host_value], &[burn_value], "surrogate");
        close(
            &[host.old_surrogate()],
            &[burn.old_surrogate()],
            "old surrogate",
        );
        close(&host.gradient(), &burn.gradient(), "gradient");
        let v = random(&mut rng, theta.len(), 1.0);
        let fv = host.fisher_vector_product(&v);
        close(&fv, &burn.fisher_vector_product(&v), "F·v");
        close(&[host_kl], &[burn_kl], "KL");

        // F·v on a third of the rows: the two paths still agree, and it is the exact F·v
        // of that sub-batch, not the full one.
        let third = PolicyStepConfig {
            fisher_fraction: 1.0 / 3.0,
            ..exact
        };
        let host_third = HostObjective::new(&policy, &data, &advantages, &third);
        let fv_third = host_third.fisher_vector_product(&v);
        close(
            &fv_third,
            &BurnObjective::new(&policy, &data, &advantages, &third).fisher_vector_product(&v),
            "F·v on a third",
        );
        let rows_kept = fisher_rows(rows, third.fisher_fraction).unwrap();
        assert_eq!(rows_kept.len(), 700);
        let obs = to_f64(data.obs.clone());
        let actions = to_f64(data.actions.clone());
        let pick = |values: &[f64], width: usize| -> Vec<f64> {
            rows_kept
                .iter()
                .flat_map(|&r| values[r * width..(r + 1) * width].iter().copied())
                .collect()
        };
        let sub = StepData::<Cpu> {
            obs: from_f64(&pick(&obs, 4), [700, 4], &device),
            actions: from_f64(&pick(&actions, 2), [700, 2], &device),
            logp_old: from_f64(&pick(&logp_old, 1), [700], &device),
        };
        let sub_advantages = pick(&advantages, 1);
        let on_sub = HostObjective::new(&policy, &sub, &sub_advantages, &exact);
        close(
            &fv_third,
            &on_sub.fisher_vector_product(&v),
            "F·v of the sub-batch",
        );
        let differs = fv_third
            .iter()
            .zip(&fv)
            .any(|(a, b)| (a - b).abs() > 1e-6 * b.abs());
        assert!(differs, "a third of the rows gave the full batch's F·v");
    }

    #[test]
    fn fisher_rows_spread_over_the_batch() {
        assert_eq!(fisher_rows(10, 1.0), None);
        assert_eq!(fisher_rows(10, 0.5), Some(vec![0, 2, 4, 6, 8]));
        assert_eq!(fisher_rows(10, 0.2), Some(vec![0, 5]));
        assert_eq!(fisher_rows(10, 0.01), Some(vec![0]));
        assert_eq!(fisher_rows(20_000, 0.2).map(|r| r.len()), Some(4000));
    }

    #[test]
    fn a_fisher_fraction_outside_0_1_is_refused() {
        for bad in [0.0, -0.5, 1.5, f64::NAN] {
            let config = PolicyStepConfig {
                fisher_fraction: bad,
                ..PolicyStepConfig::default()
            };
            let err = config.validate().unwrap_err();
            assert!(err.contains("policy_step.fisher_fraction"), "{err}");
        }
        assert!(PolicyStepConfig::default().validate().is_ok());
    }
}

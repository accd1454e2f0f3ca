//! What every policy-update kind evaluates, written once over an engine: the surrogate
//! (plain ratio, clipped or KL-penalised) and the mean KL from the step's starting policy,
//! their values at a candidate, and the surrogate's gradient (burn's autodiff over the
//! policy's outputs, carried back through the mean net by the engine).

use burn::backend::Autodiff;
use burn::tensor::Tensor;
use burn::tensor::backend::Backend;
use logo_nn::engine::select_rows;
use logo_nn::loss::{
    clipped_surrogate, gaussian_kl, gaussian_log_prob, ratio, ratio_surrogate, value_and_grad2,
};
use logo_nn::{Engine, Policy};

/// The batch one step works on, on the engine (uploaded once per iteration).
pub struct StepBatch<E: Engine> {
    pub obs: E::Rows,
    pub actions: Tensor<E::B, 2>,
    /// log π_k(a|s), of the policy that collected the batch: every ratio is against it
    /// (in the guidance step too, which starts from π_{k+½}).
    pub logp_old: Tensor<E::B, 1>,
    /// The step's (normalised) advantages.
    pub advantages: Tensor<E::B, 1>,
    pub rows: usize,
    /// How many of the last rows are demonstrations rather than the policy's own
    /// (DAPG's `[demonstration_rows]`; 0 otherwise): they enter the surrogate, not F·v.
    pub demonstration_rows: usize,
}

impl<E: Engine> StepBatch<E> {
    /// The policy's own batch (no demonstration rows).
    pub fn of_policy(
        obs: E::Rows,
        actions: Tensor<E::B, 2>,
        logp_old: Tensor<E::B, 1>,
        advantages: Tensor<E::B, 1>,
        rows: usize,
    ) -> Self {
        Self {
            obs,
            actions,
            logp_old,
            advantages,
            rows,
            demonstration_rows: 0,
        }
    }

    /// The rows at `indices` (a minibatch, a subsample of the policy's own rows).
    pub fn select(&self, engine: &E, indices: &[usize]) -> Self {
        Self {
            obs: engine.select(&self.obs, indices),
            actions: select_rows(&self.actions, indices),
            logp_old: select_rows(&self.logp_old, indices),
            advantages: select_rows(&self.advantages, indices),
            rows: indices.len(),
            demonstration_rows: 0,
        }
    }

    /// The same rows with other advantages.
    pub fn with_advantages(&self, advantages: Tensor<E::B, 1>) -> Self {
        Self {
            obs: self.obs.clone(),
            actions: self.actions.clone(),
            logp_old: self.logp_old.clone(),
            advantages,
            rows: self.rows,
            demonstration_rows: self.demonstration_rows,
        }
    }
}

/// Which surrogate a step maximises (r = π/π_k, Â the advantages).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Surrogate {
    /// mean(r·Â): TRPO's.
    Ratio,
    /// mean(min(r·Â, clip(r, 1 − ε, 1 + ε)·Â)): PPO-Clip's.
    Clipped { epsilon: f64 },
    /// mean(r·Â) − β·mean KL(π_start ‖ π): PPO-Penalty's.
    Penalised { beta: f64 },
}

/// The policy a step starts from, on the batch's rows: its means and log σ (the KL is
/// measured from it).
pub struct Anchor<B: Backend> {
    pub means: Tensor<B, 2>,
    pub log_std: Tensor<B, 1>,
}

impl<B: Backend> Anchor<B> {
    pub fn select(&self, indices: &[usize]) -> Self {
        Self {
            means: select_rows(&self.means, indices),
            log_std: self.log_std.clone(),
        }
    }
}

/// The surrogate and the mean KL(anchor ‖ π) of a policy with `means` and `log_std`, on
/// any backend: the one definition the values (plain backend) and the gradients (its
/// autodiff) both come from.
fn surrogate_and_kl<B: Backend>(
    kind: Surrogate,
    means: Tensor<B, 2>,
    log_std: Tensor<B, 1>,
    actions: Tensor<B, 2>,
    logp_old: Tensor<B, 1>,
    advantages: Tensor<B, 1>,
    anchor: &Anchor<B>,
) -> (Tensor<B, 1>, Tensor<B, 1>) {
    let kl = gaussian_kl(
        anchor.means.clone(),
        anchor.log_std.clone(),
        means.clone(),
        log_std.clone(),
    )
    .mean();
    let r = ratio(gaussian_log_prob(means, log_std, actions), logp_old);
    let value = match kind {
        Surrogate::Ratio => ratio_surrogate(r, advantages),
        Surrogate::Clipped { epsilon } => clipped_surrogate(r, advantages, epsilon),
        Surrogate::Penalised { beta } => {
            ratio_surrogate(r, advantages) - kl.clone().mul_scalar(beta)
        }
    };
    (value, kl)
}

/// The policy's anchor on the batch from its trace: a step starting there.
pub fn anchor<E: Engine>(engine: &E, policy: &Policy<E>, trace: &E::Trace) -> Anchor<E::B> {
    Anchor {
        means: engine.output(trace),
        log_std: policy.log_std_tensor(engine),
    }
}

/// (surrogate, mean KL from the anchor) of `policy` on `batch`: one forward pass.
pub fn evaluate<E: Engine>(
    engine: &E,
    kind: Surrogate,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    anchor: &Anchor<E::B>,
) -> (f64, f64) {
    let means = policy.means(engine, &batch.obs);
    evaluate_means(engine, kind, policy, means, batch, anchor)
}

/// As [`evaluate`], from means already computed.
pub fn evaluate_means<E: Engine>(
    engine: &E,
    kind: Surrogate,
    policy: &Policy<E>,
    means: Tensor<E::B, 2>,
    batch: &StepBatch<E>,
    anchor: &Anchor<E::B>,
) -> (f64, f64) {
    let (value, kl) = surrogate_and_kl(
        kind,
        means,
        policy.log_std_tensor(engine),
        batch.actions.clone(),
        batch.logp_old.clone(),
        batch.advantages.clone(),
        anchor,
    );
    (engine.download(value)[0], engine.download(kl)[0])
}

/// The surrogate at `policy` and its gradient with respect to the policy's parameters
/// (laid out as [`Policy::params`]), from `trace`, the mean net's pass over `batch.obs`.
pub fn gradient<E: Engine>(
    engine: &E,
    kind: Surrogate,
    policy: &Policy<E>,
    trace: &E::Trace,
    batch: &StepBatch<E>,
    anchor: &Anchor<E::B>,
) -> (f64, Vec<f64>) {
    let lift = |t: Tensor<E::B, 2>| Tensor::<Autodiff<E::B>, 2>::from_inner(t);
    let lift1 = |t: Tensor<E::B, 1>| Tensor::<Autodiff<E::B>, 1>::from_inner(t);
    let anchor = Anchor {
        means: lift(anchor.means.clone()),
        log_std: lift1(anchor.log_std.clone()),
    };
    let (value, d_means, d_log_std) = value_and_grad2(
        engine.output(trace),
        policy.log_std_tensor(engine),
        |means, log_std| {
            surrogate_and_kl(
                kind,
                means,
                log_std,
                lift(batch.actions.clone()),
                lift1(batch.logp_old.clone()),
                lift1(batch.advantages.clone()),
                &anchor,
            )
            .0
        },
    );
    let mut grad = engine.vjp(&policy.mean, trace, d_means);
    grad.extend(engine.download(d_log_std));
    (engine.download(value)[0], grad)
}

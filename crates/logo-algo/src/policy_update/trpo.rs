//! `kind = "trpo"`: the natural-gradient step of both of LOGO's steps (docs/reference.md):
//! maximise the surrogate within KL ≤ δ: s = CG(F, g, 10 iterations), full step
//! s·√(2δ / sᵀFs), backtracking over fractions 0.5^i (i < 10) until actual / expected
//! improvement > 0.1, else no step.

use crate::error::Invalid;
use logo_nn::flat::dot;
use logo_nn::{Engine, FisherKind, FisherOperator, Policy, conjugate_gradient};
use serde::{Deserialize, Serialize};

use super::objective::{Anchor, StepBatch, Surrogate, anchor, evaluate, gradient};
use super::stats::{StopReason, UpdateStats};
use crate::validate::{check_clip, check_count, check_fraction, check_positive};

/// `[improvement]` (or `[guidance.update]`) with `kind = "trpo"`, `"npg"` or
/// `"clip-in-trpo"`; a key left out takes its value from [`TrpoConfig::default`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrpoConfig {
    /// Added to F (times v). The reference: 0.01.
    pub damping: f64,
    pub cg_iters: usize,
    pub backtracks: usize,
    pub accept_ratio: f64,
    /// Also require the measured KL to be at most `kl_limit`·δ before accepting a step
    /// (backtracking further otherwise). Off by default: the reference's line search checks
    /// only the improvement, and its guidance steps often overshoot δ_k.
    pub kl_limit: Option<f64>,
    /// F·v on this fraction of the batch (rows spread evenly over it, see
    /// [`fisher_rows`]) instead of all of it: a cheaper, approximate curvature for the
    /// conjugate gradient and the step size. 1 (the default) is exact, as the reference.
    pub fisher_fraction: f64,
    /// The operator F·v computes: "exact" (the default) or "reference" (LOGO's code).
    pub fisher: FisherKind,
    /// `clip-in-trpo` only: ε of the clipped surrogate (default 0.2).
    pub clip_epsilon: Option<f64>,
}

/// The reference's values (docs/reference.md): CG 10 iterations with damping 0.01,
/// backtracking over 0.5^i for i < 10, accepted at actual / expected > 0.1.
impl Default for TrpoConfig {
    fn default() -> Self {
        Self {
            damping: 0.01,
            cg_iters: 10,
            backtracks: 10,
            accept_ratio: 0.1,
            kl_limit: None,
            fisher_fraction: 1.0,
            fisher: FisherKind::Exact,
            clip_epsilon: None,
        }
    }
}

impl TrpoConfig {
    pub fn validate(&self, table: &str) -> Result<(), Invalid> {
        check_fraction(&format!("{table}.fisher_fraction"), self.fisher_fraction)?;
        check_positive(&format!("{table}.damping"), self.damping, true)?;
        check_positive(&format!("{table}.accept_ratio"), self.accept_ratio, true)?;
        if let Some(limit) = self.kl_limit {
            check_positive(&format!("{table}.kl_limit"), limit, false)?;
        }
        if let Some(epsilon) = self.clip_epsilon {
            check_clip(&format!("{table}.clip_epsilon"), epsilon)?;
        }
        // CG in more iterations than there are parameters gains nothing; 60 halvings
        // already shrink a step below float64's resolution.
        check_count(&format!("{table}.cg_iters"), self.cg_iters, 10_000)?;
        check_count(&format!("{table}.backtracks"), self.backtracks, 60)
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

pub(super) fn update<E: Engine>(
    config: &TrpoConfig,
    engine: &E,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    delta: f64,
) -> (Policy<E>, UpdateStats) {
    natural_gradient_step(config, Surrogate::Ratio, engine, policy, batch, delta)
}

/// How the natural-gradient kinds (`trpo`, `clip-in-trpo`, `npg`) solve F·s = g.
#[derive(Debug, Clone, Copy)]
pub(super) struct Curvature {
    pub damping: f64,
    pub cg_iters: usize,
    pub fisher_fraction: f64,
    pub fisher: FisherKind,
}

impl TrpoConfig {
    pub(super) fn curvature(&self) -> Curvature {
        Curvature {
            damping: self.damping,
            cg_iters: self.cg_iters,
            fisher_fraction: self.fisher_fraction,
            fisher: self.fisher,
        }
    }
}

/// Where a natural-gradient step starts and the full step it may take.
pub(super) struct FullStep<E: Engine> {
    pub theta: Vec<f64>,
    pub start: Anchor<E::B>,
    /// The surrogate at θ, and its gradient.
    pub before: f64,
    pub grad: Vec<f64>,
    /// s·√(2δ / sᵀFs).
    pub step: Vec<f64>,
}

/// g = ∇ surrogate, s = CG(F, g), full step s·√(2δ / sᵀFs); `Err(Degenerate)` when
/// sᵀFs is not a positive number. F·v is on the policy's own rows (not a batch's
/// demonstration rows), all of them or `fisher_fraction` of them.
pub(super) fn full_step<E: Engine>(
    curvature: Curvature,
    surrogate: Surrogate,
    engine: &E,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    delta: f64,
) -> Result<FullStep<E>, StopReason> {
    let theta = policy.params(engine);
    let trace = engine.trace(&policy.mean, &batch.obs);
    let start = anchor(engine, policy, &trace);
    let (before, grad) = gradient(engine, surrogate, policy, &trace, batch, &start);

    // F·v on all rows (the trace above), or on a subset with a trace of its own.
    let own = batch.rows - batch.demonstration_rows;
    let subset = match fisher_rows(own, curvature.fisher_fraction) {
        None if own < batch.rows => Some((0..own).collect()),
        rows => rows,
    };
    let subset_trace = subset
        .as_ref()
        .map(|rows| engine.trace(&policy.mean, &engine.select(&batch.obs, rows)));
    let (fisher_trace, fisher_n) = match (&subset_trace, &subset) {
        (Some(t), Some(rows)) => (t, rows.len()),
        _ => (&trace, batch.rows),
    };
    let fisher = FisherOperator::new(
        engine,
        policy,
        fisher_trace,
        fisher_n,
        curvature.damping,
        curvature.fisher,
    );
    let direction = conjugate_gradient(|v| fisher.apply(v), &grad, curvature.cg_iters, 1e-10);
    let shs = 0.5 * dot(&direction, &fisher.apply(&direction));
    if !(shs > 0.0 && shs.is_finite()) {
        return Err(StopReason::Degenerate);
    }
    let scale = (shs / delta).sqrt();
    let step = direction.iter().map(|d| d / scale).collect();
    Ok(FullStep {
        theta,
        start,
        before,
        grad,
        step,
    })
}

/// The policy unchanged, and why.
pub(super) fn unchanged<E: Engine>(
    policy: &Policy<E>,
    stop: StopReason,
) -> (Policy<E>, UpdateStats) {
    let stats = UpdateStats {
        stop,
        ..UpdateStats::default()
    };
    (policy.clone(), stats)
}

/// The full step, then the backtracking line search over fractions 0.5^i;
/// `surrogate` is the objective (TRPO's ratio, or the clipped one).
pub(super) fn natural_gradient_step<E: Engine>(
    config: &TrpoConfig,
    surrogate: Surrogate,
    engine: &E,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    delta: f64,
) -> (Policy<E>, UpdateStats) {
    let full = match full_step(config.curvature(), surrogate, engine, policy, batch, delta) {
        Ok(full) => full,
        Err(stop) => return unchanged(policy, stop),
    };
    let expected_full = dot(&full.grad, &full.step);
    let mut fraction = 1.0;
    for _ in 0..config.backtracks {
        let candidate: Vec<f64> = full
            .theta
            .iter()
            .zip(&full.step)
            .map(|(t, s)| t + fraction * s)
            .collect();
        let moved = policy.with_params(engine, &candidate);
        let (value, kl) = evaluate(engine, surrogate, &moved, batch, &full.start);
        let actual = value - full.before;
        let expected = expected_full * fraction;
        let kl_ok = config.kl_limit.is_none_or(|limit| kl <= limit * delta);
        if actual / expected > config.accept_ratio && kl_ok {
            let stats = UpdateStats {
                kl,
                step_norm: fraction * dot(&full.step, &full.step).sqrt(),
                improvement: actual,
                steps: fraction,
                epochs: 0,
                stop: StopReason::Accepted,
                beta: 0.0,
            };
            return (moved, stats);
        }
        fraction *= 0.5;
    }
    unchanged(policy, StopReason::NoImprovement)
}

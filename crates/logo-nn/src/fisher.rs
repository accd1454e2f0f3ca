//! The natural-gradient machinery of TRPO and LOGO's guidance step: the Fisher-vector
//! product of the Gaussian policy, written once over an [`Engine`], and conjugate
//! gradient.

use serde::{Deserialize, Serialize};

use crate::engine::Engine;
use crate::flat::dot;
use crate::loss::fisher_output_weights;
use crate::policy::Policy;

/// Which operator F·v computes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FisherKind {
    /// The Hessian of the mean KL: [Jᵀ W J v_μ / N ; 2 v_logσ] (textbook TRPO).
    #[default]
    Exact,
    /// What the LOGO reference's code computes (docs/reference.md): Jᵀ W J v_μ / N on the mean
    /// parameters plus 2·v on *every* parameter, i.e. Jᵀ W J / N + 2·I. Its steps are much
    /// shorter in parameter space than the exact Fisher's.
    Reference,
}

/// F·v for a Gaussian policy at fixed parameters θ and states, F the Hessian at θ' = θ of
/// the mean KL(π_θ ‖ π_θ') (see [`FisherKind`]), plus `damping`·v:
///
/// F v = [ Jᵀ W J v_μ / N ; 2 v_logσ ] + damping · v,   W = diag(1/σ²),
///
/// J the Jacobian of the mean network over the rows of `trace`. Exact (no finite
/// differences, no double backward): the engine's Gauss–Newton product, from activations
/// cached once. The tests compare it with an explicit Fisher matrix and with a
/// finite-difference Hessian of the KL.
pub struct FisherOperator<'a, E: Engine> {
    engine: &'a E,
    net: &'a E::Net,
    trace: &'a E::Trace,
    curvature: E::Curvature,
    /// W / N.
    output_weights: Vec<f64>,
    mean_params: usize,
    damping: f64,
    kind: FisherKind,
}

impl<'a, E: Engine> FisherOperator<'a, E> {
    /// `trace`: the policy's mean network over the rows the Fisher is taken on.
    pub fn new(
        engine: &'a E,
        policy: &'a Policy<E>,
        trace: &'a E::Trace,
        rows: usize,
        damping: f64,
        kind: FisherKind,
    ) -> Self {
        let output_weights = fisher_output_weights(&policy.log_std)
            .into_iter()
            .map(|w| w / rows as f64)
            .collect();
        Self {
            engine,
            net: &policy.mean,
            trace,
            curvature: engine.curvature(&policy.mean, trace),
            output_weights,
            mean_params: policy.num_params() - policy.log_std.len(),
            damping,
            kind,
        }
    }

    /// F·v, with `v` laid out like [`Policy::params`].
    pub fn apply(&self, v: &[f64]) -> Vec<f64> {
        assert_eq!(
            v.len(),
            self.mean_params + self.output_weights.len(),
            "F·v: vector of the wrong length"
        );
        let (v_mean, v_log_std) = v.split_at(self.mean_params);
        let mut out = self.engine.gauss_newton(
            self.net,
            self.trace,
            &self.curvature,
            v_mean,
            &self.output_weights,
        );
        out.extend(v_log_std.iter().map(|x| 2.0 * x));
        if self.kind == FisherKind::Reference {
            // The reference's slice [0, act_dim·N) covers the whole vector (docs/reference.md).
            for (o, x) in out[..self.mean_params].iter_mut().zip(v_mean) {
                *o += 2.0 * x;
            }
        }
        for (o, x) in out.iter_mut().zip(v) {
            *o += self.damping * x;
        }
        out
    }
}

/// Solves A x = b for symmetric positive-definite A given only x ↦ A x, starting from
/// x = 0; stops after `iterations` or once the squared residual is below `residual_tol`
/// (the reference: 10 iterations, 1e-10).
pub fn conjugate_gradient(
    mut apply: impl FnMut(&[f64]) -> Vec<f64>,
    b: &[f64],
    iterations: usize,
    residual_tol: f64,
) -> Vec<f64> {
    let mut x = vec![0.0; b.len()];
    let mut r = b.to_vec();
    let mut p = b.to_vec();
    let mut rr = dot(&r, &r);
    for _ in 0..iterations {
        if rr < residual_tol {
            break;
        }
        let ap = apply(&p);
        let alpha = rr / dot(&p, &ap);
        for i in 0..x.len() {
            x[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
        }
        let rr_new = dot(&r, &r);
        let beta = rr_new / rr;
        for (pi, ri) in p.iter_mut().zip(&r) {
            *pi = ri + beta * *pi;
        }
        rr = rr_new;
    }
    x
}

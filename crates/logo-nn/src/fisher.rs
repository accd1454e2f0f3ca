//! The natural-gradient machinery of TRPO and LOGO's guidance step: the closed-form mean
//! KL between diagonal Gaussians, the exact Fisher-vector product of the Gaussian policy,
//! and conjugate gradient.

use burn::tensor::{Tensor, backend::Backend};

use crate::flat::{flatten_layers, split_layers};
use crate::mlp::Mlp;
use crate::policy::GaussianPolicy;

/// Mean over the batch of KL(old ‖ new) for diagonal Gaussians, in closed form:
/// Σ_j [log σ_new − log σ_old + (σ_old² + (μ_old − μ_new)²) / (2σ_new²) − ½].
pub fn mean_kl<B: Backend>(
    old_mean: Tensor<B, 2>,
    old_log_std: Tensor<B, 1>,
    new_mean: Tensor<B, 2>,
    new_log_std: Tensor<B, 1>,
) -> Tensor<B, 1> {
    let old_log_std = old_log_std.unsqueeze_dim::<2>(0);
    let new_log_std = new_log_std.unsqueeze_dim::<2>(0);
    let old_var = old_log_std.clone().mul_scalar(2.0).exp();
    let new_var = new_log_std.clone().mul_scalar(2.0).exp();
    let diff = old_mean - new_mean;
    let per_dim =
        (new_log_std - old_log_std) + (old_var + diff.clone() * diff) / new_var.mul_scalar(2.0);
    per_dim.sub_scalar(0.5).sum_dim(1).mean()
}

/// F·v for the Gaussian policy at fixed parameters θ and states, F being the Hessian of
/// the mean KL(π_θ ‖ π_θ') at θ' = θ:
///
/// F v = [ Jᵀ M J v_μ / N ; 2 v_logσ ] + damping · v,   M = diag(1/σ²),
///
/// J the Jacobian of the mean network over the batch. J v is the network's forward-mode
/// derivative and Jᵀ u its reverse-mode one, both over activations cached once here, so
/// each product costs about two matrix products per layer and no second forward pass.
/// Exact (no finite differences, no double backward); the tests compare it with an
/// explicit Fisher matrix and with a finite-difference Hessian of [`mean_kl`].
pub struct FisherVectorProduct<B: Backend> {
    mean_net: Mlp<B>,
    inputs: Vec<Tensor<B, 2>>,
    /// 1/σ² / N, shape `[1, act_dim]`.
    scale: Tensor<B, 2>,
    mean_params: usize,
    damping: f64,
    device: B::Device,
}

impl<B: Backend> FisherVectorProduct<B> {
    /// Caches the activations of `policy` on `obs` (`[N, obs_dim]`). Use the inner
    /// (non-autodiff) backend: nothing here needs a graph.
    pub fn new(policy: &GaussianPolicy<B>, obs: Tensor<B, 2>, damping: f64) -> Self {
        let n = obs.dims()[0] as f64;
        let device = obs.device();
        let (inputs, _) = policy.mean.forward_trace(obs);
        let scale = policy
            .log_std
            .val()
            .mul_scalar(-2.0)
            .exp()
            .div_scalar(n)
            .unsqueeze_dim::<2>(0);
        let mean_params = policy
            .mean
            .layers
            .iter()
            .map(|l| l.weight.shape().num_elements() + l.weight.dims()[1])
            .sum();
        Self {
            mean_net: policy.mean.clone(),
            inputs,
            scale,
            mean_params,
            damping,
            device,
        }
    }

    /// Length of the vectors this operates on: the policy's parameter count.
    pub fn dim(&self) -> usize {
        self.mean_params + self.scale.dims()[1]
    }

    /// F·v, with `v` laid out like [`crate::flat::params_to_vec`] of the policy.
    pub fn apply(&self, v: &[f64]) -> Vec<f64> {
        assert_eq!(v.len(), self.dim(), "F·v: vector of the wrong length");
        let (v_mean, v_log_std) = v.split_at(self.mean_params);
        let tangent = split_layers(&self.mean_net, v_mean, &self.device);
        let jv = self.mean_net.jvp(&self.inputs, &tangent);
        let mut out = flatten_layers(self.mean_net.vjp(&self.inputs, jv * self.scale.clone()));
        out.extend(v_log_std.iter().map(|x| 2.0 * x));
        for (o, x) in out.iter_mut().zip(v) {
            *o += self.damping * x;
        }
        out
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
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

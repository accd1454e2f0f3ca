//! Every loss of LOGO and its variants, written once in burn over network outputs (the
//! policy's action means and log σ, a value net's values, the discriminator's logits),
//! for any backend. Their gradients with respect to those outputs are burn's autodiff
//! ([`value_and_grad`], [`value_and_grad2`]): small tensors (batch × action dim) that the
//! engine then carries back through the network (Jᵀ·u).
//!
//! Scalars are rank-1 tensors of one element, as burn's reductions return them.

use burn::backend::Autodiff;
use burn::tensor::Tensor;
use burn::tensor::backend::Backend;

/// ln(2π), of the Gaussian log-density.
pub const LOG_2PI: f64 = 1.837_877_066_409_345_5;

/// log N(a; μ, diag σ²) summed over the action dimensions: one value per row.
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

/// KL(old ‖ new) between diagonal Gaussians, one value per row:
/// Σ_j [log σ_new − log σ_old + (σ_old² + (μ_old − μ_new)²) / (2σ_new²) − ½].
pub fn gaussian_kl<B: Backend>(
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
    per_dim.sub_scalar(0.5).sum_dim(1).squeeze_dim::<1>(1)
}

/// Entropy of N(μ, diag σ²), the same for every state: Σ log σ + ½ d (1 + ln 2π).
pub fn gaussian_entropy<B: Backend>(log_std: Tensor<B, 1>) -> Tensor<B, 1> {
    let d = log_std.dims()[0] as f64;
    log_std.sum().add_scalar(0.5 * d * (1.0 + LOG_2PI))
}

/// The weights W of the Gaussian policy's Fisher on its mean outputs, ∂²KL/∂μ_new² at
/// μ_new = μ_old: 1/σ² per action dimension. Closed form, because the Fisher-vector
/// product uses it ten times per step; a test holds it to autodiff's Hessian of
/// [`gaussian_kl`].
pub fn fisher_output_weights(log_std: &[f64]) -> Vec<f64> {
    log_std.iter().map(|l| (-2.0 * l).exp()).collect()
}

/// The probability ratio π/π_old of each row from log-probabilities.
pub fn ratio<B: Backend>(logp: Tensor<B, 1>, logp_old: Tensor<B, 1>) -> Tensor<B, 1> {
    (logp - logp_old).exp()
}

/// TRPO's surrogate mean(r · Â), to maximise.
pub fn ratio_surrogate<B: Backend>(ratio: Tensor<B, 1>, advantages: Tensor<B, 1>) -> Tensor<B, 1> {
    (ratio * advantages).mean()
}

/// PPO-Clip's surrogate mean(min(r·Â, clip(r, 1 − ε, 1 + ε)·Â)), to maximise.
pub fn clipped_surrogate<B: Backend>(
    ratio: Tensor<B, 1>,
    advantages: Tensor<B, 1>,
    epsilon: f64,
) -> Tensor<B, 1> {
    let clipped = ratio.clone().clamp(1.0 - epsilon, 1.0 + epsilon) * advantages.clone();
    (ratio * advantages).min_pair(clipped).mean()
}

/// Mean squared error between values and targets (same shape).
pub fn mse<B: Backend, const D: usize>(
    values: Tensor<B, D>,
    targets: Tensor<B, D>,
) -> Tensor<B, 1> {
    let diff = values - targets;
    (diff.clone() * diff).mean()
}

/// log(1 + eˣ), stable for large |x|: max(x, 0) + log1p(e^{−|x|}).
///
/// Written here rather than taken from burn: burn 0.21's `sigmoid` computes in f32
/// whatever the backend's precision, and its `softplus` overflows for large x.
pub fn softplus<B: Backend, const D: usize>(x: Tensor<B, D>) -> Tensor<B, D> {
    x.clone().clamp_min(0.0) + x.abs().neg().exp().log1p()
}

/// Binary cross-entropy of logits against one label for every row, averaged:
/// −log σ(l) = softplus(−l) for label 1, −log(1 − σ(l)) = softplus(l) for label 0.
pub fn binary_cross_entropy<B: Backend>(logits: Tensor<B, 1>, label_one: bool) -> Tensor<B, 1> {
    let signed = if label_one { logits.neg() } else { logits };
    softplus(signed).mean()
}

/// LOGO's guidance reward −log D(s, a) from the discriminator's logits (D = σ(logit) is
/// the probability that a pair came from the policy): softplus(−logit).
pub fn guidance_reward<B: Backend>(logits: Tensor<B, 1>) -> Tensor<B, 1> {
    softplus(logits.neg())
}

/// A scalar loss of `x` and its gradient with respect to `x`, by burn's autodiff; the
/// value stays a tensor on `x`'s device until the caller downloads it.
pub fn value_and_grad<B: Backend, const D: usize>(
    x: Tensor<B, D>,
    loss: impl FnOnce(Tensor<Autodiff<B>, D>) -> Tensor<Autodiff<B>, 1>,
) -> (Tensor<B, 1>, Tensor<B, D>) {
    let x = Tensor::<Autodiff<B>, D>::from_inner(x).require_grad();
    let value = loss(x.clone());
    let grads = value.backward();
    let grad = x.grad(&grads).unwrap_or_else(|| x.inner().zeros_like());
    (value.inner(), grad)
}

/// As [`value_and_grad`], for a loss of two tensors (a policy's means and its log σ).
pub fn value_and_grad2<B: Backend, const D1: usize, const D2: usize>(
    x: Tensor<B, D1>,
    y: Tensor<B, D2>,
    loss: impl FnOnce(Tensor<Autodiff<B>, D1>, Tensor<Autodiff<B>, D2>) -> Tensor<Autodiff<B>, 1>,
) -> (Tensor<B, 1>, Tensor<B, D1>, Tensor<B, D2>) {
    let x = Tensor::<Autodiff<B>, D1>::from_inner(x).require_grad();
    let y = Tensor::<Autodiff<B>, D2>::from_inner(y).require_grad();
    let value = loss(x.clone(), y.clone());
    let grads = value.backward();
    let gx = x.grad(&grads).unwrap_or_else(|| x.inner().zeros_like());
    let gy = y.grad(&grads).unwrap_or_else(|| y.inner().zeros_like());
    (value.inner(), gx, gy)
}

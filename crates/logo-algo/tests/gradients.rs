//! The hand-written gradients the training loop uses, against burn's autodiff.

use burn::module::AutodiffModule;
use logo_algo::critic::{HostValueObjective, value_loss_and_grad};
use logo_algo::lbfgs::Objective;
use logo_algo::trpo::{StepData, surrogate_gradient};
use logo_nn::flat::{from_f64, grads_to_vec, params_to_vec, vec_to_params};
use logo_nn::{CpuAutodiff, PolicyConfig, ValueNetConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

type B = CpuAutodiff;

fn relative_error(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt();
    d / b.iter().map(|y| y * y).sum::<f64>().sqrt()
}

#[test]
fn the_critic_gradient_matches_autodiff() {
    let device = Default::default();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let net = ValueNetConfig {
        obs_dim: 4,
        hidden: vec![6, 5],
    }
    .init::<B>(&device);
    let theta: Vec<f64> = (0..params_to_vec(&net).len())
        .map(|_| rng.random_range(-0.7..0.7))
        .collect();
    let net = vec_to_params(net, &theta);
    let obs: Vec<f64> = (0..9 * 4).map(|_| rng.random_range(-2.0..2.0)).collect();
    let target: Vec<f64> = (0..9).map(|_| rng.random_range(-3.0..3.0)).collect();
    let l2 = 1e-3;

    let diff = net.forward(from_f64(&obs, [9, 4], &device)) - from_f64(&target, [9], &device);
    let mse = (diff.clone() * diff).mean();
    let mut want = grads_to_vec(&net, &mse.backward());
    want.iter_mut()
        .zip(&theta)
        .for_each(|(g, t)| *g += 2.0 * l2 * t);

    let inner = net.valid();
    let (loss, got) = value_loss_and_grad(
        &inner,
        from_f64(&obs, [9, 4], &device),
        from_f64(&target, [9, 1], &device),
        &theta,
        l2,
    );
    assert!(relative_error(&got, &want) < 1e-12, "{got:?}\nvs {want:?}");
    assert!(loss > 0.0);

    // The host-buffer objective the CPU critic fits use: same loss, same gradient.
    let mut host = HostValueObjective::new(vec![4, 6, 5, 1], &obs, &target, l2);
    let host_loss = host.loss(&theta);
    assert!(
        (host_loss - loss).abs() < 1e-12 * loss,
        "{host_loss} vs {loss}"
    );
    let host_grad = host.gradient();
    assert!(
        relative_error(&host_grad, &got) < 1e-12,
        "{host_grad:?}\nvs {got:?}"
    );
}

#[test]
fn the_surrogate_gradient_matches_autodiff_away_from_the_old_policy() {
    let device = Default::default();
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let config = PolicyConfig {
        obs_dim: 3,
        act_dim: 2,
        hidden: vec![5, 4],
        log_std_init: -0.2,
    };
    let policy = config.init::<B>(&device);
    let theta: Vec<f64> = (0..params_to_vec(&policy).len())
        .map(|_| rng.random_range(-0.6..0.6))
        .collect();
    let policy = vec_to_params(policy, &theta);
    let (n, obs_dim, act_dim) = (8, 3, 2);
    let obs: Vec<f64> = (0..n * obs_dim)
        .map(|_| rng.random_range(-2.0..2.0))
        .collect();
    let actions: Vec<f64> = (0..n * act_dim)
        .map(|_| rng.random_range(-1.5..1.5))
        .collect();
    let adv: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
    // Old log-probs from another policy, so the ratio is not 1.
    let logp_old: Vec<f64> = (0..n).map(|_| rng.random_range(-3.0..-1.0)).collect();

    let logp = policy.log_prob(
        from_f64(&obs, [n, obs_dim], &device),
        from_f64(&actions, [n, act_dim], &device),
    );
    let surr =
        ((logp - from_f64(&logp_old, [n], &device)).exp() * from_f64(&adv, [n], &device)).mean();
    let want = grads_to_vec(&policy, &surr.backward());

    let inner = policy.valid();
    let data = StepData {
        obs: from_f64(&obs, [n, obs_dim], &device),
        actions: from_f64(&actions, [n, act_dim], &device),
        logp_old: from_f64(&logp_old, [n], &device),
    };
    let got = surrogate_gradient(&inner, &data, &from_f64(&adv, [n], &device));
    assert!(relative_error(&got, &want) < 1e-12, "{got:?}\nvs {want:?}");
}

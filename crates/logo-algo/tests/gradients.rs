//! The gradients the training loop uses, against burn's autodiff through the whole burn
//! module, on both engines: every policy surrogate (away from the old policy, so ratios
//! and clipping matter) and the critic's loss.

use burn::module::AutodiffModule;
use burn::tensor::Tensor;
use logo_algo::critic::ValueObjective;
use logo_algo::lbfgs::Objective;
use logo_algo::policy_update::objective::{StepBatch, Surrogate, anchor, evaluate, gradient};
use logo_nn::flat::{from_f64, grads_to_vec, params_to_vec, vec_to_params};
use logo_nn::loss::{clipped_surrogate, gaussian_kl, gaussian_log_prob, ratio, ratio_surrogate};
use logo_nn::{
    BurnEngine, Cpu, CpuAutodiff, Engine, GaussianPolicy, Kernels, Policy, PolicyConfig,
    ValueNetConfig,
};
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

/// A policy π with random parameters, a start policy π₀ (another random point, from
/// which the KL is measured), and a batch whose old log-probs come from a third policy.
struct Case {
    policy: GaussianPolicy<B>,
    start: GaussianPolicy<B>,
    obs: Vec<f64>,
    actions: Vec<f64>,
    advantages: Vec<f64>,
    logp_old: Vec<f64>,
    n: usize,
}

fn case() -> Case {
    let device = Default::default();
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let config = PolicyConfig {
        obs_dim: 3,
        act_dim: 2,
        hidden: vec![5, 4],
        log_std_init: -0.2,
    };
    let mut random_policy = |scale: f64| {
        let p = config.init::<B>(&device);
        let theta: Vec<f64> = (0..params_to_vec(&p).len())
            .map(|_| rng.random_range(-scale..scale))
            .collect();
        vec_to_params(p, &theta)
    };
    let policy = random_policy(0.6);
    let start = random_policy(0.6);
    let n = 300;
    let obs: Vec<f64> = (0..n * 3).map(|_| rng.random_range(-2.0..2.0)).collect();
    let actions: Vec<f64> = (0..n * 2).map(|_| rng.random_range(-1.5..1.5)).collect();
    let advantages: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
    // Old log-probs near the policy's, so that ratios fall on both sides of the clip range.
    let logp = policy.valid().log_prob(
        from_f64(&obs, [n, 3], &device),
        from_f64(&actions, [n, 2], &device),
    );
    let logp_old: Vec<f64> = logo_nn::flat::to_f64(logp)
        .iter()
        .map(|l| l + rng.random_range(-0.5..0.5))
        .collect();
    Case {
        policy,
        start,
        obs,
        actions,
        advantages,
        logp_old,
        n,
    }
}

/// The surrogate of `kind` through burn's autodiff on the whole module, and its gradient.
fn autodiff_surrogate(case: &Case, kind: Surrogate) -> (f64, Vec<f64>) {
    let device = Default::default();
    let n = case.n;
    let obs = from_f64::<B, 2>(&case.obs, [n, 3], &device);
    let means = case.policy.mean_action(obs.clone());
    let log_std = case.policy.log_std.val();
    let logp = gaussian_log_prob(
        means.clone(),
        log_std.clone(),
        from_f64(&case.actions, [n, 2], &device),
    );
    let r = ratio(logp, from_f64(&case.logp_old, [n], &device));
    let adv = from_f64::<B, 1>(&case.advantages, [n], &device);
    let start_means = case.start.mean_action(obs).detach();
    let kl = gaussian_kl(
        start_means,
        case.start.log_std.val().detach(),
        means,
        log_std,
    )
    .mean();
    let value = match kind {
        Surrogate::Ratio => ratio_surrogate(r, adv),
        Surrogate::Clipped { epsilon } => clipped_surrogate(r, adv, epsilon),
        Surrogate::Penalised { beta } => ratio_surrogate(r, adv) - kl.mul_scalar(beta),
    };
    let grads = value.backward();
    (
        logo_nn::flat::to_f64(value.inner())[0],
        grads_to_vec(&case.policy, &grads),
    )
}

/// The same through the engine: the surrogate from the loss module, its gradient carried
/// back by the engine's Jᵀ·u.
fn engine_surrogate<E: Engine>(engine: &E, case: &Case, kind: Surrogate) -> (f64, Vec<f64>, f64) {
    let n = case.n;
    let policy = Policy::from_module(engine, &case.policy.valid());
    let start = Policy::from_module(engine, &case.start.valid());
    let batch = StepBatch {
        obs: engine.rows(&case.obs, 3),
        actions: engine.upload(&case.actions, [n, 2]),
        logp_old: engine.upload(&case.logp_old, [n]),
        advantages: engine.upload(&case.advantages, [n]),
        rows: n,
        demonstration_rows: 0,
    };
    let start_anchor = anchor(engine, &start, &engine.trace(&start.mean, &batch.obs));
    let trace = engine.trace(&policy.mean, &batch.obs);
    let (value, grad) = gradient(engine, kind, &policy, &trace, &batch, &start_anchor);
    let (again, _) = evaluate(engine, kind, &policy, &batch, &start_anchor);
    assert!((value - again).abs() <= 1e-13 * value.abs().max(1.0));
    (value, grad, again)
}

#[test]
fn every_surrogate_gradient_matches_autodiff_on_both_engines() {
    let case = case();
    let burn = BurnEngine::<Cpu>::new(Default::default(), "ndarray f64");
    for kind in [
        Surrogate::Ratio,
        Surrogate::Clipped { epsilon: 0.2 },
        Surrogate::Penalised { beta: 3.0 },
    ] {
        let (want_value, want) = autodiff_surrogate(&case, kind);
        for (name, (value, got, _)) in [
            ("kernels", engine_surrogate(&Kernels, &case, kind)),
            ("burn", engine_surrogate(&burn, &case, kind)),
        ] {
            assert!(
                (value - want_value).abs() < 1e-12 * want_value.abs().max(1.0),
                "{name} {kind:?}: {value} vs {want_value}"
            );
            let err = relative_error(&got, &want);
            assert!(err < 1e-11, "{name} {kind:?}: gradient error {err:e}");
        }
    }
    // The clip matters on this batch: the clipped gradient is not the plain one.
    let (_, plain) = autodiff_surrogate(&case, Surrogate::Ratio);
    let (_, clipped) = autodiff_surrogate(&case, Surrogate::Clipped { epsilon: 0.2 });
    assert!(relative_error(&clipped, &plain) > 1e-3);
}

#[test]
fn the_critic_loss_and_gradient_match_autodiff_on_both_engines() {
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
    let want_loss = logo_nn::flat::to_f64(mse.clone().inner())[0]
        + l2 * theta.iter().map(|t| t * t).sum::<f64>();
    let mut want = grads_to_vec(&net, &mse.backward());
    want.iter_mut()
        .zip(&theta)
        .for_each(|(g, t)| *g += 2.0 * l2 * t);

    fn engine_loss<E: Engine>(
        engine: &E,
        obs: &[f64],
        target: &[f64],
        theta: &[f64],
        l2: f64,
    ) -> (f64, Vec<f64>) {
        let dims = [4, 6, 5, 1];
        let rows = engine.rows(obs, 4);
        let targets: Tensor<E::B, 2> = engine.upload(target, [target.len(), 1]);
        let mut objective = ValueObjective::new(engine, &dims, &rows, &targets, l2);
        let loss = objective.loss(theta);
        assert!((objective.value(theta) - loss).abs() < 1e-13 * loss);
        (loss, objective.gradient())
    }
    let burn = BurnEngine::<Cpu>::new(Default::default(), "ndarray f64");
    for (name, (loss, got)) in [
        ("kernels", engine_loss(&Kernels, &obs, &target, &theta, l2)),
        ("burn", engine_loss(&burn, &obs, &target, &theta, l2)),
    ] {
        assert!(
            (loss - want_loss).abs() < 1e-12 * want_loss,
            "{name}: {loss} vs {want_loss}"
        );
        assert!(
            relative_error(&got, &want) < 1e-12,
            "{name}: {got:?}\nvs {want:?}"
        );
    }
}

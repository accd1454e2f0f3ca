//! The natural-gradient pieces against independent computations, on both engines.

use burn::backend::ndarray::NdArrayDevice;
use burn::module::AutodiffModule;
use burn::tensor::Tensor;
use logo_nn::flat::{from_f64, grads_to_vec, params_to_vec, to_f64, vec_to_params};
use logo_nn::loss::gaussian_kl;
use logo_nn::{
    BurnEngine, Cpu, CpuAutodiff, Engine, FisherKind, FisherOperator, GaussianPolicy, Kernels,
    Policy, PolicyConfig, conjugate_gradient,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

type B = CpuAutodiff;

fn mean_kl<B: burn::tensor::backend::Backend>(
    old_mean: Tensor<B, 2>,
    old_log_std: Tensor<B, 1>,
    new_mean: Tensor<B, 2>,
    new_log_std: Tensor<B, 1>,
) -> Tensor<B, 1> {
    gaussian_kl(old_mean, old_log_std, new_mean, new_log_std).mean()
}

/// F·v of `policy` on `obs` through `engine`'s FisherOperator.
fn fisher_product<E: Engine>(
    engine: &E,
    policy: &GaussianPolicy<B>,
    obs: &Tensor<B, 2>,
    damping: f64,
    kind: FisherKind,
    v: &[f64],
) -> Vec<f64> {
    let on_engine = Policy::from_module(engine, &policy.valid());
    let obs = to_f64(obs.clone());
    let rows = engine.rows(&obs, policy.obs_dim());
    let trace = engine.trace(&on_engine.mean, &rows);
    let n = engine.num_rows(&rows);
    FisherOperator::new(engine, &on_engine, &trace, n, damping, kind).apply(v)
}

/// v ↦ F·v.
type Product<'a> = Box<dyn Fn(&[f64]) -> Vec<f64> + 'a>;

/// F·v on the kernels and on burn (ndarray f64): the same operator, two engines.
fn both_engines<'a>(
    policy: &'a GaussianPolicy<B>,
    obs: &'a Tensor<B, 2>,
    damping: f64,
    kind: FisherKind,
) -> [Product<'a>; 2] {
    let burn = BurnEngine::<Cpu>::new(Default::default(), "ndarray f64");
    [
        Box::new(move |v| fisher_product(&Kernels, policy, obs, damping, kind, v)),
        Box::new(move |v| fisher_product(&burn, policy, obs, damping, kind, v)),
    ]
}

fn tiny_policy(device: &NdArrayDevice) -> (GaussianPolicy<B>, Tensor<B, 2>) {
    let config = PolicyConfig {
        obs_dim: 3,
        act_dim: 2,
        hidden: vec![4, 5],
        log_std_init: -0.3,
    };
    let mut policy = config.init::<B>(device);
    // Random parameters everywhere (the init's zero output bias would hide errors), and
    // unequal standard deviations so M = diag(1/σ²) matters.
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let theta: Vec<f64> = (0..policy.num_params())
        .map(|_| rng.random_range(-0.8..0.8))
        .collect();
    policy = vec_to_params(policy, &theta);
    let obs: Vec<f64> = (0..7 * 3).map(|_| rng.random_range(-2.0..2.0)).collect();
    (policy, from_f64(&obs, [7, 3], device))
}

fn relative_error(a: &[f64], b: &[f64]) -> f64 {
    let diff: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt();
    let norm: f64 = b.iter().map(|y| y * y).sum::<f64>().sqrt();
    diff / norm
}

use burn::module::Module;

/// F assembled column by column from autodiff Jacobians: F = Σ_ij ∇μ_ij ∇μ_ijᵀ / (σ_j² N)
/// on the mean parameters, 2·I on the log-stds, plus damping.
fn explicit_fisher(
    policy: &GaussianPolicy<B>,
    obs: &Tensor<B, 2>,
    damping: f64,
    kind: FisherKind,
) -> Vec<Vec<f64>> {
    let p = policy.num_params();
    let (n, act_dim) = (obs.dims()[0], policy.act_dim());
    let std = to_f64(policy.log_std.val().exp());
    let mut f = vec![vec![0.0; p]; p];
    for i in 0..n {
        for (j, sj) in std.iter().enumerate() {
            let mean = policy.mean_action(obs.clone());
            let entry = mean.slice([i..i + 1, j..j + 1]).sum();
            let row = grads_to_vec(policy, &entry.backward());
            let w = 1.0 / (sj * sj * n as f64);
            for a in 0..p {
                for b in 0..p {
                    f[a][b] += w * row[a] * row[b];
                }
            }
        }
    }
    for (k, row) in f.iter_mut().enumerate() {
        // The exact Fisher has 2·I on the log-stds; the reference's code adds 2·I to every
        // parameter (docs/reference.md): Jᵀ M J / N + 2.01·I with its damping.
        if k >= p - act_dim || kind == FisherKind::Reference {
            row[k] += 2.0;
        }
        row[k] += damping;
    }
    f
}

#[test]
fn fisher_vector_product_matches_the_explicit_fisher_matrix_on_both_engines() {
    let device = Default::default();
    let (policy, obs) = tiny_policy(&device);
    let damping = 0.01;
    for kind in [FisherKind::Exact, FisherKind::Reference] {
        let f = explicit_fisher(&policy, &obs, damping, kind);
        let p = policy.num_params();
        for (engine, fvp) in ["kernels", "burn"]
            .iter()
            .zip(both_engines(&policy, &obs, damping, kind))
        {
            // Every column, then random directions.
            let mut worst = 0.0f64;
            for k in 0..p {
                let mut e = vec![0.0; p];
                e[k] = 1.0;
                let column: Vec<f64> = (0..p).map(|a| f[a][k]).collect();
                worst = worst.max(relative_error(&fvp(&e), &column));
            }
            let mut rng = ChaCha8Rng::seed_from_u64(2);
            for _ in 0..5 {
                let v: Vec<f64> = (0..p).map(|_| rng.random_range(-1.0..1.0)).collect();
                let want: Vec<f64> = (0..p)
                    .map(|a| (0..p).map(|b| f[a][b] * v[b]).sum())
                    .collect();
                worst = worst.max(relative_error(&fvp(&v), &want));
            }
            assert!(
                worst <= 1e-8,
                "{engine}, {kind:?}: relative error {worst:e}"
            );
        }
    }
}

/// The reference operator is the exact one plus 2·v on the mean parameters: a test that
/// fails on the exact operator (and on one that adds 2·v to the log-stds twice).
#[test]
fn the_reference_fisher_adds_two_v_to_every_parameter() {
    let device = Default::default();
    let (policy, obs) = tiny_policy(&device);
    let p = policy.num_params();
    let act_dim = policy.act_dim();
    let v: Vec<f64> = (0..p).map(|k| (k as f64 * 0.61).sin()).collect();
    let [exact, _] = both_engines(&policy, &obs, 0.01, FisherKind::Exact);
    let [reference, _] = both_engines(&policy, &obs, 0.01, FisherKind::Reference);
    let (fe, fr) = (exact(&v), reference(&v));
    for k in 0..p {
        let extra = if k < p - act_dim { 2.0 * v[k] } else { 0.0 };
        assert!(
            (fr[k] - fe[k] - extra).abs() <= 1e-12 * fr[k].abs().max(1.0),
            "parameter {k}: reference {} exact {} v {}",
            fr[k],
            fe[k],
            v[k]
        );
    }
}

#[test]
fn fisher_vector_product_is_the_hessian_of_the_mean_kl() {
    let device = Default::default();
    let (policy, obs) = tiny_policy(&device);
    let theta = params_to_vec(&policy);
    let old_mean = policy.mean_action(obs.clone()).detach();
    let old_log_std = policy.log_std.val().detach();
    // ∇θ' KL(π_θ ‖ π_θ') by autodiff.
    let kl_grad = |theta_new: &[f64]| {
        let p = vec_to_params(policy.clone(), theta_new);
        let kl = mean_kl(
            old_mean.clone(),
            old_log_std.clone(),
            p.mean_action(obs.clone()),
            p.log_std.val(),
        );
        grads_to_vec(&p, &kl.backward())
    };
    let [fvp, _] = both_engines(&policy, &obs, 0.0, FisherKind::Exact);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let eps = 1e-5;
    for _ in 0..3 {
        let v: Vec<f64> = (0..theta.len())
            .map(|_| rng.random_range(-1.0..1.0))
            .collect();
        let plus: Vec<f64> = theta.iter().zip(&v).map(|(t, d)| t + eps * d).collect();
        let minus: Vec<f64> = theta.iter().zip(&v).map(|(t, d)| t - eps * d).collect();
        let hv: Vec<f64> = kl_grad(&plus)
            .iter()
            .zip(kl_grad(&minus))
            .map(|(a, b)| (a - b) / (2.0 * eps))
            .collect();
        let err = relative_error(&fvp(&v), &hv);
        assert!(
            err <= 1e-7,
            "F·v vs finite-difference Hessian of KL: relative error {err:e}"
        );
    }
    // And the KL's gradient vanishes at θ' = θ (the old policy is the minimum).
    let g = kl_grad(&theta);
    assert!(g.iter().all(|x| x.abs() < 1e-12), "{g:?}");
}

#[test]
fn conjugate_gradient_solves_a_known_spd_system() {
    let n = 12;
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let q: Vec<Vec<f64>> = (0..n)
        .map(|_| (0..n).map(|_| rng.random_range(-1.0..1.0)).collect())
        .collect();
    // A = QᵀQ + I is symmetric positive definite.
    let a: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    (0..n).map(|k| q[k][i] * q[k][j]).sum::<f64>() + f64::from(u8::from(i == j))
                })
                .collect()
        })
        .collect();
    let x_true: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
    let b: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| a[i][j] * x_true[j]).sum())
        .collect();
    let mut calls = 0;
    let x = conjugate_gradient(
        |v| {
            calls += 1;
            (0..n)
                .map(|i| (0..n).map(|j| a[i][j] * v[j]).sum())
                .collect()
        },
        &b,
        100,
        1e-20,
    );
    assert!(relative_error(&x, &x_true) < 1e-9, "{x:?}");
    assert!(
        calls <= n + 2,
        "CG on an n×n SPD system converges in about n steps ({calls})"
    );
    // The reference's budget: 10 iterations.
    let mut calls = 0;
    conjugate_gradient(
        |v| {
            calls += 1;
            v.to_vec()
        },
        &b,
        10,
        1e-10,
    );
    assert_eq!(
        calls, 1,
        "A = I is solved in one step, then the residual test stops it"
    );
}

#[test]
fn gaussian_formulas_match_hand_computation() {
    let device = Default::default();
    let (policy, obs) = tiny_policy(&device);
    let mean = to_f64(policy.mean_action(obs.clone()));
    let log_std = to_f64(policy.log_std.val());
    let actions: Vec<f64> = mean
        .iter()
        .enumerate()
        .map(|(k, m)| m + 0.3 * (k as f64).cos())
        .collect();
    let lp = to_f64(policy.log_prob(obs.clone(), from_f64(&actions, [7, 2], &device)));
    for i in 0..7 {
        let want: f64 = (0..2)
            .map(|j| {
                let (m, s) = (mean[i * 2 + j], log_std[j].exp());
                let z = (actions[i * 2 + j] - m) / s;
                -0.5 * z * z - s.ln() - 0.5 * (2.0 * std::f64::consts::PI).ln()
            })
            .sum();
        assert!((lp[i] - want).abs() < 1e-12, "row {i}: {} vs {want}", lp[i]);
    }
    let entropy = to_f64(policy.entropy())[0];
    let want: f64 = log_std
        .iter()
        .map(|l| l + 0.5 * (1.0 + (2.0 * std::f64::consts::PI).ln()))
        .sum();
    assert!((entropy - want).abs() < 1e-12);
    // KL: zero against itself; for 1-D Gaussians N(0,1) ‖ N(1, e²) = 1 + (1+1)/(2e²) − ½.
    let m = policy.mean_action(obs);
    let kl_self = to_f64(mean_kl(
        m.clone(),
        policy.log_std.val(),
        m,
        policy.log_std.val(),
    ))[0];
    assert!(kl_self.abs() < 1e-15);
    let kl = to_f64(mean_kl(
        from_f64::<B, 2>(&[0.0], [1, 1], &device),
        from_f64(&[0.0], [1], &device),
        from_f64(&[1.0], [1, 1], &device),
        from_f64(&[1.0], [1], &device),
    ))[0];
    assert!(
        (kl - (1.0 + 2.0 / (2.0 * 1f64.exp().powi(2)) - 0.5)).abs() < 1e-15,
        "{kl}"
    );
}

#[test]
fn flat_parameters_round_trip_and_follow_the_module_order() {
    let device = Default::default();
    let policy = PolicyConfig::new(11, 3).init::<B>(&device);
    let theta = params_to_vec(&policy);
    assert_eq!(
        theta.len(),
        11 * 128 + 128 + 128 * 128 + 128 + 128 * 3 + 3 + 3
    );
    // The reference's init: output layer bias 0, log-std 0.
    assert!(theta[theta.len() - 6..].iter().all(|x| *x == 0.0));
    let shifted: Vec<f64> = theta.iter().map(|x| x + 0.25).collect();
    let back = params_to_vec(&vec_to_params(policy, &shifted));
    assert_eq!(back, shifted);
}

#[test]
fn every_parameter_of_a_fresh_policy_receives_a_gradient() {
    // Regression: the output layer's weight, scaled ×0.1 at init, once became a non-leaf
    // of the autodiff graph and silently got no gradient.
    let device = Default::default();
    let policy = PolicyConfig::new(3, 2).init::<B>(&device);
    let obs = from_f64(&[0.1, -0.2, 0.3, 0.5, 0.4, -0.6], [2, 3], &device);
    let actions = from_f64(&[0.3, -0.1, 0.2, 0.2], [2, 2], &device);
    let grads = policy.log_prob(obs, actions).sum().backward();
    let g = grads_to_vec(&policy, &grads);
    let mut pos = 0;
    for (i, layer) in policy.mean.layers.iter().enumerate() {
        let n = layer.weight.shape().num_elements();
        assert!(
            g[pos..pos + n].iter().any(|x| *x != 0.0),
            "layer {i} weight has no gradient"
        );
        pos += n + layer.weight.dims()[1];
    }
    assert!(
        g[pos..].iter().all(|x| *x != 0.0),
        "log_std has no gradient"
    );
}

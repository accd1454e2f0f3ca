//! Behaviour cloning (`logo_algo::bc`): on pairs from a known linear-Gaussian
//! demonstrator, a linear policy recovers the demonstrator's mean and σ.

use logo_algo::bc::{self, InitConfig, InitKind};
use logo_nn::{Cpu, Kernels, Policy, PolicyConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const OBS: usize = 3;
const ACT: usize = 2;
const W: [[f64; OBS]; ACT] = [[0.8, -0.5, 0.3], [-0.2, 0.6, 0.9]];
const B: [f64; ACT] = [0.1, -0.4];
const SIGMA: [f64; ACT] = [0.2, 0.5];

fn demonstrator_mean(s: &[f64]) -> Vec<f64> {
    (0..ACT)
        .map(|j| B[j] + (0..OBS).map(|i| W[j][i] * s[i]).sum::<f64>())
        .collect()
}

/// `pairs` (s, a) with s ~ U(−1, 1)³ and a ~ N(W s + b, diag σ²).
fn demonstrations(pairs: usize) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut obs = Vec::new();
    let mut actions = Vec::new();
    for _ in 0..pairs {
        let s: Vec<f64> = (0..OBS).map(|_| rng.random_range(-1.0..1.0)).collect();
        let mean = demonstrator_mean(&s);
        for j in 0..ACT {
            // Box–Muller.
            let (u, v): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random());
            let noise = (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos();
            actions.push(mean[j] + SIGMA[j] * noise);
        }
        obs.extend(s);
    }
    (obs, actions)
}

/// A linear Gaussian policy (no hidden layer), σ = 1.
fn linear_policy() -> Policy<Kernels> {
    let device = Default::default();
    <Cpu as burn::tensor::backend::Backend>::seed(&device, 3);
    let module = PolicyConfig {
        obs_dim: OBS,
        act_dim: ACT,
        hidden: vec![],
        log_std_init: 0.0,
    }
    .init::<Cpu>(&device);
    Policy::from_module(&Kernels, &module)
}

fn settings(learn_std: bool) -> InitConfig {
    InitConfig {
        kind: InitKind::Bc,
        epochs: 60,
        minibatch: 64,
        learning_rate: 3e-3,
        learn_std,
        ..InitConfig::default()
    }
}

/// The largest gap between the fitted mean and the demonstrator's on a grid of states.
fn worst_mean_error(policy: &Policy<Kernels>) -> f64 {
    let acting = policy.acting(&Kernels);
    let grid = [-1.0, -0.5, 0.0, 0.5, 1.0];
    let mut worst: f64 = 0.0;
    for &x in &grid {
        for &y in &grid {
            for &z in &grid {
                let s = [x, y, z];
                let want = demonstrator_mean(&s);
                let got = acting.mean(&s);
                for j in 0..ACT {
                    worst = worst.max((got[j] - want[j]).abs());
                }
            }
        }
    }
    worst
}

#[test]
fn bc_recovers_a_linear_gaussian_demonstrator() {
    let (obs, actions) = demonstrations(4000);
    let start = linear_policy();
    assert!(worst_mean_error(&start) > 0.5, "the start is far from it");
    let mut rng = bc::generator(0);
    let (fitted, report) = bc::fit(&Kernels, &start, &obs, &actions, &settings(true), &mut rng);
    assert_eq!(report.pairs, 4000);
    assert_eq!(report.steps, 60 * 4000usize.div_ceil(64));
    assert!(report.loss_after < report.loss_before);
    // Standard error of each coefficient is about σ/√(N/3) ≤ 0.014; the grid's corners add
    // three of them up, and Adam's last steps a little.
    let error = worst_mean_error(&fitted);
    assert!(error < 0.06, "mean off by {error}");
    let sigma: Vec<f64> = fitted
        .acting(&Kernels)
        .log_std()
        .iter()
        .map(|l| l.exp())
        .collect();
    for j in 0..ACT {
        let relative = (sigma[j] - SIGMA[j]).abs() / SIGMA[j];
        assert!(
            relative < 0.05,
            "σ[{j}] = {} against {}",
            sigma[j],
            SIGMA[j]
        );
    }
    // The loss at the optimum is the demonstrator's own entropy, per pair.
    let entropy: f64 = SIGMA
        .iter()
        .map(|s| s.ln() + 0.5 * (1.0 + logo_nn::loss::LOG_2PI))
        .sum();
    assert!(
        (report.loss_after - entropy).abs() < 0.02,
        "loss {} against the entropy {entropy}",
        report.loss_after
    );
}

#[test]
fn bc_with_a_fixed_std_fits_the_mean_alone() {
    let (obs, actions) = demonstrations(4000);
    let start = linear_policy();
    let mut rng = bc::generator(0);
    let (fitted, _) = bc::fit(&Kernels, &start, &obs, &actions, &settings(false), &mut rng);
    assert_eq!(fitted.acting(&Kernels).log_std(), &[0.0, 0.0]);
    let error = worst_mean_error(&fitted);
    assert!(error < 0.06, "mean off by {error}");
}

#[test]
fn bc_is_a_function_of_its_seed() {
    let (obs, actions) = demonstrations(500);
    let fit = |seed| {
        let (p, _) = bc::fit(
            &Kernels,
            &linear_policy(),
            &obs,
            &actions,
            &settings(true),
            &mut bc::generator(seed),
        );
        p.params(&Kernels)
    };
    assert_eq!(fit(1), fit(1));
    assert_ne!(fit(1), fit(2));
}

#[test]
fn init_settings_are_checked() {
    let bad = [
        (
            InitConfig {
                epochs: 0,
                ..InitConfig::default()
            },
            "init.epochs",
        ),
        (
            InitConfig {
                minibatch: 0,
                ..InitConfig::default()
            },
            "init.minibatch",
        ),
        (
            InitConfig {
                learning_rate: f64::NAN,
                ..InitConfig::default()
            },
            "init.learning_rate",
        ),
    ];
    for (config, key) in bad {
        let e = config.validate().unwrap_err();
        assert!(e.message().contains(key), "{e}");
    }
}

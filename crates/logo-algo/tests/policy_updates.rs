//! The policy-update kinds and critic kinds: their losses against hand-computed values,
//! their stopping and adaptation rules, and each kind's step improving its own surrogate.

use burn::tensor::Tensor;
use logo_algo::critic::{CriticConfig, CriticKind, CriticSet};
use logo_algo::dapg::DemonstrationRows;
use logo_algo::policy_update::objective::{StepBatch, Surrogate, anchor, evaluate};
use logo_algo::policy_update::{
    NpgConfig, PolicyUpdateConfig, PpoClipConfig, PpoPenaltyConfig, StopReason, TrpoConfig,
    UpdateState, UpdateStats, fisher_rows,
};
use logo_nn::flat::{from_f64, to_f64, vec_to_params};
use logo_nn::loss::{clipped_surrogate, value_and_grad};
use logo_nn::{Cpu, Engine, Kernels, Policy, PolicyConfig, ValueNetConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// min(r·A, clip(r, 0.8, 1.2)·A) and its derivative in r, row by row, for ratios inside
/// and outside the clip range with positive and negative advantages.
#[test]
fn the_clipped_surrogate_and_its_gradient_match_hand_computation() {
    let device = Default::default();
    // (r, A, value, d value / d r)
    let rows = [
        (1.0, 2.0, 2.0, 2.0),    // inside: r·A
        (1.5, 2.0, 2.4, 0.0),    // A > 0, r above 1 + ε: clipped at 1.2·A, flat
        (0.5, 2.0, 1.0, 2.0),    // A > 0, r below 1 − ε: min picks r·A (pessimistic)
        (1.5, -2.0, -3.0, -2.0), // A < 0, r above 1 + ε: min picks r·A
        (0.5, -2.0, -1.6, 0.0),  // A < 0, r below 1 − ε: clipped at 0.8·A, flat
        (0.9, -1.0, -0.9, -1.0), // inside, A < 0
    ];
    let n = rows.len();
    let r: Vec<f64> = rows.iter().map(|x| x.0).collect();
    let a: Vec<f64> = rows.iter().map(|x| x.1).collect();
    let adv = from_f64::<Cpu, 1>(&a, [n], &device);
    let (value, grad) = value_and_grad(from_f64::<Cpu, 1>(&r, [n], &device), |r| {
        clipped_surrogate(r, Tensor::from_inner(adv.clone()), 0.2)
    });
    let value = to_f64(value)[0];
    let want_value: f64 = rows.iter().map(|x| x.2).sum::<f64>() / n as f64;
    assert!(
        (value - want_value).abs() < 1e-15,
        "{value} vs {want_value}"
    );
    for (i, (g, row)) in to_f64(grad).iter().zip(&rows).enumerate() {
        assert!(
            (g - row.3 / n as f64).abs() < 1e-15,
            "row {i}: {g} vs {}",
            row.3 / n as f64
        );
    }
}

#[test]
fn ppo_penalty_adapts_beta_around_the_target() {
    let config = PpoPenaltyConfig::default();
    let delta = 0.01;
    assert_eq!(config.adapt(1.0, 0.02, delta), 2.0, "KL > 1.5·δ: β doubles");
    assert_eq!(config.adapt(1.0, 0.005, delta), 0.5, "KL < δ/1.5: β halves");
    assert_eq!(config.adapt(1.0, 0.01, delta), 1.0, "in between: β stays");
    assert_eq!(config.adapt(4.0, 0.0151, delta), 8.0);
    assert_eq!(config.adapt(4.0, 0.0066, delta), 2.0);
}

/// A random policy and a batch from it with random advantages, on the kernels engine.
fn problem(rows: usize) -> (Kernels, Policy<Kernels>, StepBatch<Kernels>) {
    let (engine, policy, batch, _) = problem_on_host(rows);
    (engine, policy, batch)
}

/// [`problem`], with the batch's observations, actions and advantages on the host.
#[allow(clippy::type_complexity)]
fn problem_on_host(rows: usize) -> (Kernels, Policy<Kernels>, StepBatch<Kernels>, [Vec<f64>; 3]) {
    let engine = Kernels;
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let config = PolicyConfig {
        obs_dim: 4,
        act_dim: 2,
        hidden: vec![16, 16],
        log_std_init: -0.5,
    };
    let module = config.init::<Cpu>(&Default::default());
    let n_params = logo_nn::flat::params_to_vec(&module).len();
    let theta: Vec<f64> = (0..n_params).map(|_| rng.random_range(-0.4..0.4)).collect();
    let policy = Policy::from_module(&engine, &vec_to_params(module, &theta));
    let obs: Vec<f64> = (0..rows * 4).map(|_| rng.random_range(-2.0..2.0)).collect();
    let obs_rows = engine.rows(&obs, 4);
    let acting = policy.acting(&engine);
    let actions = acting.sample(&obs, &mut rng);
    let actions = engine.upload(&actions, [rows, 2]);
    let logp_old = policy.log_prob(&engine, &obs_rows, &actions);
    let advantages: Vec<f64> = (0..rows).map(|_| rng.random_range(-1.0..1.0)).collect();
    let batch = StepBatch {
        obs: obs_rows,
        actions,
        logp_old,
        advantages: engine.upload(&advantages, [rows]),
        rows,
        demonstration_rows: 0,
    };
    let actions = engine.download(batch.actions.clone());
    (engine, policy, batch, [obs, actions, advantages])
}

/// The problem's batch followed by `demos` demonstration pairs (actions 0.8 on every
/// dimension) with advantage `weight`, as DAPG's improvement step sees them.
fn with_demonstrations(
    rows: usize,
    demos: usize,
    weight: f64,
) -> (Kernels, Policy<Kernels>, StepBatch<Kernels>) {
    let (engine, policy, _, [obs, actions, advantages]) = problem_on_host(rows);
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let demo_obs: Vec<f64> = (0..demos * 4)
        .map(|_| rng.random_range(-2.0..2.0))
        .collect();
    let demonstrations = DemonstrationRows::new(demo_obs, vec![0.8; demos * 2], 4, 2);
    let batch = demonstrations.append(&engine, &policy, (&obs, &actions), &advantages, weight);
    assert_eq!(
        (batch.rows, batch.demonstration_rows),
        (rows + demos, demos)
    );
    (engine, policy, batch)
}

fn npg_step(
    engine: &Kernels,
    policy: &Policy<Kernels>,
    batch: &StepBatch<Kernels>,
) -> (Policy<Kernels>, UpdateStats) {
    let config = PolicyUpdateConfig::Npg(NpgConfig::default());
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    config.update(
        engine,
        policy,
        batch,
        0.01,
        &mut UpdateState::default(),
        &mut rng,
    )
}

/// NPG's step is TRPO's full step, taken without the line search.
#[test]
fn npg_takes_the_full_step_that_trpo_tries_first() {
    let (engine, policy, batch) = problem(1000);
    let (npg, stats) = npg_step(&engine, &policy, &batch);
    let trpo = PolicyUpdateConfig::Trpo(TrpoConfig::default());
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let (moved, trpo_stats) = trpo.update(
        &engine,
        &policy,
        &batch,
        0.01,
        &mut UpdateState::default(),
        &mut rng,
    );
    assert_eq!(
        trpo_stats.steps, 1.0,
        "TRPO accepted its full step here: {trpo_stats:?}"
    );
    assert_eq!(npg.params(&engine), moved.params(&engine));
    assert_eq!((stats.steps, stats.stop), (1.0, StopReason::Accepted));
    // Its KL is near δ, as the step size √(2δ / sᵀFs) aims.
    assert!(stats.kl > 0.005 && stats.kl < 0.02, "{stats:?}");
}

/// DAPG's rows shape the gradient, not F: with weight 0 they only rescale g (by
/// N / (N + M)), which the normalised step undoes; F over them too would change it.
#[test]
fn demonstration_rows_with_weight_zero_leave_the_npg_step_as_it_was() {
    let (engine, policy, batch) = problem(600);
    let (plain, _) = npg_step(&engine, &policy, &batch);
    let (engine2, policy2, augmented) = with_demonstrations(600, 300, 0.0);
    let (zero, stats) = npg_step(&engine2, &policy2, &augmented);
    let (a, b) = (plain.params(&engine), zero.params(&engine2));
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "largest difference {worst}");
    // The KL reported is the policy's own rows', as the plain step's.
    assert!(stats.kl > 0.005 && stats.kl < 0.02, "{stats:?}");
}

/// Weighted demonstration rows raise their log-likelihood under the step; the more so
/// the larger the weight.
#[test]
fn demonstration_rows_pull_the_policy_toward_the_demonstrations() {
    let likelihood = |weight: f64| {
        let (engine, policy, batch) = with_demonstrations(600, 300, weight);
        let (moved, _) = npg_step(&engine, &policy, &batch);
        let logp = moved.log_prob(&engine, &batch.obs, &batch.actions);
        engine.download(logp)[600..].iter().sum::<f64>() / 300.0
    };
    let (none, some, more) = (likelihood(0.0), likelihood(0.5), likelihood(2.0));
    assert!(some > none + 0.01, "{none} -> {some}");
    assert!(more > some, "{some} -> {more}");
}

/// What kind `config` maximises, as an evaluable surrogate.
fn own_surrogate(config: &PolicyUpdateConfig, state: &UpdateState) -> Surrogate {
    match config {
        PolicyUpdateConfig::Trpo(_) | PolicyUpdateConfig::Npg(_) => Surrogate::Ratio,
        PolicyUpdateConfig::ClipInTrpo(c) => Surrogate::Clipped {
            epsilon: c.clip_epsilon.unwrap_or(0.2),
        },
        PolicyUpdateConfig::PpoClip(c) => Surrogate::Clipped {
            epsilon: c.clip_epsilon,
        },
        PolicyUpdateConfig::PpoPenalty(c) => Surrogate::Penalised {
            beta: state.beta.unwrap_or(c.beta_init),
        },
    }
}

#[test]
fn every_kind_improves_its_own_surrogate_on_a_fixed_batch() {
    let (engine, policy, batch) = problem(2000);
    let start = anchor(&engine, &policy, &engine.trace(&policy.mean, &batch.obs));
    let clip_in_trpo = TrpoConfig {
        clip_epsilon: Some(0.2),
        ..TrpoConfig::default()
    };
    for config in [
        PolicyUpdateConfig::Trpo(TrpoConfig::default()),
        PolicyUpdateConfig::Npg(NpgConfig::default()),
        PolicyUpdateConfig::ClipInTrpo(clip_in_trpo),
        PolicyUpdateConfig::PpoClip(PpoClipConfig::default()),
        PolicyUpdateConfig::PpoPenalty(PpoPenaltyConfig::default()),
    ] {
        let mut state = UpdateState::default();
        let surrogate = own_surrogate(&config, &state);
        let (before, _) = evaluate(&engine, surrogate, &policy, &batch, &start);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let (moved, stats) = config.update(&engine, &policy, &batch, 0.01, &mut state, &mut rng);
        let (after, kl) = evaluate(&engine, surrogate, &moved, &batch, &start);
        assert!(
            after > before + 1e-4,
            "{}: surrogate {before} -> {after} ({stats:?})",
            config.kind()
        );
        assert!(
            (kl - stats.kl).abs() < 1e-12,
            "{}: KL reported {}",
            config.kind(),
            stats.kl
        );
        assert!(
            stats.step_norm > 0.0 && kl > 0.0,
            "{}: {stats:?}",
            config.kind()
        );
    }
}

#[test]
fn ppo_clip_stops_once_the_kl_passes_lambda_delta() {
    let (engine, policy, batch) = problem(2000);
    let config = PolicyUpdateConfig::PpoClip(PpoClipConfig {
        learning_rate: 3e-3,
        ..PpoClipConfig::default()
    });
    let run = |delta: f64| {
        let mut state = UpdateState::default();
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        config
            .update(&engine, &policy, &batch, delta, &mut state, &mut rng)
            .1
    };
    // A tight δ: stops early, in the first epoch, with its KL just past 1.5·δ.
    let tight = run(1e-4);
    assert_eq!(tight.stop, StopReason::KlBound, "{tight:?}");
    assert_eq!(tight.epochs, 1, "{tight:?}");
    assert!(tight.steps >= 1.0, "{tight:?}");
    // A loose δ: every epoch runs (10 epochs of ⌈2000 / 64⌉ = 32 minibatches).
    let loose = run(1e3);
    assert_eq!(loose.stop, StopReason::MaxEpochs, "{loose:?}");
    assert_eq!((loose.epochs, loose.steps), (10, 320.0), "{loose:?}");
    assert!(loose.kl > tight.kl);
}

/// With `kl_limit`, TRPO's line search backtracks past steps whose KL exceeds it.
#[test]
fn the_kl_limit_keeps_accepted_trpo_steps_within_it() {
    let (engine, policy, batch) = problem(500);
    let max_kl = 0.05;
    let run = |kl_limit| {
        let config = PolicyUpdateConfig::Trpo(TrpoConfig {
            kl_limit,
            ..TrpoConfig::default()
        });
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        config
            .update(
                &engine,
                &policy,
                &batch,
                max_kl,
                &mut UpdateState::default(),
                &mut rng,
            )
            .1
    };
    let (unlimited, limited) = (run(None), run(Some(0.25)));
    assert!(
        unlimited.kl > 0.25 * max_kl,
        "the test needs a step beyond the limit: {unlimited:?}"
    );
    assert!(
        limited.kl <= 0.25 * max_kl && limited.steps < unlimited.steps,
        "{limited:?}"
    );
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
fn a_fisher_fraction_outside_0_1_is_refused_naming_the_key() {
    for bad in [0.0, -0.5, 1.5, f64::NAN] {
        let config = PolicyUpdateConfig::Trpo(TrpoConfig {
            fisher_fraction: bad,
            ..TrpoConfig::default()
        });
        let err = config.validate("improvement").unwrap_err().to_string();
        assert!(err.contains("improvement.fisher_fraction"), "{err}");
    }
    let trpo_with_clip = PolicyUpdateConfig::Trpo(TrpoConfig {
        clip_epsilon: Some(0.2),
        ..TrpoConfig::default()
    });
    let err = trpo_with_clip
        .validate("guidance.update")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("guidance.update.clip_epsilon") && err.contains("clip-in-trpo"),
        "{err}"
    );
}

#[test]
fn the_twin_min_baseline_is_the_elementwise_minimum() {
    let engine = Kernels;
    let config = CriticConfig {
        kind: CriticKind::TwinMin,
        ..CriticConfig::default()
    };
    let device = Default::default();
    let nets: Vec<_> = (0..2)
        .map(|_| ValueNetConfig::new(3).init::<Cpu>(&device))
        .collect();
    let critic = CriticSet::new(&engine, &config, &nets);
    let obs = [0.5, -1.0, 2.0, -0.3, 0.8, 0.1, 1.5, 1.5, -2.0];
    let v1 = to_f64(nets[0].forward(from_f64::<Cpu, 2>(&obs, [3, 3], &device)));
    let v2 = to_f64(nets[1].forward(from_f64::<Cpu, 2>(&obs, [3, 3], &device)));
    assert_ne!(v1, v2, "two independently initialised nets");
    let base = critic.values(&engine, &engine.rows(&obs, 3));
    for i in 0..3 {
        assert!((base[i] - v1[i].min(v2[i])).abs() < 1e-15, "{i}");
    }
    // A single critic is its one net.
    let single = CriticSet::new(&engine, &CriticConfig::default(), &nets[..1]);
    let values = single.values(&engine, &engine.rows(&obs, 3));
    assert!(values.iter().zip(&v1).all(|(a, b)| (a - b).abs() < 1e-15));
}

/// 400 three-dimensional states and a smooth nonlinear return of each: a critic's batch.
fn regression_batch() -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let obs: Vec<f64> = (0..400 * 3).map(|_| rng.random_range(-1.0..1.0)).collect();
    let returns = obs.chunks(3).map(|o| 3.0 * o[0] - o[1] * o[2]).collect();
    (obs, returns)
}

/// Both fits lower the loss; twin nets are fitted each to the same returns.
#[test]
fn both_critic_fits_reduce_the_loss() {
    let engine = Kernels;
    let device = Default::default();
    let (obs, returns) = regression_batch();
    let n = returns.len();
    let rows = engine.rows(&obs, 3);
    for fit in [
        r#"method = "lbfgs""#,
        r#"method = "adam"
epochs = 20
learning_rate = 3e-3"#,
    ] {
        let config: CriticConfig = toml::from_str(&format!(
            "kind = \"twin-min\"\nhidden = [16, 16]\n[fit]\n{fit}"
        ))
        .unwrap();
        let nets: Vec<_> = (0..2).map(|_| config.net(3).init::<Cpu>(&device)).collect();
        let mut critic = CriticSet::new(&engine, &config, &nets);
        let mse = |c: &CriticSet<Kernels>| -> f64 {
            let v = c.values(&engine, &rows);
            v.iter()
                .zip(&returns)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                / n as f64
        };
        let before = mse(&critic);
        let loss = critic.fit(&engine, &rows, &returns, &mut ChaCha8Rng::seed_from_u64(0));
        let after = mse(&critic);
        assert!(after < 0.5 * before, "{fit}: MSE {before} -> {after}");
        assert!(loss.is_finite() && loss > 0.0);
    }
}

/// `[critic.fit] subsample`: the fit sees a random part of the batch, drawn from the fit's
/// stream (another stream, another part); the whole batch (the default) draws nothing.
#[test]
fn a_subsampled_critic_fit_sees_part_of_the_batch() {
    let engine = Kernels;
    let device = Default::default();
    let (obs, returns) = regression_batch();
    let rows = engine.rows(&obs, 3);
    let net = ValueNetConfig::new(3).init::<Cpu>(&device);
    let fitted = |subsample: &str, stream: u64| {
        let config: CriticConfig =
            toml::from_str(&format!("[fit]\nmethod = \"lbfgs\"\n{subsample}")).unwrap();
        config.validate("critic").unwrap();
        let mut critic = CriticSet::new(&engine, &config, std::slice::from_ref(&net));
        let mut rng = ChaCha8Rng::seed_from_u64(stream);
        critic.fit(&engine, &rows, &returns, &mut rng);
        (critic.values(&engine, &rows), rng.random::<u64>())
    };
    let (whole, after_whole) = fitted("", 0);
    assert_eq!(fitted("subsample = 1.0", 0), (whole.clone(), after_whole));
    assert_eq!(
        after_whole,
        ChaCha8Rng::seed_from_u64(0).random::<u64>(),
        "no draw"
    );
    let (half, _) = fitted("subsample = 0.5", 0);
    let (other_half, _) = fitted("subsample = 0.5", 1);
    assert_ne!(half, whole);
    assert_ne!(half, other_half);
    assert_eq!(
        fitted("subsample = 0.5", 0).0,
        half,
        "the same stream, the same part"
    );
    for bad in ["subsample = 0.0", "subsample = 1.5", "subsample = nan"] {
        let config: CriticConfig =
            toml::from_str(&format!("[fit]\nmethod = \"lbfgs\"\n{bad}")).unwrap();
        let err = config.validate("critic").unwrap_err().to_string();
        assert!(err.contains("critic.fit.subsample"), "{bad}: {err}");
    }
}

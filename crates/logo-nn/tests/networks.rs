//! Critic and discriminator behaviour.

use logo_nn::flat::{from_f64, to_f64};
use logo_nn::{Cpu, DiscriminatorConfig, ValueNetConfig};

#[test]
fn the_censored_discriminator_ignores_the_hidden_observation_dims() {
    let device = Default::default();
    let disc = DiscriminatorConfig::new(2, 1).init::<Cpu>(&device);
    let obs_a = from_f64::<Cpu, 2>(&[0.1, 0.2, 5.0, -3.0, 0.3, 0.4, -7.0, 2.0], [2, 4], &device);
    let obs_b = from_f64::<Cpu, 2>(&[0.1, 0.2, -1.0, 9.0, 0.3, 0.4, 0.0, 0.0], [2, 4], &device);
    let act = from_f64::<Cpu, 2>(&[0.5, -0.5], [2, 1], &device);
    let da = to_f64(disc.forward(obs_a.clone(), act.clone()));
    assert_eq!(da, to_f64(disc.forward(obs_b, act.clone())));
    assert!(da.iter().all(|d| *d > 0.0 && *d < 1.0));
    // −log D, computed without forming D, agrees with it.
    let reward = to_f64(disc.guidance_reward(obs_a.clone(), act.clone()));
    for (r, d) in reward.iter().zip(&da) {
        assert!((r + d.ln()).abs() < 1e-14, "{r} {d}");
    }
    // But the dims it sees do matter.
    let obs_c = from_f64::<Cpu, 2>(
        &[1.1, 0.2, 5.0, -3.0, 0.3, -0.4, -7.0, 2.0],
        [2, 4],
        &device,
    );
    assert_ne!(da, to_f64(disc.forward(obs_c, act)));
}

#[test]
fn the_twin_critic_baseline_is_the_elementwise_minimum() {
    let device = Default::default();
    let twin = ValueNetConfig::new(3).init_twin::<Cpu>(&device);
    let obs = from_f64::<Cpu, 2>(
        &[0.5, -1.0, 2.0, -0.3, 0.8, 0.1, 1.5, 1.5, -2.0],
        [3, 3],
        &device,
    );
    let v1 = to_f64(twin.v1.forward(obs.clone()));
    let v2 = to_f64(twin.v2.forward(obs.clone()));
    assert_ne!(v1, v2, "two independently initialised nets");
    let base = to_f64(twin.baseline(obs));
    for i in 0..3 {
        assert_eq!(base[i], v1[i].min(v2[i]));
    }
}

#[test]
fn softplus_is_stable_and_float64_exact() {
    let device = Default::default();
    let x = from_f64::<Cpu, 1>(&[-800.0, -30.0, -1e-3, 0.0, 0.7, 30.0, 800.0], [7], &device);
    let y = to_f64(logo_nn::discriminator::softplus(x));
    let want = [
        0.0,
        (-30f64).exp().ln_1p(),
        (-1e-3f64).exp().ln_1p(),
        2f64.ln(),
        0.7f64.exp().ln_1p(),
        30.0 + (-30f64).exp().ln_1p(),
        800.0,
    ];
    for (a, b) in y.iter().zip(want) {
        assert!((a - b).abs() <= 1e-15 * b.abs().max(1e-300), "{a} vs {b}");
    }
}

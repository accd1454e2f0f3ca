//! The discriminator and the losses on its logits.

use logo_nn::flat::{from_f64, to_f64};
use logo_nn::loss::{binary_cross_entropy, guidance_reward, softplus};
use logo_nn::{Cpu, DiscriminatorConfig};

#[test]
fn the_censored_discriminator_ignores_the_hidden_observation_dims() {
    let device = Default::default();
    let disc = DiscriminatorConfig::new(2, 1).init::<Cpu>(&device);
    let obs_a = from_f64::<Cpu, 2>(&[0.1, 0.2, 5.0, -3.0, 0.3, 0.4, -7.0, 2.0], [2, 4], &device);
    let obs_b = from_f64::<Cpu, 2>(&[0.1, 0.2, -1.0, 9.0, 0.3, 0.4, 0.0, 0.0], [2, 4], &device);
    let act = from_f64::<Cpu, 2>(&[0.5, -0.5], [2, 1], &device);
    let la = disc.logits(obs_a.clone(), act.clone());
    assert_eq!(to_f64(la.clone()), to_f64(disc.logits(obs_b, act.clone())));
    // −log D, computed without forming D = σ(logit), agrees with it.
    let reward = to_f64(guidance_reward(la.clone()));
    for (r, l) in reward.iter().zip(to_f64(la.clone())) {
        let d = 1.0 / (1.0 + (-l).exp());
        assert!((r + d.ln()).abs() < 1e-14, "{r} {d}");
    }
    // But the dims it sees do matter.
    let obs_c = from_f64::<Cpu, 2>(
        &[1.1, 0.2, 5.0, -3.0, 0.3, -0.4, -7.0, 2.0],
        [2, 4],
        &device,
    );
    assert_ne!(to_f64(la), to_f64(disc.logits(obs_c, act)));
}

#[test]
fn binary_cross_entropy_is_minus_log_sigmoid_of_the_label() {
    let device = Default::default();
    let logits = [-3.0, -0.2, 0.0, 1.5, 40.0];
    let t = from_f64::<Cpu, 1>(&logits, [5], &device);
    let sigmoid = |l: f64| 1.0 / (1.0 + (-l).exp());
    let one: f64 = logits.iter().map(|&l| -sigmoid(l).ln()).sum::<f64>() / 5.0;
    // 1 − σ(l) = e^{−l} / (1 + e^{−l}), which does not round to 0 at l = 40.
    let zero: f64 = logits
        .iter()
        .map(|&l| -((-l).exp() / (1.0 + (-l).exp())).ln())
        .sum::<f64>()
        / 5.0;
    let got_one = to_f64(binary_cross_entropy(t.clone(), true))[0];
    let got_zero = to_f64(binary_cross_entropy(t, false))[0];
    assert!((got_one - one).abs() < 1e-12, "{got_one} vs {one}");
    assert!(
        (got_zero - zero).abs() < 1e-12 * zero,
        "{got_zero} vs {zero}"
    );
}

#[test]
fn softplus_is_stable_and_float64_exact() {
    let device = Default::default();
    let x = from_f64::<Cpu, 1>(&[-800.0, -30.0, -1e-3, 0.0, 0.7, 30.0, 800.0], [7], &device);
    let y = to_f64(softplus(x));
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

/// The reference initialises the discriminator's output layer ×0.1 with zero bias
/// (docs/reference.md), so D starts near ½; "uniform" keeps PyTorch's default init.
#[test]
fn the_discriminator_output_layer_starts_as_the_reference_s() {
    use logo_nn::DiscriminatorInit;
    use logo_nn::flat::params_to_vec;
    let device = Default::default();
    let mut config = DiscriminatorConfig::new(11, 3);
    assert_eq!(config.init, DiscriminatorInit::Reference, "the default");
    let bound = 1.0 / (128f64).sqrt(); // U(±1/√fan_in) before the scaling
    let mut output_layer = |init| {
        config.init = init;
        let disc = config.init::<Cpu>(&device);
        let last = disc.net.layers.last().unwrap();
        (
            to_f64(last.weight.val()),
            to_f64(last.bias.as_ref().unwrap().val()),
            params_to_vec(&disc.net),
        )
    };
    let (w, b, _) = output_layer(DiscriminatorInit::Reference);
    assert!(
        w.iter().all(|w| w.abs() <= 0.1 * bound),
        "weights within 0.1/√128"
    );
    assert!(
        w.iter().any(|w| w.abs() > 0.05 * bound),
        "scaled, not zeroed"
    );
    assert_eq!(b, vec![0.0]);
    let (w, b, _) = output_layer(DiscriminatorInit::Uniform);
    assert!(
        w.iter().any(|w| w.abs() > 0.1 * bound),
        "PyTorch's default range"
    );
    assert_ne!(b, vec![0.0]);
}

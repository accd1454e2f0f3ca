//! GAIL and POfD as configurations: the improvement step's reward mixes the env's with
//! the discriminator's −log D (`[reward]`), and `[guidance] step = false` leaves out
//! LOGO's second step. DAPG: `npg` from behaviour cloning with `[demonstration_rows]`.
//! Each test can fail: it compares whole checkpoints' tensors.

use std::path::Path;

use logo_algo::config::RewardConfig;
use logo_algo::discriminator::DiscriminatorTrainer;
use logo_algo::{TrainConfig, Trainer};
use logo_data::Demonstrations;
use logo_nn::{Checkpoint, Cpu, DiscriminatorConfig, DiscriminatorInit, Kernels};
use logo_testkit::{Tiny, scratch, workspace};

/// `tiny` trained to its end in `dir`; the final checkpoint's tensors by name.
fn train(tiny: Tiny, dir: &Path) -> Vec<(String, Vec<f64>)> {
    let path = tiny
        .lbfgs(3)
        .with("iterations = 3\nseed = 5\nnum_envs = 2\nthreads = 1")
        .write(&dir.join("config.toml"));
    let mut trainer = Trainer::new(Kernels, TrainConfig::load(&path).unwrap(), dir).unwrap();
    while !trainer.done() {
        trainer.step().unwrap();
    }
    drop(trainer);
    let ckpt = Checkpoint::load(&dir.join("checkpoint.safetensors")).unwrap();
    let mut names: Vec<String> = ckpt.tensor_names().map(str::to_string).collect();
    names.sort();
    names
        .into_iter()
        .map(|n| {
            let values = ckpt.tensor(&n).unwrap().1.to_vec();
            (n, values)
        })
        .collect()
}

fn demos() -> String {
    workspace()
        .join("data/logo/inverted_double_pendulum")
        .display()
        .to_string()
}

/// `[guidance]` with the discriminator alone, and `[reward]`'s weights.
fn discriminator_reward(tiny: Tiny, env: f64, discriminator: f64) -> Tiny {
    tiny.set("guidance.demos", demos())
        .set("guidance.step", false)
        .set("reward.env", env)
        .set("reward.discriminator", discriminator)
}

fn without(tensors: &[(String, Vec<f64>)], prefix: &str) -> Vec<(String, Vec<f64>)> {
    tensors
        .iter()
        .filter(|(n, _)| !n.starts_with(prefix))
        .cloned()
        .collect()
}

#[test]
fn pofd_with_lambda_zero_trains_as_trpo() {
    let trpo = train(Tiny::trpo(), &scratch("trpo"));
    let pofd = train(
        discriminator_reward(Tiny::trpo(), 1.0, 0.0),
        &scratch("pofd0"),
    );
    // The same policy and critic, bit for bit; POfD also keeps its discriminator.
    assert!(pofd.iter().any(|(n, _)| n.starts_with("discriminator.")));
    assert_eq!(without(&pofd, "discriminator."), trpo);
    // With λ₁ > 0 the discriminator's reward moves the policy.
    let pofd = train(
        discriminator_reward(Tiny::trpo(), 1.0, 0.5),
        &scratch("pofd"),
    );
    assert_ne!(without(&pofd, "discriminator."), trpo);
}

#[test]
fn pofd_weighs_the_discriminator_by_lambda1() {
    let pofd = train(
        discriminator_reward(Tiny::trpo(), 1.0, 0.5),
        &scratch("pofd-half"),
    );
    let heavier = train(
        discriminator_reward(Tiny::trpo(), 1.0, 1.0),
        &scratch("pofd1"),
    );
    // A weight read as 1 whatever its value would leave them equal.
    assert_ne!(
        without(&heavier, "discriminator."),
        without(&pofd, "discriminator.")
    );
}

/// The improvement step's reward: env·r + λ·(−log D), each weight applied.
#[test]
fn the_mixed_reward_weighs_each_source() {
    let mix = RewardConfig {
        env: 2.0,
        discriminator: 0.5,
    };
    assert_eq!(mix.mix(&[1.0, 3.0], &[10.0, 20.0]), vec![7.0, 16.0]);
}

#[test]
fn gail_does_not_read_the_env_reward() {
    // Dense Hopper, and the same task whose reward is never paid (a 1000 m threshold):
    // the same states, actions and discriminator, so GAIL trains to the same tensors.
    let hopper_demos = workspace().join("data/logo/hopper").display().to_string();
    let gail = |env: &str, name: &str| {
        let tiny = Tiny::trpo()
            .with(env)
            .set("guidance.demos", hopper_demos.as_str())
            .set("guidance.step", false)
            .set("reward.env", 0.0)
            .set("reward.discriminator", 1.0);
        train(tiny, &scratch(name))
    };
    let paid = gail("env = \"Hopper-v4\"", "gail-dense");
    let unpaid = gail(
        "[env]\nid = \"Hopper-v4\"\nsparse = { kind = \"distance\", threshold = 1000.0 }",
        "gail-unpaid",
    );
    assert_eq!(paid, unpaid);
    // TRPO on the same two tasks does read it.
    let trpo = |env: &str, name: &str| train(Tiny::trpo().with(env), &scratch(name));
    assert_ne!(
        trpo("env = \"Hopper-v4\"", "trpo-dense"),
        trpo(
            "[env]\nid = \"Hopper-v4\"\nsparse = { kind = \"distance\", threshold = 1000.0 }",
            "trpo-unpaid"
        )
    );
}

#[test]
fn without_the_guidance_step_logo_keys_are_refused_and_required_with_it() {
    let dir = scratch("gail-keys");
    let bad = discriminator_reward(Tiny::trpo(), 0.0, 1.0).set("guidance.delta0", 0.1);
    let e = TrainConfig::load(&bad.write(&dir.join("a.toml"))).unwrap_err();
    assert!(
        e.to_string()
            .contains("guidance.delta0 belongs to the guidance step"),
        "{e}"
    );
    let missing = Tiny::trpo()
        .set("guidance.demos", demos())
        .set("guidance.alpha", 0.9)
        .set("guidance.warmup", 0);
    let e = TrainConfig::load(&missing.write(&dir.join("b.toml"))).unwrap_err();
    assert!(e.to_string().contains("guidance.delta0 is required"), "{e}");
    let no_discriminator = Tiny::trpo().set("reward.discriminator", 1.0);
    let e = TrainConfig::load(&no_discriminator.write(&dir.join("c.toml"))).unwrap_err();
    assert!(
        e.to_string()
            .contains("reward.discriminator needs a discriminator"),
        "{e}"
    );
    let nothing = discriminator_reward(Tiny::trpo(), 0.0, 0.0);
    let e = TrainConfig::load(&nothing.write(&dir.join("d.toml"))).unwrap_err();
    assert!(e.to_string().contains("both 0"), "{e}");
    // The names runs go by.
    let name = |tiny: Tiny, file: &str| {
        TrainConfig::load(&tiny.write(&dir.join(file)))
            .unwrap()
            .algorithm()
    };
    assert_eq!(
        name(discriminator_reward(Tiny::trpo(), 0.0, 1.0), "g.toml"),
        "GAIL"
    );
    assert_eq!(
        name(discriminator_reward(Tiny::trpo(), 1.0, 0.1), "p.toml"),
        "POfD"
    );
    assert_eq!(name(Tiny::logo(), "l.toml"), "LOGO");
}

#[test]
fn minus_log_d_rewards_demonstration_like_pairs_more() {
    let demos = Demonstrations::load(
        &workspace().join("data/logo/inverted_double_pendulum"),
        "InvertedDoublePendulum-v4",
        11,
        1,
    )
    .unwrap();
    let device = Default::default();
    let module = DiscriminatorConfig {
        observe: 11,
        act_dim: 1,
        hidden: vec![16, 16],
        init: DiscriminatorInit::Reference,
    }
    .init::<Cpu>(&device);
    let mut d = DiscriminatorTrainer::new(&Kernels, &module, &demos, 3e-3, 1);
    // "Policy" pairs: the demonstrations' states with the opposite actions.
    let flipped: Vec<f64> = demos.actions.iter().map(|a| -a - 1.0).collect();
    let policy = d.inputs(&Kernels, &demos.obs, &flipped);
    let demo = d.inputs(&Kernels, &demos.obs, &demos.actions);
    for _ in 0..200 {
        d.update(&Kernels, &policy);
    }
    let mean = |v: Vec<f64>| v.iter().sum::<f64>() / v.len() as f64;
    let on_demos = mean(d.rewards(&Kernels, &demo));
    let on_policy = mean(d.rewards(&Kernels, &policy));
    assert!(
        on_demos > on_policy + 0.5,
        "−log D: {on_demos} on the demonstrations against {on_policy} on the policy's pairs"
    );
}

/// NPG from behaviour cloning on the IDP demonstrations; with `lambda0`, DAPG.
fn npg_from_bc(lambda0: Option<f64>) -> Tiny {
    let tiny = Tiny::trpo()
        .set("init.kind", "bc")
        .set("init.demos", demos())
        .set("init.epochs", 2)
        .set("improvement.kind", "npg");
    match lambda0 {
        Some(lambda0) => tiny
            .set("demonstration_rows.lambda0", lambda0)
            .set("demonstration_rows.lambda1", 0.9),
        None => tiny,
    }
}

#[test]
fn dapg_with_lambda0_zero_is_npg_from_the_same_clone() {
    let npg = train(npg_from_bc(None), &scratch("npg"));
    let dapg0 = train(npg_from_bc(Some(0.0)), &scratch("dapg0"));
    assert_eq!(dapg0, npg);
    // With λ0 > 0 the demonstration rows move the policy.
    let dir = scratch("dapg");
    let dapg = train(npg_from_bc(Some(1.0)), &dir);
    assert_ne!(dapg, npg);
    // metrics.csv says what weight they had: λ0·λ1^k·max Â > 0 (Â normalised).
    let metrics = std::fs::read_to_string(dir.join("metrics.csv")).unwrap();
    let mut lines = metrics.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = header.iter().position(|c| *c == "demo_weight").unwrap();
    for line in lines {
        let weight: f64 = line.split(',').nth(column).unwrap().parse().unwrap();
        assert!(weight > 0.0 && weight < 10.0, "{line}");
    }
}

#[test]
fn demonstration_rows_need_npg_and_demonstrations() {
    let dir = scratch("dapg-refused");
    let refused = |tiny: Tiny| {
        let path = tiny.write(&dir.join("config.toml"));
        TrainConfig::load(&path).unwrap_err().to_string()
    };
    let trpo = npg_from_bc(Some(0.1)).set("improvement.kind", "trpo");
    assert!(refused(trpo).contains("kind = \"npg\", not \"trpo\""));
    let no_demos = Tiny::trpo()
        .set("improvement.kind", "npg")
        .set("demonstration_rows.lambda0", 0.1)
        .set("demonstration_rows.lambda1", 0.9);
    assert!(refused(no_demos).contains("demonstration_rows needs demonstrations"));
    let missing = npg_from_bc(None).set("demonstration_rows.lambda0", 0.1);
    assert!(refused(missing).contains("lambda1"));
    let decay = npg_from_bc(Some(0.1)).set("demonstration_rows.lambda1", 1.5);
    assert!(refused(decay).contains("lambda1 must be in [0, 1]"));
}

/// `skip_improvement_without_reward` skips TRPO's step on a batch without env reward, but
/// not DAPG's: its demonstration rows are the step's signal then.
#[test]
fn the_rewardless_skip_keeps_dapgs_step() {
    let hopper_demos = workspace().join("data/logo/hopper").display().to_string();
    let unpaid = "[env]\nid = \"Hopper-v4\"\nsparse = { kind = \"distance\", threshold = 1000.0 }";
    let stops = |tiny: Tiny, name: &str| {
        let dir = scratch(name);
        train(
            tiny.with(unpaid)
                .set("skip_improvement_without_reward", true),
            &dir,
        );
        let metrics = std::fs::read_to_string(dir.join("metrics.csv")).unwrap();
        let mut lines = metrics.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let column = header.iter().position(|c| *c == "update_stop").unwrap();
        lines
            .map(|l| l.split(',').nth(column).unwrap().to_string())
            .collect::<Vec<_>>()
    };
    let trpo = stops(Tiny::trpo(), "skip-trpo");
    assert!(trpo.iter().all(|s| s == "no-reward"), "{trpo:?}");
    let dapg = Tiny::trpo()
        .set("init.demos", hopper_demos.as_str())
        .set("init.epochs", 2)
        .set("algorithm.name", "dapg");
    let dapg = stops(dapg, "skip-dapg");
    assert!(dapg.iter().all(|s| s == "accepted"), "{dapg:?}");
}

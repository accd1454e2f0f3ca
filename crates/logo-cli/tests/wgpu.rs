//! burn's wgpu backend against ndarray, both float32, and a short training run on wgpu
//! that `logo eval` then loads. Built only with `--features wgpu`; on a machine without a
//! GPU, Mesa's lavapipe (Vulkan on the CPU, `mesa-vulkan-drivers`) is the device
//! (scripts/test.sh installs it). Without any Vulkan driver the tests are skipped, unless
//! LOGO_REQUIRE_WGPU is set (CI sets it).
#![cfg(feature = "wgpu")]

use logo_testkit::{Tiny, max_relative_error};
use std::process::Command;

use burn::tensor::Tensor;
use logo_algo::critic::ValueObjective;
use logo_algo::discriminator::DiscriminatorTrainer;
use logo_algo::lbfgs::Objective;
use logo_algo::policy_update::objective::{StepBatch, Surrogate, anchor, evaluate, gradient};
use logo_data::Demonstrations;
use logo_nn::burn::backend::Wgpu;
use logo_nn::{
    BurnEngine, Cpu, Cpu32, DiscriminatorConfig, Engine, FisherKind, FisherOperator, Policy,
    PolicyConfig, ValueNetConfig,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Whether a Vulkan driver is installed (lavapipe or a GPU's).
fn vulkan() -> bool {
    let found = ["/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"]
        .iter()
        .filter_map(|d| std::fs::read_dir(d).ok())
        .flatten()
        .any(|e| e.is_ok());
    if !found {
        assert!(
            std::env::var_os("LOGO_REQUIRE_WGPU").is_none(),
            "LOGO_REQUIRE_WGPU is set but no Vulkan driver is installed (mesa-vulkan-drivers)"
        );
        eprintln!("skipped: no Vulkan driver (install mesa-vulkan-drivers for lavapipe)");
    }
    found
}

/// Everything one LOGO iteration computes through the seam, on one engine.
#[derive(Debug)]
struct Iteration {
    means: Vec<f64>,
    log_probs: Vec<f64>,
    surrogate: f64,
    gradient: Vec<f64>,
    fisher_product: Vec<f64>,
    critic_loss: f64,
    critic_gradient: Vec<f64>,
    discriminator_losses: Vec<f64>,
}

fn iteration<E: Engine>(engine: &E) -> Iteration {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let (n, obs_dim, act_dim) = (600, 11, 3);
    let mut random =
        |k: usize, s: f64| -> Vec<f64> { (0..k).map(|_| rng.random_range(-s..s)).collect() };
    let (obs, actions, advantages) = (
        random(n * obs_dim, 1.5),
        random(n * act_dim, 1.0),
        random(n, 1.0),
    );
    let returns = random(n, 5.0);
    let device = Default::default();
    // The same initial weights on both engines.
    <Cpu as burn::tensor::backend::Backend>::seed(&device, 7);
    let module = PolicyConfig {
        obs_dim,
        act_dim,
        hidden: vec![32, 32],
        log_std_init: -0.3,
    }
    .init::<Cpu>(&device);
    let policy = Policy::from_module(engine, &module);
    let rows = engine.rows(&obs, obs_dim);
    let actions_t = engine.upload(&actions, [n, act_dim]);
    let logp = policy.log_prob(engine, &rows, &actions_t);
    let batch = StepBatch {
        obs: rows.clone(),
        actions: actions_t,
        logp_old: logp.clone() - 0.1,
        advantages: engine.upload(&advantages, [n]),
        rows: n,
        demonstration_rows: 0,
    };
    let trace = engine.trace(&policy.mean, &rows);
    let start = anchor(engine, &policy, &trace);
    let (surrogate, gradient) = gradient(engine, Surrogate::Ratio, &policy, &trace, &batch, &start);
    let (again, _) = evaluate(engine, Surrogate::Ratio, &policy, &batch, &start);
    assert!((again - surrogate).abs() < 1e-5 * surrogate.abs());
    let v: Vec<f64> = (0..policy.num_params())
        .map(|k| (k as f64 * 0.3).sin())
        .collect();
    let fisher = FisherOperator::new(engine, &policy, &trace, n, 0.01, FisherKind::Exact);

    let critic = ValueNetConfig {
        obs_dim,
        hidden: vec![32, 32],
    }
    .init::<Cpu>(&device);
    let dims = critic.net.dims();
    let targets: Tensor<E::B, 2> = engine.upload(&returns, [n, 1]);
    let mut objective = ValueObjective::new(engine, &dims, &rows, &targets, 1e-3);
    let critic_loss = objective.loss(&logo_nn::flat::params_to_vec(&critic));
    let critic_gradient = objective.gradient();

    let demos = Demonstrations {
        obs_dim,
        act_dim,
        obs: random(200 * obs_dim, 1.0),
        actions: random(200 * act_dim, 1.0),
        source: "test".into(),
    };
    let disc = DiscriminatorConfig {
        hidden: vec![32, 32],
        ..DiscriminatorConfig::new(obs_dim, act_dim)
    }
    .init::<Cpu>(&device);
    let mut trainer = DiscriminatorTrainer::new(engine, &disc, &demos, 3e-4, 1);
    let inputs = trainer.inputs(engine, &obs, &actions);
    let discriminator_losses = (0..3).map(|_| trainer.update(engine, &inputs)).collect();
    Iteration {
        means: engine.download(policy.means(engine, &rows)),
        log_probs: engine.download(logp),
        surrogate,
        gradient,
        fisher_product: fisher.apply(&v),
        critic_loss,
        critic_gradient,
        discriminator_losses,
    }
}

/// float32 on wgpu and on ndarray run the same operations in other orders (reductions,
/// fused kernels): they agree to a few float32 ulps of each quantity's scale (measured on
/// lavapipe: 1e-7 to 4e-7 for everything, 1.6e-6 for the surrogate's gradient).
#[test]
fn one_logo_iteration_on_wgpu_matches_ndarray_at_f32() {
    if !vulkan() {
        return;
    }
    let ndarray = iteration(&BurnEngine::<Cpu32>::new(Default::default(), "ndarray f32"));
    let wgpu = iteration(&BurnEngine::<Wgpu>::new(Default::default(), "wgpu f32"));
    for (what, a, b, tol) in [
        ("policy means", &wgpu.means, &ndarray.means, 1e-5),
        ("log-probs", &wgpu.log_probs, &ndarray.log_probs, 1e-5),
        (
            "surrogate",
            &vec![wgpu.surrogate],
            &vec![ndarray.surrogate],
            1e-5,
        ),
        (
            "surrogate gradient",
            &wgpu.gradient,
            &ndarray.gradient,
            1e-4,
        ),
        ("F·v", &wgpu.fisher_product, &ndarray.fisher_product, 1e-4),
        (
            "critic loss",
            &vec![wgpu.critic_loss],
            &vec![ndarray.critic_loss],
            1e-5,
        ),
        (
            "critic gradient",
            &wgpu.critic_gradient,
            &ndarray.critic_gradient,
            1e-4,
        ),
        (
            "discriminator losses",
            &wgpu.discriminator_losses,
            &ndarray.discriminator_losses,
            1e-5,
        ),
    ] {
        let err = max_relative_error(a, b);
        assert!(
            err <= tol,
            "{what}: wgpu vs ndarray {err:e} (tolerance {tol:e})"
        );
    }
}

/// `logo train --backend wgpu` for 2 iterations writes a checkpoint that `logo eval`
/// (which acts on the host copy) loads, that training resumes from on wgpu when no engine
/// is named, and on the CPU kernels when `--engine kernels` is.
#[test]
fn a_wgpu_run_is_evaluated_and_resumed_on_the_cpu() {
    if !vulkan() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("logo-wgpu-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let config = Tiny::logo()
        .lbfgs(5)
        .with("[guidance]\ndiscriminator_hidden = [16, 16]")
        .write(&dir.join("tiny.toml"));
    let logo = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_logo"))
            .args(args)
            .env("XDG_RUNTIME_DIR", &dir)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "logo {}: {text}{}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        );
        text
    };
    let run = dir.join("run");
    // No --dtype: the GPU backends have float32 only, and it is taken.
    let trained = logo(&[
        "train",
        "--config",
        config.to_str().unwrap(),
        "--backend",
        "wgpu",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(
        trained.contains("burn wgpu f32") && trained.contains("done in"),
        "{trained}"
    );
    let checkpoint = run.join("checkpoint.safetensors");
    let ckpt = logo_nn::Checkpoint::load(&checkpoint).unwrap();
    assert_eq!(ckpt.meta.extra["engine"], "burn wgpu f32");
    let evaluated = logo(&[
        "eval",
        "--checkpoint",
        checkpoint.to_str().unwrap(),
        "--episodes",
        "2",
    ]);
    assert!(
        evaluated.contains("InvertedDoublePendulum-v4") && evaluated.contains("dense return"),
        "{evaluated}"
    );
    // Without engine flags a resume stays on the engine the run last trained on...
    let resumed = logo(&[
        "train",
        "--resume",
        run.to_str().unwrap(),
        "--iterations",
        "3",
    ]);
    assert!(
        resumed.contains("burn wgpu f32") && resumed.contains("[   3/3]"),
        "{resumed}"
    );
    // ...and `--engine` moves it to the CPU kernels.
    let moved = logo(&[
        "train",
        "--resume",
        run.to_str().unwrap(),
        "--iterations",
        "4",
        "--engine",
        "kernels",
    ]);
    assert!(
        moved.contains("kernels f64") && moved.contains("[   4/4]"),
        "{moved}"
    );
}

/// With no adapter to run on (here: the Vulkan loader pointed at no driver), `--backend
/// wgpu` is a one-line error naming what to install, not a panic inside burn's runtime;
/// `--dtype f64` on it is refused before anything starts.
#[test]
fn no_wgpu_adapter_is_an_error_naming_the_driver_to_install() {
    if !vulkan() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("logo-wgpu-none-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let config = Tiny::trpo()
        .set("iterations", 1)
        .write(&dir.join("tiny.toml"));
    let train = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_logo"))
            .args(["train", "--config", config.to_str().unwrap()])
            .args([
                "--out",
                dir.join("run").to_str().unwrap(),
                "--backend",
                "wgpu",
            ])
            .args(extra)
            .env("VK_ICD_FILENAMES", dir.join("no-such-driver.json"))
            .env("XDG_RUNTIME_DIR", &dir)
            .output()
            .unwrap()
    };
    let out = train(&[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("wgpu found no adapter")
            && stderr.contains("mesa-vulkan-drivers")
            && !stderr.contains("panicked"),
        "{stderr}"
    );
    let out = train(&["--dtype", "f64"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success()
            && stderr.contains("--dtype f64: the GPU backends compute in float32"),
        "{stderr}"
    );
}

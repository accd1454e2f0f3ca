//! Every config under configs/ loads, names a real env, and its demonstrations fit it;
//! the algorithm folders hold the four sparse envs each and differ only in their kinds.

use std::path::Path;

use logo_algo::algorithms::{Guided, METHODS, Start, comparable, configure};
use logo_algo::critic::CriticFit;
use logo_algo::{Dtype, TrainConfig};
use logo_data::Demonstrations;
use logo_envs::{EnvFactory, EnvOptions};

/// The table's methods that are configs of the trainer, by what they take of LOGO's
/// guidance: its variants (the guidance step) and the rest (TRPO's config with a reward,
/// an initialisation or a step kind of their own).
fn methods(step: bool) -> Vec<&'static str> {
    METHODS
        .iter()
        .filter(|m| m.command.is_none() && (m.guided == Guided::Step) == step)
        .map(|m| m.name)
        .collect()
}
const ENVS: [&str; 4] = [
    "hopper",
    "walker2d",
    "halfcheetah",
    "inverted_double_pendulum",
];

#[test]
fn every_shipped_config_loads_and_its_demos_fit_the_env() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut checked = 0;
    for entry in std::fs::read_dir(root.join("configs")).unwrap() {
        let folder = entry.unwrap().path();
        let algo = folder.file_name().unwrap().to_string_lossy().into_owned();
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            let config = TrainConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let spec = config.env.factory().unwrap().spec().clone();
            EnvFactory::new(&config.eval_env_id(), &EnvOptions::default()).unwrap();
            // A method's folder has [guidance] where the method takes the discriminator or
            // the guidance step; the reference configs are LOGO's.
            let guided = match logo_algo::algorithms::method(&algo) {
                Some(m) => Some(m.guided != Guided::No),
                None => (algo == "reference").then_some(true),
            };
            if let Some(guided) = guided {
                assert_eq!(config.guidance.is_some(), guided, "{}", path.display());
            }
            if let Some(demos) = config.guidance.as_ref().and_then(|g| g.demos.as_ref()) {
                let d = Demonstrations::load(demos, &spec.id, spec.obs_dim, spec.act_dim)
                    .unwrap_or_else(|e| panic!("{e}"));
                assert!(d.len() > 100, "{}", path.display());
            }
            checked += 1;
        }
    }
    let listed = logo_algo::presets::names().len();
    assert!(checked >= listed * ENVS.len() + 2, "{checked}");
}

/// The variants of one env differ from `configs/logo/<env>.toml` in their policy-update
/// and critic kinds only (and, for PPO and TRPO alone, in having no guidance).
#[test]
fn variants_are_configurations_of_the_same_run() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    for env in ENVS {
        let logo = TrainConfig::load(&root.join("logo").join(format!("{env}.toml"))).unwrap();
        for algo in methods(true).into_iter().chain(["ppo", "trpo"]) {
            let path = root.join(algo).join(format!("{env}.toml"));
            let mut config = TrainConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
            // A run of it records its folder's method, read off its keys.
            assert_eq!(config.method.as_deref(), Some(algo), "{}", path.display());
            if algo == "logo-fast" {
                continue; // the_fast_preset_is_the_default_with_its_levers
            }
            config.method = logo.method.clone();
            config.init = logo.init.clone();
            config.improvement = logo.improvement.clone();
            config.critic = logo.critic.clone();
            match (&mut config.guidance, &logo.guidance) {
                (Some(g), Some(l)) => {
                    g.update = l.update.clone();
                    g.critic = l.critic.clone();
                }
                (None, _) => config.guidance = logo.guidance.clone(),
                _ => panic!("{}: guidance where LOGO's has none", path.display()),
            }
            assert_eq!(config, logo, "{} differs beyond its kinds", path.display());
        }
    }
}

/// `configs/reference/<env>.toml` is `configs/logo/<env>.toml` with the reference code's
/// F·v and nothing else, and it is the config of the runs its header quotes (the
/// experiments arm `<env>_reference_fisher.toml`, IDP's `idp_reference_fisher.toml`).
#[test]
fn the_reference_configs_are_the_default_with_the_references_fv() {
    use logo_algo::policy_update::PolicyUpdateConfig;
    use logo_nn::FisherKind;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    for env in ENVS {
        let path = root.join("reference").join(format!("{env}.toml"));
        let reference = TrainConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let arm = match env {
            "inverted_double_pendulum" => "idp".to_string(),
            _ => env.to_string(),
        };
        let measured = root
            .join("experiments")
            .join(format!("{arm}_reference_fisher.toml"));
        let measured = TrainConfig::load(&measured).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(reference, measured, "{}", path.display());
        let mut config = reference.clone();
        let PolicyUpdateConfig::Trpo(trpo) = &mut config.improvement else {
            panic!("{}: not a TRPO step", path.display());
        };
        assert_eq!(trpo.fisher, FisherKind::Reference, "{}", path.display());
        trpo.fisher = FisherKind::Exact;
        let logo = TrainConfig::load(&root.join("logo").join(format!("{env}.toml"))).unwrap();
        assert_eq!(config, logo, "{} differs beyond its F·v", path.display());
    }
}

/// The fast preset is `configs/logo/<env>.toml` with its two cost levers and nothing
/// else: float32, and the L-BFGS critic fits on a quarter of the batch.
#[test]
fn the_fast_preset_is_the_default_with_its_levers() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    for env in ENVS {
        let logo = TrainConfig::load(&root.join("logo").join(format!("{env}.toml"))).unwrap();
        let path = root.join("logo-fast").join(format!("{env}.toml"));
        let mut fast = TrainConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
        // IDP's preset keeps float64, which learned faster there (docs/results.md).
        let dtype = (env != "inverted_double_pendulum").then_some(Dtype::F32);
        assert_eq!(fast.dtype, dtype, "{}", path.display());
        let CriticFit::Lbfgs(fit) = &mut fast.critic.fit else {
            panic!("{}: the preset's critic fit is not L-BFGS", path.display());
        };
        assert_eq!(fit.subsample, 0.25, "{}", path.display());
        fit.subsample = 1.0;
        fast.dtype = None;
        assert_eq!(
            fast.method.as_deref(),
            Some("logo-fast"),
            "{}",
            path.display()
        );
        fast.method = logo.method.clone();
        assert_eq!(fast, logo, "{} differs beyond its levers", path.display());
    }
}

#[test]
fn sizes_past_what_a_machine_holds_are_refused_naming_the_key() {
    let dir = std::env::temp_dir().join(format!("logo-config-bounds-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = [
        "env = \"SparseHopper-v4\"",
        "iterations = 2",
        "samples_per_iter = 1000",
    ];
    for (line, expected) in [
        (
            "samples_per_iter = 2000000000",
            "samples_per_iter must be at most 10000000",
        ),
        ("eval_steps = 99999999999", "eval_steps must be at most"),
        ("num_envs = 100000", "num_envs must be at most 4096"),
        ("log_std_init = 400.0", "log_std_init must be in [-20, 5]"),
        (
            "policy_hidden = [65536, 65536]",
            "policy_hidden: 4294967296 weights",
        ),
        (
            "policy_hidden = [64, 1000000]",
            "policy_hidden: every layer needs 1 to 65536",
        ),
        (
            "[critic]\nhidden = [0]",
            "critic.hidden: every layer needs 1 to 65536",
        ),
        (
            "[critic]\nfit = { method = \"lbfgs\", iterations = 100000000 }",
            "critic.fit.iterations must be in 1..=100000",
        ),
        (
            "[improvement]\ncg_iters = 0",
            "improvement.cg_iters must be in 1..=10000",
        ),
        (
            "[improvement]\nbacktracks = 1000",
            "improvement.backtracks must be in 1..=60",
        ),
        (
            "[improvement]\nkind = \"ppo-clip\"\nclip_epsilon = 1.5",
            "improvement.clip_epsilon must be in (0, 1)",
        ),
        (
            "[improvement]\nkind = \"ppo-clip\"\nepochs = 99999999",
            "improvement.epochs must be in 1..=10000",
        ),
    ] {
        let path = dir.join("bounds.toml");
        let key = line.split(' ').next().unwrap();
        let kept: Vec<&str> = base.into_iter().filter(|b| !b.starts_with(key)).collect();
        std::fs::write(&path, format!("{}\n{line}\n", kept.join("\n"))).unwrap();
        let err = TrainConfig::load(&path).unwrap_err().to_string();
        assert!(
            err.contains("bounds.toml") && err.contains(expected),
            "{line}: {err}"
        );
    }
}

/// The name a run prints and records says which of its critics are twin-min.
#[test]
fn algorithm_names_say_which_critics_are_twin() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    let name = |path: &str| TrainConfig::load(&root.join(path)).unwrap().algorithm();
    assert_eq!(name("logo/hopper.toml"), "LOGO");
    assert_eq!(name("logo-cdq/hopper.toml"), "LOGO (twin-min critics)");
    assert_eq!(
        name("experiments/hopper_cdq_env_critic_only.toml"),
        "LOGO (twin-min env critic)"
    );
    assert_eq!(
        name("experiments/hopper_cdq_guidance_critic_only.toml"),
        "LOGO (twin-min guidance critic)"
    );
    assert_eq!(
        name("logo-ppo-penalty/hopper.toml"),
        "LOGO+PPO-CLIP (guidance ppo-penalty)"
    );
}

/// The baselines differ from `configs/trpo/<env>.toml` in `[init]`, `[reward]`,
/// `[guidance]`, `[improvement]`'s kind and `[demonstration_rows]` only, and their
/// demonstrations are LOGO's.
#[test]
fn baselines_are_trpo_with_a_reward_or_an_initialisation() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    for env in ENVS {
        let trpo = TrainConfig::load(&root.join("trpo").join(format!("{env}.toml"))).unwrap();
        let logo = TrainConfig::load(&root.join("logo").join(format!("{env}.toml"))).unwrap();
        let logo_demos = logo.guidance.as_ref().and_then(|g| g.demos.clone());
        for algo in methods(false) {
            let path = root.join(algo).join(format!("{env}.toml"));
            let mut config = TrainConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
            if config.bc_demos().is_none() && config.guidance.is_none() {
                continue; // TRPO and PPO: no demonstrations (variants_are_...)
            }
            let demos = config.bc_demos().map(Path::to_path_buf);
            assert_eq!(
                demos,
                logo_demos,
                "{}: not LOGO's demonstrations",
                path.display()
            );
            assert_eq!(config.method.as_deref(), Some(algo), "{}", path.display());
            config.method = trpo.method.clone();
            config.init = trpo.init.clone();
            config.reward = trpo.reward.clone();
            config.guidance = None;
            config.improvement = trpo.improvement.clone();
            config.demonstration_rows = None;
            assert_eq!(
                config,
                trpo,
                "{} differs beyond its baseline's keys",
                path.display()
            );
        }
    }
}

/// `logo compare` makes each baseline from the LOGO config as its `configs/` folder has it.
#[test]
fn compare_makes_the_baselines_of_the_config_folders() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    for env in ENVS {
        let logo = TrainConfig::load(&root.join("logo").join(format!("{env}.toml"))).unwrap();
        for algo in comparable() {
            let path = root.join(algo).join(format!("{env}.toml"));
            let shipped = TrainConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let made = configure(&logo, algo).unwrap();
            assert_eq!(made, shipped, "{}", path.display());
        }
    }
    // A LOGO config whose δ_k waits for the agent: the methods without the guidance step
    // drop its schedule's keys, and each of them is made.
    let mut waiting = TrainConfig::load(&root.join("logo/hopper.toml")).unwrap();
    let guidance = waiting.guidance.as_mut().unwrap();
    guidance.decay_on = logo_algo::config::DecaySignal::Success;
    guidance.decay_from = Some(0.9);
    let stepless = |a: &&str| logo_algo::algorithms::method(a).unwrap().guided != Guided::Step;
    for algo in comparable().into_iter().filter(stepless) {
        let made = configure(&waiting, algo).unwrap_or_else(|e| panic!("{algo}: {e}"));
        assert!(
            made.guidance.is_none_or(|g| g.decay_from.is_none()),
            "{algo}"
        );
    }
}

/// `[algorithm] name = "…"` over the TRPO config (or LOGO's, for its variants) gives the
/// algorithm's `configs/` folder: each preset is what its folder adds, no more.
#[test]
fn each_preset_makes_its_config_folder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = std::env::temp_dir().join(format!("logo-presets-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for env in ENVS {
        let demos = root.join("data/logo").join(env).canonicalize().unwrap();
        let demos = format!("demos = {:?}\n", demos.display().to_string());
        let text = |algo: &str| {
            let path = root.join("configs").join(algo).join(format!("{env}.toml"));
            std::fs::read_to_string(path).unwrap()
        };
        for name in logo_algo::presets::names() {
            if name == "logo-fast" && env == "inverted_double_pendulum" {
                continue; // IDP's fast preset keeps float64 (the_fast_preset_is_...).
            }
            let method = logo_algo::algorithms::method(name).unwrap();
            let base = match (method.guided, method.start) {
                (Guided::No, Start::Random) => text("trpo"),
                (Guided::No, Start::Clone) => format!("{}\n[init]\n{demos}", text("trpo")),
                (Guided::Discriminator, _) => format!("{}\n[guidance]\n{demos}", text("trpo")),
                (Guided::Step, _) => {
                    text("logo").replace(&format!("demos = \"../../data/logo/{env}\"\n"), &demos)
                }
            };
            let path = dir.join(format!("{name}-{env}.toml"));
            std::fs::write(&path, format!("{base}\n[algorithm]\nname = \"{name}\"\n")).unwrap();
            let mut made = TrainConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(made.preset.take().map(|p| p.name).as_deref(), Some(name));
            let folder = root.join("configs").join(name).join(format!("{env}.toml"));
            let shipped = TrainConfig::load(&folder).unwrap();
            assert_eq!(made, shipped, "[algorithm] name = {name:?} on {env}");
            // What a run stores of it reads back to the same config.
            let stored = dir.join(format!("{name}-{env}-stored.toml"));
            std::fs::write(&stored, toml::to_string(&made).unwrap()).unwrap();
            assert_eq!(TrainConfig::load(&stored).unwrap(), made, "{name} on {env}");
        }
    }
}

#[test]
fn a_preset_that_cannot_go_with_the_config_is_refused_naming_it() {
    let dir = std::env::temp_dir().join(format!("logo-presets-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = "env = \"SparseHopper-v4\"\niterations = 1\nsamples_per_iter = 1000\n";
    let guidance = "[guidance]\ndemos = \"x\"\ndelta0 = 0.1\nalpha = 0.9\nwarmup = 1\n";
    for (tables, expected) in [
        (
            "[algorithm]\nname = \"sac\"\n",
            "is no preset; expected one of trpo",
        ),
        (
            "[algorithm]\nname = \"logo\"\n",
            "needs [guidance] with its demos and delta0",
        ),
        (
            "[algorithm]\nname = \"gail\"\n",
            "needs [guidance] with its demos",
        ),
        (
            "[algorithm]\nname = \"trpo\"\nother = 1\n",
            "algorithm: unknown field `other`",
        ),
    ] {
        let path = dir.join("bad.toml");
        std::fs::write(&path, format!("{base}{tables}")).unwrap();
        let err = TrainConfig::load(&path).unwrap_err().to_string();
        assert!(
            err.contains("bad.toml") && err.contains(expected),
            "{tables}: {err}"
        );
    }
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        format!("{base}{guidance}[algorithm]\nname = \"dapg\"\n"),
    )
    .unwrap();
    let err = TrainConfig::load(&path).unwrap_err().to_string();
    assert!(err.contains("remove [guidance]"), "{err}");
    // A key of the config wins over the preset's.
    let path = dir.join("own.toml");
    std::fs::write(
        &path,
        format!("{base}[algorithm]\nname = \"dapg\"\n[init]\ndemos = \"x\"\n[demonstration_rows]\nlambda0 = 0.5\n"),
    )
    .unwrap();
    let err = TrainConfig::load(&path).unwrap_err().to_string();
    // (the demonstrations "x" do not exist: the config got as far as its files)
    assert!(err.contains("init.demos"), "{err}");
    // A key set back to its default stays so through the stored config: DAPG without
    // behaviour cloning remains without it.
    let demos = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/logo/hopper");
    let path = dir.join("random.toml");
    std::fs::write(
        &path,
        format!(
            "{base}[algorithm]\nname = \"dapg\"\n[init]\nkind = \"random\"\n\
             [demonstration_rows]\ndemos = {:?}\n",
            demos.display().to_string()
        ),
    )
    .unwrap();
    let config = TrainConfig::load(&path).unwrap();
    assert_eq!(config.algorithm(), "DAPG (no behaviour cloning)");
    let stored = dir.join("random-stored.toml");
    std::fs::write(&stored, toml::to_string(&config).unwrap()).unwrap();
    let again = TrainConfig::load(&stored).unwrap();
    assert_eq!(again.algorithm(), "DAPG (no behaviour cloning)");
    assert!(again.preset.is_none());
}

/// A config's error says its kind by the mistake, not by the words on the file's line: a
/// missing file, a value of the wrong type, an unknown key (whose line may read anything).
#[test]
fn a_config_errors_kind_is_the_mistakes() {
    use logo_algo::ConfigErrorKind;
    let dir = std::env::temp_dir().join(format!("logo-config-kinds-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = "env = \"SparseHopper-v4\"\niterations = 1\nsamples_per_iter = 1000\n";
    let kind = |name: &str, text: Option<&str>| {
        let path = dir.join(name);
        if let Some(text) = text {
            std::fs::write(&path, text).unwrap();
        }
        TrainConfig::load(&path).unwrap_err().kind
    };
    assert_eq!(kind("missing.toml", None), ConfigErrorKind::NotFound);
    let wrong_type = base.replace("iterations = 1", "iterations = \"many\"");
    assert_eq!(kind("type.toml", Some(&wrong_type)), ConfigErrorKind::Type);
    let unknown = format!("{base}no_such_key = \"an invalid type\"\n");
    assert_eq!(kind("unknown.toml", Some(&unknown)), ConfigErrorKind::Value);
    let range = format!("{base}gamma = 2.0\n");
    assert_eq!(kind("range.toml", Some(&range)), ConfigErrorKind::Value);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The new-task preset holds δ_k at δ_0 on every task (docs/findings/suite.md): on a task
/// with no goal (`success = "none"`) it loads and δ_k stays put while the return rises.
/// Its documented way to let the guidance fade, decaying on success, is refused there with
/// a hint to hold δ_k; decaying on the return shrinks it.
#[test]
fn the_preset_holds_delta_and_decays_only_when_told() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = std::env::temp_dir().join(format!("logo-no-goal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let template = std::fs::read_to_string(root.join("configs/templates/new_task.toml")).unwrap();
    // Each edit replaces exactly one whole line of the template.
    let edit = |text: &str, line: &str, with: &str| {
        let line = format!("\n{line}\n");
        assert_eq!(text.matches(&line).count(), 1, "{line:?} in the template");
        text.replace(&line, &format!("\n{with}\n"))
    };
    let demos = root.join("data/logo/hopper").canonicalize().unwrap();
    let preset = edit(
        &template,
        "env = \"SparseHopper-v4\"",
        "env = \"Hopper-v4+delayed\"",
    );
    let preset = edit(&preset, "success = \"task\"", "success = \"none\"");
    let preset = edit(
        &preset,
        "demos = \"../../data/logo/hopper\"",
        &format!("demos = {demos:?}"),
    );
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    // The return rising every iteration, past the warm-up.
    let delta_after = |text: &str, name: &str| {
        let config = TrainConfig::load(&write(name, text)).unwrap();
        assert_eq!(config.success, logo_algo::episode::SuccessRule::None);
        let mut schedule = config.guidance.as_ref().unwrap().schedule();
        for i in 0..20 {
            schedule.update(i, 100.0 * i as f64);
        }
        (config.guidance.unwrap().delta0.unwrap(), schedule.delta)
    };
    let (delta0, held) = delta_after(&preset, "preset.toml");
    assert_eq!(held, delta0);
    let decaying = edit(&preset, "alpha = 1.0", "alpha = 0.9");
    let on_success = format!("{decaying}decay_on = \"success\"\n");
    let e = TrainConfig::load(&write("refused.toml", &on_success)).unwrap_err();
    let message = e.to_string();
    assert!(
        message.contains("needs a success rule")
            && message.contains("guidance.decay_on = \"return\" with guidance.alpha = 1.0"),
        "{message}"
    );
    let (_, decayed) = delta_after(&decaying, "decaying.toml");
    assert!(decayed < 0.5 * delta0, "{decayed} from {delta0}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `decay_from`: a share in (0, 1], read with `decay_on = "success"` only, carried into
/// the schedule; a task without a success may set it (δ_k then holds).
#[test]
fn decay_from_is_checked_and_reaches_the_schedule() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = std::env::temp_dir().join(format!("logo-decay-from-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let demos = root.join("data/logo/hopper").canonicalize().unwrap();
    let load = |success: &str, guidance: &str| {
        let path = dir.join("config.toml");
        let text = format!(
            "env = \"SparseHopper-v4\"\niterations = 1\nsamples_per_iter = 1000\nsuccess = \"{success}\"\n[guidance]\ndemos = {demos:?}\n\
             delta0 = 0.01\nalpha = 0.9\nwarmup = 0\n{guidance}"
        );
        std::fs::write(&path, text).unwrap();
        TrainConfig::load(&path).map_err(|e| e.to_string())
    };
    let waiting = load("task", "decay_on = \"success\"\ndecay_from = 0.9\n").unwrap();
    let mut schedule = waiting.guidance.as_ref().unwrap().schedule();
    assert_eq!(schedule.decay_from, Some(0.9));
    schedule.update(1, 0.89);
    assert_eq!(schedule.delta, 0.01);
    schedule.update(2, 0.9);
    assert!((schedule.delta - 0.009).abs() < 1e-15);
    // Without it, the schedule is LOGO's.
    // grow_back: the level's schedule that follows the agent back up to δ_0.
    let following = "decay_on = \"evaluation\"\ndecay_from = 0.9\ngrow_back = true\n";
    let following = load("task", following).unwrap();
    let schedule = following.guidance.as_ref().unwrap().schedule();
    assert_eq!(
        (schedule.decay_from, schedule.grow_back_to),
        (Some(0.9), Some(0.01))
    );
    let message = load("task", "grow_back = true\n").unwrap_err();
    assert!(
        message.contains("grow_back needs guidance.decay_from"),
        "{message}"
    );
    let logo = load("task", "decay_on = \"success\"\n").unwrap();
    assert_eq!(logo.guidance.unwrap().schedule().decay_from, None);
    // A task with no goal: decay_on = "success" alone is refused, with decay_from accepted.
    assert!(load("none", "decay_on = \"success\"\n").is_err());
    assert!(load("none", "decay_on = \"success\"\ndecay_from = 0.9\n").is_ok());
    for (guidance, expected) in [
        ("decay_from = 0.9\n", "set guidance.decay_on = \"success\""),
        (
            "decay_on = \"success\"\ndecay_from = 1.5\n",
            "in (0, 1], got 1.5",
        ),
        (
            "decay_on = \"success\"\ndecay_from = 0.0\n",
            "in (0, 1], got 0",
        ),
    ] {
        let message = load("task", guidance).unwrap_err();
        assert!(message.contains(expected), "{guidance:?}: {message}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

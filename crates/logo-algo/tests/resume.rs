//! A run killed after its last checkpoint and resumed ends exactly where an uninterrupted
//! run of the same seed does: same final checkpoint bytes, same metrics.

use std::path::Path;

use logo_algo::{TrainConfig, Trainer};
use logo_nn::Kernels;
use logo_testkit::{Tiny, metrics_without_timings, scratch};

/// The run each test resumes: LOGO (`guidance`) or TRPO.
fn algorithm(guidance: bool) -> Tiny {
    match guidance {
        true => Tiny::logo().set("guidance.warmup", 1),
        false => Tiny::trpo(),
    }
}

fn config(dir: &Path, guidance: bool) -> TrainConfig {
    config_of(dir, algorithm(guidance))
}

fn config_of(dir: &Path, tiny: Tiny) -> TrainConfig {
    let path = tiny
        .lbfgs(4)
        .with("iterations = 5\nnum_envs = 3\nthreads = 2\neval_steps = 60")
        .with("checkpoint_every = 2\nseed = 11")
        .write(&dir.join("config.toml"));
    TrainConfig::load(&path).unwrap()
}

fn check(name: &str, tiny: Tiny) {
    let whole = scratch(&format!("{name}-whole"));
    let mut trainer = Trainer::new(Kernels, config_of(&whole, tiny.clone()), &whole).unwrap();
    while !trainer.done() {
        trainer.step().unwrap();
    }
    drop(trainer);

    let killed = scratch(&format!("{name}-killed"));
    let mut trainer = Trainer::new(Kernels, config_of(&killed, tiny), &killed).unwrap();
    for _ in 0..3 {
        trainer.step().unwrap(); // checkpoint after iteration 2, then one more row
    }
    drop(trainer); // killed before the next checkpoint
    let mut resumed = Trainer::resume(Kernels, &killed, None).unwrap();
    assert_eq!(resumed.iteration(), 2);
    while !resumed.done() {
        resumed.step().unwrap();
    }
    drop(resumed);

    let bytes = |dir: &Path| std::fs::read(dir.join("checkpoint.safetensors")).unwrap();
    assert!(
        bytes(&whole) == bytes(&killed),
        "{name}: the resumed run's final checkpoint differs from the uninterrupted one"
    );
    assert_eq!(
        metrics_without_timings(&whole),
        metrics_without_timings(&killed),
        "{name}"
    );
    assert_eq!(
        metrics_without_timings(&whole).len(),
        6,
        "a header and 5 rows"
    );
}

#[test]
fn a_killed_logo_run_resumes_to_the_same_final_checkpoint() {
    check("logo", algorithm(true));
}

#[test]
fn a_killed_trpo_run_resumes_to_the_same_final_checkpoint() {
    check("trpo", algorithm(false));
}

/// GAIL: the discriminator's reward alone, no guidance step.
#[test]
fn a_killed_gail_run_resumes_to_the_same_final_checkpoint() {
    let demos = logo_testkit::workspace().join("data/logo/inverted_double_pendulum");
    let gail = Tiny::trpo()
        .set("guidance.demos", demos.to_str().expect("a UTF-8 path"))
        .set("guidance.step", false)
        .set("reward.env", 0.0)
        .set("reward.discriminator", 1.0);
    check("gail", gail);
}

/// δ_k decaying on the evaluation: set at the end of an iteration, so the checkpoint must
/// carry δ_{k+1} (dense IDP ends every episode by falling, "terminated" a success).
#[test]
fn a_killed_run_decaying_on_its_evaluation_resumes_to_the_same_final_checkpoint() {
    let on_evaluation = algorithm(true)
        .set("env", "InvertedDoublePendulum-v4")
        .set("success", "terminated")
        .set("guidance.decay_on", "evaluation")
        .set("guidance.decay_from", 0.5);
    check("decay-on-evaluation", on_evaluation);
}

/// DAPG: behaviour cloning, NPG steps with the demonstrations' rows (their weight decays
/// with the iteration, so a resume must continue k).
#[test]
fn a_killed_dapg_run_resumes_to_the_same_final_checkpoint() {
    let demos = logo_testkit::workspace().join("data/logo/inverted_double_pendulum");
    let dapg = Tiny::trpo()
        .set("init.demos", demos.to_str().expect("a UTF-8 path"))
        .set("init.epochs", 2)
        .set("algorithm.name", "dapg");
    check("dapg", dapg);
}

#[test]
fn a_steps_mode_run_says_it_cannot_be_resumed() {
    let dir = scratch("steps");
    let mut config = config(&dir, false);
    config.rollout = logo_algo::sampler::RolloutMode::Steps;
    config.iterations = 2;
    let mut trainer = Trainer::new(Kernels, config, &dir).unwrap();
    while !trainer.done() {
        trainer.step().unwrap();
    }
    drop(trainer);
    let err = Trainer::resume(Kernels, &dir, None)
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("cannot be resumed"), "{err}");
}

#[test]
fn a_non_finite_update_stops_the_run_and_keeps_the_last_checkpoint() {
    let dir = scratch("non-finite");
    let mut trainer = Trainer::new(Kernels, config(&dir, true), &dir).unwrap();
    trainer.step().unwrap();
    trainer.step().unwrap(); // checkpoint_every = 2: written here
    let checkpoint = std::fs::read(dir.join("checkpoint.safetensors")).unwrap();
    let rows = metrics_without_timings(&dir);
    // Adam's steps are ≈ the learning rate whatever the gradient: 1e300 overflows.
    trainer.config.improvement = serde_json::from_value(serde_json::json!({
        "kind": "ppo-clip",
        "learning_rate": 1e300,
    }))
    .unwrap();
    let err = trainer.step().unwrap_err().to_string();
    assert!(
        err.starts_with("iteration 2: the improvement step produced a non-finite number")
            && err.contains("the checkpoint of iteration 2 is kept"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(dir.join("checkpoint.safetensors")).unwrap(),
        checkpoint
    );
    assert_eq!(metrics_without_timings(&dir), rows);
}

/// A LOGO run of two iterations in a scratch folder `name`, its process ended (so the
/// folder is free to resume): the folder and its checkpoint's path.
fn two_logo_iterations(name: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = scratch(name);
    let mut trainer = Trainer::new(Kernels, config(&dir, true), &dir).unwrap();
    trainer.step().unwrap();
    trainer.step().unwrap();
    drop(trainer);
    let path = dir.join("checkpoint.safetensors");
    (dir, path)
}

#[test]
fn a_checkpoint_whose_metadata_disagrees_with_itself_is_refused() {
    let (dir, path) = two_logo_iterations("tampered");
    let good = logo_nn::Checkpoint::load(&path).unwrap();
    // The checkpoint with one edit, saved over the run's; the error resuming it.
    let resume_edited = |edit: &dyn Fn(&mut logo_nn::Checkpoint)| {
        let mut ckpt = good.clone();
        edit(&mut ckpt);
        ckpt.save(&path).unwrap();
        Trainer::resume(Kernels, &dir, None)
            .err()
            .unwrap()
            .to_string()
    };
    // A LOGO checkpoint whose stored config lost its guidance: not resumed as TRPO.
    let err = resume_edited(&|c| c.meta.extra["config"]["guidance"] = serde_json::Value::Null);
    assert!(
        err.contains("algorithm is logo, its config says trpo"),
        "{err}"
    );
    // A config whose networks are not the stored ones.
    let err =
        resume_edited(&|c| c.meta.extra["config"]["policy_hidden"] = serde_json::json!([32, 32]));
    assert!(err.contains("policy network is Some([16, 16])"), "{err}");
    // Optimiser moments that do not fit the networks (they would be reset silently).
    let err = resume_edited(&|c| {
        c.meta.extra["resume"]["critic_adam"][0] =
            serde_json::json!({"m": [1.0, 2.0, 3.0], "v": [1.0, 2.0, 3.0], "t": 4})
    });
    assert!(
        err.contains("resume state critic_adam: Adam moments of lengths 3 and 3"),
        "{err}"
    );
    // Resume-state values out of range or out of step with each other, with the metadata
    // or with metrics.csv (each was once resumed, writing NaN or wrong rows with exit 0).
    for (edit, expected) in [
        (
            ("schedule", "delta", serde_json::json!(-0.1)),
            "resume state schedule: δ_k = -0.1 is outside [5e-7, δ_0 = 0.2]",
        ),
        (
            ("schedule", "delta", serde_json::json!(0.5)),
            "δ_k = 0.5 is outside",
        ),
        (
            ("schedule", "alpha", serde_json::json!(1.5)),
            "α = 1.5 is outside (0, 1]",
        ),
        (
            ("schedule", "window", serde_json::json!(vec![1.0; 11])),
            "at most 10 finite values",
        ),
    ] {
        let ((table, key, value), expected) = (edit, expected);
        let err =
            resume_edited(&|c| c.meta.extra["resume"]["guidance"][table][key] = value.clone());
        assert!(err.contains(expected), "{table}.{key} = {value}: {err}");
    }
    let samples = good.meta.extra["resume"]["samples"].as_u64().unwrap();
    let err = resume_edited(&|c| c.meta.extra["resume"]["samples"] = (samples + 1).into());
    assert!(
        err.contains(&format!("{} samples after iteration 2, but", samples + 1))
            && err.contains(&format!("metrics.csv says {samples}")),
        "{err}"
    );
    let err = resume_edited(&|c| c.meta.extra["resume"]["samples"] = serde_json::json!(1));
    assert!(err.contains("1 samples in 2 iterations"), "{err}");
    let err = resume_edited(&|c| c.meta.extra["resume"]["iteration"] = serde_json::json!(1));
    assert!(
        err.contains("iteration is 2, its resume state says 1"),
        "{err}"
    );
    for engines in [
        serde_json::json!("kernels f64"),
        serde_json::json!([{"from_iteration": 1, "engine": "kernels f64"}]),
        serde_json::json!([
            {"from_iteration": 0, "engine": "kernels f64"},
            {"from_iteration": 0, "engine": "burn ndarray f64"}
        ]),
        serde_json::json!([{"from_iteration": 0, "engine": "kernels f64"},
                           {"from_iteration": 9, "engine": "burn ndarray f64"}]),
    ] {
        let err = resume_edited(&|c| c.meta.extra["engines"] = engines.clone());
        assert!(err.contains("metadata engines"), "{engines}: {err}");
    }
    // Sizes that the file's numbers cannot hold are refused on load, before any network
    // is built from them.
    let mut ckpt = good;
    ckpt.meta
        .networks
        .insert("policy".into(), vec![1 << 40, 16]);
    ckpt.save(&path).unwrap();
    let err = logo_nn::Checkpoint::load(&path).unwrap_err().to_string();
    assert!(
        err.contains("networks.policy: hidden sizes [1099511627776, 16] do not fit"),
        "{err}"
    );
}

#[test]
fn a_new_run_in_an_old_runs_folder_is_refused_and_stale_temporaries_go() {
    let dir = scratch("old-folder");
    let mut trainer = Trainer::new(Kernels, config(&dir, false), &dir).unwrap();
    trainer.step().unwrap();
    trainer.step().unwrap(); // the checkpoint is written here
    drop(trainer);
    let err = Trainer::new(Kernels, config(&dir, true), &dir)
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("already holds a run") && err.contains("--resume"),
        "{err}"
    );
    // A write killed before its rename leaves checkpoint.tmp.<pid>; resuming removes it.
    std::fs::write(dir.join("checkpoint.tmp.999999"), b"half a checkpoint").unwrap();
    Trainer::resume(Kernels, &dir, None).unwrap();
    assert!(!dir.join("checkpoint.tmp.999999").exists());
}

/// The kept runs' learner checkpoints: one of each checkpoint family, moved from
/// `docs/results/` (which keeps policies alone) to the tests' fixtures.
fn kept_runs() -> std::path::PathBuf {
    logo_testkit::workspace().join("tests/fixtures/kept-runs")
}

/// The kept checkpoints that hold a resume state.
fn kept_checkpoints() -> Vec<std::path::PathBuf> {
    let mut found = Vec::new();
    let mut folders = vec![kept_runs()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.file_name() == Some("checkpoint.safetensors".as_ref()) {
                let meta = logo_nn::Checkpoint::load(&path).unwrap().meta;
                if !meta.extra["resume"].is_null() {
                    found.push(path);
                }
            }
        }
    }
    found.sort();
    found
}

/// Every kept checkpoint (format 1) read as a learner's state and written again (in
/// today's format) holds the same networks, bit for bit, the same engine history, and a
/// resume state that reads back as the same learner's state: the checkpoint is that
/// state, and its migration loses nothing.
#[test]
fn kept_checkpoints_are_learner_states() {
    use logo_algo::{Learned, LearnerState};
    let kept = kept_checkpoints();
    // One per checkpoint family (golden.rs KEPT_FAMILIES).
    assert!(
        kept.len() >= 8,
        "only {} kept checkpoints found",
        kept.len()
    );
    let dir = scratch("kept-round-trip");
    for path in kept {
        let shown = path.display();
        let before = logo_nn::Checkpoint::load(&path).unwrap();
        assert!(
            before.meta.extra["resume"].get("format").is_none(),
            "{shown}: a kept checkpoint of format 1 expected"
        );
        let (config, state) =
            LearnerState::load(&path, None).unwrap_or_else(|e| panic!("{shown}: {e}"));
        let again = dir.join("checkpoint.safetensors");
        let engine = before.meta.extra["engine"]
            .as_str()
            .unwrap_or("")
            .to_string();
        state
            .save(&again, &config, &before.meta.env_id, &engine)
            .unwrap();
        let after = logo_nn::Checkpoint::load(&again).unwrap();
        assert_eq!(
            after.meta.extra["resume"]["format"],
            Learned::FORMAT,
            "{shown}"
        );
        let (_, reread) = LearnerState::load(&again, None).unwrap();
        assert_eq!(state.learned, reread.learned, "{shown}");
        for key in ["engines", "samples"] {
            if !before.meta.extra[key].is_null() {
                assert_eq!(
                    before.meta.extra[key], after.meta.extra[key],
                    "{shown}: {key}"
                );
            }
        }
        assert_eq!(before.meta.networks, after.meta.networks, "{shown}");
        assert_eq!(before.meta.iteration, after.meta.iteration, "{shown}");
        let names: Vec<&str> = before.tensor_names().collect();
        assert_eq!(names, after.tensor_names().collect::<Vec<_>>(), "{shown}");
        for name in names {
            assert_eq!(before.tensor(name), after.tensor(name), "{shown}: {name}");
        }
    }
}

/// A format-1 state that names its format (none was written so) reads as one that does not.
#[test]
fn a_format_one_state_that_names_its_number_reads_the_same() {
    use logo_algo::LearnerState;
    let kept = kept_runs().join("paper-scale/hopper/hopper/seed0/checkpoint.safetensors");
    let (_, unnumbered) = LearnerState::load(&kept, None).unwrap();
    let mut ckpt = logo_nn::Checkpoint::load(&kept).unwrap();
    ckpt.meta.extra["resume"]["format"] = serde_json::json!(1);
    let dir = scratch("format-one");
    let path = dir.join("checkpoint.safetensors");
    ckpt.save(&path).unwrap();
    let (_, numbered) = LearnerState::load(&path, None).unwrap();
    assert_eq!(numbered.learned, unnumbered.learned);
}

/// A resume state of a format this build does not know is refused by name, not read as
/// something else.
#[test]
fn an_unknown_resume_format_is_refused() {
    let (dir, path) = two_logo_iterations("unknown-format");
    let mut ckpt = logo_nn::Checkpoint::load(&path).unwrap();
    assert_eq!(ckpt.meta.extra["resume"]["format"], 2);
    ckpt.meta.extra["resume"]["format"] = serde_json::json!(3);
    ckpt.save(&path).unwrap();
    let err = Trainer::resume(Kernels, &dir, None)
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("resume state: format 3 is newer than this logo-rl reads (1 to 2)"),
        "{err}"
    );
}

/// A kept run of the paper-scale study goes on by one iteration from its checkpoint.
#[test]
fn a_kept_run_resumes() {
    let kept = kept_runs().join("paper-scale/hopper/hopper/seed0");
    let dir = scratch("kept-resume");
    for file in ["checkpoint.safetensors", "metrics.csv", "config.toml"] {
        std::fs::copy(kept.join(file), dir.join(file)).unwrap();
    }
    let done = metrics_without_timings(&dir).len() - 1;
    let mut trainer = Trainer::resume(Kernels, &dir, Some(done + 1)).unwrap();
    assert_eq!(trainer.iteration(), done);
    let row = trainer.step().unwrap();
    assert_eq!(row.iteration, done);
    assert!(trainer.done());
    assert_eq!(metrics_without_timings(&dir).len(), done + 2);
}

/// A run kept inside a copy of the project resumes wherever that copy is: the files its
/// config names by the old copy's absolute paths are found under the folders above it.
#[test]
fn a_moved_copy_of_a_run_finds_its_demonstrations_above_it() {
    let dir = scratch("moved-copy");
    let old = dir.join("old-clone");
    let demos = old.join("data/idp-demos");
    copy_folder(
        &logo_testkit::workspace().join("data/logo/inverted_double_pendulum"),
        &demos,
    );
    let run = old.join("runs/logo");
    std::fs::create_dir_all(&run).unwrap();
    let path = Tiny::logo()
        .set("guidance.demos", demos.to_str().unwrap())
        .set("checkpoint_every", 1)
        .write(&dir.join("config.toml"));
    let mut trainer = Trainer::new(Kernels, TrainConfig::load(&path).unwrap(), &run).unwrap();
    trainer.step().unwrap();
    drop(trainer);
    let new = dir.join("new-clone");
    std::fs::rename(&old, &new).unwrap();
    let mut resumed =
        Trainer::resume(Kernels, &new.join("runs/logo"), None).unwrap_or_else(|e| panic!("{e}"));
    let demos = resumed
        .config
        .guidance
        .as_ref()
        .unwrap()
        .demos
        .clone()
        .unwrap();
    assert!(
        demos.starts_with(new.canonicalize().unwrap()),
        "{}",
        demos.display()
    );
    resumed.step().unwrap();
    assert!(resumed.done());
}

fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        match path.is_dir() {
            true => copy_folder(&path, &target),
            false => drop(std::fs::copy(&path, &target).unwrap()),
        }
    }
}

/// A checkpoint that names no engine (older ones) resumes, and its continuation resumes
/// again: the history starts at iteration 0 with the engine "not recorded".
#[test]
fn a_checkpoint_without_an_engine_history_resumes_twice() {
    let dir = scratch("no-engines");
    let path = Tiny::trpo()
        .set("iterations", 3)
        .set("checkpoint_every", 1)
        .write(&dir.join("config.toml"));
    let mut trainer = Trainer::new(Kernels, TrainConfig::load(&path).unwrap(), &dir).unwrap();
    trainer.step().unwrap();
    drop(trainer);
    let checkpoint = dir.join("checkpoint.safetensors");
    let mut ckpt = logo_nn::Checkpoint::load(&checkpoint).unwrap();
    let extra = ckpt.meta.extra.as_object_mut().unwrap();
    extra.remove("engine");
    extra.remove("engines");
    ckpt.save(&checkpoint).unwrap();
    for _ in 0..2 {
        let mut resumed = Trainer::resume(Kernels, &dir, None).unwrap_or_else(|e| panic!("{e}"));
        resumed.step().unwrap();
    }
    let meta = logo_nn::Checkpoint::load(&checkpoint).unwrap().meta;
    let spans = logo_algo::engine_history(&meta).unwrap();
    assert_eq!(spans.len(), 2, "{spans:?}");
    assert_eq!(
        (spans[0].from_iteration, spans[0].engine.as_str()),
        (0, "not recorded")
    );
    assert_eq!(spans[1].from_iteration, 1);
}

//! δ_k's decay in a training run: `decay_on = "success"` reads the batch's share at the
//! goal, `"evaluation"` the evaluation's (δ_{k+1} from π_{k+1}'s); with `decay_from` a task
//! that reports no success holds δ_k, without it the run stops with an error saying what
//! to set.

use logo_algo::{TrainConfig, Trainer};
use logo_nn::Kernels;
use logo_testkit::{Tiny, scratch};

/// δ_k after each of `iterations` iterations of `tiny`.
fn deltas(tiny: Tiny, name: &str, iterations: usize) -> Result<Vec<f64>, String> {
    let dir = scratch(name);
    let config = TrainConfig::load(&tiny.write(&dir.join("config.toml"))).unwrap();
    let mut trainer = Trainer::new(Kernels, config, &dir.join("run")).unwrap();
    let result = (0..iterations)
        .map(|_| trainer.step().map(|m| m.delta_k).map_err(|e| e.to_string()))
        .collect();
    drop(trainer);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

/// Three iterations of LOGO on dense IDP, δ_k decaying by α = 0.5 on `decay_on`: every
/// episode ends by falling, which `success = "terminated"` counts as the goal and the
/// task's own rule ("task") does not judge at all.
fn dense_idp(decay_on: &str) -> Tiny {
    Tiny::logo()
        .set("iterations", 3)
        .set("env", "InvertedDoublePendulum-v4")
        .set("guidance.alpha", 0.5)
        .set("guidance.decay_on", decay_on)
}

#[test]
fn a_waiting_decay_shrinks_on_the_batchs_success_and_holds_without_one() {
    let on_success = dense_idp("success");
    let waiting = on_success.clone().set("guidance.decay_from", 0.01);
    // Each batch is at the level, so δ_k halves after the first iteration (no warm-up).
    let reached = deltas(
        waiting.clone().set("success", "terminated"),
        "decay-reached",
        3,
    );
    assert_eq!(reached.unwrap(), [0.2, 0.1, 0.05]);
    // Judged by "task", dense IDP reports no success: δ_k holds.
    assert_eq!(deltas(waiting, "decay-held", 3).unwrap(), [0.2, 0.2, 0.2]);
    // Without decay_from, LOGO's rule on success: the run stops, naming what to set.
    let e = deltas(on_success, "decay-no-success", 1).unwrap_err();
    assert!(
        e.contains("no episode of the batch reported reaching its goal")
            && e.contains("success = \"terminated\""),
        "{e}"
    );
}

#[test]
fn a_decay_on_the_evaluation_reads_the_mean_actions_episodes() {
    let on_evaluation = dense_idp("evaluation");
    let waiting = on_evaluation.clone().set("guidance.decay_from", 0.01);
    // π_1's evaluation is at the level: δ_1 = δ_0 / 2, and so on.
    let reached = deltas(
        waiting.clone().set("success", "terminated"),
        "eval-reached",
        3,
    );
    assert_eq!(reached.unwrap(), [0.2, 0.1, 0.05]);
    // Evaluated at iterations 0, 2, ... (eval_every = 2): δ moves only after one.
    let sparse = waiting
        .clone()
        .set("success", "terminated")
        .set("eval_every", 2);
    assert_eq!(deltas(sparse, "eval-every-2", 3).unwrap(), [0.2, 0.1, 0.1]);
    // Judged by "task", dense IDP reports no success: δ_k holds.
    assert_eq!(deltas(waiting, "eval-held", 3).unwrap(), [0.2, 0.2, 0.2]);
    let e = deltas(on_evaluation, "eval-no-success", 1).unwrap_err();
    assert!(
        e.contains("decay_on = \"evaluation\": no episode of the evaluation"),
        "{e}"
    );
}

/// `decay_from = "demonstrations"`: the level is the demonstrations' recorded success rate,
/// read in as that number (the saved config names it); where nothing records one, the
/// config is refused naming the key, the dataset and what to set instead.
#[test]
fn a_level_of_demonstrations_is_their_recorded_success_rate() {
    let dir = scratch("decay-from-demonstrations");
    let data = logo_testkit::workspace().join("data/suite");
    let reacher = |demos: &std::path::Path, level: &str| {
        let text = format!(
            "env = \"Reacher-v5+goal(0.02)\"\nsuccess = \"task\"\niterations = 2\n\
             samples_per_iter = 500\n[guidance]\n\
             demos = {:?}\ndelta0 = 0.01\nalpha = 0.9\nwarmup = 5\n\
             decay_on = \"evaluation\"\ndecay_from = {level}\n",
            demos.display().to_string()
        );
        let path = dir.join("config.toml");
        std::fs::write(&path, text).unwrap();
        TrainConfig::load(&path)
    };
    // The degraded Reacher set reached the goal in 10 of its 20 episodes.
    let degraded = data.join("reacher-goal-degraded/demos");
    let config = reacher(&degraded, "\"demonstrations\"").unwrap();
    let level = config.guidance.as_ref().unwrap().decay_from;
    assert_eq!(level, Some(0.5));
    // The same as the number written out: one schedule, one saved config.
    let written = reacher(&degraded, "0.5").unwrap();
    assert_eq!(config.guidance, written.guidance);
    assert_eq!(
        config.guidance.as_ref().unwrap().schedule(),
        written.guidance.as_ref().unwrap().schedule()
    );
    // The suite's own Reacher set: 20 of 20.
    let own = reacher(&data.join("reacher-goal/demos"), "\"demonstrations\"").unwrap();
    assert_eq!(own.guidance.unwrap().decay_from, Some(1.0));
    // A recording without a success rate (MountainCarContinuous' degraded set was recorded
    // without a success rule), a .npy, another word: refused, saying what to set.
    let refused =
        |demos: &std::path::Path, level: &str| reacher(demos, level).unwrap_err().to_string();
    let e = refused(
        &data.join("mountain-car-degraded/demos"),
        "\"demonstrations\"",
    );
    assert!(
        e.contains("guidance.decay_from = \"demonstrations\"")
            && e.contains("logo_recording.success_rate is not recorded")
            && e.contains("set decay_from to a share instead"),
        "{e}"
    );
    let npy = dir.join("demos.npy");
    logo_testkit::write_demos_npy(&npy, 10, 12);
    let e = refused(&npy, "\"demonstrations\"");
    assert!(e.contains("a .npy records no success rate"), "{e}");
    let e = refused(&degraded, "\"demos\"");
    assert!(
        e.contains("guidance.decay_from = \"demos\": expected a share of episodes in (0, 1], or \"demonstrations\""),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

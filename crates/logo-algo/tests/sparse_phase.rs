//! `skip_improvement_without_reward`: on a batch without any env reward (sparse Hopper
//! under a fresh policy) the improvement step is not taken, and the metrics say why;
//! without the option the same batch takes a full step of critic noise.

use logo_algo::policy_update::StopReason;
use logo_algo::{IterationMetrics, TrainConfig, Trainer};
use logo_nn::Kernels;
use logo_testkit::{Tiny, scratch};

fn train(name: &str, skip: bool) -> Vec<IterationMetrics> {
    let dir = scratch(&format!("sparse-phase-{name}"));
    let path = Tiny::trpo()
        .with("env = \"SparseHopper-v4\"\nsamples_per_iter = 400\neval_steps = 50\nseed = 1")
        .set("num_envs", 2)
        .set("skip_improvement_without_reward", skip)
        .write(&dir.join("config.toml"));
    let config = TrainConfig::load(&path).unwrap();
    let mut trainer = Trainer::new(Kernels, config, &dir).unwrap();
    let mut rows = Vec::new();
    while !trainer.done() {
        rows.push(trainer.step().unwrap());
    }
    let _ = std::fs::remove_dir_all(&dir);
    rows
}

#[test]
fn a_batch_without_env_reward_takes_no_improvement_step_when_asked() {
    for row in train("skip", true) {
        assert_eq!(row.train_sparse_return, 0.0, "{row:?}");
        assert_eq!(row.update_stop, Some(StopReason::NoReward), "{row:?}");
        assert_eq!((row.kl, row.step_norm), (0.0, 0.0), "{row:?}");
        assert_eq!(row.mean_log_std, 0.0, "the policy moved: {row:?}");
    }
    for row in train("step", false) {
        assert_eq!(row.train_sparse_return, 0.0, "{row:?}");
        assert_ne!(row.update_stop, Some(StopReason::NoReward), "{row:?}");
        assert!(row.kl > 0.0 && row.step_norm > 0.0, "{row:?}");
    }
}

//! `skip_improvement_without_reward`: on a batch without any env reward (sparse Hopper
//! under a fresh policy) the improvement step is not taken, and the metrics say why;
//! without the option the same batch takes a full step of critic noise.

use std::path::{Path, PathBuf};

use logo_algo::policy_update::StopReason;
use logo_algo::{IterationMetrics, TrainConfig, Trainer};
use logo_nn::Kernels;

fn train(name: &str, skip: bool) -> Vec<IterationMetrics> {
    let dir: PathBuf =
        std::env::temp_dir().join(format!("logo-sparse-phase-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = format!(
        r#"
env = "SparseHopper-v4"
iterations = 2
samples_per_iter = 400
num_envs = 2
policy_hidden = [16, 16]
eval_steps = 50
seed = 1
skip_improvement_without_reward = {skip}
[critic]
hidden = [16, 16]
"#
    );
    let path = dir.join("config.toml");
    std::fs::write(&path, text).unwrap();
    let config = TrainConfig::load(Path::new(&path)).unwrap();
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

//! One row of `metrics.csv` per iteration: what the run did and where its time went.
//! Written and read back (for `--resume`) through this one struct with the `csv` crate.

use serde::{Deserialize, Serialize};

use crate::policy_update::{StopReason, UpdateStats};

/// A row of `metrics.csv`. NaN marks what an iteration did not compute (no evaluation,
/// no guidance step); the stop reasons are then empty.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct IterationMetrics {
    pub iteration: usize,
    /// Samples collected up to and including this iteration.
    pub samples: usize,
    /// Seconds since the run started (across resumes).
    pub wall_s: f64,
    pub episodes: usize,
    pub train_sparse_return: f64,
    pub train_dense_return: f64,
    /// The share of the batch's episodes that reached the goal by the run's success rule
    /// (NaN where it defines none, and in older files).
    #[serde(default = "nan")]
    pub train_success: f64,
    /// Mean dense return of the deterministic policy (NaN when not evaluated).
    pub eval_dense_return: f64,
    /// Its mean return of the trained task's own reward (the sparse one on a sparse
    /// task), by which `best.safetensors` is chosen. Absent (NaN) in files written
    /// before this column existed.
    #[serde(default = "nan")]
    pub eval_return: f64,
    /// The evaluation episodes' mean distance moved (`qpos[0]`, end minus start) and mean
    /// action RMS (as given to the env, before MuJoCo clamps it). Absent (NaN) in files
    /// written before these columns existed.
    #[serde(default = "nan")]
    pub eval_moved: f64,
    #[serde(default = "nan")]
    pub eval_action_rms: f64,
    /// The share of evaluation episodes that reached the goal, where the run's success
    /// rule defines one (`success`); NaN where it does not, and in older files.
    #[serde(default = "nan")]
    pub eval_success: f64,
    /// The improvement step: mean KL(π_k ‖ π_{k+½}), step length ‖Δθ‖, why it stopped,
    /// epochs (first-order kinds), β (`ppo-penalty`).
    pub kl: f64,
    pub step_norm: f64,
    pub update_stop: Option<StopReason>,
    pub update_epochs: usize,
    pub update_beta: f64,
    /// The guidance step, likewise (NaN / empty when it did not run).
    pub guidance_kl: f64,
    pub guidance_step_norm: f64,
    pub guidance_stop: Option<StopReason>,
    pub guidance_epochs: usize,
    pub guidance_beta: f64,
    pub delta_k: f64,
    /// The batch's mean guidance reward r_C (NaN without a guidance step).
    #[serde(default = "nan")]
    pub guidance_reward: f64,
    /// DAPG: the demonstration rows' advantage w_k = λ0·λ1^k·max Â (NaN without
    /// `[demonstration_rows]`, and in older files).
    #[serde(default = "nan")]
    pub demo_weight: f64,
    /// Mean log σ of the policy after the iteration.
    pub mean_log_std: f64,
    pub critic_loss: f64,
    pub guidance_critic_loss: f64,
    pub disc_loss: f64,
    pub t_sampling: f64,
    /// Advantages of both reward streams (critic evaluations, the guidance reward).
    pub t_advantages: f64,
    /// The critic fits (they run beside the policy steps).
    pub t_critics: f64,
    pub t_policy_step: f64,
    pub t_guidance: f64,
    pub t_discriminator: f64,
    pub t_evaluation: f64,
}

fn nan() -> f64 {
    f64::NAN
}

impl IterationMetrics {
    /// The numeric columns of `metrics.csv`, in file order: those a summary, figure or
    /// comparison can read (the stop reasons are words).
    pub fn numeric_columns() -> Vec<String> {
        let mut writer = csv::Writer::from_writer(Vec::new());
        writer
            .serialize(Self::default())
            .expect("a default row serialises");
        let text = String::from_utf8(writer.into_inner().expect("an in-memory writer"))
            .expect("csv writes UTF-8");
        let mut lines = text.lines();
        let (header, row) = (lines.next().unwrap_or(""), lines.next().unwrap_or(""));
        header
            .split(',')
            .zip(row.split(','))
            .filter(|(_, value)| value.parse::<f64>().is_ok())
            .map(|(name, _)| name.to_string())
            .collect()
    }

    /// Records the improvement step.
    pub fn improvement(&mut self, stats: &UpdateStats) {
        self.kl = stats.kl;
        self.step_norm = stats.step_norm;
        self.update_stop = Some(stats.stop);
        self.update_epochs = stats.epochs;
        self.update_beta = stats.beta;
    }

    /// Records the guidance step, or that it did not run.
    pub fn guidance(&mut self, stats: Option<&UpdateStats>) {
        match stats {
            Some(stats) => {
                self.guidance_kl = stats.kl;
                self.guidance_step_norm = stats.step_norm;
                self.guidance_stop = Some(stats.stop);
                self.guidance_epochs = stats.epochs;
                self.guidance_beta = stats.beta;
            }
            None => {
                self.guidance_kl = f64::NAN;
                self.guidance_step_norm = f64::NAN;
                self.guidance_stop = None;
                self.guidance_beta = f64::NAN;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::IterationMetrics;

    #[test]
    fn the_numeric_columns_are_the_header_less_the_stop_reasons() {
        let columns = IterationMetrics::numeric_columns();
        for name in [
            "iteration",
            "samples",
            "train_sparse_return",
            "eval_dense_return",
            "eval_success",
            "t_evaluation",
        ] {
            assert!(columns.iter().any(|c| c == name), "{name}: {columns:?}");
        }
        for name in ["update_stop", "guidance_stop"] {
            assert!(!columns.iter().any(|c| c == name), "{name}: {columns:?}");
        }
        assert_eq!(columns.first().map(String::as_str), Some("iteration"));
    }
}

//! DAPG's augmented objective (Rajeswaran et al. 2018, eq. 6): the demonstrations join
//! the improvement step's batch as extra rows, each with the advantage
//! w_k = λ0 · λ1^k · max Â (Â: the batch's normalised advantages), so that the natural
//! gradient also raises log π on them, less so every iteration. F stays the policy's own
//! (`StepBatch::demonstration_rows`). With `[init] kind = "bc"` and `[improvement] kind =
//! "npg"` this is DAPG (`configs/dapg/`).
//!
//! mjrl's code gives the demonstrations λ0·λ1^k against advantages scaled to unit
//! deviation, without the max; the paper's max Â is used here (docs/algorithms.md).

use crate::error::{Invalid, TrainError};
use std::path::PathBuf;

use burn::tensor::Tensor;
use logo_data::Demonstrations;
use logo_nn::{Engine, ObservationStats, Policy};
use serde::{Deserialize, Serialize};

use crate::policy_update::StepBatch;

/// `[demonstration_rows]`: λ0 and λ1 are required (no silent defaults for an
/// algorithm's own constants).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DemonstrationRowsConfig {
    /// The demonstrations (a Minari folder or LOGO's `.npy`); default: `[init] demos`,
    /// else `[guidance] demos`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub demos: Option<PathBuf>,
    /// The demonstrations' weight against the batch's largest advantage.
    pub lambda0: f64,
    /// Its decay per iteration (in [0, 1]).
    pub lambda1: f64,
}

impl DemonstrationRowsConfig {
    pub fn validate(&self) -> Result<(), Invalid> {
        if !(self.lambda0.is_finite() && self.lambda0 >= 0.0) {
            return Err(format!(
                "demonstration_rows.lambda0 must be a number ≥ 0, got {}",
                self.lambda0
            )
            .into());
        }
        if !(0.0..=1.0).contains(&self.lambda1) {
            return Err(format!(
                "demonstration_rows.lambda1 must be in [0, 1], got {}",
                self.lambda1
            )
            .into());
        }
        Ok(())
    }

    /// w_k = λ0 · λ1^k · max Â (never below 0: the demonstrations are never pushed away).
    pub fn weight(&self, k: usize, advantages: &[f64]) -> f64 {
        let largest = advantages.iter().copied().fold(0.0, f64::max);
        self.lambda0 * self.lambda1.powi(k.min(i32::MAX as usize) as i32) * largest
    }
}

/// The demonstrations' pairs on the host: as loaded, and as the networks see them (through
/// the run's observation statistics, where it keeps them).
pub struct DemonstrationRows {
    raw_obs: Vec<f64>,
    seen_obs: Vec<f64>,
    actions: Vec<f64>,
    obs_dim: usize,
    act_dim: usize,
}

impl DemonstrationRows {
    /// The rows of `demos`, read from `path` (named, with `key`, in an error).
    pub fn of(
        demos: &Demonstrations,
        path: &std::path::Path,
        key: &str,
    ) -> Result<Self, TrainError> {
        if demos.is_empty() {
            let empty = Invalid::Value(format!("{} holds no pairs", path.display()));
            return Err(TrainError::from(empty).at(key));
        }
        Ok(Self::new(
            demos.obs.clone(),
            demos.actions.clone(),
            demos.obs_dim,
            demos.act_dim,
        ))
    }

    /// Pairs given row-major.
    pub fn new(obs: Vec<f64>, actions: Vec<f64>, obs_dim: usize, act_dim: usize) -> Self {
        Self {
            seen_obs: obs.clone(),
            raw_obs: obs,
            actions,
            obs_dim,
            act_dim,
        }
    }

    pub fn rows(&self) -> usize {
        self.actions.len() / self.act_dim.max(1)
    }

    /// Sees the demonstrations through `stats`, as this iteration's batch is seen.
    pub fn observe_through(&mut self, stats: &ObservationStats) {
        self.seen_obs.clone_from(&self.raw_obs);
        stats.normalise(&mut self.seen_obs);
    }

    /// The improvement step's batch: the policy's rows (`obs`, `actions`, as the
    /// networks see them, with `advantages`) then the demonstrations' (with `weight`),
    /// each ratio against π_k (`policy`), so that a demonstration row's gradient is
    /// w·∇ log π(a|s).
    pub fn append<E: Engine>(
        &self,
        engine: &E,
        policy: &Policy<E>,
        (obs, actions): (&[f64], &[f64]),
        advantages: &[f64],
        weight: f64,
    ) -> StepBatch<E> {
        let rows = advantages.len() + self.rows();
        let obs = engine.rows(&[obs, &self.seen_obs].concat(), self.obs_dim);
        let actions: Tensor<E::B, 2> =
            engine.upload(&[actions, &self.actions].concat(), [rows, self.act_dim]);
        let logp_old = policy.log_prob(engine, &obs, &actions);
        let mut all = advantages.to_vec();
        all.resize(rows, weight);
        StepBatch {
            advantages: engine.upload(&all, [rows]),
            obs,
            actions,
            logp_old,
            rows,
            demonstration_rows: self.rows(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weight_is_lambda0_times_lambda1_to_the_k_times_the_largest_advantage() {
        let config = DemonstrationRowsConfig {
            demos: None,
            lambda0: 0.1,
            lambda1: 0.5,
        };
        let advantages = [-1.0, 2.0, 0.5];
        assert_eq!(config.weight(0, &advantages), 0.1 * 2.0);
        assert_eq!(config.weight(3, &advantages), 0.1 * 0.125 * 2.0);
        // Never negative: a batch whose advantages are all below 0 gives weight 0.
        assert_eq!(config.weight(0, &[-1.0, -2.0]), 0.0);
    }
}

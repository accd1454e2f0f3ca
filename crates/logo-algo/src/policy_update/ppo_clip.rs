//! `kind = "ppo-clip"`: the seed paper's Algorithm 3, early-stopping PPO-Clip. Epochs of
//! minibatch Adam on the clipped surrogate −min(r·Â, clip(r, 1 − ε, 1 + ε)·Â), stopped as
//! soon as a minibatch's mean KL from the step's starting policy exceeds λ·δ (δ: `max_kl`
//! in the improvement step, δ_k in the guidance step), or after `epochs`.
//!
//! The seed paper gives no hyperparameters. The defaults are the PPO paper's for MuJoCo
//! (Schulman et al. 2017, Table 3: ε 0.2, 10 epochs, minibatch 64, Adam lr 3e-4), the
//! gradient-norm clip 0.5 and the stop at 1.5·target of Stable-Baselines3's PPO
//! (`max_grad_norm`, `target_kl`).

use crate::error::Invalid;
use logo_nn::{Engine, Policy};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::first_order::{Ascent, minibatch_ascent};
use super::objective::{StepBatch, Surrogate};
use super::stats::{UpdateState, UpdateStats};
use crate::adam::AdamEpochs;
use crate::validate::{MAX_SAMPLES_PER_ITER, check_clip, check_count, check_positive};

/// A key left out takes its value from [`PpoClipConfig::default`] (the module's doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PpoClipConfig {
    pub clip_epsilon: f64,
    /// λ: stop once the KL exceeds λ·δ.
    pub kl_stop: f64,
    pub epochs: usize,
    pub minibatch: usize,
    pub learning_rate: f64,
    pub max_grad_norm: f64,
}

impl Default for PpoClipConfig {
    fn default() -> Self {
        Self {
            clip_epsilon: 0.2,
            kl_stop: 1.5,
            epochs: 10,
            minibatch: 64,
            learning_rate: 3e-4,
            max_grad_norm: 0.5,
        }
    }
}

impl PpoClipConfig {
    pub fn validate(&self, table: &str) -> Result<(), Invalid> {
        check_clip(&format!("{table}.clip_epsilon"), self.clip_epsilon)?;
        check_positive(&format!("{table}.kl_stop"), self.kl_stop, false)?;
        check_positive(&format!("{table}.learning_rate"), self.learning_rate, false)?;
        check_positive(&format!("{table}.max_grad_norm"), self.max_grad_norm, false)?;
        check_counts(table, self.epochs, self.minibatch)
    }
}

/// `epochs` (1..=10,000) and `minibatch` (1..=the largest batch) of a first-order kind.
pub(super) fn check_counts(table: &str, epochs: usize, minibatch: usize) -> Result<(), Invalid> {
    check_count(&format!("{table}.epochs"), epochs, 10_000)?;
    check_count(
        &format!("{table}.minibatch"),
        minibatch,
        MAX_SAMPLES_PER_ITER,
    )
}

pub(super) fn update<E: Engine>(
    config: &PpoClipConfig,
    engine: &E,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    delta: f64,
    state: &mut UpdateState,
    rng: &mut ChaCha8Rng,
) -> (Policy<E>, UpdateStats) {
    let epochs = AdamEpochs {
        epochs: config.epochs,
        minibatch: config.minibatch,
        learning_rate: config.learning_rate,
        max_grad_norm: Some(config.max_grad_norm),
    };
    let ascent = Ascent {
        surrogate: Surrogate::Clipped {
            epsilon: config.clip_epsilon,
        },
        epochs,
        kl_bound: Some(config.kl_stop * delta),
    };
    minibatch_ascent(&ascent, engine, policy, batch, &mut state.adam, rng)
}

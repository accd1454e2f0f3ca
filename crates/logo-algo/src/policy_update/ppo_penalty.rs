//! `kind = "ppo-penalty"`: the seed paper's Algorithm 4 (after Heess et al. 2017), with the
//! decaying δ_k as its KL target in the guidance step: the seed's proposed direction.
//! Epochs of minibatch Adam on −(mean(r·Â) − β·mean KL(π_start ‖ π)); then, on the whole
//! batch, β ← β·α when KL > high·δ, β ← β/α when KL < low·δ (δ: `max_kl` in the
//! improvement step, δ_k in the guidance step). β carries over between iterations.
//!
//! Defaults: β₀ = 1, α = 2, high = 1.5, low = 1/1.5 (the PPO paper's adaptive-KL rule,
//! Schulman et al. 2017 §4); epochs, minibatch, learning rate and gradient clip as
//! `ppo-clip`'s.

use crate::error::Invalid;
use logo_nn::{Engine, Policy};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::first_order::{Ascent, minibatch_ascent};
use super::objective::{StepBatch, Surrogate};
use super::ppo_clip::{PpoClipConfig, check_counts};
use super::stats::{UpdateState, UpdateStats};
use crate::adam::AdamEpochs;
use crate::validate::check_positive;

/// A key left out takes its value from [`PpoPenaltyConfig::default`] (the module's doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PpoPenaltyConfig {
    pub beta_init: f64,
    /// α: the factor β is multiplied or divided by.
    pub beta_factor: f64,
    pub kl_high: f64,
    pub kl_low: f64,
    pub epochs: usize,
    pub minibatch: usize,
    pub learning_rate: f64,
    pub max_grad_norm: f64,
}

impl Default for PpoPenaltyConfig {
    fn default() -> Self {
        let first_order = PpoClipConfig::default();
        Self {
            beta_init: 1.0,
            beta_factor: 2.0,
            kl_high: 1.5,
            kl_low: 1.0 / 1.5,
            epochs: first_order.epochs,
            minibatch: first_order.minibatch,
            learning_rate: first_order.learning_rate,
            max_grad_norm: first_order.max_grad_norm,
        }
    }
}

impl PpoPenaltyConfig {
    pub fn validate(&self, table: &str) -> Result<(), Invalid> {
        for (key, value) in [
            ("beta_init", self.beta_init),
            ("learning_rate", self.learning_rate),
            ("max_grad_norm", self.max_grad_norm),
            ("kl_low", self.kl_low),
        ] {
            check_positive(&format!("{table}.{key}"), value, false)?;
        }
        if !(self.beta_factor > 1.0 && self.beta_factor.is_finite()) {
            return Err(format!(
                "{table}.beta_factor must be a finite number > 1, got {}",
                self.beta_factor
            )
            .into());
        }
        if !(self.kl_high >= self.kl_low && self.kl_high.is_finite()) {
            return Err(format!(
                "{table}.kl_high must be finite and >= kl_low ({}), got {}",
                self.kl_low, self.kl_high
            )
            .into());
        }
        check_counts(table, self.epochs, self.minibatch)
    }

    /// β after a step that ended at mean KL `kl` with target `delta`.
    pub fn adapt(&self, beta: f64, kl: f64, delta: f64) -> f64 {
        if kl > self.kl_high * delta {
            beta * self.beta_factor
        } else if kl < self.kl_low * delta {
            beta / self.beta_factor
        } else {
            beta
        }
    }
}

pub(super) fn update<E: Engine>(
    config: &PpoPenaltyConfig,
    engine: &E,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    delta: f64,
    state: &mut UpdateState,
    rng: &mut ChaCha8Rng,
) -> (Policy<E>, UpdateStats) {
    let beta = state.beta.unwrap_or(config.beta_init);
    let epochs = AdamEpochs {
        epochs: config.epochs,
        minibatch: config.minibatch,
        learning_rate: config.learning_rate,
        max_grad_norm: Some(config.max_grad_norm),
    };
    let ascent = Ascent {
        surrogate: Surrogate::Penalised { beta },
        epochs,
        kl_bound: None,
    };
    let (moved, mut stats) = minibatch_ascent(&ascent, engine, policy, batch, &mut state.adam, rng);
    let next = config.adapt(beta, stats.kl, delta);
    state.beta = Some(next);
    stats.beta = next;
    (moved, stats)
}

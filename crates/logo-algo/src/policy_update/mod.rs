//! Policy updates: how a step moves the policy to improve a surrogate on a batch while
//! staying near where it started (KL ≈ δ). LOGO makes two per iteration (improvement,
//! then guidance), and each chooses its kind in the config:
//!
//! | kind | file | paper |
//! | --- | --- | --- |
//! | `trpo` | `trpo.rs` | LOGO's steps (Algorithm 1, eqs. 9-10): CG on F·v, step √(2δ/sᵀFs), line search |
//! | `clip-in-trpo` | `clip_in_trpo.rs` | the clipped surrogate inside that natural-gradient step: what the seed paper's code ran |
//! | `ppo-clip` | `ppo_clip.rs` | the seed paper's Algorithm 3: minibatch Adam on the clipped surrogate, stopped when KL > λδ |
//! | `ppo-penalty` | `ppo_penalty.rs` | the seed paper's Algorithm 4: the KL-penalised surrogate, β adapted around δ |
//!
//! A new kind is a file with its config struct and an `update` function of the shape
//! below, plus a variant of [`PolicyUpdateConfig`] and its arm in
//! [`PolicyUpdateConfig::update`]; the trainer does not change.

mod clip_in_trpo;
mod first_order;
pub mod objective;
mod ppo_clip;
mod ppo_penalty;
mod trpo;

pub use objective::{StepBatch, Surrogate};
pub use ppo_clip::PpoClipConfig;
pub use ppo_penalty::PpoPenaltyConfig;
pub use trpo::{TrpoConfig, fisher_rows};

use logo_nn::{Engine, Policy};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::adam::Adam;

/// A policy-update kind and its own fields (`kind = "..."` in the config table, "trpo"
/// when left out; a field of another kind is an error naming it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[serde(remote = "Self")]
pub enum PolicyUpdateConfig {
    Trpo(TrpoConfig),
    ClipInTrpo(TrpoConfig),
    PpoClip(PpoClipConfig),
    PpoPenalty(PpoPenaltyConfig),
}

impl Serialize for PolicyUpdateConfig {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        Self::serialize(self, serializer)
    }
}

impl<'de> Deserialize<'de> for PolicyUpdateConfig {
    /// As derived, with `kind` defaulting to "trpo".
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        // Through a JSON map: it holds what TOML files and the checkpoint's JSON metadata
        // (with its nulls) both hold.
        let mut fields = serde_json::Map::deserialize(deserializer)?;
        fields
            .entry("kind")
            .or_insert_with(|| serde_json::Value::String("trpo".into()));
        Self::deserialize(serde_json::Value::Object(fields)).map_err(D::Error::custom)
    }
}

impl Default for PolicyUpdateConfig {
    fn default() -> Self {
        Self::Trpo(TrpoConfig::default())
    }
}

/// What an update carries from one iteration to the next (saved for `--resume`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct UpdateState {
    /// The first-order kinds' Adam moments.
    #[serde(default)]
    pub adam: Adam,
    /// `ppo-penalty`'s KL coefficient β (`None` until its first step).
    #[serde(default)]
    pub beta: Option<f64>,
}

/// Why an update ended where it did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StopReason {
    /// The line search accepted a step.
    #[default]
    Accepted,
    /// The line search found no step that improves enough: the policy is unchanged.
    NoImprovement,
    /// The search direction was degenerate (sᵀFs ≤ 0 or not finite): unchanged.
    Degenerate,
    /// A first-order kind stopped because the KL left its bound.
    KlBound,
    /// A first-order kind ran all its epochs.
    MaxEpochs,
    /// Not run: the batch held no env reward (`skip_improvement_without_reward`).
    NoReward,
}

/// What an update did, for `metrics.csv`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct UpdateStats {
    /// Mean KL(π_before ‖ π_after) on the batch.
    pub kl: f64,
    /// ‖θ_after − θ_before‖, the step's length in parameter space.
    pub step_norm: f64,
    /// The surrogate's gain over the step (natural-gradient kinds: actual improvement).
    pub improvement: f64,
    /// Natural-gradient kinds: fraction of the full step taken (0: none). First-order
    /// kinds: Adam steps taken.
    pub steps: f64,
    /// First-order kinds: epochs begun.
    pub epochs: usize,
    pub stop: StopReason,
    /// `ppo-penalty`: β after the step's adaptation.
    pub beta: f64,
}

impl UpdateStats {
    /// Whether the step's measurements are numbers: a step that overflowed the policy's
    /// outputs leaves a non-finite KL or surrogate even where its parameters are finite.
    pub fn is_finite(&self) -> bool {
        [self.kl, self.step_norm, self.improvement, self.beta]
            .iter()
            .all(|v| v.is_finite())
    }
}

impl PolicyUpdateConfig {
    /// Moves `policy` to improve its surrogate on `batch`, keeping KL(policy ‖ result)
    /// near `delta`. `rng` shuffles minibatches (first-order kinds).
    pub fn update<E: Engine>(
        &self,
        engine: &E,
        policy: &Policy<E>,
        batch: &StepBatch<E>,
        delta: f64,
        state: &mut UpdateState,
        rng: &mut ChaCha8Rng,
    ) -> (Policy<E>, UpdateStats) {
        match self {
            Self::Trpo(config) => trpo::update(config, engine, policy, batch, delta),
            Self::ClipInTrpo(config) => clip_in_trpo::update(config, engine, policy, batch, delta),
            Self::PpoClip(config) => {
                ppo_clip::update(config, engine, policy, batch, delta, state, rng)
            }
            Self::PpoPenalty(config) => {
                ppo_penalty::update(config, engine, policy, batch, delta, state, rng)
            }
        }
    }

    /// What a config file cannot be trusted to hold; `table` names where it is.
    pub fn validate(&self, table: &str) -> Result<(), String> {
        match self {
            Self::Trpo(config) => {
                if config.clip_epsilon.is_some() {
                    return Err(format!(
                        "{table}.clip_epsilon belongs to kind \"clip-in-trpo\", not \"trpo\""
                    ));
                }
                config.validate(table)
            }
            Self::ClipInTrpo(config) => config.validate(table),
            Self::PpoClip(config) => config.validate(table),
            Self::PpoPenalty(config) => config.validate(table),
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Self::Trpo(_) => "trpo",
            Self::ClipInTrpo(_) => "clip-in-trpo",
            Self::PpoClip(_) => "ppo-clip",
            Self::PpoPenalty(_) => "ppo-penalty",
        }
    }
}

/// A count from a config: 1..=`max`; the message names the key.
pub(crate) fn check_count(key: &str, value: usize, max: usize) -> Result<(), String> {
    if value == 0 || value > max {
        return Err(format!("{key} must be in 1..={max}, got {value}"));
    }
    Ok(())
}

/// A clip range ε: in (0, 1), so that 1 − ε stays a positive ratio.
pub(crate) fn check_clip(key: &str, value: f64) -> Result<(), String> {
    if !(value > 0.0 && value < 1.0) {
        return Err(format!("{key} must be in (0, 1), got {value}"));
    }
    Ok(())
}

/// `value` must be finite and > 0 (or ≥ 0 with `allow_zero`); the message names the key.
pub(crate) fn check_positive(key: &str, value: f64, allow_zero: bool) -> Result<(), String> {
    let ok = value.is_finite() && (value > 0.0 || (allow_zero && value == 0.0));
    if ok {
        Ok(())
    } else {
        let bound = if allow_zero { ">= 0" } else { "> 0" };
        Err(format!(
            "{key} must be a finite number {bound}, got {value}"
        ))
    }
}

//! Policy updates: how a step moves the policy to improve a surrogate on a batch while
//! staying near where it started (KL ≈ δ). LOGO makes two per iteration (improvement,
//! then guidance), and each chooses its kind in the config:
//!
//! | kind | file | paper |
//! | --- | --- | --- |
//! | `trpo` | `trpo.rs` | LOGO's steps (Algorithm 1, eqs. 9-10): CG on F·v, step √(2δ/sᵀFs), line search |
//! | `npg` | `npg.rs` | the natural policy gradient, its full step taken without a line search (DAPG's step) |
//! | `clip-in-trpo` | `clip_in_trpo.rs` | the clipped surrogate inside that natural-gradient step: what the seed paper's code ran |
//! | `ppo-clip` | `ppo_clip.rs` | the seed paper's Algorithm 3: minibatch Adam on the clipped surrogate, stopped when KL > λδ |
//! | `ppo-penalty` | `ppo_penalty.rs` | the seed paper's Algorithm 4: the KL-penalised surrogate, β adapted around δ |
//!
//! A new kind is a file with its config struct and an `update` function of the shape
//! below, plus a variant of [`PolicyUpdateConfig`] and its arm in
//! [`PolicyUpdateConfig::update`]; the trainer does not change.

mod clip_in_trpo;
mod first_order;
mod npg;
pub mod objective;
mod ppo_clip;
mod ppo_penalty;
mod stats;
mod trpo;

pub use npg::NpgConfig;
pub use objective::{StepBatch, Surrogate};
pub use ppo_clip::PpoClipConfig;
pub use ppo_penalty::PpoPenaltyConfig;
pub use stats::{StopReason, UpdateState, UpdateStats};
pub use trpo::{TrpoConfig, fisher_rows};

use crate::error::Invalid;
use logo_nn::{Engine, Policy};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// A policy-update kind and its own fields (`kind = "..."` in the config table, "trpo"
/// when left out; a field of another kind is an error naming it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[serde(remote = "Self")]
pub enum PolicyUpdateConfig {
    Trpo(TrpoConfig),
    Npg(NpgConfig),
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
            Self::Npg(config) => npg::update(config, engine, policy, batch, delta),
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
    pub fn validate(&self, table: &str) -> Result<(), Invalid> {
        match self {
            Self::Trpo(config) => {
                if config.clip_epsilon.is_some() {
                    return Err(format!(
                        "{table}.clip_epsilon belongs to kind \"clip-in-trpo\", not \"trpo\""
                    )
                    .into());
                }
                config.validate(table)
            }
            Self::Npg(config) => config.validate(table),
            Self::ClipInTrpo(config) => config.validate(table),
            Self::PpoClip(config) => config.validate(table),
            Self::PpoPenalty(config) => config.validate(table),
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Self::Trpo(_) => "trpo",
            Self::Npg(_) => "npg",
            Self::ClipInTrpo(_) => "clip-in-trpo",
            Self::PpoClip(_) => "ppo-clip",
            Self::PpoPenalty(_) => "ppo-penalty",
        }
    }
}

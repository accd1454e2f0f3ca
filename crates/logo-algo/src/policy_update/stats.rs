//! What a policy update reports and carries between iterations: shared by every kind
//! (a leaf of `policy_update`, so that the kinds and the dispatch in `mod.rs` do not
//! import each other).

use serde::{Deserialize, Serialize};

use crate::adam::Adam;

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

//! `kind = "clip-in-trpo"`: PPO's clipped surrogate mean(min(r·Â, clip(r, 1 − ε, 1 + ε)·Â))
//! maximised by TRPO's natural-gradient step (CG on F·v, step size from δ, line search).
//! This is what the seed paper's code ran as "PPO" (docs/reference.md), as opposed to its
//! Algorithm 3 (`ppo-clip`). Its fields are `trpo`'s plus `clip_epsilon` (default 0.2,
//! the seed's and the PPO paper's).

use logo_nn::{Engine, Policy};

use super::objective::{StepBatch, Surrogate};
use super::ppo_clip::PpoClipConfig;
use super::stats::UpdateStats;
use super::trpo::{TrpoConfig, natural_gradient_step};

pub(super) fn update<E: Engine>(
    config: &TrpoConfig,
    engine: &E,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    delta: f64,
) -> (Policy<E>, UpdateStats) {
    let epsilon = config
        .clip_epsilon
        .unwrap_or(PpoClipConfig::default().clip_epsilon);
    natural_gradient_step(
        config,
        Surrogate::Clipped { epsilon },
        engine,
        policy,
        batch,
        delta,
    )
}

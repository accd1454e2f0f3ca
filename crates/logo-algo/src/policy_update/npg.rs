//! `kind = "npg"`: the natural policy gradient with a normalised step (Kakade 2001; the
//! step of DAPG, Rajeswaran et al. 2018): s = CG(F, g), and θ + s·√(2δ / sᵀFs) taken
//! whole, with no line search. It is TRPO's full step without TRPO's check that the
//! step improves the surrogate. With `[demonstration_rows]` (DAPG) the batch carries the
//! demonstrations as extra rows: they shape g, while F stays the policy's own.

use crate::error::Invalid;
use logo_nn::flat::dot;
use logo_nn::{Engine, FisherKind, Policy};
use serde::{Deserialize, Serialize};

use super::objective::{StepBatch, Surrogate, evaluate};
use super::stats::{StopReason, UpdateStats};
use super::trpo::{Curvature, full_step, unchanged};
use crate::validate::{check_count, check_fraction, check_positive};

/// `[improvement] kind = "npg"`'s fields: how F·s = g is solved, as `trpo`'s (and with
/// its defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NpgConfig {
    /// Added to F (times v).
    pub damping: f64,
    pub cg_iters: usize,
    /// F·v on this fraction of the policy's rows (1: all, exact).
    pub fisher_fraction: f64,
    /// The operator F·v computes: "exact" or "reference" (LOGO's code).
    pub fisher: FisherKind,
}

impl Default for NpgConfig {
    fn default() -> Self {
        Self::from(&super::TrpoConfig::default())
    }
}

/// `trpo`'s settings of the natural-gradient direction (its line search left out).
impl From<&super::TrpoConfig> for NpgConfig {
    fn from(trpo: &super::TrpoConfig) -> Self {
        Self {
            damping: trpo.damping,
            cg_iters: trpo.cg_iters,
            fisher_fraction: trpo.fisher_fraction,
            fisher: trpo.fisher,
        }
    }
}

impl NpgConfig {
    fn curvature(&self) -> Curvature {
        Curvature {
            damping: self.damping,
            cg_iters: self.cg_iters,
            fisher_fraction: self.fisher_fraction,
            fisher: self.fisher,
        }
    }

    pub fn validate(&self, table: &str) -> Result<(), Invalid> {
        check_fraction(&format!("{table}.fisher_fraction"), self.fisher_fraction)?;
        check_positive(&format!("{table}.damping"), self.damping, true)?;
        check_count(&format!("{table}.cg_iters"), self.cg_iters, 10_000)
    }
}

pub(super) fn update<E: Engine>(
    config: &NpgConfig,
    engine: &E,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    delta: f64,
) -> (Policy<E>, UpdateStats) {
    let surrogate = Surrogate::Ratio;
    let full = match full_step(config.curvature(), surrogate, engine, policy, batch, delta) {
        Ok(full) => full,
        Err(stop) => return unchanged(policy, stop),
    };
    let moved_params: Vec<f64> = full
        .theta
        .iter()
        .zip(&full.step)
        .map(|(t, s)| t + s)
        .collect();
    let moved = policy.with_params(engine, &moved_params);
    // The KL and the gain are measured on the policy's own rows: the trust region is
    // over the states it visits.
    let own = batch.rows - batch.demonstration_rows;
    let (value, kl) = if own < batch.rows {
        let rows: Vec<usize> = (0..own).collect();
        let own_batch = batch.select(engine, &rows);
        let start = full.start.select(&rows);
        let (before, _) = evaluate(engine, surrogate, policy, &own_batch, &start);
        let (after, kl) = evaluate(engine, surrogate, &moved, &own_batch, &start);
        (after - before, kl)
    } else {
        let (after, kl) = evaluate(engine, surrogate, &moved, batch, &full.start);
        (after - full.before, kl)
    };
    let stats = UpdateStats {
        kl,
        step_norm: dot(&full.step, &full.step).sqrt(),
        improvement: value,
        steps: 1.0,
        epochs: 0,
        stop: StopReason::Accepted,
        beta: 0.0,
    };
    (moved, stats)
}

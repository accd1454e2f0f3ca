//! δ_k, the guidance step's KL bound, and when it decays (LOGO's Algorithm 1, line 12, as
//! the reference code runs it: docs/reference.md).

use crate::error::Invalid;
use std::collections::VecDeque;

use serde::{Deserialize, Serialize};

/// δ_k: starts at δ_0; after the warm-up (iterations > K_δ, 0-based) it shrinks by α each
/// time the batch's mean sparse return beats the mean of the previous (up to) 10, down
/// to [`DELTA_FLOOR`]; guidance stops once δ_k is at or below [`GUIDANCE_THRESHOLD`], just
/// above the floor (docs/reference.md).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeltaSchedule {
    pub delta: f64,
    pub alpha: f64,
    pub warmup: usize,
    window: VecDeque<f64>,
}

/// The floor of δ_k (the reference's 5e-7).
pub const DELTA_FLOOR: f64 = 5e-7;
/// The guidance step runs while δ_k is above this (the reference's test, δ_k > 6e-7).
pub const GUIDANCE_THRESHOLD: f64 = 6e-7;
const WINDOW: usize = 10;

impl DeltaSchedule {
    pub fn new(delta0: f64, alpha: f64, warmup: usize) -> Self {
        Self {
            delta: delta0,
            alpha,
            warmup,
            window: VecDeque::new(),
        }
    }

    /// Feeds iteration `iteration`'s mean sparse training return.
    pub fn update(&mut self, iteration: usize, sparse_return: f64) {
        if iteration > self.warmup && !self.window.is_empty() {
            let previous = self.window.iter().sum::<f64>() / self.window.len() as f64;
            if sparse_return > previous {
                self.delta = (self.alpha * self.delta).max(DELTA_FLOOR);
            }
        }
        if self.window.len() == WINDOW {
            self.window.pop_front();
        }
        self.window.push_back(sparse_return);
    }

    /// What a resume state must hold for a run whose config starts δ at `delta0`: δ in
    /// [floor, δ_0] (it only ever shrinks), α in (0, 1], at most the window's 10 finite
    /// returns.
    pub fn check(&self, delta0: f64) -> Result<(), Invalid> {
        if !(self.delta.is_finite() && self.delta >= DELTA_FLOOR && self.delta <= delta0) {
            return Err(format!(
                "δ_k = {} is outside [{DELTA_FLOOR:e}, δ_0 = {delta0}]",
                self.delta
            )
            .into());
        }
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(format!("α = {} is outside (0, 1]", self.alpha).into());
        }
        if self.window.len() > WINDOW || self.window.iter().any(|r| !r.is_finite()) {
            return Err(format!(
                "the window of returns must hold at most {WINDOW} finite values, got {:?}",
                self.window
            )
            .into());
        }
        Ok(())
    }

    /// Whether the guidance step still runs.
    pub fn guidance_on(&self) -> bool {
        self.delta > GUIDANCE_THRESHOLD
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delta_shrinks_only_after_warmup_and_only_on_improvement() {
        let mut s = DeltaSchedule::new(0.2, 0.9, 5);
        for i in 0..=5 {
            s.update(i, i as f64); // improving, but within the warm-up
        }
        assert_eq!(s.delta, 0.2);
        s.update(6, 100.0);
        assert!((s.delta - 0.18).abs() < 1e-15);
        s.update(7, 0.0); // worse than the window's mean
        assert!((s.delta - 0.18).abs() < 1e-15);
        // A sparse return that stays 0 never shrinks δ.
        let mut zero = DeltaSchedule::new(0.01, 0.95, 0);
        for i in 0..50 {
            zero.update(i, 0.0);
        }
        assert_eq!(zero.delta, 0.01);
        // The floor, and guidance off there.
        let mut fast = DeltaSchedule::new(1e-6, 0.1, 0);
        for i in 0..5 {
            fast.update(i, i as f64);
        }
        assert_eq!(fast.delta, DELTA_FLOOR);
        assert!(!fast.guidance_on());
        // Just above the threshold guidance runs; at it, it does not.
        assert!(DeltaSchedule::new(GUIDANCE_THRESHOLD * 1.01, 0.9, 0).guidance_on());
        assert!(!DeltaSchedule::new(GUIDANCE_THRESHOLD, 0.9, 0).guidance_on());
    }
}

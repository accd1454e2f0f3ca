//! δ_k, the guidance step's KL bound, and when it decays (LOGO's Algorithm 1, line 12, as
//! the reference code runs it: docs/reference.md).

use crate::error::Invalid;
use std::collections::VecDeque;

use serde::{Deserialize, Serialize};

/// δ_k: starts at δ_0; after the warm-up (iterations > K_δ, 0-based) it shrinks by α each
/// time the batch's decay signal (its mean sparse return in LOGO) beats the mean of the
/// previous (up to) 10, down to [`DELTA_FLOOR`]; guidance stops once δ_k is at or below
/// [`GUIDANCE_THRESHOLD`], just above the floor (docs/reference.md). With a level
/// (`decay_from`) it shrinks instead at each iteration whose signal, a share of episodes
/// at the goal, is at least that level: it waits for the agent.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeltaSchedule {
    pub delta: f64,
    pub alpha: f64,
    pub warmup: usize,
    /// The level from which δ_k shrinks; absent in LOGO's rule (and in checkpoints made
    /// before it existed, which therefore load unchanged).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decay_from: Option<f64>,
    /// With a level: where the signal falls short of it, δ_k grows back by 1/α, up to
    /// this (δ_0), so that the guidance returns when the agent loses the goal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grow_back_to: Option<f64>,
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
            decay_from: None,
            grow_back_to: None,
            window: VecDeque::new(),
        }
    }

    /// The same, shrinking only at iterations whose signal reaches `level`.
    pub fn waiting(delta0: f64, alpha: f64, warmup: usize, level: f64) -> Self {
        Self {
            decay_from: Some(level),
            ..Self::new(delta0, alpha, warmup)
        }
    }

    /// The waiting schedule that also grows back, up to δ_0, where the signal falls
    /// short of `level`.
    pub fn following(delta0: f64, alpha: f64, warmup: usize, level: f64) -> Self {
        Self {
            grow_back_to: Some(delta0),
            ..Self::waiting(delta0, alpha, warmup, level)
        }
    }

    /// Feeds iteration `iteration`'s decay signal (`decay_on`: the mean sparse training
    /// return, the batch's share of episodes at the goal, or the evaluation's).
    pub fn update(&mut self, iteration: usize, signal: f64) {
        if iteration > self.warmup {
            if self.improved(signal) {
                self.delta = (self.alpha * self.delta).max(DELTA_FLOOR);
            } else if let Some(ceiling) = self.grow_back_to {
                self.delta = (self.delta / self.alpha).min(ceiling);
            }
        }
        if self.window.len() == WINDOW {
            self.window.pop_front();
        }
        self.window.push_back(signal);
    }

    /// Whether `signal` earns a shrink: at the level where there is one, else above the
    /// window's mean (LOGO's rule; never on the first signal).
    fn improved(&self, signal: f64) -> bool {
        match self.decay_from {
            Some(level) => signal >= level,
            None => {
                !self.window.is_empty()
                    && signal > self.window.iter().sum::<f64>() / self.window.len() as f64
            }
        }
    }

    /// What a resume state must hold for a run whose config starts δ at `delta0`: δ in
    /// [floor, δ_0] (it shrinks to the floor at most and grows back to δ_0 at most), α in
    /// (0, 1], at most the window's 10 finite
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
        if let Some(level) = self.decay_from
            && !(level > 0.0 && level <= 1.0)
        {
            return Err(format!("decay_from = {level} is outside (0, 1]").into());
        }
        if self.grow_back_to.is_some_and(|ceiling| ceiling != delta0) {
            return Err(format!(
                "δ_k grows back to {:?}, not to δ_0 = {delta0}",
                self.grow_back_to
            )
            .into());
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

    #[test]
    fn a_waiting_schedule_shrinks_at_the_level_and_only_there() {
        // Rising shares below the level: LOGO's rule shrinks at each; the waiting one never.
        let (mut logo, mut waiting) = (
            DeltaSchedule::new(0.01, 0.9, 2),
            DeltaSchedule::waiting(0.01, 0.9, 2, 0.9),
        );
        for i in 0..10 {
            let share = 0.05 * i as f64;
            logo.update(i, share);
            waiting.update(i, share);
        }
        assert!(logo.delta < 0.01 * 0.9_f64.powi(6));
        assert_eq!(waiting.delta, 0.01);
        // At the level, steady (not beating the window's mean): the waiting rule shrinks
        // every iteration, LOGO's not once.
        let mut steady = DeltaSchedule::new(0.01, 0.9, 0);
        steady.update(0, 0.9);
        for i in 10..13 {
            waiting.update(i, 0.9);
            steady.update(i - 9, 0.9);
        }
        assert!((waiting.delta - 0.01 * 0.9_f64.powi(3)).abs() < 1e-15);
        assert_eq!(steady.delta, 0.01);
        // Not within the warm-up, and not below the level after it.
        let mut early = DeltaSchedule::waiting(0.01, 0.9, 5, 0.5);
        for i in 0..=5 {
            early.update(i, 1.0);
        }
        early.update(6, 0.49);
        assert_eq!(early.delta, 0.01);
        assert!(early.check(0.01).is_ok());
        assert!(
            DeltaSchedule::waiting(0.01, 0.9, 5, 1.5)
                .check(0.01)
                .is_err()
        );
    }

    #[test]
    fn a_following_schedule_grows_back_below_the_level_up_to_delta0() {
        let mut s = DeltaSchedule::following(0.01, 0.5, 1, 0.9);
        s.update(0, 0.0); // within the warm-up: nothing
        s.update(1, 1.0);
        assert_eq!(s.delta, 0.01);
        for (i, share, delta) in [(2, 1.0, 0.005), (3, 0.95, 0.0025), (4, 0.5, 0.005)] {
            s.update(i, share);
            assert!(
                (s.delta - delta).abs() < 1e-15,
                "iteration {i}: {}",
                s.delta
            );
        }
        for i in 5..10 {
            s.update(i, 0.0);
        }
        assert_eq!(s.delta, 0.01); // up to δ_0, not past it
        assert!(s.check(0.01).is_ok());
        assert!(s.check(0.02).is_err());
        // The waiting schedule alone never grows back.
        let mut waiting = DeltaSchedule::waiting(0.01, 0.5, 0, 0.9);
        waiting.update(1, 1.0);
        waiting.update(2, 0.0);
        assert_eq!(waiting.delta, 0.005);
    }
}

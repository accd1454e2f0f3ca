//! The checks every config table shares, and the limits they hold values to. A leaf:
//! `config`, `critic` and `policy_update` import it, it imports none of them.

use crate::error::Invalid;

/// The largest batch (and evaluation) a run may ask for.
pub const MAX_SAMPLES_PER_ITER: usize = 10_000_000;
/// The most env copies or worker threads.
pub const MAX_ENVS: usize = 4096;
/// Evaluation episodes per iteration: each is played whole, every iteration.
pub const MAX_EVAL_EPISODES: usize = 10_000;
/// The widest hidden layer, and the most hidden layers, of any network.
pub const MAX_WIDTH: usize = 65_536;
pub const MAX_LAYERS: usize = 64;
/// The most weights between a network's hidden layers (400 MB in float64).
pub const MAX_HIDDEN_WEIGHTS: usize = 50_000_000;

/// A network's hidden sizes: each 1..=MAX_WIDTH, at most MAX_LAYERS of them.
pub fn check_widths(key: &str, hidden: &[usize]) -> Result<(), Invalid> {
    if hidden.len() > MAX_LAYERS {
        return Err(format!("{key}: {} layers, at most {MAX_LAYERS}", hidden.len()).into());
    }
    if let Some(w) = hidden.iter().find(|&&w| w == 0 || w > MAX_WIDTH) {
        return Err(format!("{key}: every layer needs 1 to {MAX_WIDTH} units, got {w}").into());
    }
    let between: usize = hidden.windows(2).map(|w| w[0] * w[1]).sum();
    if between > MAX_HIDDEN_WEIGHTS {
        return Err(format!(
            "{key}: {between} weights between hidden layers, at most {MAX_HIDDEN_WEIGHTS}"
        )
        .into());
    }
    Ok(())
}

/// A count from a config: 1..=`max`; the message names the key.
pub fn check_count(key: &str, value: usize, max: usize) -> Result<(), Invalid> {
    if value == 0 || value > max {
        return Err(format!("{key} must be in 1..={max}, got {value}").into());
    }
    Ok(())
}

/// A fraction of a batch: in (0, 1] (1: the whole batch).
pub fn check_fraction(key: &str, value: f64) -> Result<(), Invalid> {
    if !(value > 0.0 && value <= 1.0) {
        return Err(format!("{key} must be in (0, 1], got {value}").into());
    }
    Ok(())
}

/// A clip range ε: in (0, 1), so that 1 − ε stays a positive ratio.
pub fn check_clip(key: &str, value: f64) -> Result<(), Invalid> {
    if !(value > 0.0 && value < 1.0) {
        return Err(format!("{key} must be in (0, 1), got {value}").into());
    }
    Ok(())
}

/// `value` must be finite and > 0 (or ≥ 0 with `allow_zero`); the message names the key.
pub fn check_positive(key: &str, value: f64, allow_zero: bool) -> Result<(), Invalid> {
    let ok = value.is_finite() && (value > 0.0 || (allow_zero && value == 0.0));
    if ok {
        Ok(())
    } else {
        let bound = if allow_zero { ">= 0" } else { "> 0" };
        Err(format!("{key} must be a finite number {bound}, got {value}").into())
    }
}

//! Counting the floating-point work of the kernels' MLP passes (multiply-adds of their
//! matrix products and contractions, 2 per multiply-add; not tanh or bias adds), per
//! phase of a training iteration: what `logo bench iteration` turns into a compute
//! floor. Off unless [`enable`]d: then each pass adds its count, computed from its shape
//! on the calling thread, under the phase that thread is in ([`in_phase`]). A phase
//! label is per thread and restored when its scope ends, so work that rayon runs nested
//! on another phase's thread is still counted under its own phase.

use std::cell::Cell;
use std::collections::BTreeMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

static ENABLED: AtomicBool = AtomicBool::new(false);
static COUNTS: Mutex<BTreeMap<&'static str, u64>> = Mutex::new(BTreeMap::new());

thread_local! {
    static PHASE: Cell<&'static str> = const { Cell::new("other") };
}

/// Starts (or stops) counting.
pub fn enable(on: bool) {
    ENABLED.store(on, Ordering::Relaxed);
}

/// Runs `f` with the work of this thread counted under `phase`.
pub fn in_phase<R>(phase: &'static str, f: impl FnOnce() -> R) -> R {
    let previous = PHASE.replace(phase);
    let result = f();
    PHASE.set(previous);
    result
}

/// Adds `flops` to the current phase (when counting).
pub(crate) fn add(flops: u64) {
    if ENABLED.load(Ordering::Relaxed) {
        let phase = PHASE.get();
        *COUNTS
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .entry(phase)
            .or_default() += flops;
    }
}

/// The counts since the last call, by phase, and a fresh start.
pub fn take() -> BTreeMap<&'static str, u64> {
    std::mem::take(&mut *COUNTS.lock().unwrap_or_else(|p| p.into_inner()))
}

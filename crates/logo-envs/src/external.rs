//! Envs the caller brings: the Python package registers a user's Gymnasium env here under
//! an id `python:<name>`, and the trainer builds it by that id like any other (its sampler,
//! its evaluation, the run's final evaluation). This crate only keeps the makers.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, PoisonError};

use crate::env::{Env, EnvError, EnvSpec};

/// The prefix of every external id.
pub const EXTERNAL_PREFIX: &str = "python:";

/// Builds copies of one external env.
pub trait EnvMaker: Send + Sync {
    fn spec(&self) -> &EnvSpec;
    /// One new copy; building may fail (the user's code raised).
    fn build(&self) -> Result<Box<dyn Env>, EnvError>;
}

static MAKERS: Mutex<BTreeMap<String, Arc<dyn EnvMaker>>> = Mutex::new(BTreeMap::new());

/// Registers `maker` under its spec's id, which must start with [`EXTERNAL_PREFIX`] and
/// must not be in use (two runs of one process training at once name their envs apart).
pub fn register_external(maker: Arc<dyn EnvMaker>) -> Result<(), EnvError> {
    let id = maker.spec().id.clone();
    if !id.starts_with(EXTERNAL_PREFIX) || id.len() == EXTERNAL_PREFIX.len() {
        return Err(EnvError::InvalidOption(format!(
            "an external env's id is {EXTERNAL_PREFIX}<name>, got {id:?}"
        )));
    }
    let mut makers = MAKERS.lock().unwrap_or_else(PoisonError::into_inner);
    if makers.contains_key(&id) {
        return Err(EnvError::InvalidOption(format!(
            "{id} is in use by another run of this process: give this env another name"
        )));
    }
    makers.insert(id, maker);
    Ok(())
}

/// Forgets `maker` (the run that needed it is over); another maker registered under the
/// same id since stays.
pub fn unregister_external(maker: &Arc<dyn EnvMaker>) {
    let mut makers = MAKERS.lock().unwrap_or_else(PoisonError::into_inner);
    let id = &maker.spec().id;
    if makers.get(id).is_some_and(|m| Arc::ptr_eq(m, maker)) {
        makers.remove(id);
    }
}

/// The maker registered as `id`; for an id with the prefix that none is registered as, an
/// error saying where such an env comes from.
pub(crate) fn external(id: &str) -> Option<Result<Arc<dyn EnvMaker>, EnvError>> {
    if !id.starts_with(EXTERNAL_PREFIX) {
        return None;
    }
    let makers = MAKERS.lock().unwrap_or_else(PoisonError::into_inner);
    Some(makers.get(id).cloned().ok_or_else(|| {
        EnvError::InvalidOption(format!(
            "{id} is a Python env: it exists only in the Python process that trains on it \
             (logo_rl.train(..., env=...)); evaluate its checkpoints there (logo_rl.load)"
        ))
    }))
}

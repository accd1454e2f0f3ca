//! The repository's configs as presets inside the package, with the datasets they name
//! (build.rs lists them): `logo_rl.presets()`, `logo_rl.train("new-task", ...)`.

use pyo3::prelude::*;
use pyo3::types::PyBytes;

include!(concat!(env!("OUT_DIR"), "/presets.rs"));

/// Every preset: (name, its path in the repository, what it is).
#[pyfunction]
pub fn presets() -> Vec<(&'static str, &'static str, &'static str)> {
    PRESETS
        .iter()
        .map(|&(name, path, about, _)| (name, path, about))
        .collect()
}

/// The preset's config text, or None for a name that is not one.
#[pyfunction]
pub fn preset_text(name: &str) -> Option<&'static str> {
    PRESETS
        .iter()
        .find(|(n, ..)| *n == name)
        .map(|&(.., text)| text)
}

/// The files the presets name: (path in the repository, bytes).
#[pyfunction]
pub fn preset_data(py: Python<'_>) -> Vec<(&'static str, Bound<'_, PyBytes>)> {
    PRESET_DATA
        .iter()
        .map(|&(path, bytes)| (path, PyBytes::new(py, bytes)))
        .collect()
}

/// The table of methods (`logo algorithms`): (name, what it is, its paper, whether `logo
/// compare` makes it), in the order `logo compare` runs the comparable ones.
#[pyfunction]
pub fn methods() -> Vec<(&'static str, &'static str, &'static str, bool)> {
    let comparable = logo_algo::algorithms::comparable();
    let mut listed: Vec<_> = logo_algo::algorithms::METHODS
        .iter()
        .map(|m| (m.name, m.summary, m.paper, m.comparable))
        .collect();
    listed.sort_by_key(|(name, ..)| {
        comparable
            .iter()
            .position(|c| c == name)
            .unwrap_or(usize::MAX)
    });
    listed
}

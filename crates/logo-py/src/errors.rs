//! The Python exception of the Rust side's errors.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _logo_rl,
    LogoError,
    PyException,
    "An error of logo-rl's Rust side (a config, a checkpoint, an env), on one line."
);

/// anyhow's chain on one line, as `logo` prints it.
pub(crate) fn logo_error(e: &anyhow::Error) -> PyErr {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !line.contains(&text) {
            line = format!("{line}: {text}");
        }
    }
    LogoError::new_err(line)
}

/// An error of the Rust envs (an unknown id, a non-finite action) as a LogoError.
pub(crate) fn env_error(e: impl std::fmt::Display) -> PyErr {
    LogoError::new_err(e.to_string())
}

//! The Python exception of the Rust side's errors.

use logo_algo::{ConfigError, ConfigErrorKind, Invalid, TrainError};
use logo_data::DataError;
use logo_envs::EnvError;
use logo_nn::{CheckpointError, DamagedStats, ImportError};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyType;

create_exception!(
    _logo_rl,
    LogoError,
    PyException,
    "An error of logo-rl's Rust side (a config, a checkpoint, an env), on one line."
);

/// Which subclass of LogoError an error is raised as (`logo_rl/_errors.py`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `LogoFileNotFoundError`, also a `FileNotFoundError`.
    NotFound,
    /// `LogoTypeError`, also a `TypeError`.
    Type,
    /// `LogoValueError`, also a `ValueError`.
    Value,
    /// `LogoError` itself.
    Other,
}

impl Kind {
    fn of_config(kind: ConfigErrorKind) -> Self {
        match kind {
            ConfigErrorKind::NotFound => Self::NotFound,
            ConfigErrorKind::Type => Self::Type,
            ConfigErrorKind::Value => Self::Value,
            ConfigErrorKind::Unreadable => Self::Other,
        }
    }

    /// A missing model is a missing file; an unknown id, a bad option, an action or a
    /// state of the wrong size or not finite are bad values; the rest (a model MuJoCo
    /// refuses, a step before reset, a Python env's own error) are LogoError itself.
    fn of_env(e: &EnvError) -> Self {
        match e {
            EnvError::ModelMissing(_) => Self::NotFound,
            EnvError::UnknownId(..)
            | EnvError::InvalidOption(_)
            | EnvError::ActionLength { .. }
            | EnvError::NonFiniteAction { .. }
            | EnvError::StateLength { .. }
            | EnvError::RngPosition(_) => Self::Value,
            EnvError::ModelLoad { .. }
            | EnvError::NeedsReset { .. }
            | EnvError::NotAtReset(_)
            | EnvError::External { .. } => Self::Other,
        }
    }

    /// A missing file is a missing file; a value a check refuses, a file whose contents
    /// are wrong (a demonstrations file, a checkpoint, its resume state) are bad values;
    /// a busy run folder, a step that left NaN, a failed write are LogoError itself.
    fn of_train(e: &TrainError) -> Self {
        match e.cause() {
            TrainError::Config(e) => Self::of_config(e.kind),
            TrainError::Env(e) => Self::of_env(e),
            TrainError::Io { source, .. } => Self::of_io(source),
            TrainError::Csv { source, .. } => match source.kind() {
                csv::ErrorKind::Io(e) => Self::of_io(e),
                _ => Self::Value,
            },
            TrainError::Invalid(e) => Self::of_invalid(e),
            TrainError::Data(e) => Self::of_data(e),
            TrainError::Checkpoint(e) => Self::of_checkpoint(e),
            TrainError::Import(_) | TrainError::Stats(_) | TrainError::Resume(_) => Self::Value,
            TrainError::Toml(_)
            | TrainError::Json(_)
            | TrainError::Threads { .. }
            | TrainError::Busy(_)
            | TrainError::NonFinite(_) => Self::Other,
            // `cause()` has looked through these to what went wrong.
            TrainError::At { .. } | TrainError::Stopped { .. } => Self::Other,
        }
    }

    /// A file that is not there; any other I/O failure is LogoError itself.
    fn of_io(e: &std::io::Error) -> Self {
        match e.kind() {
            std::io::ErrorKind::NotFound => Self::NotFound,
            _ => Self::Other,
        }
    }

    fn of_invalid(e: &Invalid) -> Self {
        match e {
            Invalid::Missing(_) => Self::NotFound,
            Invalid::Value(_) => Self::Value,
        }
    }

    /// A demonstrations file that is not there, or whose contents are wrong.
    fn of_data(e: &DataError) -> Self {
        match e {
            DataError::Io { source, .. } => Self::of_io(source),
            _ => Self::Value,
        }
    }

    /// A checkpoint that is not there, or whose contents are wrong.
    fn of_checkpoint(e: &CheckpointError) -> Self {
        match e {
            CheckpointError::Io { source, .. } => Self::of_io(source),
            _ => Self::Value,
        }
    }

    /// The kind of the first error in a chain that says one: a run's error by its
    /// variant, a missing file, a config's mistake, an env's, a file's contents, a value
    /// refused.
    fn of_chain<'a>(chain: impl Iterator<Item = &'a (dyn std::error::Error + 'static)>) -> Self {
        for cause in chain {
            if let Some(e) = cause.downcast_ref::<TrainError>() {
                return Self::of_train(e);
            } else if let Some(e) = cause.downcast_ref::<std::io::Error>() {
                if e.kind() == std::io::ErrorKind::NotFound {
                    return Self::NotFound;
                }
            } else if let Some(e) = cause.downcast_ref::<ConfigError>() {
                return Self::of_config(e.kind);
            } else if let Some(e) = cause.downcast_ref::<EnvError>() {
                return Self::of_env(e);
            } else if let Some(e) = cause.downcast_ref::<Invalid>() {
                return Self::of_invalid(e);
            } else if let Some(e) = cause.downcast_ref::<DataError>() {
                return Self::of_data(e);
            } else if let Some(e) = cause.downcast_ref::<CheckpointError>() {
                return Self::of_checkpoint(e);
            } else if cause.is::<ImportError>() || cause.is::<DamagedStats>() {
                return Self::Value;
            }
        }
        Self::Other
    }
}

/// `message` raised as the LogoError subclass of `kind`.
pub(crate) fn raised(kind: Kind, message: String) -> PyErr {
    let class = match kind {
        Kind::NotFound => "LogoFileNotFoundError",
        Kind::Type => "LogoTypeError",
        Kind::Value => "LogoValueError",
        Kind::Other => return LogoError::new_err(message),
    };
    Python::attach(|py| {
        let class = py
            .import("logo_rl._errors")
            .and_then(|m| m.getattr(class))
            .and_then(|c| c.cast_into::<PyType>().map_err(PyErr::from));
        match class {
            Ok(class) => PyErr::from_type(class, message),
            // Imported without the package around it: the base class still says it.
            Err(_) => LogoError::new_err(message),
        }
    })
}

/// A value the package refuses (an array of the wrong shape, a bad argument): a
/// `LogoValueError`, which is also a `ValueError`.
pub(crate) fn value_error(message: impl Into<String>) -> PyErr {
    raised(Kind::Value, message.into())
}

/// A file the package was given that is not there: a `LogoFileNotFoundError`.
pub(crate) fn not_found(message: impl Into<String>) -> PyErr {
    raised(Kind::NotFound, message.into())
}

/// What a check refused, raised by its kind (a missing file, a value).
pub(crate) fn invalid(e: &Invalid, message: String) -> PyErr {
    raised(Kind::of_invalid(e), message)
}

/// A config that cannot be used, raised by its kind.
pub(crate) fn config_error(e: &ConfigError, message: String) -> PyErr {
    raised(Kind::of_config(e.kind), message)
}

/// anyhow's chain on one line, as `logo` prints it, raised by the kind of its first
/// cause that says one.
pub(crate) fn logo_error(e: &anyhow::Error) -> PyErr {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !line.contains(&text) {
            line = format!("{line}: {text}");
        }
    }
    raised(Kind::of_chain(e.chain()), in_python_words(&line))
}

/// An error of the Rust envs (an unknown id, a non-finite action), raised by its kind.
pub(crate) fn env_error(e: EnvError) -> PyErr {
    raised(Kind::of_env(&e), e.to_string())
}

/// A renderer's failure (no GL, no display): LogoError itself.
pub(crate) fn render_error(e: impl std::fmt::Display) -> PyErr {
    raised(Kind::Other, e.to_string())
}

/// `logo train`'s flags and the keyword arguments of `logo_rl.train` that say the same.
const FLAG_WORDS: [(&str, &str); 8] = [
    ("--resume", "resume="),
    ("--out", "out="),
    ("--iterations", "iterations="),
    ("--config", "config="),
    ("--seed", "seed="),
    ("--engine", "engine="),
    ("--backend", "backend="),
    ("--dtype", "dtype="),
];

/// A line of the trainer's (an error, a progress line) in Python's words: each of
/// `logo train`'s flags named as the keyword argument that does the same.
pub(crate) fn in_python_words(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut rest = line;
    'scan: while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let tail = &rest[at..];
        for (flag, word) in FLAG_WORDS {
            let after = &tail[flag.len().min(tail.len())..];
            let whole = !after.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '-');
            if tail.starts_with(flag) && whole {
                out.push_str(word);
                // "--resume runs/a" reads "resume=runs/a"; a flag named in a sentence
                // ("--iterations extends it") keeps its space.
                let value = after.strip_prefix(' ').filter(|v| {
                    v.starts_with(|c: char| c.is_ascii_digit() || "/.~".contains(c))
                        || v.split(' ').next().is_some_and(|w| w.contains('/'))
                });
                rest = value.unwrap_or(after);
                continue 'scan;
            }
        }
        out.push_str("--");
        rest = &tail[2..];
    }
    out.push_str(rest);
    out
}

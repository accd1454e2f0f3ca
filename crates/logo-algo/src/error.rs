//! What stops a config check, a run or a resume, as values a caller can tell apart: the
//! Python package raises `FileNotFoundError`, `ValueError` or `LogoError` by the variant,
//! and the tests match on it. The words stay those the message always had; the variant
//! says what kind of mistake it is.

use std::fmt::Display;
use std::path::PathBuf;

use logo_data::DataError;
use logo_envs::EnvError;
use logo_nn::{CheckpointError, DamagedStats, ImportError};

/// A config that cannot be used: which file (or `<config dict>`), what kind of mistake,
/// and the message naming the key.
#[derive(Debug, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct ConfigError {
    pub path: PathBuf,
    pub kind: ConfigErrorKind,
    pub message: String,
}

/// What kind of mistake a [`ConfigError`] is, for callers that act on it: the Python
/// package raises `FileNotFoundError`, `TypeError` or `ValueError` by it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConfigErrorKind {
    /// The config file, or a file one of its keys names, is not there.
    NotFound,
    /// It is there but could not be read (permissions, not UTF-8).
    Unreadable,
    /// A value of the wrong type for its key.
    Type,
    /// Anything else: not TOML, an unknown or missing key, a value out of its range.
    Value,
}

/// What a check refuses; the message names the key and what was expected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Invalid {
    /// A value out of its range, or a combination of values the trainer cannot run.
    #[error("{0}")]
    Value(String),
    /// A file that a key names and that is not there.
    #[error("{0}")]
    Missing(String),
}

impl Invalid {
    pub fn new(message: impl Into<String>) -> Self {
        Self::Value(message.into())
    }

    /// The words, naming the key.
    pub fn message(&self) -> &str {
        match self {
            Self::Value(m) | Self::Missing(m) => m,
        }
    }
}

/// Anything that stops a run. Each wrapped error stays the source of this one, so a
/// caller walking the chain finds the config's, the env's or the file's own error.
#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    /// A config that cannot be used (its file, its kind of mistake).
    #[error("{0}")]
    Config(#[from] ConfigError),
    /// A value, or a combination, that a check refuses.
    #[error("{0}")]
    Invalid(#[from] Invalid),
    /// An env that cannot be made or stepped.
    #[error("{0}")]
    Env(#[from] EnvError),
    /// A checkpoint that cannot be read or written.
    #[error("{0}")]
    Checkpoint(#[from] CheckpointError),
    /// A LOGO `.pt` policy that cannot be read.
    #[error("{0}")]
    Import(#[from] ImportError),
    /// A demonstrations file that cannot be used.
    #[error("{0}")]
    Data(#[from] DataError),
    /// Observation statistics a damaged checkpoint holds.
    #[error("{0}")]
    Stats(#[from] DamagedStats),
    /// A file or folder that could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A CSV file (metrics.csv) that could not be read or written.
    #[error("{}: {source}", path.display())]
    Csv { path: PathBuf, source: csv::Error },
    /// A config that could not be written as TOML.
    #[error("{0}")]
    Toml(#[from] toml::ser::Error),
    /// A result that could not be written as JSON.
    #[error("{0}")]
    Json(#[from] serde_json::Error),
    /// The worker threads `threads` asks for could not be started.
    #[error("cannot start {threads} worker threads: {source}")]
    Threads {
        threads: usize,
        source: rayon::ThreadPoolBuildError,
    },
    /// A checkpoint's resume state that does not fit the checkpoint or its run.
    #[error("{0}")]
    Resume(String),
    /// A run folder that holds another run, or that another process is training.
    #[error("{0}")]
    Busy(String),
    /// A step that left a non-finite number (NaN or ±inf).
    #[error("{0}")]
    NonFinite(String),
    /// `source`, with where it happened in front of it (a file, a key, an iteration).
    #[error("{context}: {source}")]
    At {
        context: String,
        source: Box<TrainError>,
    },
    /// `source`, and what the run kept when it stopped.
    #[error("{source}; the run stopped ({kept})")]
    Stopped {
        source: Box<TrainError>,
        kept: String,
    },
}

impl TrainError {
    /// A file or folder's I/O error, with its path.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }

    /// This error with where it happened in front of it.
    pub fn at(self, context: impl Display) -> Self {
        Self::At {
            context: context.to_string(),
            source: Box::new(self),
        }
    }

    /// The error under the places and the stop it was wrapped in: what went wrong.
    pub fn cause(&self) -> &TrainError {
        match self {
            Self::At { source, .. } | Self::Stopped { source, .. } => source.cause(),
            other => other,
        }
    }
}

/// [`TrainError::at`] for a result whose error becomes a [`TrainError`].
pub trait At<T> {
    fn at(self, context: impl Display) -> Result<T, TrainError>;
}

impl<T, E: Into<TrainError>> At<T> for Result<T, E> {
    fn at(self, context: impl Display) -> Result<T, TrainError> {
        self.map_err(|e| e.into().at(context))
    }
}

impl From<String> for Invalid {
    fn from(message: String) -> Self {
        Self::Value(message)
    }
}

impl From<&str> for Invalid {
    fn from(message: &str) -> Self {
        Self::Value(message.to_string())
    }
}

//! Every way a dataset file can be wrong, each naming the file and what was expected.

use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum DataError {
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: not a .npy array of floats: {reason}", path.display())]
    Npy { path: PathBuf, reason: String },
    #[error("{}: rows have {found} columns, expected obs {obs_dim} + action {act_dim} = {}", path.display(), obs_dim + act_dim)]
    Columns {
        path: PathBuf,
        found: usize,
        obs_dim: usize,
        act_dim: usize,
    },
    #[error("{}: row {row}, column {column} ({field}) is {value}, expected a finite number", path.display())]
    NonFinite {
        path: PathBuf,
        row: usize,
        column: usize,
        field: &'static str,
        value: f64,
    },
    #[error("{}: no demonstration rows", path.display())]
    Empty { path: PathBuf },
    #[error("{}: not a readable HDF5 file: {reason}", path.display())]
    Hdf5 { path: PathBuf, reason: String },
    #[error("{}: {}{field}: {reason}", path.display(), episode.map(|e| format!("episode {e}, ")).unwrap_or_default())]
    Field {
        path: PathBuf,
        episode: Option<usize>,
        field: String,
        reason: String,
    },
}

impl DataError {
    pub(crate) fn field(path: &Path, episode: Option<usize>, field: &str, reason: &str) -> Self {
        Self::Field {
            path: path.to_path_buf(),
            episode,
            field: field.to_string(),
            reason: reason.to_string(),
        }
    }
}

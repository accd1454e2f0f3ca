//! Demonstration datasets: episodes in Minari's HDF5 layout ([`minari`]), imports from
//! the LOGO `.npy` arrays and D4RL files ([`import`]), validation, and the state-action
//! pairs LOGO's discriminator trains on ([`Demonstrations`]).

pub mod dataset;
mod error;
pub mod import;
pub mod minari;
mod npy;

use std::path::{Path, PathBuf};

pub use dataset::{Dataset, Episode};
pub use error::DataError;
pub use minari::{is_minari_dir, read_minari, write_minari};
pub use npy::{NpyArray, read_npy, write_npy};

/// State-action pairs from demonstrations, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Demonstrations {
    pub obs_dim: usize,
    pub act_dim: usize,
    pub obs: Vec<f64>,
    pub actions: Vec<f64>,
    pub source: PathBuf,
}

impl Demonstrations {
    pub fn len(&self) -> usize {
        self.obs.len() / self.obs_dim.max(1)
    }

    pub fn is_empty(&self) -> bool {
        self.obs.is_empty()
    }

    /// Loads demonstrations from a Minari dataset folder or a LOGO `.npy` array, checking
    /// the dims against the env's.
    /// Demonstrations for `env_id` (a Minari folder, or LOGO's `.npy`): dims must match,
    /// and a dataset that names the env it was recorded in must name the same env family.
    pub fn load(
        path: &Path,
        env_id: &str,
        obs_dim: usize,
        act_dim: usize,
    ) -> Result<Self, DataError> {
        if !path.is_dir() {
            return Self::from_npy(path, obs_dim, act_dim);
        }
        let dataset = read_minari(path)?;
        dataset.check_dims(path, obs_dim, act_dim)?;
        dataset.check_env(path, env_id)?;
        Ok(Self::from_dataset(&dataset, path))
    }

    /// Every (observation, action) pair of every episode (final observations excluded).
    pub fn from_dataset(dataset: &Dataset, source: &Path) -> Self {
        let (mut obs, mut actions) = (Vec::new(), Vec::new());
        for ep in &dataset.episodes {
            obs.extend_from_slice(&ep.observations[..ep.steps() * dataset.obs_dim]);
            actions.extend_from_slice(&ep.actions);
        }
        Self {
            obs_dim: dataset.obs_dim,
            act_dim: dataset.act_dim,
            obs,
            actions,
            source: source.to_path_buf(),
        }
    }

    /// Reads a `[rows, obs_dim + act_dim]` float `.npy` array of `[obs ‖ action]` rows,
    /// checking the width against the env's dims and every value for finiteness.
    pub fn from_npy(path: &Path, obs_dim: usize, act_dim: usize) -> Result<Self, DataError> {
        let array = read_npy(path)?;
        let cols = if array.shape.len() == 2 {
            array.shape[1]
        } else {
            0
        };
        if cols != obs_dim + act_dim {
            return Err(DataError::Columns {
                path: path.to_path_buf(),
                found: cols,
                obs_dim,
                act_dim,
            });
        }
        if array.shape[0] == 0 {
            return Err(DataError::Empty {
                path: path.to_path_buf(),
            });
        }
        let mut obs = Vec::with_capacity(array.shape[0] * obs_dim);
        let mut actions = Vec::with_capacity(array.shape[0] * act_dim);
        for (row, values) in array.data.chunks(cols).enumerate() {
            if let Some(column) = values.iter().position(|v| !v.is_finite()) {
                let field = if column < obs_dim {
                    "observation"
                } else {
                    "action"
                };
                return Err(DataError::NonFinite {
                    path: path.to_path_buf(),
                    row,
                    column,
                    field,
                    value: values[column],
                });
            }
            obs.extend_from_slice(&values[..obs_dim]);
            actions.extend_from_slice(&values[obs_dim..]);
        }
        Ok(Self {
            obs_dim,
            act_dim,
            obs,
            actions,
            source: path.to_path_buf(),
        })
    }
}

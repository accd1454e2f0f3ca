//! `logo_rl.record`'s writer: episodes played in Python, written by logo-data as a Minari
//! dataset folder (Python's `minari` reads it; no `minari[create]` and its jax needed).

use std::path::PathBuf;

use logo_data::minari::box_space;
use logo_data::{Dataset, Episode, write_minari};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use serde_json::{Map, Value};

use crate::errors::LogoError;

/// One episode from Python: observations `[steps + 1, obs_dim]`, actions
/// `[steps, act_dim]`, the env's rewards, terminations and truncations `[steps]`.
type PyEpisode<'py> = (
    PyReadonlyArray2<'py, f64>,
    PyReadonlyArray2<'py, f64>,
    PyReadonlyArray1<'py, f64>,
    Vec<bool>,
    Vec<bool>,
);

fn values(array: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<f64>> {
    Ok(array
        .as_slice()
        .map_err(|e| PyValueError::new_err(e.to_string()))?
        .to_vec())
}

/// Writes `episodes` as the Minari dataset folder `dir` (`dir/data/main_data.hdf5`,
/// `metadata.json`) with the env's id and action space.
#[pyfunction]
#[pyo3(signature = (dir, episodes, *, dataset_id, env_id, action_low, action_high))]
pub fn write_dataset(
    dir: PathBuf,
    episodes: Vec<PyEpisode<'_>>,
    dataset_id: &str,
    env_id: &str,
    action_low: Vec<f64>,
    action_high: Vec<f64>,
) -> PyResult<()> {
    let (Some(first), act_dim) = (episodes.first(), action_low.len()) else {
        return Err(PyValueError::new_err("no episodes to write"));
    };
    let obs_dim = first.0.shape()[1];
    let mut parts = Vec::with_capacity(episodes.len());
    for (observations, actions, rewards, terminations, truncations) in &episodes {
        parts.push(Episode {
            observations: values(observations)?,
            actions: values(actions)?,
            rewards: rewards
                .as_slice()
                .map_err(|e| PyValueError::new_err(e.to_string()))?
                .to_vec(),
            terminations: terminations.clone(),
            truncations: truncations.clone(),
        });
    }
    let mut metadata = Map::new();
    metadata.insert("dataset_id".into(), dataset_id.into());
    metadata.insert("logo_env_id".into(), env_id.into());
    metadata.insert(
        "action_space".into(),
        Value::from(box_space(&action_low, &action_high)),
    );
    let dataset = Dataset::checked(obs_dim, act_dim, parts, metadata, &dir)
        .map_err(|e| LogoError::new_err(e.to_string()))?;
    write_minari(&dataset, &dir).map_err(|e| LogoError::new_err(e.to_string()))
}

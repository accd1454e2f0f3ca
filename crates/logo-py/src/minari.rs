//! `logo_rl.record`'s writer: episodes played in Python, written by logo-data as a Minari
//! dataset folder (Python's `minari` reads it; no `minari[create]` and its jax needed).

use std::path::PathBuf;

use logo_data::minari::typed_box_space;
use logo_data::{Dataset, Episode, write_minari};
use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use serde_json::{Map, Value};

use crate::errors::{Kind, LogoError, not_found, raised, value_error};

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
        .map_err(|e| value_error(e.to_string()))?
        .to_vec())
}

/// A Box space as the env declares it: its bounds and its NumPy dtype.
type Space = (Vec<f64>, Vec<f64>, String);

/// Writes `episodes` as the Minari dataset folder `dir` (`dir/data/main_data.hdf5`,
/// `metadata.json`) with the env's id and spaces, and `summary_json` (the recording's
/// returns and success rate) as the metadata's `logo_recording`.
#[pyfunction]
#[pyo3(signature = (dir, episodes, *, dataset_id, env_id, observation_space, action_space, summary_json))]
pub fn write_dataset(
    dir: PathBuf,
    episodes: Vec<PyEpisode<'_>>,
    dataset_id: &str,
    env_id: &str,
    observation_space: Space,
    action_space: Space,
    summary_json: &str,
) -> PyResult<()> {
    let (Some(first), act_dim) = (episodes.first(), action_space.0.len()) else {
        return Err(value_error("no episodes to write"));
    };
    let summary: Value = serde_json::from_str(summary_json)
        .map_err(|e| value_error(format!("summary_json: {e}")))?;
    let obs_dim = first.0.shape()[1];
    let mut parts = Vec::with_capacity(episodes.len());
    for (observations, actions, rewards, terminations, truncations) in &episodes {
        parts.push(Episode {
            observations: values(observations)?,
            actions: values(actions)?,
            rewards: rewards
                .as_slice()
                .map_err(|e| value_error(e.to_string()))?
                .to_vec(),
            terminations: terminations.clone(),
            truncations: truncations.clone(),
        });
    }
    let mut metadata = Map::new();
    metadata.insert("dataset_id".into(), dataset_id.into());
    metadata.insert("logo_env_id".into(), env_id.into());
    for (key, (low, high, dtype)) in [
        ("observation_space", &observation_space),
        ("action_space", &action_space),
    ] {
        metadata.insert(key.into(), Value::from(typed_box_space(low, high, dtype)));
    }
    metadata.insert("logo_recording".into(), summary);
    let dataset = Dataset::checked(obs_dim, act_dim, parts, metadata, &dir)
        .map_err(|e| raised(Kind::Value, e.to_string()))?;
    write_minari(&dataset, &dir).map_err(|e| LogoError::new_err(e.to_string()))
}

/// One episode for Python: observations `[steps + 1, obs_dim]`, actions `[steps,
/// act_dim]`, rewards, terminations and truncations `[steps]`.
type ReadEpisode<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Vec<bool>,
    Vec<bool>,
);

/// A Minari dataset folder read by logo-data (no `minari` package needed): its episodes
/// and its metadata as JSON. A folder that does not exist is a FileNotFoundError.
#[pyfunction]
pub fn read_dataset<'py>(
    py: Python<'py>,
    dir: PathBuf,
) -> PyResult<(Vec<ReadEpisode<'py>>, String)> {
    if !dir.exists() {
        return Err(not_found(format!(
            "{}: no such dataset folder",
            dir.display()
        )));
    }
    // A folder that is there but not a dataset this reads: a bad value.
    let dataset = logo_data::read_minari(&dir).map_err(|e| raised(Kind::Value, e.to_string()))?;
    let (obs_dim, act_dim) = (dataset.obs_dim, dataset.act_dim);
    let mut out = Vec::with_capacity(dataset.episodes.len());
    for episode in &dataset.episodes {
        let steps = episode.steps();
        let shaped = |values: &[f64], rows: usize, cols: usize| {
            PyArray1::from_slice(py, values).reshape([rows, cols])
        };
        out.push((
            shaped(&episode.observations, steps + 1, obs_dim)?,
            shaped(&episode.actions, steps, act_dim)?,
            PyArray1::from_slice(py, &episode.rewards),
            episode.terminations.clone(),
            episode.truncations.clone(),
        ));
    }
    let metadata = serde_json::to_string(&Value::Object(dataset.metadata))
        .map_err(|e| value_error(e.to_string()))?;
    Ok((out, metadata))
}

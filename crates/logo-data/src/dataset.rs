//! Episodes in the Minari layout: T+1 observations, T actions, rewards, terminations and
//! truncations per episode, plus the dataset's metadata.

use std::path::Path;

use serde_json::{Map, Value};

use crate::DataError;

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Episode {
    /// `(steps + 1) * obs_dim` values, row-major: the last row is the final observation.
    pub observations: Vec<f64>,
    /// `steps * act_dim` values.
    pub actions: Vec<f64>,
    pub rewards: Vec<f64>,
    pub terminations: Vec<bool>,
    pub truncations: Vec<bool>,
}

impl Episode {
    pub fn steps(&self) -> usize {
        self.rewards.len()
    }

    pub fn total_reward(&self) -> f64 {
        self.rewards.iter().sum()
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    pub obs_dim: usize,
    pub act_dim: usize,
    pub episodes: Vec<Episode>,
    /// `metadata.json`: Minari's keys (dataset_id, minari_version, spaces, totals, ...)
    /// and logo-rl's own (`logo_*`): provenance, per-episode returns.
    pub metadata: Map<String, Value>,
}

impl Dataset {
    /// A dataset from its parts, validated; `source` names it in errors.
    pub fn checked(
        obs_dim: usize,
        act_dim: usize,
        episodes: Vec<Episode>,
        metadata: Map<String, Value>,
        source: &Path,
    ) -> Result<Self, DataError> {
        let dataset = Self {
            obs_dim,
            act_dim,
            episodes,
            metadata,
        };
        dataset.validate(source)?;
        Ok(dataset)
    }

    pub fn total_steps(&self) -> usize {
        self.episodes.iter().map(Episode::steps).sum()
    }

    /// The env this dataset was made in, if its metadata says.
    pub fn env_id(&self) -> Option<&str> {
        self.metadata.get("logo_env_id").and_then(Value::as_str)
    }

    /// Checks every episode: non-empty, lengths consistent with its step count, finite
    /// values, exactly one end flag on the last step at most. `path` names the source in
    /// the error.
    pub fn validate(&self, path: &Path) -> Result<(), DataError> {
        if self.obs_dim == 0 || self.act_dim == 0 {
            return Err(DataError::field(
                path,
                None,
                "observations/actions",
                "zero-width rows",
            ));
        }
        if self.episodes.is_empty() {
            return Err(DataError::Empty {
                path: path.to_path_buf(),
            });
        }
        for (i, ep) in self.episodes.iter().enumerate() {
            let t = ep.steps();
            let bad = |field: &str, reason: String| DataError::field(path, Some(i), field, &reason);
            if t == 0 {
                return Err(bad("rewards", "empty episode (0 steps)".into()));
            }
            let checks = [
                (
                    "observations",
                    ep.observations.len(),
                    (t + 1) * self.obs_dim,
                ),
                ("actions", ep.actions.len(), t * self.act_dim),
                ("terminations", ep.terminations.len(), t),
                ("truncations", ep.truncations.len(), t),
            ];
            for (field, found, expected) in checks {
                if found != expected {
                    return Err(bad(
                        field,
                        format!("{found} values, expected {expected} for {t} steps"),
                    ));
                }
            }
            // Only the last step may end the episode, with one flag (terminated or
            // truncated), not both.
            let flagged = |k: usize| ep.terminations[k] || ep.truncations[k];
            if let Some(k) = (0..t - 1).find(|&k| flagged(k)) {
                return Err(bad(
                    if ep.terminations[k] {
                        "terminations"
                    } else {
                        "truncations"
                    },
                    format!("step {k} of {t} ends the episode before its last step"),
                ));
            }
            if ep.terminations[t - 1] && ep.truncations[t - 1] {
                return Err(bad(
                    "terminations/truncations",
                    "both set on the last step, expected one".into(),
                ));
            }
            for (field, values, width) in [
                ("observations", &ep.observations, self.obs_dim),
                ("actions", &ep.actions, self.act_dim),
                ("rewards", &ep.rewards, 1),
            ] {
                if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                    return Err(bad(
                        field,
                        format!(
                            "row {}, column {} is {}, expected a finite number",
                            k / width,
                            k % width,
                            values[k]
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Checks the env the dataset names (if any) against `env_id`: the same family
    /// (`SparseHopper-v4` and `Hopper-v5` are both Hopper; Walker2d and HalfCheetah, with
    /// equal dims, are not).
    pub fn check_env(&self, path: &Path, env_id: &str) -> Result<(), DataError> {
        // A Python env (`python:<name>`, logo_envs::EXTERNAL_PREFIX) has a name of its
        // user's choosing: the dims are what can be checked.
        if env_id.starts_with("python:") {
            return Ok(());
        }
        let family = |id: &str| {
            let id = id.strip_prefix("Sparse").unwrap_or(id);
            id.rsplit_once("-v")
                .map_or(id, |(name, _)| name)
                .to_string()
        };
        match self.env_id() {
            Some(recorded) if family(recorded) != family(env_id) => Err(DataError::field(
                path,
                None,
                "logo_env_id",
                &format!("recorded in {recorded}, but the run's env is {env_id}"),
            )),
            _ => Ok(()),
        }
    }

    /// Checks the dims against an env's.
    pub fn check_dims(&self, path: &Path, obs_dim: usize, act_dim: usize) -> Result<(), DataError> {
        if (self.obs_dim, self.act_dim) != (obs_dim, act_dim) {
            return Err(DataError::field(
                path,
                None,
                "observations/actions",
                &format!(
                    "dims ({}, {}), expected the env's ({obs_dim}, {act_dim})",
                    self.obs_dim, self.act_dim
                ),
            ));
        }
        Ok(())
    }
}

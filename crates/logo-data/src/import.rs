//! Importing demonstrations from other layouts into a [`Dataset`].
//!
//! - The LOGO paper's `.npy` arrays: rows `[obs ‖ action]`, no episode markers, no
//!   rewards, no final observations. Episodes are split by [`split_at_resets`].
//! - D4RL-style flat HDF5: `observations`, `actions`, `rewards`, `terminals`, `timeouts`
//!   (optionally `next_observations`) over all steps; an episode ends at a terminal or a
//!   timeout.

use std::path::Path;

use serde_json::{Map, Value};

use crate::dataset::{Dataset, Episode};
use crate::minari::{read_flags, read_table};
use crate::{DataError, Demonstrations};

/// Where an env's observation starts an episode: the initial pose and, per dimension, how
/// far Gymnasium's reset noise can move it. Dimensions with `f64::INFINITY` are not
/// checked (constraint forces), `position_dims` says which are positions (for the jump
/// test).
pub struct ResetPose {
    pub center: Vec<f64>,
    pub tolerance: Vec<f64>,
    pub position_dims: std::ops::Range<usize>,
}

/// The reset pose of the four LOGO envs in their v2/v4 observation layouts (what the LOGO
/// demonstrations use), from Gymnasium's reset rules:
/// - Hopper, Walker2d: qpos and qvel + U(±0.005); obs = qpos[1:] ‖ qvel, z starts at 1.25.
/// - HalfCheetah: qpos + U(±0.1), qvel + 0.1·N(0, 1): velocities bounded at 4σ = 0.4.
/// - InvertedDoublePendulum: qpos + U(±0.1), qvel + 0.1·N(0, 1); obs = cart x,
///   sin q1, sin q2, cos q1, cos q2, qvel (3), constraint forces (3, unchecked).
pub fn reset_pose(env: &str) -> Option<ResetPose> {
    let base = env.trim_start_matches("Sparse");
    let base = base.split("-v").next().unwrap_or(base);
    let pose = |center: Vec<f64>, positions: usize, p: f64, v: f64| {
        let tolerance = (0..center.len())
            .map(|i| if i < positions { p } else { v })
            .collect();
        ResetPose {
            center,
            tolerance,
            position_dims: 0..positions,
        }
    };
    let with_z = |positions: usize, total: usize| {
        let mut c = vec![0.0; total];
        c[0] = 1.25;
        pose(c, positions, 0.005, 0.005)
    };
    match base {
        "Hopper" => Some(with_z(5, 11)),
        "Walker2d" => Some(with_z(8, 17)),
        "HalfCheetah" => Some(pose(vec![0.0; 17], 8, 0.1, 0.4)),
        "InvertedDoublePendulum" => {
            let (p, v, cos) = (0.1, 0.4, 1.0 - 0.1f64.cos());
            Some(ResetPose {
                center: vec![0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                tolerance: vec![
                    p,
                    p,
                    p,
                    cos,
                    cos,
                    v,
                    v,
                    v,
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::INFINITY,
                ],
                position_dims: 0..5,
            })
        }
        _ => None,
    }
}

impl ResetPose {
    fn contains(&self, obs: &[f64]) -> bool {
        obs.iter()
            .zip(&self.center)
            .zip(&self.tolerance)
            .all(|((x, c), t)| (x - c).abs() <= t + 1e-12)
    }
}

/// The first row of every episode in consecutive `obs` rows. Row 0 starts one; row i > 0
/// starts one when (1) its observation is within the reset noise of the initial pose and
/// (2) its position part jumped from row i − 1 by more than twice the reset noise (a
/// reset teleports the body; a step moves it continuously). (2) matters for balancing
/// tasks, whose states stay near the initial pose for many steps.
pub fn split_at_resets(obs: &[f64], obs_dim: usize, pose: &ResetPose) -> Vec<usize> {
    let rows: Vec<&[f64]> = obs.chunks_exact(obs_dim).collect();
    let mut starts = vec![0];
    for i in 1..rows.len() {
        let jumped = pose
            .position_dims
            .clone()
            .any(|j| (rows[i][j] - rows[i - 1][j]).abs() > 2.0 * pose.tolerance[j]);
        if jumped && pose.contains(rows[i]) {
            starts.push(i);
        }
    }
    starts
}

/// Imports a LOGO `.npy` demonstration array for `env` (an id such as `Hopper-v4`).
///
/// The source has no final observations and no rewards: each episode's final observation
/// is its last observed one repeated, rewards are zero, and the last step is marked
/// `truncated` when the episode reached `max_episode_steps`, else `terminated`. All of
/// this is recorded in the metadata (`logo_source`, `logo_notes`).
pub fn import_logo_npy(
    path: &Path,
    env: &str,
    obs_dim: usize,
    act_dim: usize,
    max_episode_steps: usize,
) -> Result<Dataset, DataError> {
    // Width, emptiness and finiteness, checked as for any demonstrations file.
    let Demonstrations { obs, actions, .. } = Demonstrations::from_npy(path, obs_dim, act_dim)?;
    let pose = reset_pose(env).ok_or_else(|| {
        DataError::field(path, None, "env", &format!("no reset pose known for {env}"))
    })?;
    let rows = obs.len() / obs_dim;
    let mut starts = split_at_resets(&obs, obs_dim, &pose);
    starts.push(rows);
    let episodes = starts
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let t = b - a;
            let mut observations = obs[a * obs_dim..b * obs_dim].to_vec();
            observations.extend_from_slice(&obs[(b - 1) * obs_dim..b * obs_dim]);
            let timed_out = t >= max_episode_steps;
            let mut terminations = vec![false; t];
            let mut truncations = vec![false; t];
            terminations[t - 1] = !timed_out;
            truncations[t - 1] = timed_out;
            Episode {
                observations,
                actions: actions[a * act_dim..b * act_dim].to_vec(),
                rewards: vec![0.0; t],
                terminations,
                truncations,
            }
        })
        .collect();
    let mut metadata = Map::new();
    metadata.insert("logo_env_id".into(), env.into());
    metadata.insert("logo_source".into(), path.display().to_string().into());
    metadata.insert(
        "logo_notes".into(),
        Value::from(
            "Imported from a LOGO .npy array ([obs | action] rows): episodes split where the \
             state jumps back to the reset pose; the source has no rewards (stored as 0) and \
             no final observations (the last observation is repeated).",
        ),
    );
    Dataset::checked(obs_dim, act_dim, episodes, metadata, path)
}

/// A D4RL file's flat columns, one row per step.
struct D4rlColumns<'a> {
    obs: &'a [f64],
    next_obs: Option<&'a [f64]>,
    actions: &'a [f64],
    rewards: &'a [f64],
    terminals: &'a [bool],
    timeouts: &'a [bool],
}

impl D4rlColumns<'_> {
    /// The rows cut into episodes at each terminal or timeout (and at the end).
    fn episodes(&self, obs_dim: usize, act_dim: usize) -> Vec<Episode> {
        let (n, obs, terminals, timeouts) =
            (self.rewards.len(), self.obs, self.terminals, self.timeouts);
        let mut episodes = Vec::new();
        let mut start = 0;
        for i in 0..n {
            let last = i + 1 == n;
            if !(terminals[i] || timeouts[i] || last) {
                continue;
            }
            let end = i + 1;
            let mut observations = obs[start * obs_dim..end * obs_dim].to_vec();
            // The final observation: next_observations when given, else the next row
            // (the next episode's first state is not this one's successor, so repeat the
            // last).
            let last_row = self.next_obs.unwrap_or(obs);
            observations.extend_from_slice(&last_row[i * obs_dim..end * obs_dim]);
            episodes.push(Episode {
                observations,
                actions: self.actions[start * act_dim..end * act_dim].to_vec(),
                rewards: self.rewards[start..end].to_vec(),
                terminations: terminals[start..end].to_vec(),
                truncations: (start..end)
                    .map(|k| timeouts[k] || (k + 1 == n && !terminals[k]))
                    .collect(),
            });
            start = end;
        }
        episodes
    }
}

/// Imports a D4RL-style flat HDF5 file.
pub fn import_d4rl(path: &Path) -> Result<Dataset, DataError> {
    let bytes = std::fs::read(path).map_err(|source| DataError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let hdf5_error = |e: hdf5_pure::Error| DataError::Hdf5 {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    let limit = crate::minari::max_values(bytes.len());
    let file = hdf5_pure::File::from_bytes(bytes).map_err(hdf5_error)?;
    let bad = |field: &str, reason: String| DataError::field(path, None, field, &reason);
    let matrix = |field: &str| {
        read_table(file.dataset(field), field, &bad, limit).map(|(values, _, cols)| (values, cols))
    };
    let flags = |field: &str| read_flags(file.dataset(field), field, &bad);
    let (obs, obs_dim) = matrix("observations")?;
    let (actions, act_dim) = matrix("actions")?;
    let (rewards, _) = matrix("rewards")?;
    let terminals = flags("terminals")?;
    let timeouts = flags("timeouts")?;
    let next_obs = file
        .dataset("next_observations")
        .ok()
        .map(|_| matrix("next_observations"))
        .transpose()?;
    let n = rewards.len();
    if let Some((_, next_dim)) = &next_obs
        && *next_dim != obs_dim
    {
        return Err(bad(
            "next_observations",
            format!("{next_dim} columns, observations have {obs_dim}"),
        ));
    }
    let next_len = next_obs.as_ref().map(|(next, _)| next.len());
    for (field, len, expected) in [
        ("observations", obs.len(), n * obs_dim),
        ("actions", actions.len(), n * act_dim),
        ("terminals", terminals.len(), n),
        ("timeouts", timeouts.len(), n),
        (
            "next_observations",
            next_len.unwrap_or(n * obs_dim),
            n * obs_dim,
        ),
    ] {
        if len != expected {
            return Err(bad(
                field,
                format!("{len} values, expected {expected} ({n} steps)"),
            ));
        }
    }
    let columns = D4rlColumns {
        obs: &obs,
        next_obs: next_obs.as_ref().map(|(next, _)| next.as_slice()),
        actions: &actions,
        rewards: &rewards,
        terminals: &terminals,
        timeouts: &timeouts,
    };
    let episodes = columns.episodes(obs_dim, act_dim);
    let mut metadata = Map::new();
    metadata.insert("logo_source".into(), path.display().to_string().into());
    Dataset::checked(obs_dim, act_dim, episodes, metadata, path)
}

//! InvertedDoublePendulum, as Gymnasium 1.4.0's `inverted_double_pendulum_v4.py` /
//! `inverted_double_pendulum_v5.py` compute it.

use crate::env::Version;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task};

/// Cart with a two-link pole. obs = [x, sin θ, cos θ, clip(qvel, ±10), clip(qfrc_constraint, ±10)]
/// (v4: 11 dims; v5 keeps only qfrc_constraint[0]: 9 dims). Reward = 10 − 0.01x² − (y−2)²
/// − 1e-3 v1² − 5e-3 v2² with (x, y) the pole tip; terminates when y ≤ 1.
/// v5 pays no alive bonus on the terminating step.
#[derive(Debug, Clone, Copy)]
pub struct InvertedDoublePendulum {
    pub version: Version,
}

impl Task for InvertedDoublePendulum {
    fn id(&self) -> String {
        format!("InvertedDoublePendulum-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "inverted_double_pendulum.xml"
    }
    fn frame_skip(&self) -> usize {
        5
    }
    fn obs_dim(&self) -> usize {
        match self.version {
            Version::V4 => 11,
            Version::V5 => 9,
        }
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::UniformPosNormalVel { scale: 0.1 }
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        let (qpos, qvel) = (data.qpos(), data.qvel());
        let constraint = data.qfrc_constraint();
        let angles = &qpos[1..];
        let n = angles.len();
        obs[0] = qpos[0];
        for (i, a) in angles.iter().enumerate() {
            obs[1 + i] = a.sin();
            obs[1 + n + i] = a.cos();
        }
        let mut k = 1 + 2 * n;
        for v in qvel {
            obs[k] = v.clamp(-10.0, 10.0);
            k += 1;
        }
        let kept = match self.version {
            Version::V4 => constraint.len(),
            Version::V5 => 1,
        };
        for f in &constraint[..kept] {
            obs[k] = f.clamp(-10.0, 10.0);
            k += 1;
        }
    }
    fn reward(&self, data: &Data, _: BeforeStep, _dt: f64, _action: &[f64]) -> (f64, bool) {
        let [x, _, y] = data.site_xpos()[0];
        let terminated = y <= 1.0;
        let dist_penalty = 0.01 * (x * x) + (y - 2.0) * (y - 2.0);
        let (v1, v2) = (data.qvel()[1], data.qvel()[2]);
        let vel_penalty = 1e-3 * (v1 * v1) + 5e-3 * (v2 * v2);
        let alive_bonus = match self.version {
            Version::V4 => 10.0,
            Version::V5 if terminated => 0.0,
            Version::V5 => 10.0,
        };
        (alive_bonus - dist_penalty - vel_penalty, terminated)
    }
}

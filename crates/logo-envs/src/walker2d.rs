//! Walker2d, as Gymnasium 1.4.0's `walker2d_v4.py` / `walker2d_v5.py` compute it.

use crate::env::Version;
use crate::hopper::{observe_clipped, upright_reward};
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task};

/// Two-legged walker: obs = qpos[1:] ‖ clip(qvel, ±10) (17), reward = v_x + healthy − 1e-3‖a‖².
/// v5 loads `walker2d_v5.xml` (right foot friction 1.9 instead of 0.9).
#[derive(Debug, Clone, Copy)]
pub struct Walker2d {
    pub version: Version,
}

/// 0.8 < z < 2.0 and −1 < torso angle < 1.
fn is_healthy(data: &Data) -> bool {
    let (z, angle) = (data.qpos()[1], data.qpos()[2]);
    0.8 < z && z < 2.0 && -1.0 < angle && angle < 1.0
}

impl Task for Walker2d {
    fn id(&self) -> String {
        format!("Walker2d-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        match self.version {
            Version::V4 => "walker2d.xml",
            Version::V5 => "walker2d_v5.xml",
        }
    }
    fn frame_skip(&self) -> usize {
        4
    }
    fn obs_dim(&self) -> usize {
        17
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::Uniform { scale: 5e-3 }
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        observe_clipped(data, obs);
    }
    fn reward(&self, data: &Data, before: BeforeStep, dt: f64, action: &[f64]) -> (f64, bool) {
        upright_reward(self.version, is_healthy(data), data, before, dt, action)
    }
}

//! InvertedPendulum, as Gymnasium 1.4.0's `inverted_pendulum_v4.py` /
//! `inverted_pendulum_v5.py` compute it.

use crate::env::Version;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task, state_is_finite};

/// Cart with a one-link pole: obs = qpos ‖ qvel (4), +1 per step (v5: 0 on the terminating
/// step); terminates when the pole leans past 0.2 rad or the state is not finite.
#[derive(Debug, Clone, Copy)]
pub struct InvertedPendulum {
    pub version: Version,
}

impl Task for InvertedPendulum {
    fn id(&self) -> String {
        format!("InvertedPendulum-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "inverted_pendulum.xml"
    }
    fn frame_skip(&self) -> usize {
        2
    }
    fn obs_dim(&self) -> usize {
        4
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::Uniform { scale: 0.01 }
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        obs[..2].copy_from_slice(data.qpos());
        obs[2..].copy_from_slice(data.qvel());
    }
    fn reward(&self, data: &Data, _: BeforeStep, _dt: f64, _action: &[f64]) -> (f64, bool) {
        // Not `angle.abs() <= 0.2`: a NaN angle must terminate.
        let terminated = !state_is_finite(data) || data.qpos()[1].abs() > 0.2;
        let reward = match self.version {
            Version::V4 => 1.0,
            Version::V5 => f64::from(u8::from(!terminated)),
        };
        (reward, terminated)
    }
}

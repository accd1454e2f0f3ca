//! Swimmer, as Gymnasium 1.4.0's `swimmer_v4.py` / `swimmer_v5.py` compute it (the two
//! versions pay alike).

use crate::env::Version;
use crate::hopper::locomotion_reward;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task};

/// Three-link swimmer in a viscous fluid: obs = qpos[2:] ‖ qvel (8),
/// reward = v_x − 1e-4‖a‖², never terminates.
#[derive(Debug, Clone, Copy)]
pub struct Swimmer {
    pub version: Version,
}

impl Task for Swimmer {
    fn id(&self) -> String {
        format!("Swimmer-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "swimmer.xml"
    }
    fn frame_skip(&self) -> usize {
        4
    }
    fn obs_dim(&self) -> usize {
        8
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::Uniform { scale: 0.1 }
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        let (qpos, qvel) = (&data.qpos()[2..], data.qvel());
        obs[..qpos.len()].copy_from_slice(qpos);
        obs[qpos.len()..].copy_from_slice(qvel);
    }
    fn reward(&self, data: &Data, before: BeforeStep, dt: f64, action: &[f64]) -> (f64, bool) {
        let x_velocity = (data.qpos()[0] - before.x) / dt;
        (locomotion_reward(x_velocity, 0.0, 1e-4, action), false)
    }
}

//! HalfCheetah, as Gymnasium 1.4.0's `half_cheetah_v4.py` / `half_cheetah_v5.py` compute it
//! (the two versions have the same formulas and model).

use crate::env::Version;
use crate::hopper::locomotion_reward;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task};

/// Planar cheetah: obs = qpos[1:] ‖ qvel (17, velocities not clipped),
/// reward = v_x − 0.1‖a‖², never terminates.
#[derive(Debug, Clone, Copy)]
pub struct HalfCheetah {
    pub version: Version,
}

impl Task for HalfCheetah {
    fn id(&self) -> String {
        format!("HalfCheetah-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "half_cheetah.xml"
    }
    fn frame_skip(&self) -> usize {
        5
    }
    fn obs_dim(&self) -> usize {
        17
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::UniformPosNormalVel { scale: 0.1 }
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        let (qpos, qvel) = (&data.qpos()[1..], data.qvel());
        obs[..qpos.len()].copy_from_slice(qpos);
        obs[qpos.len()..].copy_from_slice(qvel);
    }
    fn reward(&self, data: &Data, before: BeforeStep, dt: f64, action: &[f64]) -> (f64, bool) {
        let x_velocity = (data.qpos()[0] - before.x) / dt;
        (locomotion_reward(x_velocity, 0.0, 0.1, action), false)
    }
}

//! Hopper, as Gymnasium 1.4.0's `hopper_v4.py` / `hopper_v5.py` compute it.

use crate::env::Version;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task};
use crate::numpy_sum::numpy_sum_of;

/// One-legged hopper: obs = qpos[1:] ‖ clip(qvel, ±10) (11), reward = v_x + healthy − 1e-3‖a‖².
#[derive(Debug, Clone, Copy)]
pub struct Hopper {
    pub version: Version,
}

/// Gymnasium's `is_healthy`: every state entry after x and z in (−100, 100),
/// z > 0.7, |torso angle| < 0.2. Written as `lo < v && v < hi` so NaN is unhealthy.
fn is_healthy(data: &Data) -> bool {
    let (qpos, qvel) = (data.qpos(), data.qvel());
    let state_ok = qpos[2..]
        .iter()
        .chain(qvel)
        .all(|&s| -100.0 < s && s < 100.0);
    let (z, angle) = (qpos[1], qpos[2]);
    state_ok && 0.7 < z && z < f64::INFINITY && -0.2 < angle && angle < 0.2
}

/// Forward reward, healthy bonus and control cost in Gymnasium's order of operations.
pub(crate) fn locomotion_reward(
    x_velocity: f64,
    healthy_reward: f64,
    ctrl_cost_weight: f64,
    action: &[f64],
) -> f64 {
    let ctrl_cost = ctrl_cost_weight * numpy_sum_of(action, |a| a * a);
    (x_velocity + healthy_reward) - ctrl_cost
}

/// The step of Hopper and Walker2d: v_x + the healthy bonus − 1e-3‖a‖², ending where the
/// body is no longer healthy. v4 pays the bonus on the terminating step too; v5 does not.
pub(crate) fn upright_reward(
    version: Version,
    healthy: bool,
    data: &Data,
    before: BeforeStep,
    dt: f64,
    action: &[f64],
) -> (f64, bool) {
    let x_velocity = (data.qpos()[0] - before.x) / dt;
    let healthy_reward = match version {
        Version::V4 => 1.0,
        Version::V5 => f64::from(u8::from(healthy)),
    };
    (
        locomotion_reward(x_velocity, healthy_reward, 1e-3, action),
        !healthy,
    )
}

/// qpos[1:] ‖ clip(qvel, ±10): the observation of Hopper and Walker2d.
pub(crate) fn observe_clipped(data: &Data, obs: &mut [f64]) {
    let (qpos, qvel) = (&data.qpos()[1..], data.qvel());
    obs[..qpos.len()].copy_from_slice(qpos);
    for (o, v) in obs[qpos.len()..].iter_mut().zip(qvel) {
        *o = v.clamp(-10.0, 10.0);
    }
}

impl Task for Hopper {
    fn id(&self) -> String {
        format!("Hopper-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "hopper.xml"
    }
    fn frame_skip(&self) -> usize {
        4
    }
    fn obs_dim(&self) -> usize {
        11
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

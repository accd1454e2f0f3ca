//! Ant, as Gymnasium 1.4.0's `ant_v4.py` / `ant_v5.py` compute it with their defaults.

use crate::env::Version;
use crate::hopper::locomotion_reward;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task, state_is_finite};
use crate::numpy_sum::numpy_sum_of;

/// Body id of the torso in `ant.xml`: its frame's x is what the forward reward differentiates.
const TORSO: usize = 1;

/// Four-legged walker on a free joint. obs = qpos[2:] ‖ qvel (27); v5 appends the
/// contact forces of bodies 1.. clipped to ±1 (105). reward = v_x + 1 − 0.5‖a‖² (v4: the
/// healthy bonus on every step, no contact cost); v5: v_x + 1[healthy] − 0.5‖a‖² −
/// 5e-4‖clip(cfrc_ext, ±1)‖². Terminates unless the state is finite and 0.2 ≤ z ≤ 1.
#[derive(Debug, Clone, Copy)]
pub struct Ant {
    pub version: Version,
}

fn is_healthy(data: &Data) -> bool {
    state_is_finite(data) && (0.2..=1.0).contains(&data.qpos()[2])
}

/// Contact forces of bodies `from..`, row-major (6 per body), each to be clipped to ±1.
fn contact_forces(data: &Data, from: usize) -> &[f64] {
    data.cfrc_ext()[from..].as_flattened()
}

impl Task for Ant {
    fn id(&self) -> String {
        format!("Ant-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "ant.xml"
    }
    fn frame_skip(&self) -> usize {
        5
    }
    fn obs_dim(&self) -> usize {
        match self.version {
            Version::V4 => 27,
            Version::V5 => 27 + 13 * 6,
        }
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::UniformPosNormalVel { scale: 0.1 }
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        let (qpos, qvel) = (&data.qpos()[2..], data.qvel());
        let (positions, rest) = obs.split_at_mut(qpos.len());
        positions.copy_from_slice(qpos);
        let (velocities, forces) = rest.split_at_mut(qvel.len());
        velocities.copy_from_slice(qvel);
        for (o, f) in forces.iter_mut().zip(contact_forces(data, 1)) {
            *o = f.clamp(-1.0, 1.0);
        }
    }
    fn before_step(&self, data: &Data, _action: &[f64]) -> BeforeStep {
        BeforeStep {
            x: data.xpos()[TORSO][0],
            reward: 0.0,
        }
    }
    fn reward(&self, data: &Data, before: BeforeStep, dt: f64, action: &[f64]) -> (f64, bool) {
        let x_velocity = (data.xpos()[TORSO][0] - before.x) / dt;
        let healthy = is_healthy(data);
        let reward = match self.version {
            Version::V4 => locomotion_reward(x_velocity, 1.0, 0.5, action),
            Version::V5 => {
                let ctrl_cost = 0.5 * numpy_sum_of(action, |a| a * a);
                let clipped_square = |f: f64| {
                    let clipped = f.clamp(-1.0, 1.0);
                    clipped * clipped
                };
                let contact_cost = 5e-4 * numpy_sum_of(contact_forces(data, 0), clipped_square);
                (x_velocity + f64::from(u8::from(healthy))) - (ctrl_cost + contact_cost)
            }
        };
        (reward, !healthy)
    }
}

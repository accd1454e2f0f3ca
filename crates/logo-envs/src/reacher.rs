//! Reacher, as Gymnasium 1.4.0's `reacher_v4.py` / `reacher_v5.py` compute it.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::env::Version;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task, uniform_noise};
use crate::numpy_sum::{norm3, numpy_sum_of};

/// Body ids in `reacher.xml`.
const FINGERTIP: usize = 3;
const TARGET: usize = 4;

/// Two-link planar arm reaching a target placed at random in its disk. obs = cos, sin of
/// the two joint angles, the target's place, the joint velocities and fingertip − target
/// (v4: 11 with its z, v5: 10). reward = −‖fingertip − target‖ − ‖a‖²; v4 pays it for the
/// state before the step, v5 for the state after. Never terminates; 50 steps an episode.
#[derive(Debug, Clone, Copy)]
pub struct Reacher {
    pub version: Version,
}

/// Fingertip − target, in the world frame.
fn fingertip_to_target(data: &Data) -> [f64; 3] {
    let (tip, target) = (data.xpos()[FINGERTIP], data.xpos()[TARGET]);
    [tip[0] - target[0], tip[1] - target[1], tip[2] - target[2]]
}

/// The distance and control terms Gymnasium adds, in its order.
fn reach_reward(data: &Data, action: &[f64]) -> f64 {
    let distance = norm3(fingertip_to_target(data));
    -distance - numpy_sum_of(action, |a| a * a)
}

impl Task for Reacher {
    fn id(&self) -> String {
        format!("Reacher-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "reacher.xml"
    }
    fn frame_skip(&self) -> usize {
        2
    }
    fn obs_dim(&self) -> usize {
        match self.version {
            Version::V4 => 11,
            Version::V5 => 10,
        }
    }
    fn max_episode_steps(&self) -> usize {
        50
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::Own
    }
    /// Gymnasium's draws, in its order: qpos += U(-0.1, 0.1); the target (the last two
    /// qpos) drawn in pairs from U(-0.2, 0.2)² until inside the disk of radius 0.2 the
    /// arm reaches; qvel += U(-0.005, 0.005), the target's two at rest.
    fn reset_state(
        &self,
        rng: &mut ChaCha8Rng,
        init: (&[f64], &[f64]),
        qpos: &mut [f64],
        qvel: &mut [f64],
    ) {
        ResetNoise::Own.draw(rng, init, qpos, qvel);
        uniform_noise(rng, qpos, 0.1);
        let target = loop {
            let goal: [f64; 2] = [rng.random_range(-0.2..0.2), rng.random_range(-0.2..0.2)];
            if goal[0].hypot(goal[1]) < 0.2 {
                break goal;
            }
        };
        let nq = qpos.len();
        qpos[nq - 2..].copy_from_slice(&target);
        uniform_noise(rng, qvel, 0.005);
        let nv = qvel.len();
        qvel[nv - 2..].fill(0.0);
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        let (qpos, qvel) = (data.qpos(), data.qvel());
        let (a, b) = (qpos[0], qpos[1]);
        obs[..8].copy_from_slice(&[
            a.cos(),
            b.cos(),
            a.sin(),
            b.sin(),
            qpos[2],
            qpos[3],
            qvel[0],
            qvel[1],
        ]);
        let difference = fingertip_to_target(data);
        let kept = self.obs_dim() - 8;
        obs[8..].copy_from_slice(&difference[..kept]);
    }
    fn before_step(&self, data: &Data, action: &[f64]) -> BeforeStep {
        BeforeStep {
            x: data.qpos()[0],
            reward: match self.version {
                Version::V4 => reach_reward(data, action),
                Version::V5 => 0.0,
            },
        }
    }
    fn reward(&self, data: &Data, before: BeforeStep, _dt: f64, action: &[f64]) -> (f64, bool) {
        let reward = match self.version {
            Version::V4 => before.reward,
            Version::V5 => reach_reward(data, action),
        };
        (reward, false)
    }
    fn goal_distance(&self, data: &Data) -> Option<f64> {
        let [dx, dy, _] = fingertip_to_target(data);
        Some(dx.hypot(dy))
    }
}

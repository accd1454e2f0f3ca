//! Pusher, as Gymnasium 1.4.0's `pusher_v5.py` computes it. (Gymnasium refuses
//! `Pusher-v4` under MuJoCo 3, so there is no oracle to hold a `-v4` to.)

use crate::env::Version;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task};
use crate::numpy_sum::sum_of_squares;

/// Body ids in `pusher_v5.xml`.
const TIPS_ARM: usize = 10;
const OBJECT: usize = 11;
const GOAL: usize = 12;

/// Seven-joint arm pushing a cylinder to a goal on a table, without gravity. obs = the
/// arm's qpos[:7] ‖ qvel[:7] ‖ the fingertip's, object's and goal's places (23).
/// reward = −‖object − goal‖ − 0.1‖a‖² − 0.5‖object − fingertip‖, never terminates;
/// 100 steps an episode.
#[derive(Debug, Clone, Copy)]
pub struct Pusher {
    pub version: Version,
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    let [dx, dy, dz] = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    dz.mul_add(dz, dy.mul_add(dy, dx * dx)).sqrt()
}

impl Task for Pusher {
    fn id(&self) -> String {
        format!("Pusher-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "pusher_v5.xml"
    }
    fn frame_skip(&self) -> usize {
        5
    }
    fn obs_dim(&self) -> usize {
        23
    }
    fn max_episode_steps(&self) -> usize {
        100
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::PusherObject
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        obs[..7].copy_from_slice(&data.qpos()[..7]);
        obs[7..14].copy_from_slice(&data.qvel()[..7]);
        for (i, body) in [TIPS_ARM, OBJECT, GOAL].into_iter().enumerate() {
            obs[14 + 3 * i..][..3].copy_from_slice(&data.xpos()[body]);
        }
    }
    fn reward(&self, data: &Data, _: BeforeStep, _dt: f64, action: &[f64]) -> (f64, bool) {
        let xpos = data.xpos();
        let near = -distance(xpos[OBJECT], xpos[TIPS_ARM]) * 0.5;
        let to_goal = -distance(xpos[OBJECT], xpos[GOAL]);
        let control = -sum_of_squares(action.iter().copied()) * 0.1;
        ((to_goal + control) + near, false)
    }
    fn goal_distance(&self, data: &Data) -> Option<f64> {
        let (object, goal) = (data.xpos()[OBJECT], data.xpos()[GOAL]);
        Some((object[0] - goal[0]).hypot(object[1] - goal[1]))
    }
}

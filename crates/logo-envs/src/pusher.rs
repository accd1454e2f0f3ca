//! Pusher, as Gymnasium 1.4.0's `pusher_v5.py` computes it. (Gymnasium refuses
//! `Pusher-v4` under MuJoCo 3, so there is no oracle to hold a `-v4` to, and none here.)

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task, uniform_noise};
use crate::numpy_sum::{norm3, numpy_sum_of};

/// Body ids in `pusher_v5.xml`.
const TIPS_ARM: usize = 10;
const OBJECT: usize = 11;
const GOAL: usize = 12;

/// Seven-joint arm pushing a cylinder to a goal on a table, without gravity. obs = the
/// arm's qpos[:7] ‖ qvel[:7] ‖ the fingertip's, object's and goal's places (23).
/// reward = −‖object − goal‖ − 0.1‖a‖² − 0.5‖object − fingertip‖, never terminates;
/// 100 steps an episode. `-v5` only.
#[derive(Debug, Clone, Copy)]
pub struct Pusher;

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm3([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

impl Task for Pusher {
    fn id(&self) -> String {
        "Pusher-v5".into()
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
        ResetNoise::Own
    }
    /// Gymnasium's draws: the arm as the model has it; the object's two slides (qpos[7],
    /// qpos[8]) drawn as U(-0.3, 0) and U(-0.2, 0.2) until more than 0.17 from the goal;
    /// qvel += U(-0.005, 0.005), the object's and goal's four at rest.
    fn reset_state(
        &self,
        rng: &mut ChaCha8Rng,
        init: (&[f64], &[f64]),
        qpos: &mut [f64],
        qvel: &mut [f64],
    ) {
        ResetNoise::Own.draw(rng, init, qpos, qvel);
        let object = loop {
            let place: [f64; 2] = [rng.random_range(-0.3..0.0), rng.random_range(-0.2..0.2)];
            if place[0].hypot(place[1]) > 0.17 {
                break place;
            }
        };
        let nq = qpos.len();
        qpos[nq - 4..nq - 2].copy_from_slice(&object);
        qpos[nq - 2..].fill(0.0);
        uniform_noise(rng, qvel, 0.005);
        let nv = qvel.len();
        qvel[nv - 4..].fill(0.0);
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
        let control = -numpy_sum_of(action, |a| a * a) * 0.1;
        ((to_goal + control) + near, false)
    }
    fn goal_distance(&self, data: &Data) -> Option<f64> {
        let (object, goal) = (data.xpos()[OBJECT], data.xpos()[GOAL]);
        Some((object[0] - goal[0]).hypot(object[1] - goal[1]))
    }
}

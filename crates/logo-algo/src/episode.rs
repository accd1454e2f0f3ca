//! One episode of a fixed policy, and the evaluation made of such episodes: the one
//! episode loop that training's evaluation, `logo eval` and `logo rollout` share.

use logo_envs::{Env, EnvError, clip_to_range};
use logo_nn::ActingPolicy;

/// One episode's totals.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Episode {
    /// The env's own (e.g. sparse) return.
    pub return_: f64,
    pub dense_return: f64,
    pub length: usize,
    /// Ended by the MDP (a fall), not by the time limit.
    pub terminated: bool,
    /// `qpos[0]` at the end minus at the start: forward distance for the locomotion envs,
    /// the cart's travel for IDP.
    pub moved: f64,
    /// Root mean square over every action component of every step, as given to the env
    /// (before MuJoCo clamps it to the actuator range).
    pub action_rms: f64,
    /// Whether the task reported its goal reached at some step (None: it reports none).
    pub reached: Option<bool>,
}

/// When an episode counts as a success, a config's `success`: what the task reports
/// (`"task"`, the default: a sparse kind's goal, a Python env's `info["is_success"]`),
/// an episode that ends by termination rather than the time limit (`"terminated"`: a
/// task that stops at its goal, as MountainCar does), or nothing (`"none"`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SuccessRule {
    #[default]
    Task,
    Terminated,
    None,
}

impl SuccessRule {
    /// Whether an episode succeeded, from whether the task reported its goal reached
    /// (None: it reports nothing) and whether it ended by termination; None where the
    /// rule and the task define no success.
    pub fn judge(self, reached: Option<bool>, terminated: bool) -> Option<bool> {
        match self {
            Self::Task => reached,
            Self::Terminated => Some(terminated),
            Self::None => None,
        }
    }

    /// The successes among episodes of (reached, terminated): (k, n), or None where
    /// none is defined.
    pub fn count(
        self,
        episodes: impl IntoIterator<Item = (Option<bool>, bool)>,
    ) -> Option<(usize, usize)> {
        let judged: Vec<Option<bool>> = episodes
            .into_iter()
            .map(|(reached, terminated)| self.judge(reached, terminated))
            .collect();
        judged.iter().any(Option::is_some).then(|| {
            let k = judged.iter().filter(|s| **s == Some(true)).count();
            (k, judged.len())
        })
    }
}

impl std::str::FromStr for SuccessRule {
    type Err = String;

    /// The config's spelling (`"task"`, `"terminated"`, `"none"`), for flags and Python.
    fn from_str(text: &str) -> Result<Self, String> {
        serde_json::from_value(serde_json::Value::String(text.into()))
            .map_err(|_| format!("{text:?}: expected task, terminated or none"))
    }
}

/// Runs one episode from `reset(seed)` to its end, acting with `act`.
pub fn run_episode(
    env: &mut dyn Env,
    seed: u64,
    act: impl FnMut(&[f64]) -> Vec<f64>,
) -> Result<Episode, EnvError> {
    run_episode_with(env, seed, act, |_, _| Ok(()))
}

/// [`run_episode`], calling `after_step` with the env and the episode's totals so far
/// after every step (a video's frames).
pub fn run_episode_with<E: From<EnvError>>(
    env: &mut dyn Env,
    seed: u64,
    mut act: impl FnMut(&[f64]) -> Vec<f64>,
    mut after_step: impl FnMut(&dyn Env, &Episode) -> Result<(), E>,
) -> Result<Episode, E> {
    let mut obs = vec![0.0; env.spec().obs_dim];
    env.reset(Some(seed), &mut obs);
    let x_start = env.x_position();
    let mut episode = Episode::default();
    let mut squared_action = 0.0;
    loop {
        let action = act(&obs);
        squared_action += action.iter().map(|a| a * a).sum::<f64>();
        let step = env.step(&action, &mut obs)?;
        episode.return_ += step.reward;
        episode.dense_return += step.info.dense_reward;
        episode.length += 1;
        episode.terminated = step.terminated;
        episode.moved = env.x_position() - x_start;
        let components = (episode.length * env.spec().act_dim) as f64;
        episode.action_rms = (squared_action / components).sqrt();
        if let Some(reached) = step.info.success {
            episode.reached = Some(reached || episode.reached == Some(true));
        }
        after_step(&*env, &episode)?;
        if step.done() {
            return Ok(episode);
        }
    }
}

/// What a training run's evaluation reports: means over its episodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    /// The trained task's own return (the sparse one on a sparse task).
    pub return_: f64,
    pub dense_return: f64,
    pub moved: f64,
    pub action_rms: f64,
    /// The share of episodes that reached the goal, where the success rule defines one.
    pub success: Option<f64>,
}

/// How long an evaluation plays and how it acts and judges: whole episodes until at
/// least `min_steps` steps and `min_episodes` episodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EvaluationPlan {
    pub min_steps: usize,
    pub min_episodes: usize,
    /// Clip the mean action to the action space first.
    pub clip_actions: bool,
    pub success: SuccessRule,
}

/// The reset seed of evaluation episode `episode` of a run with `seed`: the same at every
/// iteration, so that evaluations compare the policies on the same initial states.
pub fn evaluation_seed(seed: u64, episode: usize) -> u64 {
    1_000_000 + seed * 1000 + episode as u64
}

/// The mean action of `policy` over whole episodes as `plan` says, episode i from
/// `reset(reset_seed(i))` (e.g. the fixed initial states of [`evaluation_seed`]).
pub fn evaluate(
    env: &mut dyn Env,
    policy: &ActingPolicy,
    mut reset_seed: impl FnMut(usize) -> u64,
    plan: EvaluationPlan,
) -> Result<Evaluation, EnvError> {
    let (mut steps, mut episodes) = (0, Vec::new());
    let (low, high) = (
        env.spec().action_low.clone(),
        env.spec().action_high.clone(),
    );
    let act = |obs: &[f64]| {
        let mut action = policy.mean(obs);
        if plan.clip_actions {
            clip_to_range(&mut action, &low, &high);
        }
        action
    };
    while steps < plan.min_steps || episodes.len() < plan.min_episodes {
        let episode = run_episode(env, reset_seed(episodes.len()), act)?;
        steps += episode.length;
        episodes.push(episode);
    }
    let mean = |of: fn(&Episode) -> f64| {
        episodes.iter().map(of).sum::<f64>() / episodes.len().max(1) as f64
    };
    Ok(Evaluation {
        return_: mean(|e| e.return_),
        dense_return: mean(|e| e.dense_return),
        moved: mean(|e| e.moved),
        action_rms: mean(|e| e.action_rms),
        success: plan
            .success
            .count(episodes.iter().map(|e| (e.reached, e.terminated)))
            .map(|(k, n)| k as f64 / n as f64),
    })
}

//! Collecting a batch: whole episodes from the vectorised env, the policy batched over
//! the copies, until at least `min_steps` steps (the reference's rule). Once the steps
//! taken (finished episodes and those in progress) reach `min_steps`, no copy starts a
//! new episode; the episodes in progress finish. The reference collects one episode after
//! another and overshoots by less than one episode; with N copies the overshoot is at
//! most the rest of N episodes, so keep N small (the configs use one copy per core).

use burn::tensor::backend::Backend;
use logo_envs::{EnvError, VecEnv};
use logo_nn::GaussianPolicy;
use rand_chacha::ChaCha8Rng;

/// Whole episodes laid end to end, row-major.
#[derive(Debug, Clone, Default)]
pub struct Batch {
    pub obs_dim: usize,
    pub act_dim: usize,
    pub obs: Vec<f64>,
    pub actions: Vec<f64>,
    /// The env's (training, e.g. sparse) reward.
    pub rewards: Vec<f64>,
    pub dense_rewards: Vec<f64>,
    pub terminated: Vec<bool>,
    pub episode_end: Vec<bool>,
    /// For each truncated episode: the index of its last step and its final observation.
    pub truncations: Vec<(usize, Vec<f64>)>,
    pub episode_returns: Vec<f64>,
    pub episode_dense_returns: Vec<f64>,
}

impl Batch {
    pub fn len(&self) -> usize {
        self.rewards.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rewards.is_empty()
    }

    pub fn mean_return(&self) -> f64 {
        self.episode_returns.iter().sum::<f64>() / self.episode_returns.len().max(1) as f64
    }

    pub fn mean_dense_return(&self) -> f64 {
        self.episode_dense_returns.iter().sum::<f64>()
            / self.episode_dense_returns.len().max(1) as f64
    }
}

/// One copy's episode in progress.
#[derive(Default, Clone)]
struct Episode {
    obs: Vec<f64>,
    actions: Vec<f64>,
    rewards: Vec<f64>,
    dense: Vec<f64>,
}

pub fn collect<B: Backend>(
    venv: &mut VecEnv,
    policy: &GaussianPolicy<B>,
    rng: &mut ChaCha8Rng,
    min_steps: usize,
) -> Result<Batch, EnvError> {
    let (n, obs_dim, act_dim) = (venv.num_envs(), venv.spec().obs_dim, venv.spec().act_dim);
    let policy = policy.acting();
    let mut batch = Batch {
        obs_dim,
        act_dim,
        ..Default::default()
    };
    let mut episodes = vec![Episode::default(); n];
    let mut active = vec![true; n];
    let mut steps_taken = 0;
    while active.iter().any(|a| *a) {
        let obs = venv.obs().to_vec();
        let actions = policy.sample(&obs, rng);
        let out = venv.step_active(&actions, &active)?;
        steps_taken += active.iter().filter(|a| **a).count();
        for i in 0..n {
            if !active[i] {
                continue;
            }
            let (step, ep) = (out.steps[i], &mut episodes[i]);
            ep.obs.extend_from_slice(&obs[i * obs_dim..][..obs_dim]);
            ep.actions
                .extend_from_slice(&actions[i * act_dim..][..act_dim]);
            ep.rewards.push(step.reward);
            ep.dense.push(step.info.dense_reward);
            if !step.done() {
                continue;
            }
            let len = ep.rewards.len();
            batch
                .terminated
                .extend(std::iter::repeat_n(false, len - 1).chain([step.terminated]));
            batch
                .episode_end
                .extend(std::iter::repeat_n(false, len - 1).chain([true]));
            if !step.terminated {
                batch.truncations.push((
                    batch.rewards.len() + len - 1,
                    out.final_obs[i * obs_dim..][..obs_dim].to_vec(),
                ));
            }
            batch.episode_returns.push(ep.rewards.iter().sum());
            batch.episode_dense_returns.push(ep.dense.iter().sum());
            let ep = std::mem::take(ep);
            batch.obs.extend(ep.obs);
            batch.actions.extend(ep.actions);
            batch.rewards.extend(ep.rewards);
            batch.dense_rewards.extend(ep.dense);
            if steps_taken >= min_steps {
                active[i] = false;
            }
        }
    }
    Ok(batch)
}

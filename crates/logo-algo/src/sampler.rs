//! Collecting a batch from the vectorised env, the policy batched over the copies.
//!
//! `Episodes` (default, the reference's rule): whole episodes until at least
//! `samples_per_iter` steps. The reference runs one episode after another and stops at
//! the first that takes it past the count. Here each copy runs whole episodes on its
//! thread until its share (the count / N) is reached; the batch is then the shortest
//! prefix, of at least the count, of the copies' episodes taken in turn (copy 0's first,
//! copy 1's first, ..., copy 0's second, ...): the reference's rule on one stream of
//! episodes, so it overshoots by less than one episode as the reference does. The
//! episodes past that prefix were simulated and are dropped: sampling is the cheap part
//! of an iteration, and without the cut two copies of 1000-step episodes gave 6000 steps
//! for a count of 5000 (≈ 12% more work for the critics and the policy steps on sparse
//! IDP). `Steps`: a fixed number of steps per copy.

use logo_envs::{EnvError, VecEnv, clip_to_range};

use crate::episode::SuccessRule;
use logo_nn::ActingPolicy;
use rand::{Rng, SeedableRng};
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
    /// Each ended episode's (goal reached at some step, as the task reports it; ended by
    /// termination): what a success rule judges.
    pub episode_outcomes: Vec<(Option<bool>, bool)>,
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

    /// The share of the batch's episodes that succeeded by `rule`, where it defines one.
    pub fn success_rate(&self, rule: SuccessRule) -> Option<f64> {
        rule.count(self.episode_outcomes.iter().copied())
            .map(|(k, n)| k as f64 / n.max(1) as f64)
    }

    pub fn mean_dense_return(&self) -> f64 {
        self.episode_dense_returns.iter().sum::<f64>()
            / self.episode_dense_returns.len().max(1) as f64
    }
}

/// How a batch is cut from the env copies' episodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RolloutMode {
    /// Whole episodes until at least `samples_per_iter` steps (the reference's rule);
    /// every copy ends the batch freshly reset.
    #[default]
    Episodes,
    /// Exactly ceil(`samples_per_iter` / copies) steps per copy. An episode still running
    /// at the end of a batch is cut there (bootstrapped from V of its last state, like a
    /// time-limit truncation) and continues in the next batch.
    Steps,
}

/// One copy's episode in progress: the steps of this batch, and the episode's returns
/// so far (which include earlier batches' steps in `Steps` mode).
#[derive(Default, Clone)]
struct Episode {
    obs: Vec<f64>,
    actions: Vec<f64>,
    rewards: Vec<f64>,
    dense: Vec<f64>,
    total: f64,
    total_dense: f64,
    /// Whether the task reported its goal reached at some step (None: never reported).
    reached: Option<bool>,
}

/// Collects batches from a vectorised env; keeps the episodes that continue from one
/// batch to the next (`Steps` mode).
pub struct Sampler {
    pub mode: RolloutMode,
    episodes: Vec<Episode>,
    /// `clip_actions`: each action's bounds (low, high), applied to what the env sees.
    clip: Option<(Vec<f64>, Vec<f64>)>,
}

impl Batch {
    /// Appends a copy's steps of this batch as one segment. `final_obs`: the observation
    /// after the last step, which bootstraps a segment that did not terminate;
    /// `episode_over`: the episode ended here (its returns are logged).
    fn push_segment(
        &mut self,
        ep: &mut Episode,
        terminated: bool,
        final_obs: &[f64],
        episode_over: bool,
    ) {
        let len = ep.rewards.len();
        if len == 0 {
            return;
        }
        self.terminated
            .extend(std::iter::repeat_n(false, len - 1).chain([terminated]));
        self.episode_end
            .extend(std::iter::repeat_n(false, len - 1).chain([true]));
        if !terminated {
            self.truncations
                .push((self.rewards.len() + len - 1, final_obs.to_vec()));
        }
        if episode_over {
            self.episode_returns.push(ep.total);
            self.episode_dense_returns.push(ep.total_dense);
            self.episode_outcomes.push((ep.reached, terminated));
        }
        self.obs.append(&mut ep.obs);
        self.actions.append(&mut ep.actions);
        self.rewards.append(&mut ep.rewards);
        self.dense_rewards.append(&mut ep.dense);
    }
}

impl Batch {
    /// Appends `other`'s segments after this batch's.
    fn append(&mut self, mut other: Batch) {
        let offset = self.rewards.len();
        self.truncations.extend(
            other
                .truncations
                .drain(..)
                .map(|(t, obs)| (t + offset, obs)),
        );
        self.obs.append(&mut other.obs);
        self.actions.append(&mut other.actions);
        self.rewards.append(&mut other.rewards);
        self.dense_rewards.append(&mut other.dense_rewards);
        self.terminated.append(&mut other.terminated);
        self.episode_end.append(&mut other.episode_end);
        self.episode_returns.append(&mut other.episode_returns);
        self.episode_dense_returns
            .append(&mut other.episode_dense_returns);
        self.episode_outcomes.append(&mut other.episode_outcomes);
    }
}

impl Sampler {
    pub fn new(mode: RolloutMode, num_envs: usize) -> Self {
        Self {
            mode,
            episodes: vec![Episode::default(); num_envs],
            clip: None,
        }
    }

    /// Clips every action to `[low, high]` before the env sees it; the batch keeps the
    /// sampled action, whose log-probability the policy updates use (as Stable-Baselines3
    /// and CleanRL clip).
    pub fn clipping(mut self, low: &[f64], high: &[f64]) -> Self {
        self.clip = Some((low.to_vec(), high.to_vec()));
        self
    }

    /// Whether every copy stands at the start of an episode (between batches of
    /// `Episodes` mode): then the run can be checkpointed for `--resume`.
    pub fn at_episode_starts(&self) -> bool {
        self.mode == RolloutMode::Episodes
    }

    /// One batch of at least `samples` steps with `policy` (see [`RolloutMode`]).
    ///
    /// Each copy runs on its worker thread for its whole share of the batch, with no
    /// barrier between steps, acting with the policy's host copy and its own sampling
    /// stream (seeded from `rng`, one draw per copy per batch): the batch does not depend
    /// on the number of threads. Episodes mode gives each copy a quota of
    /// ceil(`samples` / copies) steps in whole episodes, then keeps the shortest prefix
    /// of at least `samples` steps of their episodes taken in turn (module doc).
    ///
    /// Long by design: each copy's loop (act, step, end an episode, stop at the quota) is
    /// one closure run on the copy's thread; split, its episode and quota state would be
    /// threaded through helpers that each need all of it.
    pub fn collect(
        &mut self,
        venv: &mut VecEnv,
        acting: &ActingPolicy,
        rng: &mut ChaCha8Rng,
        samples: usize,
    ) -> Result<Batch, EnvError> {
        let (n, obs_dim, act_dim) = (venv.num_envs(), venv.spec().obs_dim, venv.spec().act_dim);
        let quota = samples.div_ceil(n);
        let mode = self.mode;
        let clip = self.clip.as_ref();
        let states: Vec<(Episode, u64)> = std::mem::take(&mut self.episodes)
            .into_iter()
            .map(|ep| (ep, rng.random()))
            .collect();
        let result = venv.map_copies(states, |env, obs, (mut ep, seed)| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut batch = Batch {
                obs_dim,
                act_dim,
                ..Default::default()
            };
            // Episodes mode: one batch per whole episode, cut to the prefix afterwards.
            let mut episodes = Vec::new();
            let mut taken = 0;
            loop {
                let action = acting.sample(obs, &mut rng);
                ep.obs.extend_from_slice(obs);
                ep.actions.extend_from_slice(&action);
                let step = match clip {
                    None => env.step(&action, obs)?,
                    Some((low, high)) => {
                        let mut clipped = action.clone();
                        clip_to_range(&mut clipped, low, high);
                        env.step(&clipped, obs)?
                    }
                };
                taken += 1;
                ep.rewards.push(step.reward);
                ep.dense.push(step.info.dense_reward);
                ep.total += step.reward;
                ep.total_dense += step.info.dense_reward;
                if let Some(reached) = step.info.success {
                    ep.reached = Some(reached || ep.reached == Some(true));
                }
                if step.done() {
                    match mode {
                        RolloutMode::Episodes => {
                            let mut episode = Batch {
                                obs_dim,
                                act_dim,
                                ..Default::default()
                            };
                            episode.push_segment(&mut ep, step.terminated, obs, true);
                            episodes.push(episode);
                        }
                        RolloutMode::Steps => {
                            batch.push_segment(&mut ep, step.terminated, obs, true)
                        }
                    }
                    ep = Episode::default();
                    env.reset(None, obs);
                }
                let stop = match mode {
                    RolloutMode::Episodes => step.done() && taken >= quota,
                    RolloutMode::Steps => taken == quota,
                };
                if stop {
                    // Steps mode: cut the running episode here; it goes on next batch.
                    batch.push_segment(&mut ep, false, obs, false);
                    return Ok((batch, episodes, ep));
                }
            }
        });
        let per_copy = match result {
            Ok(per_copy) => per_copy,
            Err(e) => {
                self.episodes = vec![Episode::default(); n];
                return Err(e);
            }
        };
        let mut batch = Batch {
            obs_dim,
            act_dim,
            ..Default::default()
        };
        let mut per_copy_episodes = Vec::with_capacity(n);
        for (part, episodes, ep) in per_copy {
            batch.append(part);
            per_copy_episodes.push(episodes);
            self.episodes.push(ep);
        }
        if mode == RolloutMode::Episodes {
            append_in_turns(&mut batch, per_copy_episodes, samples);
        }
        Ok(batch)
    }
}

/// Episodes mode's cut: the copies' whole episodes taken in turn (copy 0's first, copy
/// 1's first, ..., copy 0's second, ...) until the batch has `samples` steps.
fn append_in_turns(batch: &mut Batch, per_copy: Vec<Vec<Batch>>, samples: usize) {
    let mut per_copy: Vec<_> = per_copy.into_iter().map(Vec::into_iter).collect();
    loop {
        let mut any = false;
        for episodes in per_copy.iter_mut() {
            if batch.len() >= samples.max(1) {
                return;
            }
            if let Some(episode) = episodes.next() {
                batch.append(episode);
                any = true;
            }
        }
        if !any {
            return;
        }
    }
}

//! LOGO's sparse-reward versions of the tasks (see `docs/reference.md`): the agent is paid
//! only for having gone far, or only once per episode. The dense reward stays in
//! [`StepInfo::dense_reward`] so evaluation can report both.

use crate::env::{Env, EnvError, EnvSpec, ResetPoint, Step};

/// How the sparse reward is paid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SparseRule {
    /// +1 on every step where `x − x_init > threshold` (x_init: x at the episode's start),
    /// else 0. Hopper and Walker2d use 2.0, HalfCheetah 20.0. (The LOGO code pays on every
    /// step spent past the threshold, not once; its published curves follow the code.)
    Distance { threshold: f64 },
    /// The dense rewards accumulated and paid in one lump on the episode's last step
    /// (termination or time limit); 0 on every other step. InvertedDoublePendulum.
    EpisodeLump,
}

/// Wraps an env and replaces its reward by LOGO's sparse one.
pub struct SparseReward<E: Env> {
    inner: E,
    rule: SparseRule,
    spec: EnvSpec,
    x_init: f64,
    episode_dense_return: f64,
}

impl<E: Env> SparseReward<E> {
    pub fn new(inner: E, rule: SparseRule) -> Self {
        let mut spec = inner.spec().clone();
        spec.id = format!("Sparse{}", spec.id);
        Self {
            inner,
            rule,
            spec,
            x_init: 0.0,
            episode_dense_return: 0.0,
        }
    }

    pub fn rule(&self) -> SparseRule {
        self.rule
    }

    fn start_episode(&mut self) {
        self.x_init = self.inner.x_position();
        self.episode_dense_return = 0.0;
    }
}

impl<E: Env> Env for SparseReward<E> {
    fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    fn reset(&mut self, seed: Option<u64>, obs: &mut [f64]) {
        self.inner.reset(seed, obs);
        self.start_episode();
    }

    fn step(&mut self, action: &[f64], obs: &mut [f64]) -> Result<Step, EnvError> {
        let mut step = self.inner.step(action, obs)?;
        step.reward = match self.rule {
            SparseRule::Distance { threshold } => {
                if step.info.x_position - self.x_init > threshold {
                    1.0
                } else {
                    0.0
                }
            }
            SparseRule::EpisodeLump => {
                self.episode_dense_return += step.info.dense_reward;
                if step.done() {
                    self.episode_dense_return
                } else {
                    0.0
                }
            }
        };
        Ok(step)
    }

    fn reset_point(&self) -> Result<ResetPoint, EnvError> {
        self.inner.reset_point()
    }

    fn restore_reset_point(&mut self, point: &ResetPoint, obs: &mut [f64]) -> Result<(), EnvError> {
        self.inner.restore_reset_point(point, obs)?;
        self.start_episode();
        Ok(())
    }

    fn set_state(&mut self, qpos: &[f64], qvel: &[f64], obs: &mut [f64]) -> Result<(), EnvError> {
        self.inner.set_state(qpos, qvel, obs)?;
        // A state set at the start of an episode is that episode's start.
        self.start_episode();
        Ok(())
    }

    fn state(&self) -> (&[f64], &[f64]) {
        self.inner.state()
    }
}

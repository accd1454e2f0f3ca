//! N copies of one env stepped on worker threads.
//!
//! Each copy owns its `MjData` and noise generator over one shared `MjModel`, and no copy
//! reads another's state, so the results are the same whatever the thread count (tested).
//! A copy whose episode ends is reset on the spot; its last observation is kept in
//! [`VecStep::final_obs`] so a truncated episode can bootstrap from it.

use rayon::prelude::*;

use crate::env::{Env, EnvError, EnvSpec, ResetPoint, Step};
use crate::registry::EnvFactory;

/// The outcome of one vectorised step, env-major (`obs[i * obs_dim..][..obs_dim]`).
#[derive(Debug, Clone, Default)]
pub struct VecStep {
    /// Observations to act on next (after any auto-reset).
    pub obs: Vec<f64>,
    pub steps: Vec<Step>,
    /// The episode's last observation where `steps[i].done()`; stale elsewhere.
    pub final_obs: Vec<f64>,
}

/// Where the copies are stepped.
enum Workers {
    /// One after another on the calling thread.
    Serial,
    /// On the env's own pool.
    Own(rayon::ThreadPool),
    /// On the rayon pool the caller runs in, shared with the caller's other work.
    CallerPool,
}

pub struct VecEnv {
    envs: Vec<Box<dyn Env>>,
    workers: Workers,
    spec: EnvSpec,
    out: VecStep,
}

/// Steps one copy; resets it when its episode ends.
fn step_one(
    env: &mut Box<dyn Env>,
    action: &[f64],
    obs: &mut [f64],
    final_obs: &mut [f64],
    out: &mut Step,
) -> Result<(), EnvError> {
    *out = env.step(action, obs)?;
    if out.done() {
        final_obs.copy_from_slice(obs);
        env.reset(None, obs);
    }
    Ok(())
}

impl VecEnv {
    /// `num_envs` copies on `threads` worker threads (1: the calling thread). Copy `i` is
    /// first reset with seed `seed + i`, as Gymnasium's vector envs do.
    pub fn new(
        factory: &EnvFactory,
        num_envs: usize,
        threads: usize,
        seed: u64,
    ) -> Result<Self, EnvError> {
        if num_envs == 0 || threads == 0 {
            return Err(EnvError::InvalidOption(format!(
                "a vectorised env needs at least one copy and one thread (got {num_envs} copies, {threads} threads)"
            )));
        }
        let workers = if threads > 1 {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .thread_name(|i| format!("logo-env-{i}"))
                .build()
                .map_err(|e| {
                    EnvError::InvalidOption(format!("cannot start {threads} threads: {e}"))
                })?;
            Workers::Own(pool)
        } else {
            Workers::Serial
        };
        Self::with_workers(factory, num_envs, workers, seed)
    }

    /// `num_envs` copies stepped on the rayon pool of whoever calls [`Self::map_copies`]
    /// or [`Self::step`] (a trainer that runs every phase on one pool of its own).
    pub fn on_caller_pool(
        factory: &EnvFactory,
        num_envs: usize,
        seed: u64,
    ) -> Result<Self, EnvError> {
        if num_envs == 0 {
            return Err(EnvError::InvalidOption(
                "a vectorised env needs at least one copy (got 0)".into(),
            ));
        }
        Self::with_workers(factory, num_envs, Workers::CallerPool, seed)
    }

    fn with_workers(
        factory: &EnvFactory,
        num_envs: usize,
        workers: Workers,
        seed: u64,
    ) -> Result<Self, EnvError> {
        let spec = factory.spec().clone();
        let envs = (0..num_envs)
            .map(|_| factory.build())
            .collect::<Result<Vec<_>, _>>()?;
        let mut vec_env = Self {
            envs,
            workers,
            out: VecStep {
                obs: vec![0.0; num_envs * spec.obs_dim],
                steps: vec![Step::default(); num_envs],
                final_obs: vec![0.0; num_envs * spec.obs_dim],
            },
            spec,
        };
        vec_env.reset(seed);
        Ok(vec_env)
    }

    /// Every copy's reset point (see [`Env::reset_point`]): valid between rollouts that
    /// end with every copy freshly reset, as `logo_algo::sampler::Sampler::collect` does.
    pub fn reset_points(&self) -> Result<Vec<ResetPoint>, EnvError> {
        self.envs.iter().map(|env| env.reset_point()).collect()
    }

    /// Restores every copy from [`Self::reset_points`].
    pub fn restore_reset_points(&mut self, points: &[ResetPoint]) -> Result<(), EnvError> {
        if points.len() != self.envs.len() {
            return Err(EnvError::InvalidOption(format!(
                "{} reset points for {} env copies",
                points.len(),
                self.envs.len()
            )));
        }
        let obs_dim = self.spec.obs_dim;
        for ((env, obs), point) in self
            .envs
            .iter_mut()
            .zip(self.out.obs.chunks_mut(obs_dim))
            .zip(points)
        {
            env.restore_reset_point(point, obs)?;
        }
        Ok(())
    }

    /// Resets every copy, copy `i` with seed `seed + i`.
    pub fn reset(&mut self, seed: u64) -> &[f64] {
        let obs_dim = self.spec.obs_dim;
        for (i, (env, obs)) in self
            .envs
            .iter_mut()
            .zip(self.out.obs.chunks_mut(obs_dim))
            .enumerate()
        {
            env.reset(Some(seed.wrapping_add(i as u64)), obs);
        }
        &self.out.obs
    }

    pub fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    pub fn num_envs(&self) -> usize {
        self.envs.len()
    }

    /// Current observations, `num_envs * obs_dim`.
    pub fn obs(&self) -> &[f64] {
        &self.out.obs
    }

    /// Runs `f` once per copy on the worker threads, each with its own state from
    /// `states` (one per copy), the copy's env and its current observation (which `f`
    /// must leave current, resetting the env when an episode ends). The results come back
    /// in copy order. For loops that drive a copy for many steps without a barrier after
    /// each one (the rollout), where [`Self::step`] synchronises every step.
    pub fn map_copies<S: Send, T: Send>(
        &mut self,
        states: Vec<S>,
        f: impl Fn(&mut dyn Env, &mut [f64], S) -> Result<T, EnvError> + Sync,
    ) -> Result<Vec<T>, EnvError> {
        assert_eq!(states.len(), self.envs.len(), "one state per copy");
        let obs_dim = self.spec.obs_dim;
        let (envs, obs) = (&mut self.envs, &mut self.out.obs);
        let run =
            |((env, o), state): ((&mut Box<dyn Env>, &mut [f64]), S)| f(env.as_mut(), o, state);
        // One task per copy: a copy's share of a batch is long, and whichever worker is
        // free takes the next copy.
        let parallel = |envs: &mut Vec<Box<dyn Env>>, obs: &mut Vec<f64>, states: Vec<S>| {
            envs.par_iter_mut()
                .zip(obs.par_chunks_mut(obs_dim))
                .zip(states)
                .with_max_len(1)
                .map(run)
                .collect()
        };
        match &self.workers {
            Workers::Own(pool) => pool.install(|| parallel(envs, obs, states)),
            Workers::CallerPool => parallel(envs, obs, states),
            Workers::Serial => envs
                .iter_mut()
                .zip(obs.chunks_mut(obs_dim))
                .zip(states)
                .map(run)
                .collect(),
        }
    }

    /// Steps every copy with its slice of `actions` (`num_envs * act_dim`, env-major).
    pub fn step(&mut self, actions: &[f64]) -> Result<&VecStep, EnvError> {
        let (n, act_dim, obs_dim) = (self.envs.len(), self.spec.act_dim, self.spec.obs_dim);
        if actions.len() != n * act_dim {
            return Err(EnvError::ActionLength {
                env: format!("{} x {n}", self.spec.id),
                expected: n * act_dim,
                got: actions.len(),
            });
        }
        let VecStep {
            obs,
            steps,
            final_obs,
        } = &mut self.out;
        let envs = &mut self.envs;
        let mut parallel = || {
            envs.par_iter_mut()
                .zip(actions.par_chunks(act_dim))
                .zip(obs.par_chunks_mut(obs_dim))
                .zip(final_obs.par_chunks_mut(obs_dim))
                .zip(steps.par_iter_mut())
                .try_for_each(|((((env, a), o), f), s)| step_one(env, a, o, f, s))
        };
        match &self.workers {
            Workers::Own(pool) => pool.install(parallel)?,
            Workers::CallerPool => parallel()?,
            Workers::Serial => envs
                .iter_mut()
                .zip(actions.chunks(act_dim))
                .zip(obs.chunks_mut(obs_dim))
                .zip(final_obs.chunks_mut(obs_dim))
                .zip(steps.iter_mut())
                .try_for_each(|((((env, a), o), f), s)| step_one(env, a, o, f, s))?,
        }
        Ok(&self.out)
    }
}

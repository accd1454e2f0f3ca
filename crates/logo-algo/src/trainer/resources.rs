//! What a run works with but does not learn: the engine, the worker threads, the env
//! copies and their sampler, the evaluation env, DAPG's demonstration rows. None of it is in a checkpoint except
//! the sampler's random state ([`SamplerState`]), which the learner's state carries.

use std::sync::Arc;
use std::time::Instant;

use logo_envs::{Env, EnvFactory, EnvSpec, RngState, VecEnv};
use logo_nn::flops::in_phase;
use logo_nn::{ActingPolicy, Engine};
use rand::RngCore;
use rand_chacha::ChaCha8Rng;

use super::learner_state::{Networks, SamplerState};
use super::schedule::Schedule;
use crate::config::{EvalInitialStates, TrainConfig};
use crate::dapg::DemonstrationRows;
use crate::episode::{Evaluation, EvaluationPlan, evaluate, evaluation_seed};
use crate::error::TrainError;
use crate::sampler::{Batch, Sampler};
use crate::streams;

pub(super) struct Resources<E: Engine> {
    pub(super) engine: E,
    /// The worker threads of every phase (`config.threads`): one pool, so that the
    /// sampler, the GEMMs and the fits share the cores instead of oversubscribing them.
    pub(super) pool: Arc<rayon::ThreadPool>,
    pub(super) schedule: Schedule,
    pub(super) collector: Collector,
    pub(super) evaluator: Evaluator,
    /// The networks' burn modules, into which the learner's parameters are written when
    /// its state is taken (a checkpoint).
    pub(super) shapes: Networks,
    /// DAPG's demonstration rows (`[demonstration_rows]`).
    pub(super) demonstrations: Option<DemonstrationRows>,
}

impl<E: Engine> Resources<E> {
    /// The resources of a run of `config` on the envs `factory` makes.
    pub(super) fn build(
        engine: E,
        config: &TrainConfig,
        factory: &EnvFactory,
        shapes: Networks,
        demonstrations: Option<DemonstrationRows>,
    ) -> Result<Self, TrainError> {
        let spec = factory.spec();
        let evaluator = Evaluator::new(config, spec)?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(config.threads)
            .thread_name(|i| format!("logo-{i}"))
            .build()
            .map_err(|source| TrainError::Threads {
                threads: config.threads,
                source,
            })?;
        let collector = Collector {
            // The copies run on the trainer's pool, as every other phase does.
            venv: VecEnv::on_caller_pool(factory, config.num_envs, config.seed)?,
            sampler: sampler(config, spec),
            rng: streams::sampler(config.seed),
        };
        Ok(Self {
            engine,
            pool: Arc::new(pool),
            schedule: Schedule::default(),
            collector,
            evaluator,
            shapes,
            demonstrations,
        })
    }
}

/// Step 1's sampler: `clip_actions` clips what the env sees to the action space.
fn sampler(config: &TrainConfig, spec: &EnvSpec) -> Sampler {
    let sampler = Sampler::new(config.rollout, config.num_envs);
    match config.clip_actions {
        true => sampler.clipping(&spec.action_low, &spec.action_high),
        false => sampler,
    }
}

/// Step 1's state: the env copies, how batches are cut, and the sampler's generator.
pub(super) struct Collector {
    pub(super) venv: VecEnv,
    pub(super) sampler: Sampler,
    pub(super) rng: ChaCha8Rng,
}

/// A collected batch, its sampling time, and the sampler's state before it (None where
/// batches carry episodes over, which cannot be resumed).
pub(super) struct Collected {
    pub(super) batch: Batch,
    pub(super) seconds: f64,
    pub(super) before: Option<SamplerState>,
}

impl Collector {
    /// The sampler's state before the next batch; None between batches that carry
    /// episodes over.
    pub(super) fn state(&self) -> Result<Option<SamplerState>, TrainError> {
        if !self.sampler.at_episode_starts() {
            return Ok(None);
        }
        Ok(Some(SamplerState {
            rng: RngState::of(&self.rng),
            env_points: self.venv.reset_points()?,
        }))
    }

    /// The sampler as `state` left it, so that the next batch is the one it would have
    /// collected.
    pub(super) fn restore(&mut self, state: &SamplerState) -> Result<(), TrainError> {
        self.rng = state.rng.to_rng()?;
        self.venv.restore_reset_points(&state.env_points)?;
        Ok(())
    }

    /// The next batch when `wanted` (not after the last iteration).
    pub(super) fn collect_if(
        &mut self,
        wanted: bool,
        policy: &ActingPolicy,
        samples: usize,
    ) -> Result<Option<Collected>, TrainError> {
        wanted.then(|| self.collect(policy, samples)).transpose()
    }

    /// One batch of at least `samples` steps with `policy`.
    pub(super) fn collect(
        &mut self,
        policy: &ActingPolicy,
        samples: usize,
    ) -> Result<Collected, TrainError> {
        let before = self.state()?;
        let clock = Instant::now();
        let batch = in_phase("sampling", || {
            self.sampler
                .collect(&mut self.venv, policy, &mut self.rng, samples)
        })?;
        Ok(Collected {
            batch,
            seconds: clock.elapsed().as_secs_f64(),
            before,
        })
    }
}

/// Step 8's env and initial states (fixed, or fresh per iteration: `eval_initial_states`).
pub(super) struct Evaluator {
    pub(super) env: Box<dyn Env>,
    pub(super) seed: u64,
    /// How long it plays (`eval_steps`, `eval_episodes`), how it acts (`clip_actions`:
    /// clipped as the sampled actions are) and judges (`success`).
    pub(super) plan: EvaluationPlan,
    pub(super) initial_states: EvalInitialStates,
}

impl Evaluator {
    /// The evaluation env of `config`, which must fit the training env's `spec`: the
    /// trained task itself, whose steps report the dense reward beside its own (a sparse
    /// wrapper leaves the dynamics and the dense reward as they are), unless `eval_env`
    /// names another.
    fn new(config: &TrainConfig, spec: &EnvSpec) -> Result<Self, TrainError> {
        let env = config.evaluated_env().factory()?.build()?;
        if let Some(mismatch) = crate::config::dims_mismatch(spec, env.spec()) {
            return Err(mismatch.into());
        }
        Ok(Self {
            env,
            seed: config.seed,
            plan: EvaluationPlan {
                min_steps: config.eval_steps,
                min_episodes: config.eval_episodes,
                clip_actions: config.clip_actions,
                success: config.success,
            },
            initial_states: config.eval_initial_states,
        })
    }

    /// Step 8 when `due`, with its wall time (zero work and NaN metrics otherwise).
    pub(super) fn timed(
        &mut self,
        policy: &ActingPolicy,
        k: usize,
        due: bool,
    ) -> Result<(Option<Evaluation>, f64), TrainError> {
        let clock = Instant::now();
        let evaluation = due.then(|| self.evaluate(policy, k)).transpose()?;
        Ok((evaluation, clock.elapsed().as_secs_f64()))
    }

    /// Iteration `k`'s evaluation, from the initial states `eval_initial_states` says.
    pub(super) fn evaluate(
        &mut self,
        policy: &ActingPolicy,
        k: usize,
    ) -> Result<Evaluation, TrainError> {
        let (env, seed, plan) = (self.env.as_mut(), self.seed, self.plan);
        let mut fresh = streams::evaluation(seed, k);
        let initial_states = self.initial_states;
        let reset_seed = move |episode| match initial_states {
            EvalInitialStates::Fixed => evaluation_seed(seed, episode),
            EvalInitialStates::Fresh => fresh.next_u64(),
        };
        Ok(in_phase("evaluation", || {
            evaluate(env, policy, reset_seed, plan)
        })?)
    }
}

//! What a trainer holds between iterations: its parts and the types they are made of.
//! A leaf of the trainer: building (`build.rs`), checkpoints (`checkpoint.rs`), the
//! steps (`steps.rs`) and the iteration (`mod.rs`) all work on these.

use std::sync::Arc;
use std::time::Instant;

use logo_envs::{Env, ResetPoint, RngState, VecEnv};
use logo_nn::flops::in_phase;
use logo_nn::{ActingPolicy, Cpu, Discriminator, Engine, GaussianPolicy, Policy, ValueNet};
use rand::RngCore;
use rand_chacha::ChaCha8Rng;

use super::recorder::Recorder;
use super::schedule::Schedule;
use crate::config::{EvalInitialStates, TrainConfig};
use crate::critic::CriticSet;
use crate::episode::{Evaluation, evaluate, evaluation_seed};
use crate::guidance::Guidance;
use crate::policy_update::UpdateState;
use crate::run_dir::TrainError;
use crate::sampler::{Batch, Sampler};
use crate::streams::{self, Stream, generator};

pub struct Trainer<E: Engine> {
    pub config: TrainConfig,
    pub(super) engine: E,
    /// The run folder's writer: metrics.csv, TensorBoard, when checkpoints are due.
    pub(super) recorder: Recorder,
    /// The worker threads of every phase (`config.threads`): one pool, so that the
    /// sampler, the GEMMs and the fits share the cores instead of oversubscribing them.
    pub(super) pool: Arc<rayon::ThreadPool>,
    pub(super) schedule: Schedule,
    pub(super) collector: Collector,
    pub(super) evaluator: Evaluator,
    pub(super) policy: Policy<E>,
    pub(super) improvement: UpdateState,
    pub(super) critics: Critics<E>,
    pub(super) guidance: Option<Guidance<E>>,
    pub(super) modules: Modules,
    /// Batch k+1, where the pipelined schedule collected it during iteration k.
    pub(super) next_batch: Option<Collected>,
    pub(super) iteration: usize,
    pub(super) samples: usize,
    /// Which engine ran which iterations, written into every checkpoint's metadata.
    pub(super) engines: Vec<EngineSpan>,
}

/// Step 1's state: the env copies, how batches are cut, and the sampler's generator.
pub(super) struct Collector {
    pub(super) venv: VecEnv,
    pub(super) sampler: Sampler,
    pub(super) rng: ChaCha8Rng,
}

/// The sampler's generator and every env copy's reset point between two batches: what a
/// checkpoint records so that `--resume` collects the next batch again exactly.
#[derive(Debug, Clone)]
pub(super) struct SamplerState {
    pub(super) rng: RngState,
    pub(super) env_points: Vec<ResetPoint>,
}

/// A collected batch, its sampling time, and the sampler's state before it (None where
/// batches carry episodes over, which cannot be resumed).
pub(super) struct Collected {
    pub(super) batch: Batch,
    pub(super) seconds: f64,
    pub(super) before: Option<SamplerState>,
}

impl Collector {
    pub(super) fn state(&self) -> Result<Option<SamplerState>, TrainError> {
        if !self.sampler.at_episode_starts() {
            return Ok(None);
        }
        Ok(Some(SamplerState {
            rng: RngState::of(&self.rng),
            env_points: self.venv.reset_points()?,
        }))
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

/// Step 8's env and fixed initial states.
pub(super) struct Evaluator {
    pub(super) env: Box<dyn Env>,
    pub(super) seed: u64,
    pub(super) min_steps: usize,
    pub(super) initial_states: EvalInitialStates,
    /// `clip_actions`: the evaluated mean action is clipped as the sampled ones are.
    pub(super) clip_actions: bool,
}

impl Evaluator {
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
        let (env, seed, min_steps, clip) = (
            self.env.as_mut(),
            self.seed,
            self.min_steps,
            self.clip_actions,
        );
        let mut fresh = streams::evaluation(seed, k);
        let initial_states = self.initial_states;
        let reset_seed = move |episode| match initial_states {
            EvalInitialStates::Fixed => evaluation_seed(seed, episode),
            EvalInitialStates::Fresh => fresh.next_u64(),
        };
        Ok(in_phase("evaluation", || {
            evaluate(env, policy, reset_seed, min_steps, clip)
        })?)
    }
}

/// The critics of both reward streams.
pub(super) struct Critics<E: Engine> {
    pub(super) env: CriticSet<E>,
    pub(super) guidance: Option<CriticSet<E>>,
}

/// Step 7's losses (NaN for a stream not fitted) and wall time.
pub(super) struct CriticFits {
    pub(super) env_loss: f64,
    pub(super) guidance_loss: f64,
    pub(super) seconds: f64,
}

impl<E: Engine> Critics<E> {
    /// Fits each critic to its stream's returns on `obs`, each from its own stream of
    /// minibatch shuffles. The two fits are independent, so they run side by side: each
    /// alone scales imperfectly over the threads, together they keep the cores busy.
    pub(super) fn fit(
        &mut self,
        engine: &E,
        (seed, k): (u64, usize),
        obs: &E::Rows,
        env_returns: &[f64],
        guidance_returns: Option<&[f64]>,
    ) -> CriticFits {
        let clock = Instant::now();
        let Critics { env, guidance } = self;
        let (env_loss, guidance_loss) = rayon::join(
            || {
                in_phase("critic fits", || {
                    let mut rng = generator(seed, k, Stream::EnvCriticFit);
                    env.fit(engine, obs, env_returns, &mut rng)
                })
            },
            || match (guidance, guidance_returns) {
                (Some(critic), Some(returns)) => in_phase("critic fits", || {
                    let mut rng = generator(seed, k, Stream::GuidanceCriticFit);
                    critic.fit(engine, obs, returns, &mut rng)
                }),
                _ => f64::NAN,
            },
        );
        CriticFits {
            env_loss,
            guidance_loss,
            seconds: clock.elapsed().as_secs_f64(),
        }
    }
}

/// The networks as burn modules on the CPU: their definitions (the reference's
/// initialisation), and the form checkpoints are written and read in, whatever the engine.
pub(super) struct Modules {
    pub(super) policy: GaussianPolicy<Cpu>,
    pub(super) critic: Vec<ValueNet<Cpu>>,
    pub(super) guidance_critic: Option<Vec<ValueNet<Cpu>>>,
    pub(super) discriminator: Option<Discriminator<Cpu>>,
}

/// From `from_iteration` on (until the next span), the run trained on `engine`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EngineSpan {
    pub from_iteration: usize,
    pub engine: String,
}

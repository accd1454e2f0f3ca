//! The training loop: [`Trainer::step`] is one iteration of LOGO (Algorithm 1), written
//! once for every engine and every configured variant:
//!
//! 1. collect whole episodes with π_k;
//! 2. advantages of the env reward, with the env critic as it stands;
//! 3. δ_k from the batch's mean sparse return; while δ_k is above its floor, the guidance
//!    reward r_C (from last iteration's discriminator, or log π_b − log π_k) and its
//!    advantages with the guidance critic;
//! 4. improvement step (`[improvement]`'s kind, KL ≈ δ = `max_kl`) → π_{k+½};
//! 5. guidance step (`[guidance.update]`'s kind, KL ≈ δ_k, ratio against π_k) → π_{k+1};
//! 6. one discriminator update;
//! 7. both critics fitted to this batch's returns (for iteration k+1's advantages);
//! 8. evaluation of π_{k+1} on the dense env with the mean action; metrics row, checkpoint.
//!
//! Without `[guidance]` it is the improvement step alone (TRPO, PPO, ...). Which of steps
//! 4-8 run beside which is decided in one place, [`Trainer::steps_and_fits`], by the
//! run's [`Schedule`]; the arithmetic is the same under either schedule.
//! Building a trainer is in `build.rs`, checkpoints and `--resume` in `checkpoint.rs`.

mod build;
mod checkpoint;

use std::sync::Arc;
use std::time::Instant;

use burn::tensor::Tensor;
use logo_envs::{Env, ResetPoint, RngState, VecEnv};
use logo_nn::flops::in_phase;
use logo_nn::{ActingPolicy, Engine, Policy};
use rand_chacha::ChaCha8Rng;

use crate::config::TrainConfig;
use crate::critic::CriticSet;
use crate::episode::{Evaluation, evaluate};
use crate::gae::{GaeInput, gae, normalise};
use crate::guidance::Guidance;
use crate::metrics::IterationMetrics;
use crate::policy_update::{StepBatch, StopReason, UpdateState, UpdateStats};
use crate::run_dir::RunDir;
pub use crate::run_dir::TrainError;
use crate::sampler::{Batch, Sampler};
use crate::streams::{Stream, generator};
use crate::tensorboard::EventWriter;
pub use checkpoint::{EngineSpan, engine_history};

/// How an iteration's steps are laid over the run's worker threads. Either way every
/// step computes the same numbers: a run's metrics and checkpoints are bit-identical
/// under both (tested).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Schedule {
    /// One step after another, in Algorithm 1's order.
    Sequential,
    /// The critic fits of iteration k (step 7) beside its policy steps and discriminator
    /// update (4-6), then beside the sampling of batch k+1 and the evaluation of π_{k+1}:
    /// nothing among those reads the fitted critics, which iteration k+1's advantages
    /// need first.
    #[default]
    Pipelined,
}

pub struct Trainer<E: Engine> {
    pub config: TrainConfig,
    engine: E,
    run: RunDir,
    /// The worker threads of every phase (`config.threads`): one pool, so that the
    /// sampler, the GEMMs and the fits share the cores instead of oversubscribing them.
    pool: Arc<rayon::ThreadPool>,
    schedule: Schedule,
    collector: Collector,
    evaluator: Evaluator,
    policy: Policy<E>,
    improvement: UpdateState,
    critics: Critics<E>,
    guidance: Option<Guidance<E>>,
    modules: build::Modules,
    /// Batch k+1, where the pipelined schedule collected it during iteration k.
    next_batch: Option<Collected>,
    iteration: usize,
    samples: usize,
    started: Instant,
    /// Wall seconds of the iterations before a resume.
    wall_offset: f64,
    /// Which engine ran which iterations, written into every checkpoint's metadata.
    engines: Vec<EngineSpan>,
    /// The iteration count of the last checkpoint written (or resumed from).
    saved_at: Option<usize>,
    /// TensorBoard's event file, once [`Trainer::write_tensorboard`] opened it.
    events: Option<EventWriter>,
}

/// Step 1's state: the env copies, how batches are cut, and the sampler's generator.
struct Collector {
    venv: VecEnv,
    sampler: Sampler,
    rng: ChaCha8Rng,
}

/// The sampler's generator and every env copy's reset point between two batches: what a
/// checkpoint records so that `--resume` collects the next batch again exactly.
#[derive(Debug, Clone)]
struct SamplerState {
    rng: RngState,
    env_points: Vec<ResetPoint>,
}

/// A collected batch, its sampling time, and the sampler's state before it (None where
/// batches carry episodes over, which cannot be resumed).
struct Collected {
    batch: Batch,
    seconds: f64,
    before: Option<SamplerState>,
}

impl Collector {
    fn state(&self) -> Result<Option<SamplerState>, TrainError> {
        if !self.sampler.at_episode_starts() {
            return Ok(None);
        }
        Ok(Some(SamplerState {
            rng: RngState::of(&self.rng),
            env_points: self.venv.reset_points()?,
        }))
    }

    /// One batch of at least `samples` steps with `policy`.
    fn collect(&mut self, policy: &ActingPolicy, samples: usize) -> Result<Collected, TrainError> {
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
struct Evaluator {
    env: Box<dyn Env>,
    seed: u64,
    min_steps: usize,
}

impl Evaluator {
    fn evaluate(&mut self, policy: &ActingPolicy) -> Result<Evaluation, TrainError> {
        let (env, seed, min_steps) = (self.env.as_mut(), self.seed, self.min_steps);
        Ok(in_phase("evaluation", || {
            evaluate(env, policy, seed, min_steps)
        })?)
    }
}

/// The critics of both reward streams.
struct Critics<E: Engine> {
    env: CriticSet<E>,
    guidance: Option<CriticSet<E>>,
}

/// Step 7's losses (NaN for a stream not fitted) and wall time.
struct CriticFits {
    env_loss: f64,
    guidance_loss: f64,
    seconds: f64,
}

impl<E: Engine> Critics<E> {
    /// Fits each critic to its stream's returns on `obs`, each from its own stream of
    /// minibatch shuffles.
    fn fit(
        &mut self,
        engine: &E,
        (seed, k): (u64, usize),
        obs: &E::Rows,
        env_returns: &[f64],
        guidance_returns: Option<&[f64]>,
    ) -> CriticFits {
        let clock = Instant::now();
        let (env_loss, guidance_loss) = in_phase("critic fits", || {
            let mut rng = generator(seed, k, Stream::EnvCriticFit);
            let env_loss = self.env.fit(engine, obs, env_returns, &mut rng);
            let guidance_loss = match (&mut self.guidance, guidance_returns) {
                (Some(critic), Some(returns)) => {
                    let mut rng = generator(seed, k, Stream::GuidanceCriticFit);
                    critic.fit(engine, obs, returns, &mut rng)
                }
                _ => f64::NAN,
            };
            (env_loss, guidance_loss)
        });
        CriticFits {
            env_loss,
            guidance_loss,
            seconds: clock.elapsed().as_secs_f64(),
        }
    }
}

/// Normalised advantages and the critic's regression targets of one reward stream.
struct Advantages {
    normalised: Vec<f64>,
    returns: Vec<f64>,
}

/// Step 3's output while the guidance step runs.
struct GuidanceStream<E: Engine> {
    advantages: Advantages,
    discriminator_inputs: Option<E::Rows>,
    mean_reward: f64,
}

/// What steps 4-6 did.
struct PolicySteps {
    improvement: UpdateStats,
    guidance: Option<UpdateStats>,
    disc_loss: Option<f64>,
    t_policy_step: f64,
    t_guidance: f64,
    t_discriminator: f64,
}

/// What steps 4-8 produced.
struct Later {
    steps: PolicySteps,
    fits: CriticFits,
    evaluation: Option<Evaluation>,
    t_evaluation: f64,
    next: Option<Collected>,
}

/// GAE for one reward stream with `critic` as it stands.
fn advantages<E: Engine>(
    engine: &E,
    config: &TrainConfig,
    critic: &CriticSet<E>,
    batch: &Batch,
    obs: &E::Rows,
    rewards: &[f64],
) -> Advantages {
    let values = critic.values(engine, obs);
    let mut truncation_values = vec![0.0; batch.len()];
    if !batch.truncations.is_empty() {
        let rows: Vec<f64> = batch
            .truncations
            .iter()
            .flat_map(|(_, o)| o.iter().copied())
            .collect();
        let v = critic.values(engine, &engine.rows(&rows, batch.obs_dim));
        for ((t, _), value) in batch.truncations.iter().zip(v) {
            truncation_values[*t] = value;
        }
    }
    let input = GaeInput {
        rewards,
        values: &values,
        terminated: &batch.terminated,
        episode_end: &batch.episode_end,
        truncation_values: &truncation_values,
    };
    let (adv, returns) = gae(
        &input,
        config.gamma,
        config.gae_lambda,
        config.cross_episode_bootstrap,
    );
    Advantages {
        normalised: normalise(&adv),
        returns,
    }
}

/// Stops the run when a step left a non-finite number behind.
fn finite(ok: bool, step: &str, what: &str) -> Result<(), TrainError> {
    if ok {
        Ok(())
    } else {
        Err(format!("{step} produced a non-finite number (NaN or ±inf) in the {what}").into())
    }
}

/// Takes a policy step's result as the policy; an error names `step` if the step or the
/// new policy holds a non-finite number.
fn take_step<E: Engine>(
    engine: &E,
    policy: &mut Policy<E>,
    (next, stats): (Policy<E>, UpdateStats),
    step: &str,
) -> Result<UpdateStats, TrainError> {
    *policy = next;
    finite(
        stats.is_finite() && policy.is_finite(engine),
        step,
        "policy's parameters or outputs",
    )?;
    Ok(stats)
}

/// Seconds between laps, for the per-phase times.
struct Stopwatch(Instant);

impl Stopwatch {
    fn start() -> Self {
        Self(Instant::now())
    }

    /// Seconds since the start or the previous lap.
    fn lap(&mut self) -> f64 {
        let now = Instant::now();
        let seconds = (now - self.0).as_secs_f64();
        self.0 = now;
        seconds
    }
}

/// Steps 4-6 of iteration `k`: π_k → π_{k+½} → π_{k+1}, then the discriminator.
#[allow(clippy::too_many_arguments)]
fn policy_steps<E: Engine>(
    engine: &E,
    config: &TrainConfig,
    k: usize,
    policy: &mut Policy<E>,
    improvement: &mut UpdateState,
    mut guidance: Option<&mut Guidance<E>>,
    data: &StepBatch<E>,
    stream: Option<&GuidanceStream<E>>,
    skip_improvement: bool,
) -> Result<PolicySteps, TrainError> {
    let mut clock = Stopwatch::start();
    // 4. Improvement step: π_k → π_{k+½}, KL ≈ δ (or none, if asked, on a batch
    //    without env reward).
    let improvement = if skip_improvement {
        UpdateStats {
            stop: StopReason::NoReward,
            ..UpdateStats::default()
        }
    } else {
        let mut rng = generator(config.seed, k, Stream::ImprovementStep);
        let step = in_phase("improvement step", || {
            let update = &config.improvement;
            update.update(engine, policy, data, config.max_kl, improvement, &mut rng)
        });
        take_step(engine, policy, step, "the improvement step")?
    };
    let t_policy_step = clock.lap();

    // 5. Guidance step on the same batch: π_{k+½} → π_{k+1}, KL ≈ δ_k, the ratio
    //    against π_k.
    let mut guidance_stats = None;
    if let (Some(g), Some(stream)) = (guidance.as_deref_mut(), stream) {
        let advantages: Tensor<E::B, 1> = engine.upload(&stream.advantages.normalised, [data.rows]);
        let mut rng = generator(config.seed, k, Stream::GuidanceStep);
        let step = in_phase("guidance step", || {
            g.step(engine, policy, data, advantages, &mut rng)
        });
        guidance_stats = Some(take_step(engine, policy, step, "the guidance step")?);
    }
    let t_guidance = clock.lap();

    // 6. Discriminator update: policy pairs 1, demonstration pairs 0.
    let inputs = stream.and_then(|s| s.discriminator_inputs.as_ref());
    let disc_loss = in_phase("discriminator", || {
        guidance.and_then(|g| g.train_discriminator(engine, inputs))
    });
    if let Some(loss) = disc_loss {
        finite(
            loss.is_finite(),
            "the discriminator update",
            "discriminator's parameters or loss",
        )?;
    }
    Ok(PolicySteps {
        improvement,
        guidance: guidance_stats,
        disc_loss,
        t_policy_step,
        t_guidance,
        t_discriminator: clock.lap(),
    })
}

impl<E: Engine> Trainer<E> {
    pub fn iteration(&self) -> usize {
        self.iteration
    }

    pub fn done(&self) -> bool {
        self.iteration >= self.config.iterations
    }

    pub fn engine(&self) -> &E {
        &self.engine
    }

    pub fn policy(&self) -> &Policy<E> {
        &self.policy
    }

    pub fn run_dir(&self) -> &std::path::Path {
        self.run.path()
    }

    pub fn schedule(&self) -> Schedule {
        self.schedule
    }

    /// Lays the iterations over the threads by `schedule` (the numbers do not change).
    pub fn set_schedule(&mut self, schedule: Schedule) {
        self.schedule = schedule;
    }

    /// From now on, every row of metrics.csv also goes to a TensorBoard event file in the
    /// run folder (written anew from the rows metrics.csv holds, so a resumed run's curves
    /// continue without the redone iterations twice), flushed each iteration.
    pub fn write_tensorboard(&mut self) -> Result<(), TrainError> {
        let rows = self.run.read_metrics()?;
        let config = toml::to_string(&self.config)?;
        self.events = Some(EventWriter::create(self.run.path(), &config, &rows)?);
        Ok(())
    }

    /// Runs one iteration and appends its row to `metrics.csv`; an error names the
    /// iteration.
    pub fn step(&mut self) -> Result<IterationMetrics, TrainError> {
        let k = self.iteration;
        let pool = Arc::clone(&self.pool);
        pool.install(|| self.iterate())
            .map_err(|e| format!("iteration {k}: {e}").into())
    }

    /// One iteration, in Algorithm 1's order.
    fn iterate(&mut self) -> Result<IterationMetrics, TrainError> {
        let k = self.iteration;
        // 1. Collect (s, a, r) with π_k (the pipelined schedule did so during k − 1).
        let collected = match self.next_batch.take() {
            Some(collected) => collected,
            None => {
                let acting = self.policy.acting(&self.engine);
                self.collector
                    .collect(&acting, self.config.samples_per_iter)?
            }
        };
        let mut clock = Stopwatch::start();
        let batch = &collected.batch;
        let (obs, actions, logp_k) = in_phase("sampling", || self.upload(batch));
        let t_upload = clock.lap();

        // 2. Advantages of the env reward, with the env critic as it stands.
        let (engine, config) = (&self.engine, &self.config);
        let env = in_phase("advantages", || {
            advantages(
                engine,
                config,
                &self.critics.env,
                batch,
                &obs,
                &batch.rewards,
            )
        });
        let data = StepBatch {
            advantages: engine.upload(&env.normalised, [batch.len()]),
            obs,
            actions,
            logp_old: logp_k,
            rows: batch.len(),
        };

        // 3. δ_k, then the guidance reward and its advantages while δ_k is above its floor.
        let guidance = in_phase("advantages", || self.guidance_stream(k, batch, &data));
        let t_advantages = clock.lap();

        self.iteration += 1;
        self.samples += batch.len();
        // 4-8.
        let rewardless = batch.rewards.iter().all(|&r| r == 0.0);
        let later = self
            .steps_and_fits(k, &data, rewardless, &env, guidance.as_ref())
            .map_err(|e| self.stopped(e))?;
        let row = IterationMetrics {
            t_sampling: collected.seconds + t_upload,
            t_advantages,
            ..IterationMetrics::default()
        };
        self.record(k, row, batch, guidance.as_ref(), later)
    }

    /// The batch's observations, actions and log π_k on the engine: uploaded once.
    fn upload(&self, batch: &Batch) -> (E::Rows, Tensor<E::B, 2>, Tensor<E::B, 1>) {
        let engine = &self.engine;
        let obs = engine.rows(&batch.obs, batch.obs_dim);
        let actions = engine.upload(&batch.actions, [batch.len(), batch.act_dim]);
        let logp_k = self.policy.log_prob(engine, &obs, &actions);
        (obs, actions, logp_k)
    }

    /// Step 3: δ_k from the batch's mean sparse return; then, while δ_k is above its
    /// floor, r_C and its advantages with the guidance critic.
    fn guidance_stream(
        &mut self,
        k: usize,
        batch: &Batch,
        data: &StepBatch<E>,
    ) -> Option<GuidanceStream<E>> {
        let g = self.guidance.as_mut()?;
        g.schedule.update(k, batch.mean_return());
        if !g.schedule.guidance_on() {
            return None;
        }
        let reward = g.rewards(&self.engine, batch, data);
        let critic = self
            .critics
            .guidance
            .as_ref()
            .expect("guidance has a critic");
        let advantages = advantages(
            &self.engine,
            &self.config,
            critic,
            batch,
            &data.obs,
            &reward.rewards,
        );
        Some(GuidanceStream {
            advantages,
            discriminator_inputs: reward.discriminator_inputs,
            mean_reward: reward.rewards.iter().sum::<f64>() / reward.rewards.len().max(1) as f64,
        })
    }

    /// Steps 4-8 of iteration `k`, laid over the threads by the schedule: the one place
    /// that says what runs beside what.
    fn steps_and_fits(
        &mut self,
        k: usize,
        data: &StepBatch<E>,
        rewardless: bool,
        env: &Advantages,
        stream: Option<&GuidanceStream<E>>,
    ) -> Result<Later, TrainError> {
        let collect_next = !self.done();
        let evaluate_now = k.is_multiple_of(self.config.eval_every) || self.done();
        let skip_improvement = self.config.skip_improvement_without_reward && rewardless;
        let Self {
            engine,
            config,
            policy,
            improvement,
            guidance,
            critics,
            collector,
            evaluator,
            schedule,
            ..
        } = self;
        let (engine, config) = (&*engine, &*config);
        let guidance_returns = stream.map(|s| s.advantages.returns.as_slice());
        // 7.
        let mut fit = || {
            critics.fit(
                engine,
                (config.seed, k),
                &data.obs,
                &env.returns,
                guidance_returns,
            )
        };
        // 4-6.
        let mut steps = |policy: &mut Policy<E>| {
            let guidance = guidance.as_mut();
            policy_steps(
                engine,
                config,
                k,
                policy,
                improvement,
                guidance,
                data,
                stream,
                skip_improvement,
            )
        };
        // 8, timed.
        let mut evaluate = |acting: &ActingPolicy| -> Result<_, TrainError> {
            let clock = Instant::now();
            let evaluation = evaluate_now
                .then(|| evaluator.evaluate(acting))
                .transpose()?;
            Ok((evaluation, clock.elapsed().as_secs_f64()))
        };
        // Batch k + 1, with π_{k+1}.
        let mut collect = |acting: &ActingPolicy| {
            collect_next
                .then(|| collector.collect(acting, config.samples_per_iter))
                .transpose()
        };
        let (steps, fits, evaluated, next) = match schedule {
            Schedule::Sequential => {
                let steps = steps(policy)?;
                let fits = fit();
                let acting = policy.acting(engine);
                (steps, fits, evaluate(&acting)?, collect(&acting)?)
            }
            Schedule::Pipelined => {
                let (fits, rest) = rayon::join(fit, || -> Result<_, TrainError> {
                    let steps = steps(policy)?;
                    let acting = policy.acting(engine);
                    let (evaluated, next) = rayon::join(|| evaluate(&acting), || collect(&acting));
                    Ok((steps, evaluated?, next?))
                });
                let (steps, evaluated, next) = rest?;
                (steps, fits, evaluated, next)
            }
        };
        let (evaluation, t_evaluation) = evaluated;
        Ok(Later {
            steps,
            fits,
            evaluation,
            t_evaluation,
            next,
        })
    }

    /// Iteration `k`'s row of metrics.csv, and its checkpoint when one is due.
    fn record(
        &mut self,
        k: usize,
        timed: IterationMetrics,
        batch: &Batch,
        stream: Option<&GuidanceStream<E>>,
        later: Later,
    ) -> Result<IterationMetrics, TrainError> {
        let Later {
            steps,
            fits,
            evaluation,
            t_evaluation,
            next,
        } = later;
        let fitted = finite(
            fits.env_loss.is_finite(),
            "the critic fit",
            "env critic's parameters or loss",
        )
        .and_then(|()| match stream {
            Some(_) => finite(
                fits.guidance_loss.is_finite(),
                "the critic fit",
                "guidance critic's parameters or loss",
            ),
            None => Ok(()),
        });
        fitted.map_err(|e| self.stopped(e))?;
        let eval = |of: fn(&Evaluation) -> f64| evaluation.as_ref().map_or(f64::NAN, of);
        let mut row = IterationMetrics {
            iteration: k,
            samples: self.samples,
            wall_s: self.wall_offset + self.started.elapsed().as_secs_f64(),
            episodes: batch.episode_returns.len(),
            train_sparse_return: batch.mean_return(),
            train_dense_return: batch.mean_dense_return(),
            eval_dense_return: eval(|e| e.dense_return),
            eval_moved: eval(|e| e.moved),
            eval_action_rms: eval(|e| e.action_rms),
            delta_k: self.guidance.as_ref().map_or(0.0, |g| g.schedule.delta),
            guidance_reward: stream.map_or(f64::NAN, |s| s.mean_reward),
            mean_log_std: self.policy.log_std.iter().sum::<f64>() / self.policy.act_dim() as f64,
            critic_loss: fits.env_loss,
            guidance_critic_loss: fits.guidance_loss,
            disc_loss: steps.disc_loss.unwrap_or(f64::NAN),
            t_critics: fits.seconds,
            t_policy_step: steps.t_policy_step,
            t_guidance: steps.t_guidance,
            t_discriminator: steps.t_discriminator,
            t_evaluation,
            ..timed
        };
        row.improvement(&steps.improvement);
        row.guidance(steps.guidance.as_ref());
        self.run.append(&row)?;
        if let Some(events) = self.events.as_mut() {
            events.append(&row)?;
        }
        self.next_batch = next;
        if self.iteration.is_multiple_of(self.config.checkpoint_every) || self.done() {
            self.save_checkpoint(&self.run.checkpoint_path())?;
            self.saved_at = Some(self.iteration);
        }
        Ok(row)
    }

    /// `e`, saying what the run kept: metrics.csv and the checkpoint stay as the last good
    /// iteration left them.
    fn stopped(&self, e: TrainError) -> TrainError {
        let kept = match self.saved_at {
            Some(at) => format!("the checkpoint of iteration {at} is kept"),
            None => "no checkpoint had been written yet".to_string(),
        };
        format!(
            "{e}; the run stopped ({kept} in {})",
            self.run.path().display()
        )
        .into()
    }
}

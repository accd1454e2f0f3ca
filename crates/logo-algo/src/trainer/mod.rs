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
//! Building a trainer is in `build.rs`, checkpoints and `--resume` in `checkpoint.rs`,
//! steps 2-7 in `steps.rs`, and the parts a trainer holds in `state.rs`.

mod build;
mod checkpoint;
mod recorder;
mod schedule;
mod state;
mod steps;

use std::sync::Arc;

use burn::tensor::Tensor;
use logo_nn::flops::in_phase;
use logo_nn::{Engine, Policy};

use crate::episode::Evaluation;
use crate::metrics::IterationMetrics;
use crate::policy_update::StepBatch;
pub use crate::run_dir::TrainError;
use crate::sampler::Batch;
pub use checkpoint::engine_history;
pub use schedule::Schedule;
pub use state::{EngineSpan, Trainer};
use steps::{
    Advantages, GuidanceStream, Later, StepInputs, Stopwatch, advantages, check_critic_fits,
    policy_steps,
};

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
        self.recorder.path()
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
        let config = toml::to_string(&self.config)?;
        self.recorder.write_tensorboard(&config)
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
        let inputs = StepInputs {
            k,
            data: &data,
            stream: guidance.as_ref(),
            skip_improvement: self.config.skip_improvement_without_reward && rewardless,
        };
        let later = self
            .steps_and_fits(inputs, &env)
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
        inputs: StepInputs<'_, E>,
        env: &Advantages,
    ) -> Result<Later, TrainError> {
        let (k, data) = (inputs.k, inputs.data);
        let collect_next = !self.done();
        let evaluate_now = k.is_multiple_of(self.config.eval_every) || self.done();
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
        let guidance_returns = inputs.stream.map(|s| s.advantages.returns.as_slice());
        let samples = config.samples_per_iter;
        let (steps, fits, (evaluation, t_evaluation), next) = schedule.run(
            policy,
            |policy| policy.acting(engine),
            // 4-6.
            |policy| {
                policy_steps(
                    engine,
                    config,
                    policy,
                    improvement,
                    guidance.as_mut(),
                    &inputs,
                )
            },
            // 7.
            || {
                critics.fit(
                    engine,
                    (config.seed, k),
                    &data.obs,
                    &env.returns,
                    guidance_returns,
                )
            },
            // 8, and batch k + 1 with π_{k+1}.
            |acting| evaluator.timed(acting, k, evaluate_now),
            |acting| collector.collect_if(collect_next, acting, samples),
        )?;
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
        check_critic_fits(&later.fits, stream.is_some()).map_err(|e| self.stopped(e))?;
        let row = self.metrics_row(k, timed, batch, stream, &later);
        let every = self.config.checkpoint_every;
        let due = self
            .recorder
            .append(&row, self.iteration, self.done(), every)?;
        self.next_batch = later.next;
        if let Some(eval_return) = due.best {
            self.save_checkpoint(&self.recorder.best_path())?;
            self.recorder.best_saved(eval_return);
        }
        if due.checkpoint {
            self.save_checkpoint(&self.recorder.checkpoint_path())?;
            self.recorder.checkpoint_saved(self.iteration);
        }
        Ok(row)
    }

    /// The metrics.csv row of iteration `k` (the timings of steps 1-3 are in `timed`).
    fn metrics_row(
        &self,
        k: usize,
        timed: IterationMetrics,
        batch: &Batch,
        stream: Option<&GuidanceStream<E>>,
        later: &Later,
    ) -> IterationMetrics {
        let Later {
            steps,
            fits,
            evaluation,
            t_evaluation,
            ..
        } = later;
        let eval = |of: fn(&Evaluation) -> f64| evaluation.as_ref().map_or(f64::NAN, of);
        let mut row = IterationMetrics {
            iteration: k,
            samples: self.samples,
            wall_s: self.recorder.wall_s(),
            episodes: batch.episode_returns.len(),
            train_sparse_return: batch.mean_return(),
            train_dense_return: batch.mean_dense_return(),
            eval_dense_return: eval(|e| e.dense_return),
            eval_return: eval(|e| e.return_),
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
            t_evaluation: *t_evaluation,
            ..timed
        };
        row.improvement(&steps.improvement);
        row.guidance(steps.guidance.as_ref());
        row
    }

    /// `e`, saying what the run kept (see [`Recorder::stopped`]).
    fn stopped(&self, e: TrainError) -> TrainError {
        self.recorder.stopped(e)
    }
}

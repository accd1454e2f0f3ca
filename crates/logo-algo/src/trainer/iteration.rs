//! One iteration of LOGO (Algorithm 1), top to bottom: [`Trainer::iterate`] and the
//! steps it calls, each a function of what it reads and writes (so that the schedule can
//! run them side by side):
//!
//! 1. collect whole episodes with π_k;
//! 2. advantages of the env reward (or `[reward]`'s mix of it with −log D: GAIL, POfD),
//!    with the env critic as it stands;
//!    (DAPG: the demonstrations join the improvement step's batch as rows weighted
//!    λ0·λ1^k·max Â, `dapg.rs`);
//! 3. δ_k from the batch's decay signal (`decay_on`); while δ_k is above the guidance
//!    threshold (6e-7, just above its floor), the guidance
//!    reward r_C (from last iteration's discriminator, or log π_b − log π_k) and its
//!    advantages with the guidance critic;
//! 4. improvement step (`[improvement]`'s kind, KL ≈ δ = `max_kl`) → π_{k+½};
//! 5. guidance step (`[guidance.update]`'s kind, KL ≈ δ_k, ratio against π_k) → π_{k+1};
//! 6. one discriminator update;
//! 7. both critics fitted to this batch's returns (for iteration k+1's advantages);
//! 8. evaluation of π_{k+1} on the dense env with the mean action; metrics row, checkpoint
//!    (`record.rs`).
//!
//! Without `[guidance]` it is the improvement step alone (TRPO, PPO, ...). Which of steps
//! 4-8 run beside which is decided in one place, [`Trainer::steps_and_fits`], by the
//! run's [`Schedule`](super::Schedule).

use std::borrow::Cow;

use burn::tensor::Tensor;
use logo_nn::flops::in_phase;
use logo_nn::{Engine, Policy};

use super::Trainer;
use super::learner::{Advantages, CriticFits, advantages};
use super::recorder::Stopwatch;
use super::resources::{Collected, Resources};
use crate::config::{DecaySignal, GuidanceConfig, NO_GOAL_HINT, TrainConfig};
use crate::episode::Evaluation;
use crate::error::{Invalid, TrainError};
use crate::guidance::{Guidance, GuidanceReward};
use crate::metrics::IterationMetrics;
use crate::policy_update::{StepBatch, StopReason, UpdateState, UpdateStats};
use crate::sampler::Batch;
use crate::streams::{Stream, generator};

impl<E: Engine> Trainer<E> {
    /// One iteration, in Algorithm 1's order.
    pub(super) fn iterate(&mut self) -> Result<IterationMetrics, TrainError> {
        let k = self.learner.iteration;
        // 1. Collect (s, a, r) with π_k, unless the end of iteration k − 1 already did.
        let mut collected = match self.next_batch.take() {
            Some(collected) => collected,
            None => self.collect()?,
        };
        let mut clock = Stopwatch::start();
        self.standardise(&mut collected.batch);
        let batch = &collected.batch;
        let (obs, actions, logp_k) = in_phase("sampling", || self.upload(batch));
        let t_upload = clock.lap();

        // 2. Advantages of the improvement step's reward, with the env critic as it stands.
        let (env, mixed) = in_phase("advantages", || self.improvement_advantages(batch, &obs));
        let advantages = self.resources.engine.upload(&env.normalised, [batch.len()]);
        let data = StepBatch::of_policy(obs, actions, logp_k, advantages, batch.len());
        // 2b. DAPG: the demonstrations join the improvement step's batch, weighted
        //     w_k = λ0·λ1^k·max Â (`[demonstration_rows]`).
        let (with_demonstrations, demo_weight) = self.demonstration_rows(k, batch, &env);

        // 3. δ_k, then the guidance reward and its advantages while guidance is on.
        let guidance = in_phase("advantages", || {
            self.guidance_stream(k, batch, &data, mixed.as_ref())
        })?;
        let delta_k = self.delta_k();
        let t_advantages = clock.lap();

        self.learner.iteration += 1;
        self.learner.samples += batch.len();
        // 4-8.
        // The discriminator learns from this batch's pairs wherever its reward was used.
        let discriminator_inputs = guidance
            .as_ref()
            .and_then(|s| s.discriminator_inputs.as_ref())
            .or(mixed.as_ref().and_then(|r| r.discriminator_inputs.as_ref()));
        let inputs = StepInputs {
            k,
            data: &data,
            improvement_data: with_demonstrations.as_ref().unwrap_or(&data),
            stream: guidance.as_ref(),
            discriminator_inputs,
            skip_improvement: self.config.skip_improvement_without_reward
                && rewardless(batch, mixed.is_some() || with_demonstrations.is_some()),
        };
        let later = self
            .steps_and_fits(inputs, &env)
            .map_err(|e| self.stopped(e))?;
        // 8b. With decay_on = "evaluation": δ_{k+1} from π_{k+1}'s evaluation.
        self.decay_on_evaluation(k + 1, later.evaluation.as_ref())?;
        let row = IterationMetrics {
            t_sampling: collected.seconds + t_upload,
            t_advantages,
            demo_weight,
            delta_k,
            ..IterationMetrics::default()
        };
        self.record(k, row, batch, guidance.as_ref(), later)
    }

    /// Step 2: the advantages of the improvement step's reward with the env critic as it
    /// stands. The reward is the env's, or env·r + λ·(−log D) where `[reward]` mixes in
    /// the discriminator's (GAIL, POfD); then also r_C and the discriminator's inputs.
    fn improvement_advantages(
        &self,
        batch: &Batch,
        obs: &E::Rows,
    ) -> (Advantages, Option<GuidanceReward<E>>) {
        let (engine, config) = (&self.resources.engine, &self.config);
        let mixed = self.learner.guidance.as_ref().and_then(|g| {
            (config.reward.discriminator > 0.0).then(|| g.discriminator_rewards(engine, batch))?
        });
        let rewards = match &mixed {
            Some(r_c) => Cow::Owned(config.reward.mix(&batch.rewards, &r_c.rewards)),
            None => Cow::Borrowed(&batch.rewards),
        };
        let critic = &self.learner.critics.env;
        let env = advantages(engine, config, critic, batch, obs, &rewards);
        (env, mixed)
    }

    /// Step 2b (DAPG): the improvement step's batch with the demonstrations' rows, and
    /// their weight w_k; none (and NaN) without `[demonstration_rows]`. A weight of 0
    /// (λ0 = 0) leaves the batch as it is: the plain step, bit for bit.
    fn demonstration_rows(
        &self,
        k: usize,
        batch: &Batch,
        env: &Advantages,
    ) -> (Option<StepBatch<E>>, f64) {
        let (Some(config), Some(rows)) = (
            &self.config.demonstration_rows,
            &self.resources.demonstrations,
        ) else {
            return (None, f64::NAN);
        };
        let weight = config.weight(k, &env.normalised);
        if weight == 0.0 {
            return (None, weight);
        }
        let (engine, policy) = (&self.resources.engine, &self.learner.policy);
        let pairs = (&batch.obs[..], &batch.actions[..]);
        let augmented = rows.append(engine, policy, pairs, &env.normalised, weight);
        (Some(augmented), weight)
    }

    /// A batch collected with the policy as it stands.
    fn collect(&mut self) -> Result<Collected, TrainError> {
        let Resources {
            engine, collector, ..
        } = &mut self.resources;
        let acting = self.learner.acting(engine);
        collector.collect(&acting, self.config.samples_per_iter)
    }

    /// With `normalise_observations`: the batch's observations (and its truncated
    /// episodes' final ones) as the networks see them, through the statistics π_k acted
    /// with; the statistics then take in the batch's raw observations, for π_{k+1}. The
    /// discriminator's demonstrations are seen through the same statistics as the batch.
    fn standardise(&mut self, batch: &mut Batch) {
        let Some(stats) = self.learner.observation_stats.as_mut() else {
            return;
        };
        let acted_with = stats.clone();
        stats.update(&batch.obs);
        acted_with.normalise(&mut batch.obs);
        for (_, last) in &mut batch.truncations {
            acted_with.normalise(last);
        }
        if let Some(g) = self.learner.guidance.as_mut() {
            g.observe_through(&self.resources.engine, &acted_with);
        }
        if let Some(rows) = self.resources.demonstrations.as_mut() {
            rows.observe_through(&acted_with);
        }
    }

    /// The batch's observations, actions and log π_k on the engine: uploaded once.
    fn upload(&self, batch: &Batch) -> (E::Rows, Tensor<E::B, 2>, Tensor<E::B, 1>) {
        let engine = &self.resources.engine;
        let obs = engine.rows(&batch.obs, batch.obs_dim);
        let actions = engine.upload(&batch.actions, [batch.len(), batch.act_dim]);
        let logp_k = self.learner.policy.log_prob(engine, &obs, &actions);
        (obs, actions, logp_k)
    }

    /// Step 3: δ_k from the batch's mean sparse return (or success rate: `decay_on`);
    /// then, while δ_k is above the guidance threshold, r_C and its advantages with the guidance
    /// critic. Where `[reward]` mixed −log D in already (`mixed`), r_C is taken from it.
    fn guidance_stream(
        &mut self,
        k: usize,
        batch: &Batch,
        data: &StepBatch<E>,
        mixed: Option<&GuidanceReward<E>>,
    ) -> Result<Option<GuidanceStream<E>>, TrainError> {
        let step = self.config.guidance.as_ref().is_some_and(|g| g.step);
        let Some(g) = self.learner.guidance.as_mut().filter(|_| step) else {
            return Ok(None);
        };
        if let Some(signal) = decay_signal(&self.config, k, batch)? {
            g.schedule.update(k, signal);
        }
        if !g.schedule.guidance_on() {
            return Ok(None);
        }
        let reward = match mixed {
            // The same −log D; its inputs stay with `mixed` for the discriminator's update.
            Some(r_c) => GuidanceReward {
                rewards: r_c.rewards.clone(),
                discriminator_inputs: None,
            },
            None => g.rewards(&self.resources.engine, batch, data),
        };
        let critic = self
            .learner
            .critics
            .guidance
            .as_ref()
            .expect("guidance has a critic");
        let advantages = advantages(
            &self.resources.engine,
            &self.config,
            critic,
            batch,
            &data.obs,
            &reward.rewards,
        );
        Ok(Some(GuidanceStream {
            advantages,
            discriminator_inputs: reward.discriminator_inputs,
            mean_reward: reward.rewards.iter().sum::<f64>() / reward.rewards.len().max(1) as f64,
        }))
    }

    /// The δ_k the guidance step runs with this iteration; 0 without the step (GAIL,
    /// POfD, TRPO).
    fn delta_k(&self) -> f64 {
        match (&self.learner.guidance, self.config.guidance_update()) {
            (Some(g), Some(_)) => g.schedule.delta,
            _ => 0.0,
        }
    }

    /// Step 8b (`decay_on = "evaluation"`): the schedule reads the share of π_{k+1}'s
    /// evaluation episodes at the goal, as iteration `next`'s signal; an iteration
    /// without an evaluation (`eval_every`) leaves δ as it is.
    fn decay_on_evaluation(
        &mut self,
        next: usize,
        evaluation: Option<&Evaluation>,
    ) -> Result<(), TrainError> {
        let Some(g) = self.config.guidance.as_ref() else {
            return Ok(());
        };
        let (Some(guidance), Some(evaluation)) = (self.learner.guidance.as_mut(), evaluation)
        else {
            return Ok(());
        };
        if g.decay_on != DecaySignal::Evaluation || !g.step {
            return Ok(());
        }
        let share = success_signal(&self.config, g, evaluation.success, next - 1, "evaluation")?;
        if let Some(share) = share {
            guidance.schedule.update(next, share);
        }
        Ok(())
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
        let (learner, resources) = (&mut self.learner, &mut self.resources);
        let (engine, config) = (&resources.engine, &self.config);
        let guidance_returns = inputs.stream.map(|s| s.advantages.returns.as_slice());
        let samples = config.samples_per_iter;
        let norm = learner.observation_stats.clone();
        let (steps, fits, (evaluation, t_evaluation), next) = resources.schedule.run(
            &mut learner.policy,
            |policy| policy.acting(engine).with_observation_norm(norm.clone()),
            // 4-6.
            |policy| {
                policy_steps(
                    engine,
                    config,
                    policy,
                    &mut learner.improvement,
                    learner.guidance.as_mut(),
                    &inputs,
                )
            },
            // 7.
            || {
                learner.critics.fit(
                    engine,
                    (config.seed, k),
                    &data.obs,
                    &env.returns,
                    guidance_returns,
                )
            },
            // 8, and batch k + 1 with π_{k+1}.
            |acting| resources.evaluator.timed(acting, k, evaluate_now),
            |acting| {
                resources
                    .collector
                    .collect_if(collect_next, acting, samples)
            },
        )?;
        Ok(Later {
            steps,
            fits,
            evaluation,
            t_evaluation,
            next,
        })
    }
}

/// Whether the improvement step has nothing to learn from: no env reward in `batch` and
/// no other signal (`other`: a mixed reward, GAIL's and POfD's, or DAPG's demonstration
/// rows, whose pull is the step's signal then).
fn rewardless(batch: &Batch, other: bool) -> bool {
    !other && batch.rewards.iter().all(|&r| r == 0.0)
}

/// What δ_k's schedule reads of iteration `k`'s `batch` at step 3: its mean return, or
/// its success rate (`[guidance] decay_on`); nothing where it reads the evaluation (step
/// 8b).
fn decay_signal(config: &TrainConfig, k: usize, batch: &Batch) -> Result<Option<f64>, TrainError> {
    let Some(g) = config.guidance.as_ref() else {
        return Ok(Some(batch.mean_return()));
    };
    match g.decay_on {
        DecaySignal::Return => Ok(Some(batch.mean_return())),
        DecaySignal::Success => {
            success_signal(config, g, batch.success_rate(config.success), k, "batch")
        }
        DecaySignal::Evaluation => Ok(None),
    }
}

/// A share of episodes at the goal as the schedule reads it. Where the task reports no
/// success: an error, unless the schedule waits for a level (`decay_from`), which such a
/// task never reaches (None: δ_k holds; said at a run's first iteration, in case the user
/// expected a success the task does not report).
fn success_signal(
    config: &TrainConfig,
    g: &GuidanceConfig,
    share: Option<f64>,
    k: usize,
    episodes: &str,
) -> Result<Option<f64>, TrainError> {
    if share.is_some() {
        return Ok(share);
    }
    let (on, rule) = (
        g.decay_on.name(),
        format!("{:?}", config.success).to_lowercase(),
    );
    if g.decay_from.is_some() {
        if k == 0 {
            eprintln!(
                "note: guidance.decay_from: no episode of the first {episodes} reported \
                 reaching its goal or not (success = \"{rule}\"), so δ_k holds at δ_0 while \
                 none does"
            );
        }
        return Ok(None);
    }
    Err(Invalid::new(format!(
        "guidance.decay_on = \"{on}\": no episode of the {episodes} reported reaching its \
         goal or not (the task defines no success); set success = \"terminated\" for a task \
         that ends at its goal, or report info[\"is_success\"]; {NO_GOAL_HINT}"
    ))
    .into())
}

/// Step 3's output while the guidance step runs.
pub(super) struct GuidanceStream<E: Engine> {
    advantages: Advantages,
    discriminator_inputs: Option<E::Rows>,
    pub(super) mean_reward: f64,
}

/// What steps 4-6 did.
pub(super) struct PolicySteps {
    pub(super) improvement: UpdateStats,
    pub(super) guidance: Option<UpdateStats>,
    pub(super) disc_loss: Option<f64>,
    pub(super) t_policy_step: f64,
    pub(super) t_guidance: f64,
    pub(super) t_discriminator: f64,
}

/// What steps 4-8 produced.
pub(super) struct Later {
    pub(super) steps: PolicySteps,
    pub(super) fits: CriticFits,
    pub(super) evaluation: Option<Evaluation>,
    pub(super) t_evaluation: f64,
    pub(super) next: Option<Collected>,
}

/// Stops the run when a step left a non-finite number behind.
pub(super) fn finite(ok: bool, step: &str, what: &str) -> Result<(), TrainError> {
    if ok {
        Ok(())
    } else {
        Err(TrainError::NonFinite(format!(
            "{step} produced a non-finite number (NaN or ±inf) in the {what}"
        )))
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

/// What steps 4-6 of iteration `k` read.
struct StepInputs<'a, E: Engine> {
    k: usize,
    data: &'a StepBatch<E>,
    /// The improvement step's batch: `data`, with DAPG's demonstration rows where
    /// `[demonstration_rows]` adds them.
    improvement_data: &'a StepBatch<E>,
    stream: Option<&'a GuidanceStream<E>>,
    /// The batch's pairs as the discriminator's inputs, where its reward was used.
    discriminator_inputs: Option<&'a E::Rows>,
    /// `skip_improvement_without_reward` on a batch without env reward.
    skip_improvement: bool,
}

/// Steps 4-6 of iteration `k`: π_k → π_{k+½} → π_{k+1}, then the discriminator.
fn policy_steps<E: Engine>(
    engine: &E,
    config: &TrainConfig,
    policy: &mut Policy<E>,
    improvement: &mut UpdateState,
    mut guidance: Option<&mut Guidance<E>>,
    inputs: &StepInputs<'_, E>,
) -> Result<PolicySteps, TrainError> {
    let mut clock = Stopwatch::start();
    let improvement = improvement_step(engine, config, policy, improvement, inputs)?;
    let t_policy_step = clock.lap();
    let guidance_stats = match (guidance.as_deref_mut(), inputs.stream) {
        (Some(g), Some(stream)) => Some(guidance_step(
            engine,
            config.seed,
            policy,
            g,
            inputs,
            stream,
        )?),
        _ => None,
    };
    let t_guidance = clock.lap();
    let disc_loss = discriminator_step(engine, guidance, inputs.discriminator_inputs)?;
    Ok(PolicySteps {
        improvement,
        guidance: guidance_stats,
        disc_loss,
        t_policy_step,
        t_guidance,
        t_discriminator: clock.lap(),
    })
}

/// Step 4, the improvement step: π_k → π_{k+½}, KL ≈ δ (or none, if asked, on a batch
/// without env reward).
fn improvement_step<E: Engine>(
    engine: &E,
    config: &TrainConfig,
    policy: &mut Policy<E>,
    state: &mut UpdateState,
    inputs: &StepInputs<'_, E>,
) -> Result<UpdateStats, TrainError> {
    if inputs.skip_improvement {
        return Ok(UpdateStats {
            stop: StopReason::NoReward,
            ..UpdateStats::default()
        });
    }
    let mut rng = generator(config.seed, inputs.k, Stream::ImprovementStep);
    let step = in_phase("improvement step", || {
        let update = &config.improvement;
        let data = inputs.improvement_data;
        update.update(engine, policy, data, config.max_kl, state, &mut rng)
    });
    take_step(engine, policy, step, "the improvement step")
}

/// Step 5, the guidance step on the same batch: π_{k+½} → π_{k+1}, KL ≈ δ_k, the ratio against π_k.
fn guidance_step<E: Engine>(
    engine: &E,
    seed: u64,
    policy: &mut Policy<E>,
    guidance: &mut Guidance<E>,
    inputs: &StepInputs<'_, E>,
    stream: &GuidanceStream<E>,
) -> Result<UpdateStats, TrainError> {
    let data = inputs.data;
    let advantages: Tensor<E::B, 1> = engine.upload(&stream.advantages.normalised, [data.rows]);
    let mut rng = generator(seed, inputs.k, Stream::GuidanceStep);
    let step = in_phase("guidance step", || {
        guidance.step(engine, policy, data, advantages, &mut rng)
    });
    take_step(engine, policy, step, "the guidance step")
}

/// Step 6, the discriminator update: policy pairs 1, demonstration pairs 0.
fn discriminator_step<E: Engine>(
    engine: &E,
    guidance: Option<&mut Guidance<E>>,
    inputs: Option<&E::Rows>,
) -> Result<Option<f64>, TrainError> {
    let loss = in_phase("discriminator", || {
        guidance.and_then(|g| g.train_discriminator(engine, inputs))
    });
    if let Some(loss) = loss {
        finite(
            loss.is_finite(),
            "the discriminator update",
            "discriminator's parameters or loss",
        )?;
    }
    Ok(loss)
}

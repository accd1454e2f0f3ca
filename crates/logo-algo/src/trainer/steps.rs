//! Steps 2-7 of an iteration as functions of what each reads and writes, so that the
//! iteration in `mod.rs` reads as Algorithm 1 and its schedule can run them side by side.

use std::time::Instant;

use burn::tensor::Tensor;
use logo_nn::flops::in_phase;
use logo_nn::{Engine, Policy};

use super::state::{Collected, CriticFits};
use crate::config::TrainConfig;
use crate::critic::CriticSet;
use crate::episode::Evaluation;
use crate::gae::{GaeInput, gae, normalise};
use crate::guidance::Guidance;
use crate::policy_update::{StepBatch, StopReason, UpdateState, UpdateStats};
use crate::run_dir::TrainError;
use crate::sampler::Batch;
use crate::streams::{Stream, generator};

/// Normalised advantages and the critic's regression targets of one reward stream.
pub(super) struct Advantages {
    pub(super) normalised: Vec<f64>,
    pub(super) returns: Vec<f64>,
}

/// Step 3's output while the guidance step runs.
pub(super) struct GuidanceStream<E: Engine> {
    pub(super) advantages: Advantages,
    pub(super) discriminator_inputs: Option<E::Rows>,
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

/// GAE for one reward stream with `critic` as it stands.
pub(super) fn advantages<E: Engine>(
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
pub(super) struct Stopwatch(Instant);

impl Stopwatch {
    pub(super) fn start() -> Self {
        Self(Instant::now())
    }

    /// Seconds since the start or the previous lap.
    pub(super) fn lap(&mut self) -> f64 {
        let now = Instant::now();
        let seconds = (now - self.0).as_secs_f64();
        self.0 = now;
        seconds
    }
}

/// What steps 4-6 of iteration `k` read.
pub(super) struct StepInputs<'a, E: Engine> {
    pub(super) k: usize,
    pub(super) data: &'a StepBatch<E>,
    pub(super) stream: Option<&'a GuidanceStream<E>>,
    /// `skip_improvement_without_reward` on a batch without env reward.
    pub(super) skip_improvement: bool,
}

/// Steps 4-6 of iteration `k`: π_k → π_{k+½} → π_{k+1}, then the discriminator.
pub(super) fn policy_steps<E: Engine>(
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
    let disc_loss = discriminator_step(engine, guidance, inputs.stream)?;
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
        update.update(engine, policy, inputs.data, config.max_kl, state, &mut rng)
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
    stream: Option<&GuidanceStream<E>>,
) -> Result<Option<f64>, TrainError> {
    let inputs = stream.and_then(|s| s.discriminator_inputs.as_ref());
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

/// Step 7's check: a critic fit that left a non-finite loss stops the run.
pub(super) fn check_critic_fits(fits: &CriticFits, guidance: bool) -> Result<(), TrainError> {
    finite(
        fits.env_loss.is_finite(),
        "the critic fit",
        "env critic's parameters or loss",
    )?;
    if guidance {
        finite(
            fits.guidance_loss.is_finite(),
            "the critic fit",
            "guidance critic's parameters or loss",
        )?;
    }
    Ok(())
}

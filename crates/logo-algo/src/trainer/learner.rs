//! The learner: a [`LearnerState`] on the engine, the form the iteration works on. It
//! is made from a state ([`Learner::from_state`]) and gives one back
//! ([`Learner::state`]); nothing else in it lasts from one iteration to the next.

use std::time::Instant;

use logo_data::Demonstrations;
use logo_nn::flops::in_phase;
use logo_nn::{ActingPolicy, Cpu, Engine, ObservationStats, Policy, load_reference_policy};

use super::learner_state::{
    EngineSpan, GuidanceState, Learned, LearnerState, Networks, SamplerState,
};
use crate::config::{GuidanceConfig, TrainConfig};
use crate::critic::CriticSet;
use crate::discriminator::DiscriminatorTrainer;
use crate::error::{Invalid, TrainError};
use crate::gae::{GaeInput, gae, normalise};
use crate::guidance::{Guidance, GuidanceSignal};
use crate::policy_update::UpdateState;
use crate::sampler::Batch;
use crate::streams::{Stream, generator};

pub(super) struct Learner<E: Engine> {
    pub(super) policy: Policy<E>,
    pub(super) improvement: UpdateState,
    pub(super) critics: Critics<E>,
    pub(super) guidance: Option<Guidance<E>>,
    /// `normalise_observations`: the statistics the next batch is acted on and
    /// standardised with.
    pub(super) observation_stats: Option<ObservationStats>,
    pub(super) iteration: usize,
    pub(super) samples: usize,
    pub(super) engines: Vec<EngineSpan>,
}

impl<E: Engine> Learner<E> {
    /// `state` on `engine`, with the demonstrations a discriminator learns from. The
    /// engine joins the state's history where it is not the last one named.
    pub(super) fn from_state(
        engine: &E,
        config: &TrainConfig,
        state: &LearnerState,
        demos: Option<&Demonstrations>,
    ) -> Result<Self, TrainError> {
        let (networks, learned) = (&state.networks, &state.learned);
        let mut critic = CriticSet::new(engine, &config.critic, &networks.critic);
        critic.adam = learned.critic_adam.clone();
        let (guidance, guidance_critic) = match (&config.guidance, &learned.guidance) {
            (Some(g), Some(learned)) => {
                let (g, critic) = guidance(engine, config, g, networks, learned, demos)?;
                (Some(g), critic)
            }
            (None, None) => (None, None),
            _ => unreachable!("checked on load: a guidance state exactly with [guidance]"),
        };
        let critics = Critics {
            env: critic,
            guidance: guidance_critic,
        };
        let mut engines = state.engines.clone();
        // A checkpoint that names no engine (written before they were recorded) still
        // starts the history at iteration 0, as every later check of it expects.
        if engines.is_empty() && learned.iteration > 0 {
            engines.push(EngineSpan {
                from_iteration: 0,
                engine: "not recorded".into(),
            });
        }
        let now = engine.describe();
        if engines.last().map(|span| &span.engine) != Some(&now) {
            engines.push(EngineSpan {
                from_iteration: learned.iteration,
                engine: now,
            });
        }
        Ok(Self {
            policy: Policy::from_module(engine, &networks.policy),
            improvement: learned.improvement.clone(),
            critics,
            guidance,
            observation_stats: networks
                .observation_norm
                .as_ref()
                .map(ObservationStats::from_module),
            iteration: learned.iteration,
            samples: learned.samples,
            engines,
        })
    }

    /// The policy as it stands, for acting: it sees observations as the networks do.
    pub(super) fn acting(&self, engine: &E) -> ActingPolicy {
        self.policy
            .acting(engine)
            .with_observation_norm(self.observation_stats.clone())
    }

    /// The learner as a [`LearnerState`], its networks written into `shapes` (modules of
    /// the same sizes), with the sampler's state before the next batch.
    pub(super) fn state(
        &self,
        engine: &E,
        shapes: &Networks,
        sampler: Option<SamplerState>,
    ) -> LearnerState {
        let guidance = self.guidance.as_ref();
        let discriminator = guidance.and_then(|g| match &g.signal {
            GuidanceSignal::Discriminator(d) => Some(d),
            GuidanceSignal::Behaviour(_) => None,
        });
        let networks = Networks {
            policy: self.policy.to_module(engine, shapes.policy.clone()),
            critic: self.critics.env.to_modules(engine, &shapes.critic),
            guidance_critic: self
                .critics
                .guidance
                .as_ref()
                .zip(shapes.guidance_critic.as_ref())
                .map(|(critic, shapes)| critic.to_modules(engine, shapes)),
            discriminator: discriminator
                .zip(shapes.discriminator.clone())
                .map(|(d, shape)| d.to_module(engine, shape)),
            observation_norm: self
                .observation_stats
                .as_ref()
                .map(|stats| stats.module(&Default::default())),
        };
        let learned = Learned {
            iteration: self.iteration,
            samples: self.samples,
            improvement: self.improvement.clone(),
            critic_adam: self.critics.env.adam.clone(),
            guidance: guidance.map(|g| GuidanceState {
                schedule: g.schedule.clone(),
                update: g.state.clone(),
                critic_adam: self
                    .critics
                    .guidance
                    .as_ref()
                    .map(|c| c.adam.clone())
                    .unwrap_or_default(),
                discriminator_adam: discriminator.map(|d| d.optim.clone()),
            }),
            sampler,
        };
        LearnerState {
            networks,
            learned,
            engines: self.engines.clone(),
        }
    }
}

/// LOGO's guidance and its critic (where the guidance step runs) as `learned` left them:
/// a discriminator on `demos`, or a known behaviour policy.
fn guidance<E: Engine>(
    engine: &E,
    config: &TrainConfig,
    g: &GuidanceConfig,
    networks: &Networks,
    learned: &GuidanceState,
    demos: Option<&Demonstrations>,
) -> Result<(Guidance<E>, Option<CriticSet<E>>), TrainError> {
    // The guidance step's critic (none without the step: GAIL, POfD).
    let critic = config
        .guidance_critic()
        .zip(networks.guidance_critic.as_ref())
        .map(|(critic_config, nets)| {
            let mut critic = CriticSet::new(engine, critic_config, nets);
            critic.adam = learned.critic_adam.clone();
            critic
        });
    let signal = match (&g.behaviour_policy, demos, &networks.discriminator) {
        (Some(path), _, _) => GuidanceSignal::Behaviour(Policy::from_module(
            engine,
            &load_reference_policy::<Cpu>(path, &Default::default())?,
        )),
        (None, Some(demos), Some(module)) => {
            let mut d = DiscriminatorTrainer::new(
                engine,
                module,
                demos,
                g.discriminator_lr,
                g.discriminator_steps,
            );
            d.optim = learned.discriminator_adam.clone().unwrap_or_default();
            GuidanceSignal::Discriminator(d)
        }
        _ => unreachable!("validated: demos or behaviour_policy"),
    };
    let guidance = Guidance {
        signal,
        schedule: learned.schedule.clone(),
        update: config
            .guidance_update()
            .unwrap_or(&config.improvement)
            .clone(),
        state: learned.update.clone(),
    };
    Ok((guidance, critic))
}

/// The networks must fit the env's dims (a checkpoint of another env's sizes would
/// otherwise fail later, inside a product).
pub(super) fn check_dims(
    networks: &Networks,
    obs_dim: usize,
    act_dim: usize,
) -> Result<(), Invalid> {
    let policy = &networks.policy;
    if (policy.obs_dim(), policy.act_dim()) != (obs_dim, act_dim) {
        return Err(Invalid::Value(format!(
            "the policy's obs/action dims are ({}, {}), the env's ({obs_dim}, {act_dim})",
            policy.obs_dim(),
            policy.act_dim()
        )));
    }
    Ok(())
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

/// Normalised advantages and the critic's regression targets of one reward stream.
pub(super) struct Advantages {
    pub(super) normalised: Vec<f64>,
    pub(super) returns: Vec<f64>,
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

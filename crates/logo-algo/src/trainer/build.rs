//! Building a trainer: every network initialised from the seed (or the policy from a
//! file), the env copies, the evaluation env, the guidance signal and the worker pool.

use std::path::Path;
use std::sync::Arc;

use logo_data::Demonstrations;
use logo_envs::{EnvSpec, VecEnv};
use logo_nn::flat::params_to_vec;
use logo_nn::{
    Cpu, Discriminator, DiscriminatorConfig, Engine, GaussianPolicy, Policy, PolicyConfig,
    ValueNet, load_reference_policy,
};

use super::recorder::Recorder;
use super::schedule::Schedule;
use super::state::{Collector, Critics, EngineSpan, Evaluator, Modules, Trainer};
use crate::config::{GuidanceConfig, TrainConfig};
use crate::critic::{CriticConfig, CriticSet};
use crate::delta_schedule::DeltaSchedule;
use crate::discriminator::DiscriminatorTrainer;
use crate::guidance::{Guidance, GuidanceSignal};
use crate::policy_update::UpdateState;
use crate::run_dir::{RunDir, TrainError};
use crate::sampler::Sampler;
use crate::streams;

impl<E: Engine> Trainer<E> {
    /// A new run on `engine` writing into `out_dir` (metrics.csv is started afresh).
    pub fn new(engine: E, config: TrainConfig, out_dir: &Path) -> Result<Self, TrainError> {
        config.validate().map_err(|e| format!("config: {e}"))?;
        let run = RunDir::create(out_dir, &config)?;
        Self::build(engine, config, run)
    }

    pub(super) fn build(engine: E, config: TrainConfig, run: RunDir) -> Result<Self, TrainError> {
        let factory = config.env.factory()?;
        let spec = factory.spec().clone();
        let evaluator = Evaluator::new(&config, &spec)?;
        let demos = match config.guidance.as_ref().and_then(|g| g.demos.as_ref()) {
            Some(path) => Some(
                Demonstrations::load(path, &spec.id, spec.obs_dim, spec.act_dim)
                    .map_err(|e| format!("guidance.demos: {e}"))?,
            ),
            None => None,
        };
        let modules = Modules::init(&config, spec.obs_dim, spec.act_dim, demos.is_some())?;
        let critics = Critics {
            env: CriticSet::new(&engine, &config.critic, &modules.critic),
            guidance: config
                .guidance_critic()
                .zip(modules.guidance_critic.as_ref())
                .map(|(c, m)| CriticSet::new(&engine, c, m)),
        };
        let guidance = guidance(&engine, &config, demos.as_ref(), &modules)?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(config.threads)
            .thread_name(|i| format!("logo-{i}"))
            .build()
            .map_err(|e| format!("cannot start {} worker threads: {e}", config.threads))?;
        let collector = Collector {
            // The copies run on the trainer's pool, as every other phase does.
            venv: VecEnv::on_caller_pool(&factory, config.num_envs, config.seed)?,
            sampler: sampler(&config, &spec),
            rng: streams::sampler(config.seed),
        };
        let engines = vec![EngineSpan {
            from_iteration: 0,
            engine: engine.describe(),
        }];
        Ok(Self {
            pool: Arc::new(pool),
            schedule: Schedule::default(),
            collector,
            evaluator,
            policy: Policy::from_module(&engine, &modules.policy),
            improvement: UpdateState::default(),
            critics,
            guidance,
            modules,
            next_batch: None,
            iteration: 0,
            samples: 0,
            engines,
            recorder: Recorder::new(run),
            config,
            engine,
        })
    }
}

impl Evaluator {
    /// The evaluation env of `config`, which must fit the training env's `spec`: the
    /// trained task itself, whose steps report the dense reward beside its own (a sparse
    /// wrapper leaves the dynamics and the dense reward as they are), unless `eval_env`
    /// names another.
    fn new(config: &TrainConfig, spec: &EnvSpec) -> Result<Self, TrainError> {
        let env = config.evaluated_env().factory()?.build()?;
        if env.spec().obs_dim != spec.obs_dim || env.spec().act_dim != spec.act_dim {
            return Err(format!(
                "eval_env {} does not have the dims of env {}",
                env.spec().id,
                spec.id
            )
            .into());
        }
        Ok(Self {
            env,
            seed: config.seed,
            min_steps: config.eval_steps,
            initial_states: config.eval_initial_states,
            clip_actions: config.clip_actions,
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

/// LOGO's guidance as `config` asks for it: a discriminator on `demos`, or a known
/// behaviour policy; None without `[guidance]`.
fn guidance<E: Engine>(
    engine: &E,
    config: &TrainConfig,
    demos: Option<&Demonstrations>,
    modules: &Modules,
) -> Result<Option<Guidance<E>>, TrainError> {
    let Some(g) = &config.guidance else {
        return Ok(None);
    };
    let signal = match (&g.behaviour_policy, demos, &modules.discriminator) {
        (Some(path), _, _) => GuidanceSignal::Behaviour(Policy::from_module(
            engine,
            &load_reference_policy::<Cpu>(path, &Default::default())?,
        )),
        (None, Some(demos), Some(module)) => GuidanceSignal::Discriminator(
            DiscriminatorTrainer::new(engine, module, demos, g.discriminator_lr),
        ),
        _ => unreachable!("validated: demos or behaviour_policy"),
    };
    Ok(Some(Guidance {
        signal,
        schedule: DeltaSchedule::new(g.delta0, g.alpha, g.warmup),
        update: config.guidance_update().expect("guidance").clone(),
        state: UpdateState::default(),
    }))
}

impl Modules {
    /// Every network of the run, initialised from the seed (or the policy from
    /// `init_policy`). burn draws initial weights from one process-wide generator: it is
    /// held from the seeding to the last parameter drawn, or trainers built at the same
    /// time on other threads (tests, sweeps) would interleave their draws.
    pub(super) fn init(
        config: &TrainConfig,
        obs_dim: usize,
        act_dim: usize,
        discriminator: bool,
    ) -> Result<Self, TrainError> {
        use burn::tensor::backend::Backend;
        static INIT: std::sync::Mutex<()> = std::sync::Mutex::new(());
        let _init = INIT.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let device = Default::default();
        Cpu::seed(&device, config.seed);
        let policy = initial_policy(config, obs_dim, act_dim, &device)?;
        let critic_nets = |c: &CriticConfig| -> Vec<ValueNet<Cpu>> {
            (0..c.num_nets())
                .map(|_| c.net(obs_dim).init(&device))
                .collect()
        };
        let critic = critic_nets(&config.critic);
        let guidance_critic = config.guidance_critic().map(critic_nets);
        let discriminator = match (&config.guidance, discriminator) {
            (Some(g), true) => Some(discriminator_module(g, obs_dim, act_dim, &device)?),
            _ => None,
        };
        // burn initialises parameters lazily, at their first use: draw them all now, under
        // the lock, in a fixed order.
        let _ = params_to_vec(&policy);
        let _ = params_to_vec(&critic);
        if let Some(nets) = &guidance_critic {
            let _ = params_to_vec(nets);
        }
        if let Some(d) = &discriminator {
            let _ = params_to_vec(d);
        }
        Ok(Self {
            policy,
            critic,
            guidance_critic,
            discriminator,
        })
    }
}

type CpuDevice = burn::tensor::Device<Cpu>;

/// The policy from `init_policy` (a reference `.pt`, which must fit the env), or a new
/// one of the config's sizes.
fn initial_policy(
    config: &TrainConfig,
    obs_dim: usize,
    act_dim: usize,
    device: &CpuDevice,
) -> Result<GaussianPolicy<Cpu>, TrainError> {
    let Some(path) = &config.init_policy else {
        return Ok(PolicyConfig {
            obs_dim,
            act_dim,
            hidden: config.policy_hidden.clone(),
            log_std_init: config.log_std_init,
        }
        .init(device));
    };
    let policy = load_reference_policy::<Cpu>(path, device)?;
    if (policy.obs_dim(), policy.act_dim()) != (obs_dim, act_dim) {
        return Err(format!(
            "init_policy {}: obs/action dims ({}, {}) do not match {} ({obs_dim}, {act_dim})",
            path.display(),
            policy.obs_dim(),
            policy.act_dim(),
            config.env,
        )
        .into());
    }
    Ok(policy)
}

/// The discriminator of `[guidance]`, on the first `observe` observation dims.
fn discriminator_module(
    g: &GuidanceConfig,
    obs_dim: usize,
    act_dim: usize,
    device: &CpuDevice,
) -> Result<Discriminator<Cpu>, TrainError> {
    let observe = g.observe.unwrap_or(obs_dim);
    if observe > obs_dim {
        return Err(format!("guidance.observe must be in 1..={obs_dim}, got {observe}").into());
    }
    Ok(DiscriminatorConfig {
        observe,
        act_dim,
        hidden: g.discriminator_hidden.clone(),
        init: g.discriminator_init,
    }
    .init(device))
}

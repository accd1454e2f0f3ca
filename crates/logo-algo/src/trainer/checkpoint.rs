//! The training loop: [`Trainer::step`] is one iteration of LOGO (Algorithm 1, as the
//! reference runs it), written once for every engine and every configured variant:
//!
//! 1. collect whole episodes with π_k;
//! 2. advantages of the env reward with the critic as it stands;
//! 3. δ_k from the batch's mean sparse return; while δ_k is above its floor, the guidance
//!    reward r_C = −log D(s, a) (last iteration's D) or log π_b − log π_k, and its
//!    advantages with the guidance critic;
//! 4. improvement step (`[improvement]`'s kind, KL ≈ δ = `max_kl`) → π_{k+½};
//! 5. guidance step (`[guidance.update]`'s kind, KL ≈ δ_k, ratio against π_k) → π_{k+1};
//! 6. one discriminator update;
//! 7. evaluation on the dense env with the mean action; metrics row, checkpoint.
//!
//! The critic fits run beside steps 4-7 ([`beside`]): the reference, too, computes both
//! streams' advantages with the critics as they stand and fits them afterwards, so
//! nothing in between needs them. Without `[guidance]` it is the improvement step alone
//! (TRPO, PPO, ...).

use std::path::Path;
use std::time::Instant;

use logo_data::Demonstrations;
use logo_envs::{Env, EnvFactory, EnvOptions, ResetPoint, RngState, VecEnv};
use logo_nn::flat::params_to_vec;
use logo_nn::{
    Checkpoint, CheckpointMeta, Cpu, Discriminator, DiscriminatorConfig, Engine, GaussianPolicy,
    Policy, PolicyConfig, ValueNet, load_reference_policy,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::adam::Adam;
use crate::config::TrainConfig;
use crate::critic::{CriticConfig, CriticSet};
use crate::gae::{GaeInput, gae, normalise};
use crate::guidance::{DeltaSchedule, DiscriminatorTrainer, behaviour_rewards};
use crate::metrics::IterationMetrics;
use crate::policy_update::{PolicyUpdateConfig, StepBatch, StopReason, UpdateState, UpdateStats};
use crate::rollout::{Batch, Sampler};
pub use crate::run_dir::{RunDir, TrainError};

/// Where r_C comes from.
enum GuidanceSignal<E: Engine> {
    Discriminator(DiscriminatorTrainer<E>),
    Behaviour(Policy<E>),
}

/// LOGO's guidance step: its signal, δ_k, and its policy-update kind and state.
struct Guidance<E: Engine> {
    signal: GuidanceSignal<E>,
    schedule: DeltaSchedule,
    update: PolicyUpdateConfig,
    state: UpdateState,
}

/// The critics of both reward streams (fitted beside the policy steps).
struct Critics<E: Engine> {
    env: CriticSet<E>,
    guidance: Option<CriticSet<E>>,
}

/// The networks as burn modules on the CPU: their definitions (the reference's
/// initialisation), and the form checkpoints are written and read in, whatever the engine.
struct Modules {
    policy: GaussianPolicy<Cpu>,
    critic: Vec<ValueNet<Cpu>>,
    guidance_critic: Option<Vec<ValueNet<Cpu>>>,
    discriminator: Option<Discriminator<Cpu>>,
}

pub struct Trainer<E: Engine> {
    pub config: TrainConfig,
    engine: E,
    run: RunDir,
    venv: VecEnv,
    sampler: Sampler,
    eval_env: Box<dyn Env>,
    policy: Policy<E>,
    improvement: UpdateState,
    critics: Critics<E>,
    guidance: Option<Guidance<E>>,
    modules: Modules,
    /// The sampler's generator (each env copy's action noise is seeded from it).
    rng: ChaCha8Rng,
    iteration: usize,
    samples: usize,
    started: Instant,
    /// Wall seconds of the iterations before a resume.
    wall_offset: f64,
    /// Which engine ran which iterations, written into every checkpoint's metadata.
    engines: Vec<EngineSpan>,
    /// The iteration count of the last checkpoint written (or resumed from).
    saved_at: Option<usize>,
}

/// The algorithm a checkpoint's metadata names: "logo" with a guidance step, else "trpo".
fn checkpoint_algorithm(config: &TrainConfig) -> &'static str {
    if config.guidance.is_some() {
        "logo"
    } else {
        "trpo"
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

/// From `from_iteration` on (until the next span), the run trained on `engine`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EngineSpan {
    pub from_iteration: usize,
    pub engine: String,
}

/// The engine spans recorded in a checkpoint's metadata (older checkpoints name one
/// engine, or none).
pub fn engine_history(meta: &logo_nn::CheckpointMeta) -> Vec<EngineSpan> {
    let extra = &meta.extra;
    if let Ok(spans) = serde_json::from_value::<Vec<EngineSpan>>(extra["engines"].clone()) {
        return spans;
    }
    extra["engine"]
        .as_str()
        .map(|engine| {
            vec![EngineSpan {
                from_iteration: 0,
                engine: engine.to_string(),
            }]
        })
        .unwrap_or_default()
}

/// What a checkpoint holds besides the networks, for `--resume`.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct ResumeState {
    iteration: usize,
    samples: usize,
    sampler_rng: RngState,
    env_points: Vec<ResetPoint>,
    schedule: Option<DeltaSchedule>,
    discriminator_adam: Option<Adam>,
    improvement: UpdateState,
    guidance: Option<UpdateState>,
    critic_adam: Vec<Adam>,
    guidance_critic_adam: Option<Vec<Adam>>,
}

/// Normalised advantages and the critic's regression targets of one reward stream.
struct Advantages {
    normalised: Vec<f64>,
    returns: Vec<f64>,
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

/// Runs `fits` beside `steps` on rayon's pool: the critic fits of an iteration, which
/// nothing else reads before the next one, overlapped with its policy steps.
fn beside<F, S, T>(fits: F, steps: S) -> ((f64, f64, f64), T)
where
    F: FnOnce() -> (f64, f64) + Send,
    S: FnOnce() -> T + Send,
    T: Send,
{
    rayon::join(
        || {
            let mut clock = Stopwatch::start();
            let (env, guidance) = fits();
            (env, guidance, clock.lap())
        },
        steps,
    )
}

/// Mean dense return of the mean-action policy over whole episodes of at least
/// `config.eval_steps` steps in all, from fixed initial states.
fn evaluate<E: Engine>(
    engine: &E,
    config: &TrainConfig,
    policy: &Policy<E>,
    eval_env: &mut dyn Env,
) -> Result<f64, TrainError> {
    let policy = policy.acting(engine);
    let spec = eval_env.spec().clone();
    let mut obs = vec![0.0; spec.obs_dim];
    let (mut steps, mut returns) = (0, Vec::new());
    while steps < config.eval_steps {
        // Fixed evaluation seeds: every evaluation sees the same initial states.
        eval_env.reset(
            Some(1_000_000 + config.seed * 1000 + returns.len() as u64),
            &mut obs,
        );
        let mut total = 0.0;
        loop {
            let action = policy.mean(&obs);
            let step = eval_env.step(&action, &mut obs)?;
            total += step.info.dense_reward;
            steps += 1;
            if step.done() {
                break;
            }
        }
        returns.push(total);
    }
    Ok(returns.iter().sum::<f64>() / returns.len() as f64)
}

/// The generator that shuffles the minibatches of iteration `k`'s step `which` (0:
/// improvement, 1: guidance): derived from the seed, so a resumed run draws the same.
fn update_rng(seed: u64, k: usize, which: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(1 + 2 * k as u64 + which);
    rng
}

impl<E: Engine> Trainer<E> {
    /// A new run on `engine` writing into `out_dir` (metrics.csv is started afresh).
    pub fn new(engine: E, config: TrainConfig, out_dir: &Path) -> Result<Self, TrainError> {
        config.validate().map_err(|e| format!("config: {e}"))?;
        let run = RunDir::create(out_dir, &config)?;
        Self::build(engine, config, run)
    }

    /// Continues the run in `out_dir` from its checkpoint: networks, optimiser states,
    /// the δ schedule, the sampler's and every env copy's generator, the iteration and
    /// sample counts. Rows of metrics.csv after the checkpoint (a killed run's last
    /// iterations) are dropped and redone; the run then ends with the same checkpoint as
    /// one never interrupted. `iterations` extends or shortens the run.
    pub fn resume(
        engine: E,
        out_dir: &Path,
        iterations: Option<usize>,
    ) -> Result<Self, TrainError> {
        let run = RunDir::open(out_dir)?;
        run.remove_stale_temporaries()?;
        let path = run.checkpoint_path();
        let ckpt = Checkpoint::load(&path)?;
        let bad = |what: &str| format!("{}: {what}", path.display());
        let extra = &ckpt.meta.extra;
        let mut config: TrainConfig = serde_json::from_value(extra["config"].clone())
            .map_err(|e| bad(&format!("metadata config: {e}")))?;
        if extra["resume"].is_null() {
            return Err(bad(
                "holds no resume state (runs with rollout = \"steps\" continue episodes \
                 across iterations and cannot be resumed exactly; older checkpoints lack it)",
            )
            .into());
        }
        let state: ResumeState = serde_json::from_value(extra["resume"].clone())
            .map_err(|e| bad(&format!("metadata resume state: {e}")))?;
        if let Some(n) = iterations {
            config.iterations = n;
        }
        config
            .validate()
            .map_err(|e| bad(&format!("metadata config: {e}")))?;
        // The stored config must describe the stored networks (it sizes them before the
        // tensors are read) and the algorithm that wrote them.
        let meta = &ckpt.meta;
        for (what, found, expected) in [
            ("env", meta.env_id.clone(), config.env.clone()),
            (
                "algorithm",
                meta.algorithm.clone(),
                checkpoint_algorithm(&config).to_string(),
            ),
            (
                "policy network",
                format!("{:?}", meta.networks.get("policy")),
                format!("{:?}", Some(&config.policy_hidden)),
            ),
            (
                "critic network",
                format!("{:?}", meta.networks.get("critic")),
                format!("{:?}", Some(&config.critic.hidden)),
            ),
        ] {
            if found != expected {
                return Err(bad(&format!(
                    "the metadata's {what} is {found}, its config says {expected}"
                ))
                .into());
            }
        }
        let mut trainer = Self::build(engine, config, run)?;
        let t = &mut trainer;
        t.modules.policy = ckpt.apply("policy", t.modules.policy.clone())?;
        t.policy = Policy::from_module(&t.engine, &t.modules.policy);
        t.modules.critic = ckpt.apply("critic", t.modules.critic.clone())?;
        t.critics.env = CriticSet::new(&t.engine, &t.config.critic, &t.modules.critic);
        t.critics.env.adam = state.critic_adam.clone();
        t.improvement = state.improvement.clone();
        if let Some(g) = t.guidance.as_mut() {
            let modules = t
                .modules
                .guidance_critic
                .take()
                .expect("built with guidance");
            let modules = ckpt.apply("guidance_critic", modules)?;
            let config = t.config.guidance_critic().expect("guidance").clone();
            let mut critic = CriticSet::new(&t.engine, &config, &modules);
            critic.adam = state.guidance_critic_adam.clone().unwrap_or_default();
            t.critics.guidance = Some(critic);
            t.modules.guidance_critic = Some(modules);
            g.schedule = state
                .schedule
                .clone()
                .ok_or_else(|| bad("no δ schedule in the resume state"))?;
            g.state = state.guidance.clone().unwrap_or_default();
            if let GuidanceSignal::Discriminator(d) = &mut g.signal {
                let module = t
                    .modules
                    .discriminator
                    .take()
                    .expect("built with a discriminator");
                let module = ckpt.apply("discriminator", module)?;
                d.net = t
                    .engine
                    .net(&module.net.dims(), &params_to_vec(&module.net));
                d.optim = state.discriminator_adam.clone().unwrap_or_default();
                t.modules.discriminator = Some(module);
            }
        }
        // Optimiser states must fit the networks they were saved with.
        let engine = &t.engine;
        let policy_len = t.policy.params(engine).len();
        let mut adams = vec![("improvement.adam", &t.improvement.adam, policy_len)];
        let sets = [Some(&t.critics.env), t.critics.guidance.as_ref()];
        for (name, set) in ["critic_adam", "guidance_critic_adam"]
            .into_iter()
            .zip(sets)
        {
            let Some(set) = set else { continue };
            if set.adam.len() != set.nets.len() {
                return Err(bad(&format!(
                    "resume state {name}: {} Adam states for {} critics",
                    set.adam.len(),
                    set.nets.len()
                ))
                .into());
            }
            for (adam, net) in set.adam.iter().zip(&set.nets) {
                adams.push((name, adam, engine.params(net).len()));
            }
        }
        if let Some(g) = &t.guidance {
            adams.push(("guidance.adam", &g.state.adam, policy_len));
            if let GuidanceSignal::Discriminator(d) = &g.signal {
                adams.push(("discriminator_adam", &d.optim, engine.params(&d.net).len()));
            }
        }
        for (name, adam, len) in adams {
            adam.check(len)
                .map_err(|e| bad(&format!("resume state {name}: {e}")))?;
        }
        t.rng = state.sampler_rng.to_rng().map_err(|e| bad(&e))?;
        t.venv.restore_reset_points(&state.env_points)?;
        t.iteration = state.iteration;
        t.samples = state.samples;
        // A checkpoint from any engine or float type continues on this one.
        let mut engines = engine_history(&ckpt.meta);
        let now = t.engine.describe();
        if engines.last().map(|span| &span.engine) != Some(&now) {
            engines.push(EngineSpan {
                from_iteration: state.iteration,
                engine: now,
            });
        }
        t.engines = engines;
        t.saved_at = Some(state.iteration);
        // metrics.csv: keep the rows up to the checkpoint, continue its clock.
        let kept = t.run.keep_metrics_before(state.iteration)?;
        t.wall_offset = kept.last().map_or(0.0, |row| row.wall_s);
        Ok(trainer)
    }

    fn build(engine: E, config: TrainConfig, run: RunDir) -> Result<Self, TrainError> {
        let factory = EnvFactory::new(&config.env, &EnvOptions::default())?;
        let spec = factory.spec().clone();
        let venv = VecEnv::new(&factory, config.num_envs, config.threads, config.seed)?;
        let eval_env = EnvFactory::new(&config.eval_env_id(), &EnvOptions::default())?.build();
        if eval_env.spec().obs_dim != spec.obs_dim || eval_env.spec().act_dim != spec.act_dim {
            return Err(format!(
                "eval_env {} does not have the dims of env {}",
                eval_env.spec().id,
                spec.id
            )
            .into());
        }
        let demos = match config.guidance.as_ref().and_then(|g| g.demos.as_ref()) {
            Some(path) => Some(
                Demonstrations::load(path, &spec.id, spec.obs_dim, spec.act_dim)
                    .map_err(|e| format!("guidance.demos: {e}"))?,
            ),
            None => None,
        };
        let modules = Modules::init(&config, spec.obs_dim, spec.act_dim, demos.is_some())?;

        let policy = Policy::from_module(&engine, &modules.policy);
        let critics = Critics {
            env: CriticSet::new(&engine, &config.critic, &modules.critic),
            guidance: config
                .guidance_critic()
                .zip(modules.guidance_critic.as_ref())
                .map(|(c, m)| CriticSet::new(&engine, c, m)),
        };
        let guidance = match &config.guidance {
            None => None,
            Some(g) => {
                let signal = match (&g.behaviour_policy, &demos, &modules.discriminator) {
                    (Some(path), _, _) => GuidanceSignal::Behaviour(Policy::from_module(
                        &engine,
                        &load_reference_policy::<Cpu>(path, &Default::default())?,
                    )),
                    (None, Some(demos), Some(module)) => GuidanceSignal::Discriminator(
                        DiscriminatorTrainer::new(&engine, module, demos, g.discriminator_lr),
                    ),
                    _ => unreachable!("validated: demos or behaviour_policy"),
                };
                Some(Guidance {
                    signal,
                    schedule: DeltaSchedule::new(g.delta0, g.alpha, g.warmup),
                    update: config.guidance_update().expect("guidance").clone(),
                    state: UpdateState::default(),
                })
            }
        };
        let engine_name = engine.describe();
        Ok(Self {
            rng: ChaCha8Rng::seed_from_u64(config.seed),
            sampler: Sampler::new(config.rollout, config.num_envs),
            config,
            engine,
            run,
            venv,
            eval_env,
            policy,
            improvement: UpdateState::default(),
            critics,
            guidance,
            modules,
            iteration: 0,
            samples: 0,
            started: Instant::now(),
            wall_offset: 0.0,
            engines: vec![EngineSpan {
                from_iteration: 0,
                engine: engine_name,
            }],
            saved_at: None,
        })
    }

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

    pub fn run_dir(&self) -> &Path {
        self.run.path()
    }

    /// Runs one iteration and appends its row to `metrics.csv`; an error names the
    /// iteration.
    pub fn step(&mut self) -> Result<IterationMetrics, TrainError> {
        let k = self.iteration;
        self.iterate()
            .map_err(|e| format!("iteration {k}: {e}").into())
    }

    fn iterate(&mut self) -> Result<IterationMetrics, TrainError> {
        let k = self.iteration;
        let engine = &self.engine;
        let config = &self.config;
        let mut row = IterationMetrics {
            iteration: k,
            ..IterationMetrics::default()
        };
        let mut clock = Stopwatch::start();

        // 1. Collect (s, a, r) with π_k; the batch goes to the engine once.
        let batch = self.sampler.collect(
            &mut self.venv,
            &self.policy.acting(engine),
            &mut self.rng,
            config.samples_per_iter,
        )?;
        let obs = engine.rows(&batch.obs, batch.obs_dim);
        let actions = engine.upload(&batch.actions, [batch.len(), batch.act_dim]);
        let logp_k = self.policy.log_prob(engine, &obs, &actions);
        row.t_sampling = clock.lap();

        // 2. Advantages of the env reward, with the critic as it stands.
        let env = advantages(
            engine,
            config,
            &self.critics.env,
            &batch,
            &obs,
            &batch.rewards,
        );

        // 3. δ_k, then the guidance reward and its advantages while δ_k is above its floor.
        let mut guidance_advantages = None;
        let mut discriminator_inputs = None;
        if let Some(g) = &mut self.guidance {
            g.schedule.update(k, batch.mean_return());
            row.delta_k = g.schedule.delta;
            if g.schedule.guidance_on() {
                let rewards = match &g.signal {
                    GuidanceSignal::Discriminator(d) => {
                        let inputs = d.inputs(engine, &batch.obs, &batch.actions);
                        let rewards = d.rewards(engine, &inputs);
                        discriminator_inputs = Some(inputs);
                        rewards
                    }
                    GuidanceSignal::Behaviour(pi_b) => {
                        behaviour_rewards(engine, pi_b, &obs, &actions, &logp_k)
                    }
                };
                let critic = self
                    .critics
                    .guidance
                    .as_ref()
                    .expect("guidance has a critic");
                guidance_advantages =
                    Some(advantages(engine, config, critic, &batch, &obs, &rewards));
            }
        }
        row.t_advantages = clock.lap();
        let data = StepBatch {
            advantages: engine.upload(&env.normalised, [batch.len()]),
            obs: obs.clone(),
            actions,
            logp_old: logp_k,
            rows: batch.len(),
        };

        self.iteration += 1;
        self.samples += batch.len();
        let evaluate_now = k.is_multiple_of(config.eval_every) || self.done();
        let rewardless =
            config.skip_improvement_without_reward && batch.rewards.iter().all(|&r| r == 0.0);
        let (policy, improvement, guidance, eval_env) = (
            &mut self.policy,
            &mut self.improvement,
            &mut self.guidance,
            &mut self.eval_env,
        );
        let ((critic_loss, guidance_critic_loss, fit_seconds), stepped) = beside(
            || {
                let mut rng = update_rng(config.seed, k, 2);
                let env_loss = self.critics.env.fit(engine, &obs, &env.returns, &mut rng);
                let guidance_loss = match (&mut self.critics.guidance, &guidance_advantages) {
                    (Some(critic), Some(adv)) => critic.fit(engine, &obs, &adv.returns, &mut rng),
                    _ => f64::NAN,
                };
                (env_loss, guidance_loss)
            },
            || -> Result<_, TrainError> {
                let mut clock = Stopwatch::start();
                let mut row = IterationMetrics::default();

                // 4. Improvement step: π_k → π_{k+½}, KL ≈ δ (or none, if asked, on a
                //    batch without env reward).
                if rewardless {
                    row.improvement(&UpdateStats {
                        stop: StopReason::NoReward,
                        ..UpdateStats::default()
                    });
                } else {
                    let step = config.improvement.update(
                        engine,
                        policy,
                        &data,
                        config.max_kl,
                        improvement,
                        &mut update_rng(config.seed, k, 0),
                    );
                    let stats = take_step(engine, policy, step, "the improvement step")?;
                    row.improvement(&stats);
                }
                row.t_policy_step = clock.lap();

                // 5. Guidance step on the same batch: π_{k+½} → π_{k+1}, KL ≈ δ_k, the
                //    ratio against π_k.
                let mut guidance_stats = None;
                if let (Some(g), Some(adv)) = (guidance.as_mut(), &guidance_advantages) {
                    let advantages = engine.upload(&adv.normalised, [data.rows]);
                    let step = g.update.update(
                        engine,
                        policy,
                        &data.with_advantages(advantages),
                        g.schedule.delta,
                        &mut g.state,
                        &mut update_rng(config.seed, k, 1),
                    );
                    guidance_stats = Some(take_step(engine, policy, step, "the guidance step")?);
                }
                row.guidance(guidance_stats.as_ref());
                row.t_guidance = clock.lap();

                // 6. Discriminator update: policy pairs 1, demonstration pairs 0.
                row.disc_loss = f64::NAN;
                if let (Some(g), Some(inputs)) = (guidance.as_mut(), &discriminator_inputs)
                    && let GuidanceSignal::Discriminator(d) = &mut g.signal
                {
                    row.disc_loss = d.update(engine, inputs);
                    finite(
                        row.disc_loss.is_finite(),
                        "the discriminator update",
                        "discriminator's parameters or loss",
                    )?;
                }
                row.t_discriminator = clock.lap();

                // 7. Evaluate the mean action on the dense env.
                row.eval_dense_return = if evaluate_now {
                    evaluate(engine, config, policy, eval_env.as_mut())?
                } else {
                    f64::NAN
                };
                row.t_evaluation = clock.lap();
                Ok(row)
            },
        );
        // A non-finite number stops the run before anything is written: metrics.csv and
        // the checkpoint stay as the last good iteration left them.
        let stop = |e: TrainError| -> TrainError {
            let kept = match self.saved_at {
                Some(at) => format!("the checkpoint of iteration {at} is kept"),
                None => "no checkpoint had been written yet".to_string(),
            };
            format!(
                "{e}; the run stopped ({kept} in {})",
                self.run.path().display()
            )
            .into()
        };
        let steps = stepped.map_err(stop)?;
        finite(
            critic_loss.is_finite(),
            "the critic fit",
            "env critic's parameters or loss",
        )
        .map_err(stop)?;
        if guidance_advantages.is_some() {
            finite(
                guidance_critic_loss.is_finite(),
                "the critic fit",
                "guidance critic's parameters or loss",
            )
            .map_err(stop)?;
        }
        row = IterationMetrics {
            iteration: k,
            samples: self.samples,
            wall_s: self.wall_offset + self.started.elapsed().as_secs_f64(),
            episodes: batch.episode_returns.len(),
            train_sparse_return: batch.mean_return(),
            train_dense_return: batch.mean_dense_return(),
            delta_k: row.delta_k,
            mean_log_std: self.policy.log_std.iter().sum::<f64>() / self.policy.act_dim() as f64,
            critic_loss,
            guidance_critic_loss,
            t_sampling: row.t_sampling,
            t_advantages: row.t_advantages,
            t_critics: fit_seconds,
            ..steps
        };
        self.run.append(&row)?;
        if self.iteration.is_multiple_of(self.config.checkpoint_every) || self.done() {
            self.save_checkpoint(&self.run.checkpoint_path())?;
            self.saved_at = Some(self.iteration);
        }
        Ok(row)
    }

    pub fn save_checkpoint(&self, path: &Path) -> Result<(), TrainError> {
        let engine = &self.engine;
        let spec = self.venv.spec();
        let algorithm = checkpoint_algorithm(&self.config);
        let mut meta = CheckpointMeta::new(&spec.id, spec.obs_dim, spec.act_dim, algorithm);
        let dims = &self.policy.dims;
        meta.networks
            .insert("policy".into(), dims[1..dims.len() - 1].to_vec());
        meta.networks
            .insert("critic".into(), self.config.critic.hidden.clone());
        meta.iteration = self.iteration as u64;
        meta.seed = self.config.seed;
        let (schedule, discriminator_adam, guidance_state) = match &self.guidance {
            Some(g) => (
                Some(g.schedule.clone()),
                match &g.signal {
                    GuidanceSignal::Discriminator(d) => Some(d.optim.clone()),
                    GuidanceSignal::Behaviour(_) => None,
                },
                Some(g.state.clone()),
            ),
            None => (None, None, None),
        };
        // Only between batches that leave every copy freshly reset can the envs be
        // restored exactly (mid-episode MuJoCo state also holds solver warm-starts).
        let resume = if self.sampler.at_episode_starts() {
            Some(ResumeState {
                iteration: self.iteration,
                samples: self.samples,
                sampler_rng: RngState::of(&self.rng),
                env_points: self.venv.reset_points()?,
                schedule,
                discriminator_adam,
                improvement: self.improvement.clone(),
                guidance: guidance_state,
                critic_adam: self.critics.env.adam.clone(),
                guidance_critic_adam: self.critics.guidance.as_ref().map(|c| c.adam.clone()),
            })
        } else {
            None
        };
        meta.extra = serde_json::json!({
            "samples": self.samples,
            "engine": engine.describe(),
            "engines": self.engines,
            "config": self.config,
            "resume": resume,
        });
        let mut ckpt = Checkpoint::new(meta);
        ckpt.insert(
            "policy",
            &self.policy.to_module(engine, self.modules.policy.clone()),
        );
        ckpt.insert(
            "critic",
            &self.critics.env.to_modules(engine, &self.modules.critic),
        );
        if let (Some(critic), Some(templates)) =
            (&self.critics.guidance, &self.modules.guidance_critic)
        {
            ckpt.insert("guidance_critic", &critic.to_modules(engine, templates));
        }
        if let Some(Guidance {
            signal: GuidanceSignal::Discriminator(d),
            ..
        }) = &self.guidance
        {
            let template = self.modules.discriminator.clone().expect("a discriminator");
            ckpt.insert("discriminator", &d.to_module(engine, template));
        }
        ckpt.save(path)?;
        Ok(())
    }
}

impl Modules {
    /// Every network of the run, initialised from the seed (or the policy from
    /// `init_policy`). burn draws initial weights from one process-wide generator: it is
    /// held from the seeding to the last parameter drawn, or trainers built at the same
    /// time on other threads (tests, sweeps) would interleave their draws.
    fn init(
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
        let policy = match &config.init_policy {
            Some(path) => {
                let p = load_reference_policy::<Cpu>(path, &device)?;
                if (p.obs_dim(), p.act_dim()) != (obs_dim, act_dim) {
                    return Err(format!(
                        "init_policy {}: obs/action dims ({}, {}) do not match {} ({obs_dim}, {act_dim})",
                        path.display(),
                        p.obs_dim(),
                        p.act_dim(),
                        config.env,
                    )
                    .into());
                }
                p
            }
            None => PolicyConfig {
                obs_dim,
                act_dim,
                hidden: config.policy_hidden.clone(),
                log_std_init: config.log_std_init,
            }
            .init(&device),
        };
        let critic_nets = |c: &CriticConfig| -> Vec<ValueNet<Cpu>> {
            (0..c.num_nets())
                .map(|_| c.net(obs_dim).init(&device))
                .collect()
        };
        let critic = critic_nets(&config.critic);
        let guidance_critic = config.guidance_critic().map(critic_nets);
        let discriminator = match (&config.guidance, discriminator) {
            (Some(g), true) => {
                let observe = g.observe.unwrap_or(obs_dim);
                if observe > obs_dim {
                    return Err(format!(
                        "guidance.observe must be in 1..={obs_dim}, got {observe}"
                    )
                    .into());
                }
                Some(
                    DiscriminatorConfig {
                        observe,
                        act_dim,
                        hidden: g.discriminator_hidden.clone(),
                        init: g.discriminator_init,
                    }
                    .init(&device),
                )
            }
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

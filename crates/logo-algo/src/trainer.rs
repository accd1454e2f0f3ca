//! One LOGO iteration, top to bottom (Algorithm 1 of the paper, as the reference runs it):
//!
//! 1. collect whole episodes with π_k (sparse rewards);
//! 2. GAE advantages with the critics as they stand: env reward, and (while δ_k, updated
//!    on the batch's mean sparse return, is above its floor) r_C = −log D(s,a) from last
//!    iteration's D (or log π_b − log π_k) with the guidance critic;
//! 3. fit both critics to their returns — beside steps 4-6, which do not need them;
//! 4. improvement step: TRPO on the normalised advantages, KL ≤ δ → π_{k+½};
//! 5. guidance step: a second TRPO step on the same batch with the ratio against π_k and
//!    KL ≤ δ_k → π_{k+1}; then one discriminator update;
//! 6. evaluation on the dense env with the mean action; then metrics and checkpoint.
//!
//! Without `[guidance]` in the config it is plain TRPO.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use burn::tensor::Tensor;
use burn::tensor::backend::{AutodiffBackend, Backend};
use logo_data::Demonstrations;
use logo_envs::{Env, EnvFactory, EnvOptions, ResetPoint, RngState, VecEnv};
use logo_nn::flat::{from_f64, params_to_vec};
use logo_nn::{
    Checkpoint, CheckpointMeta, DiscriminatorConfig, GaussianPolicy, PolicyConfig,
    load_reference_policy,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::config::TrainConfig;
use crate::critic::Critic;
use crate::gae::{GaeInput, gae, normalise};
use crate::guidance::{Adam, DeltaSchedule, DiscriminatorTrainer, behaviour_rewards};
use crate::rollout::{Batch, Sampler};
use crate::trpo::{StepData, trpo_step};

/// Anything that stops a run, as one message naming its cause.
pub type TrainError = Box<dyn std::error::Error + Send + Sync>;

/// Where r_C comes from.
enum GuidanceSignal<B: AutodiffBackend> {
    Discriminator(DiscriminatorTrainer<B>),
    Behaviour(GaussianPolicy<B::InnerBackend>),
}

struct Guidance<B: AutodiffBackend> {
    signal: GuidanceSignal<B>,
    critic: Critic<B::InnerBackend>,
    schedule: DeltaSchedule,
}

/// The backend without autodiff: policy, critics, rollouts and policy steps run on it
/// (their gradients are hand-written reverse passes, tested against autodiff); only the
/// discriminator's Adam step uses the autodiff backend.
type Inner<B> = <B as AutodiffBackend>::InnerBackend;

/// One row of `metrics.csv`.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct IterationMetrics {
    pub iteration: usize,
    pub samples: usize,
    pub wall_s: f64,
    pub episodes: usize,
    pub train_sparse_return: f64,
    pub train_dense_return: f64,
    /// Mean dense return of the deterministic policy (NaN when not evaluated).
    pub eval_dense_return: f64,
    pub kl: f64,
    pub guidance_kl: f64,
    pub delta_k: f64,
    pub critic_loss: f64,
    pub disc_loss: f64,
    /// Seconds spent in each phase of the iteration.
    pub time: PhaseTimes,
}

/// Where an iteration's time goes.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct PhaseTimes {
    pub sampling: f64,
    pub critics: f64,
    pub policy_step: f64,
    pub guidance: f64,
    pub discriminator: f64,
    pub evaluation: f64,
}

const CSV_HEADER: &str = "iteration,samples,wall_s,episodes,train_sparse_return,train_dense_return,eval_dense_return,kl,guidance_kl,delta_k,critic_loss,disc_loss,t_sampling,t_critics,t_policy_step,t_guidance,t_discriminator,t_evaluation";

pub struct Trainer<B: AutodiffBackend> {
    pub config: TrainConfig,
    out_dir: PathBuf,
    venv: VecEnv,
    sampler: Sampler,
    eval_env: Box<dyn Env>,
    policy: GaussianPolicy<Inner<B>>,
    critic: Critic<Inner<B>>,
    guidance: Option<Guidance<B>>,
    rng: ChaCha8Rng,
    iteration: usize,
    samples: usize,
    started: Instant,
    /// Wall seconds of the iterations before a resume.
    wall_offset: f64,
    device: B::Device,
}

/// What a checkpoint holds besides the networks, for `--resume`.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct ResumeState {
    iteration: usize,
    samples: usize,
    sampler_rng: RngState,
    env_points: Vec<ResetPoint>,
    schedule: Option<DeltaSchedule>,
    adam: Option<Adam>,
}

/// GAE for one reward stream with `critic` as it stands (the reference fits the critic
/// only after computing the advantages). Returns the normalised advantages and the
/// returns the critic is then fitted to.
fn advantages<B: Backend>(
    config: &TrainConfig,
    critic: &Critic<B>,
    batch: &Batch,
    rewards: &[f64],
    obs: &Tensor<B, 2>,
) -> (Vec<f64>, Vec<f64>) {
    let values = critic.values(obs.clone());
    let mut truncation_values = vec![0.0; batch.len()];
    if !batch.truncations.is_empty() {
        let rows: Vec<f64> = batch
            .truncations
            .iter()
            .flat_map(|(_, o)| o.iter().copied())
            .collect();
        let v = critic.values(from_f64(
            &rows,
            [batch.truncations.len(), batch.obs_dim],
            &obs.device(),
        ));
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
    (normalise(&adv), returns)
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

/// Fits `critic` to `returns`; its mean final loss.
fn fit_critic<B: Backend>(
    config: &TrainConfig,
    critic: &mut Critic<B>,
    obs: &Tensor<B, 2>,
    returns: &[f64],
) -> f64 {
    let losses = critic.fit(obs, returns, config.critic_l2, config.critic_iters);
    losses.iter().sum::<f64>() / losses.len() as f64
}

/// Mean dense return of the mean-action policy over whole episodes of at least
/// `config.eval_steps` steps in all, from fixed initial states.
fn evaluate<B: Backend>(
    config: &TrainConfig,
    policy: &GaussianPolicy<B>,
    eval_env: &mut dyn Env,
) -> Result<f64, TrainError> {
    let policy = policy.acting();
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

impl<B: AutodiffBackend> Trainer<B> {
    /// A new run writing into `out_dir` (metrics.csv is started afresh).
    pub fn new(config: TrainConfig, out_dir: &Path) -> Result<Self, TrainError> {
        let trainer = Self::build(config, out_dir)?;
        std::fs::create_dir_all(out_dir)?;
        std::fs::write(
            out_dir.join("config.toml"),
            toml::to_string(&trainer.config)?,
        )?;
        let mut csv = std::fs::File::create(out_dir.join("metrics.csv"))?;
        writeln!(csv, "{CSV_HEADER}")?;
        Ok(trainer)
    }

    /// Continues the run in `out_dir` from its checkpoint: networks, the discriminator's
    /// Adam state, the δ schedule, the sampler's and every env copy's generator, the
    /// iteration and sample counts. Rows of metrics.csv after the checkpoint (a killed
    /// run's last iterations) are dropped and redone; the run then ends with the same
    /// checkpoint as one never interrupted. `iterations` extends or shortens the run.
    pub fn resume(out_dir: &Path, iterations: Option<usize>) -> Result<Self, TrainError> {
        let path = out_dir.join("checkpoint.safetensors");
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
        let mut trainer = Self::build(config, out_dir)?;
        trainer.policy = ckpt.apply("policy", trainer.policy.clone())?;
        trainer.critic.nets = ckpt.apply("critic", trainer.critic.nets.clone())?;
        if let Some(g) = trainer.guidance.as_mut() {
            g.critic.nets = ckpt.apply("guidance_critic", g.critic.nets.clone())?;
            g.schedule = state
                .schedule
                .clone()
                .ok_or_else(|| bad("no δ schedule in the resume state"))?;
            if let GuidanceSignal::Discriminator(d) = &mut g.signal {
                d.disc = ckpt.apply("discriminator", d.disc.clone())?;
                d.optim = state.adam.clone().unwrap_or_default();
            }
        }
        trainer.rng = state.sampler_rng.to_rng().map_err(|e| bad(&e))?;
        trainer.venv.restore_reset_points(&state.env_points)?;
        trainer.iteration = state.iteration;
        trainer.samples = state.samples;
        // metrics.csv: keep the rows up to the checkpoint, continue its clock.
        let csv_path = out_dir.join("metrics.csv");
        let csv = std::fs::read_to_string(&csv_path).unwrap_or_default();
        let mut kept = vec![CSV_HEADER.to_string()];
        let mut wall = 0.0;
        for line in csv.lines().skip(1) {
            let mut fields = line.split(',');
            let iteration: Option<usize> = fields.next().and_then(|f| f.parse().ok());
            if iteration.is_some_and(|i| i < state.iteration) {
                wall = fields.nth(1).and_then(|f| f.parse().ok()).unwrap_or(wall);
                kept.push(line.to_string());
            }
        }
        std::fs::write(&csv_path, kept.join("\n") + "\n")?;
        trainer.wall_offset = wall;
        Ok(trainer)
    }

    fn build(config: TrainConfig, out_dir: &Path) -> Result<Self, TrainError> {
        let device = B::Device::default();
        // burn draws initial weights from one process-wide generator: hold it from the
        // seeding to the last network built, or trainers built at the same time on other
        // threads (tests, sweeps) would interleave their draws and lose reproducibility.
        static INIT: std::sync::Mutex<()> = std::sync::Mutex::new(());
        let _init = INIT.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        B::seed(&device, config.seed);
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
        let policy = match &config.init_policy {
            Some(path) => {
                let p = load_reference_policy::<Inner<B>>(path, &device)?;
                if (p.obs_dim(), p.act_dim()) != (spec.obs_dim, spec.act_dim) {
                    return Err(format!(
                        "init_policy {}: obs/action dims ({}, {}) do not match {} ({}, {})",
                        path.display(),
                        p.obs_dim(),
                        p.act_dim(),
                        spec.id,
                        spec.obs_dim,
                        spec.act_dim
                    )
                    .into());
                }
                p
            }
            None => PolicyConfig {
                obs_dim: spec.obs_dim,
                act_dim: spec.act_dim,
                hidden: config.policy_hidden.clone(),
                log_std_init: config.log_std_init,
            }
            .init(&device),
        };
        let critic = Critic::new(config.critic, spec.obs_dim, &config.critic_hidden, &device);
        let guidance = match &config.guidance {
            None => None,
            Some(g) => {
                let signal = if let Some(path) = &g.behaviour_policy {
                    GuidanceSignal::Behaviour(load_reference_policy(path, &device)?)
                } else {
                    let path = g
                        .demos
                        .as_ref()
                        .expect("validated: demos or behaviour_policy");
                    let demos = Demonstrations::load(path, spec.obs_dim, spec.act_dim)
                        .map_err(|e| format!("guidance.demos: {e}"))?;
                    let observe = g.observe.unwrap_or(spec.obs_dim);
                    if observe == 0 || observe > spec.obs_dim {
                        return Err(format!(
                            "guidance.observe must be in 1..={}, got {observe}",
                            spec.obs_dim
                        )
                        .into());
                    }
                    let dc = DiscriminatorConfig {
                        observe,
                        act_dim: spec.act_dim,
                        hidden: g.discriminator_hidden.clone(),
                    };
                    GuidanceSignal::Discriminator(DiscriminatorTrainer::new(
                        &dc,
                        &demos,
                        g.discriminator_lr,
                        &device,
                    ))
                };
                Some(Guidance {
                    signal,
                    critic: Critic::new(
                        config.critic,
                        spec.obs_dim,
                        &config.critic_hidden,
                        &device,
                    ),
                    schedule: DeltaSchedule::new(g.delta0, g.alpha, g.warmup),
                })
            }
        };
        let trainer = Self {
            rng: ChaCha8Rng::seed_from_u64(config.seed),
            sampler: Sampler::new(config.rollout, config.num_envs),
            config,
            out_dir: out_dir.to_path_buf(),
            venv,
            eval_env,
            policy,
            critic,
            guidance,
            iteration: 0,
            samples: 0,
            started: Instant::now(),
            wall_offset: 0.0,
            device,
        };
        // burn initialises parameters lazily, at their first use: draw them all now, under
        // the lock.
        let _ = params_to_vec(&trainer.policy);
        let _ = params_to_vec(&trainer.critic.nets);
        if let Some(g) = &trainer.guidance {
            let _ = params_to_vec(&g.critic.nets);
            if let GuidanceSignal::Discriminator(d) = &g.signal {
                let _ = params_to_vec(&d.disc);
            }
        }
        Ok(trainer)
    }

    pub fn iteration(&self) -> usize {
        self.iteration
    }

    pub fn done(&self) -> bool {
        self.iteration >= self.config.iterations
    }

    pub fn policy(&self) -> &GaussianPolicy<Inner<B>> {
        &self.policy
    }

    /// Runs one iteration and appends its row to `metrics.csv`.
    pub fn step(&mut self) -> Result<IterationMetrics, TrainError> {
        let k = self.iteration;
        let mut time = PhaseTimes::default();
        let mut clock = Stopwatch::start();
        // 1. Collect with π_k.
        let batch = self.sampler.collect(
            &mut self.venv,
            &self.policy,
            &mut self.rng,
            self.config.samples_per_iter,
        )?;
        time.sampling = clock.lap();
        let n = batch.len();
        let obs = from_f64::<Inner<B>, 2>(&batch.obs, [n, batch.obs_dim], &self.device);
        let actions = from_f64::<Inner<B>, 2>(&batch.actions, [n, batch.act_dim], &self.device);
        let logp_old = self.policy.log_prob(obs.clone(), actions.clone());
        let data = StepData {
            obs: obs.clone(),
            actions: actions.clone(),
            logp_old: logp_old.clone(),
        };

        // 2. Advantages of both reward streams with the critics as they stand; δ_k.
        let (adv, returns) = advantages(&self.config, &self.critic, &batch, &batch.rewards, &obs);
        let mut guidance_batch = None; // (advantages, returns) of r_C, while guidance is on
        let mut delta_k = 0.0;
        if let Some(g) = &mut self.guidance {
            g.schedule.update(k, batch.mean_return());
            delta_k = g.schedule.delta;
            if g.schedule.guidance_on() {
                let rewards = match &g.signal {
                    GuidanceSignal::Discriminator(d) => d.rewards(obs.clone(), actions.clone()),
                    GuidanceSignal::Behaviour(pi_b) => {
                        behaviour_rewards(pi_b, &logp_old, &obs, &actions)
                    }
                };
                guidance_batch = Some(advantages(&self.config, &g.critic, &batch, &rewards, &obs));
            }
        }
        time.critics = clock.lap();
        self.iteration += 1;
        self.samples += n;
        let evaluate_now = k.is_multiple_of(self.config.eval_every) || self.done();

        // 3-6. The critic fits need nothing that follows and nothing that follows needs
        // them until the next iteration's advantages, so they run beside the policy steps,
        // the discriminator update and the evaluation (both halves on rayon's pool;
        // results do not depend on the overlap).
        let Self {
            config,
            critic,
            guidance,
            policy,
            eval_env,
            ..
        } = self;
        let (guidance_critic, mut guidance_signal) = match guidance {
            Some(g) => (Some(&mut g.critic), Some(&mut g.signal)),
            None => (None, None),
        };
        let fit_critics = || {
            let mut clock = Stopwatch::start();
            let (env_loss, _) = rayon::join(
                || fit_critic(config, critic, &obs, &returns),
                || {
                    if let (Some(critic), Some((_, returns))) = (guidance_critic, &guidance_batch) {
                        fit_critic(config, critic, &obs, returns);
                    }
                },
            );
            (env_loss, clock.lap())
        };
        let steps = || -> Result<_, TrainError> {
            let mut times = PhaseTimes::default();
            let mut clock = Stopwatch::start();
            // 4. Improvement step.
            let (next, improvement) = trpo_step(
                policy.clone(),
                &data,
                &adv,
                config.max_kl,
                &config.policy_step,
            );
            *policy = next;
            times.policy_step = clock.lap();
            // 5. Guidance step on the same batch, then the discriminator update.
            let (mut guidance_kl, mut disc_loss) = (0.0, f64::NAN);
            if let Some((adv_c, _)) = &guidance_batch {
                let (next, stats) =
                    trpo_step(policy.clone(), &data, adv_c, delta_k, &config.policy_step);
                *policy = next;
                guidance_kl = stats.kl;
                times.guidance = clock.lap();
                if let Some(GuidanceSignal::Discriminator(d)) = guidance_signal.as_deref_mut() {
                    disc_loss = d.update(
                        Tensor::from_inner(obs.clone()),
                        Tensor::from_inner(actions.clone()),
                    );
                }
                times.discriminator = clock.lap();
            }
            // 6. Evaluate.
            let eval = if evaluate_now {
                evaluate(config, policy, eval_env.as_mut())?
            } else {
                f64::NAN
            };
            times.evaluation = clock.lap();
            Ok((improvement, guidance_kl, disc_loss, eval, times))
        };
        let ((critic_loss, fit_time), stepped) = rayon::join(fit_critics, steps);
        let (improvement, guidance_kl, disc_loss, eval, step_times) = stepped?;
        time = PhaseTimes {
            sampling: time.sampling,
            critics: time.critics + fit_time,
            ..step_times
        };
        let metrics = IterationMetrics {
            iteration: k,
            samples: self.samples,
            wall_s: self.wall_offset + self.started.elapsed().as_secs_f64(),
            episodes: batch.episode_returns.len(),
            train_sparse_return: batch.mean_return(),
            train_dense_return: batch.mean_dense_return(),
            eval_dense_return: eval,
            kl: improvement.kl,
            guidance_kl,
            delta_k,
            critic_loss,
            disc_loss,
            time,
        };
        self.append_csv(&metrics)?;
        if self.iteration.is_multiple_of(self.config.checkpoint_every) || self.done() {
            self.save_checkpoint(&self.out_dir.join("checkpoint.safetensors"))?;
        }
        Ok(metrics)
    }

    fn append_csv(&self, m: &IterationMetrics) -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .append(true)
            .open(self.out_dir.join("metrics.csv"))?;
        writeln!(
            f,
            "{},{},{:.3},{},{},{},{},{},{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}",
            m.iteration,
            m.samples,
            m.wall_s,
            m.episodes,
            m.train_sparse_return,
            m.train_dense_return,
            m.eval_dense_return,
            m.kl,
            m.guidance_kl,
            m.delta_k,
            m.critic_loss,
            m.disc_loss,
            m.time.sampling,
            m.time.critics,
            m.time.policy_step,
            m.time.guidance,
            m.time.discriminator,
            m.time.evaluation
        )
    }

    pub fn save_checkpoint(&self, path: &Path) -> Result<(), TrainError> {
        let spec = self.venv.spec();
        let algorithm = if self.guidance.is_some() {
            "logo"
        } else {
            "trpo"
        };
        let mut meta = CheckpointMeta::new(&spec.id, spec.obs_dim, spec.act_dim, algorithm);
        let hidden = |layers: usize| {
            self.policy.mean.layers[..layers]
                .iter()
                .map(|l| l.weight.dims()[1])
                .collect()
        };
        meta.networks
            .insert("policy".into(), hidden(self.policy.mean.layers.len() - 1));
        meta.networks
            .insert("critic".into(), self.config.critic_hidden.clone());
        meta.iteration = self.iteration as u64;
        meta.seed = self.config.seed;
        let (schedule, adam) = match &self.guidance {
            Some(g) => (
                Some(g.schedule.clone()),
                match &g.signal {
                    GuidanceSignal::Discriminator(d) => Some(d.optim.clone()),
                    GuidanceSignal::Behaviour(_) => None,
                },
            ),
            None => (None, None),
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
                adam,
            })
        } else {
            None
        };
        meta.extra = serde_json::json!({
            "samples": self.samples,
            "config": self.config,
            "resume": resume,
        });
        let mut ckpt = Checkpoint::new(meta);
        ckpt.insert("policy", &self.policy);
        ckpt.insert("critic", &self.critic.nets);
        if let Some(g) = &self.guidance {
            ckpt.insert("guidance_critic", &g.critic.nets);
            if let GuidanceSignal::Discriminator(d) = &g.signal {
                ckpt.insert("discriminator", &d.disc);
            }
        }
        ckpt.save(path)?;
        Ok(())
    }
}

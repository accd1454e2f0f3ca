//! [`LearnerState`]: everything a run has learned and counted after an iteration, as one
//! value on the CPU. A checkpoint is this value written out ([`LearnerState::save`]);
//! `--resume` reads it back and checks it ([`LearnerState::load`]) before the run goes
//! on. A new run starts from [`LearnerState::initial`], so new and resumed runs are
//! built the same way.
//!
//! The networks are written as named tensors (what `logo eval` reads), the rest
//! ([`Learned`]) as JSON in the metadata's `resume` field with a format version. Older
//! layouts are read by one function, [`migrate`]: a new field of the state is a field of
//! [`Learned`] (its value in [`LearnerState::initial`]) and a step there, nothing else.

use std::path::Path;

use burn::module::Module;
use burn::tensor::backend::Backend;
use logo_envs::{ResetPoint, RngState};
use logo_nn::flat::params_to_vec;
use logo_nn::{
    Checkpoint, CheckpointMeta, Cpu, Discriminator, DiscriminatorConfig, GaussianPolicy,
    ObservationNorm, ObservationStats, PolicyConfig, ValueNet, load_reference_policy,
};

use crate::adam::Adam;
use crate::config::{GuidanceConfig, TrainConfig};
use crate::critic::CriticConfig;
use crate::delta_schedule::DeltaSchedule;
use crate::error::{At, Invalid, TrainError};
use crate::policy_update::UpdateState;

/// Everything a run has learned and counted: see the module's doc.
pub struct LearnerState {
    pub networks: Networks,
    /// The rest of what it has learned and counted (the checkpoint's `resume` field).
    pub learned: Learned,
    /// Which engine ran which iterations.
    pub engines: Vec<EngineSpan>,
}

/// The learner's state besides its networks, as a checkpoint holds it in format
/// [`Learned::FORMAT`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Learned {
    /// Iterations done, and env steps collected in them.
    pub iteration: usize,
    pub samples: usize,
    /// The improvement step's optimiser state (Adam moments, PPO-Penalty's β).
    pub improvement: UpdateState,
    /// Each env-critic net's Adam moments (the `adam` fit).
    pub critic_adam: Vec<Adam>,
    pub guidance: Option<GuidanceState>,
    /// The sampler's generator and every env copy's reset point before the next batch;
    /// None in a new run's state (the seed starts them) and where a run's batches carry
    /// episodes over, which cannot be restored (such a checkpoint cannot be resumed).
    pub sampler: Option<SamplerState>,
}

/// What LOGO's guidance has learned besides its networks.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GuidanceState {
    /// δ_k and how it moves.
    pub schedule: DeltaSchedule,
    /// The guidance step's optimiser state.
    pub update: UpdateState,
    pub critic_adam: Vec<Adam>,
    /// The discriminator's Adam (None with a known behaviour policy).
    pub discriminator_adam: Option<Adam>,
}

/// The networks as burn modules on the CPU: their definitions (the reference's
/// initialisation) and the form checkpoints are written and read in, whatever the engine.
/// A checkpoint names each tensor by its path here (`policy.mean.layers.0.weight`,
/// `critic.1.net.layers.2.bias`).
#[derive(Module, Debug)]
pub struct Networks<B: Backend = Cpu> {
    pub policy: GaussianPolicy<B>,
    pub critic: Vec<ValueNet<B>>,
    pub guidance_critic: Option<Vec<ValueNet<B>>>,
    pub discriminator: Option<Discriminator<B>>,
    /// `normalise_observations`: the observation statistics (not trained: counted).
    pub observation_norm: Option<ObservationNorm<B>>,
}

/// The sampler's generator and every env copy's reset point between two batches.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SamplerState {
    pub rng: RngState,
    pub env_points: Vec<ResetPoint>,
}

/// From `from_iteration` on (until the next span), the run trained on `engine`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EngineSpan {
    pub from_iteration: usize,
    pub engine: String,
}

/// The metadata's `resume` field as written: [`Learned`] with its format's number.
#[derive(serde::Serialize, serde::Deserialize)]
struct Versioned<L> {
    format: u64,
    #[serde(flatten)]
    learned: L,
}

/// Format 1, which every checkpoint before the format got its number has (no `format`
/// key; `null` where the sampler could not be restored).
#[derive(serde::Deserialize)]
struct FormatOne {
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

impl LearnerState {
    /// A new run's state: every network initialised from the seed (or the policy from
    /// `init_policy`), optimisers fresh, δ_k at δ_0, nothing counted.
    pub fn initial(
        config: &TrainConfig,
        obs_dim: usize,
        act_dim: usize,
    ) -> Result<Self, TrainError> {
        Ok(Self {
            networks: Networks::init(config, obs_dim, act_dim)?,
            learned: Learned {
                iteration: 0,
                samples: 0,
                improvement: UpdateState::default(),
                critic_adam: vec![Adam::default(); config.critic.num_nets()],
                guidance: config.guidance.as_ref().map(|g| GuidanceState {
                    schedule: g.schedule(),
                    update: UpdateState::default(),
                    critic_adam: vec![
                        Adam::default();
                        config.guidance_critic().map_or(0, |c| c.num_nets())
                    ],
                    discriminator_adam: g.demos.is_some().then(Adam::default),
                }),
                sampler: None,
            },
            engines: Vec::new(),
        })
    }

    /// The state in `path`'s checkpoint and the config it runs under (with `iterations`
    /// if given), checked against each other and against the networks it holds.
    pub fn load(path: &Path, iterations: Option<usize>) -> Result<(TrainConfig, Self), TrainError> {
        let ckpt = Checkpoint::load(path)?;
        let (config, learned) = read_record(path, &ckpt, iterations).at(path.display())?;
        let meta = &ckpt.meta;
        let networks = ckpt.apply("", Networks::init(&config, meta.obs_dim, meta.act_dim)?)?;
        let state = Self {
            networks,
            learned,
            engines: engine_history(meta).at(path.display())?,
        };
        state.check_optimisers().at(path.display())?;
        if let Some(norm) = &state.networks.observation_norm {
            ObservationStats::from_module(norm)
                .check()
                .at(path.display())?;
        }
        Ok((config, state))
    }

    /// Writes the state as a checkpoint of a run of `config` on `env_id` (atomically).
    pub fn save(
        &self,
        path: &Path,
        config: &TrainConfig,
        env_id: &str,
        engine: &str,
    ) -> Result<(), TrainError> {
        let policy = &self.networks.policy;
        let (obs_dim, act_dim) = (policy.obs_dim(), policy.act_dim());
        let mut meta = CheckpointMeta::new(env_id, obs_dim, act_dim, &algorithm(config));
        let dims = policy.mean.dims();
        meta.networks
            .insert("policy".into(), dims[1..dims.len() - 1].to_vec());
        meta.networks
            .insert("critic".into(), config.critic.hidden.clone());
        meta.iteration = self.learned.iteration as u64;
        meta.seed = config.seed;
        meta.extra = serde_json::json!({
            "samples": self.learned.samples,
            "engine": engine,
            "engines": self.engines,
            "config": config,
            "resume": Versioned { format: Learned::FORMAT, learned: &self.learned },
        });
        let mut ckpt = Checkpoint::new(meta);
        ckpt.insert("", &self.networks);
        ckpt.save(path)?;
        Ok(())
    }

    /// Every optimiser state must fit the network it steps (a damaged or hand-edited
    /// checkpoint can get that wrong).
    fn check_optimisers(&self) -> Result<(), TrainError> {
        let (networks, learned) = (&self.networks, &self.learned);
        let policy_len = networks.policy.num_params();
        let mut adams = vec![("improvement.adam", &learned.improvement.adam, policy_len)];
        let mut sets = vec![("critic_adam", &learned.critic_adam, &networks.critic)];
        if let (Some(g), Some(nets)) = (&learned.guidance, &networks.guidance_critic) {
            sets.push(("guidance_critic_adam", &g.critic_adam, nets));
        }
        for (name, set, nets) in sets {
            if set.len() != nets.len() {
                return Err(TrainError::Resume(format!(
                    "resume state {name}: {} Adam states for {} critics",
                    set.len(),
                    nets.len()
                )));
            }
            for (adam, net) in set.iter().zip(nets) {
                adams.push((name, adam, net.num_params()));
            }
        }
        if let Some(g) = &learned.guidance {
            adams.push(("guidance.adam", &g.update.adam, policy_len));
            if let (Some(adam), Some(d)) = (&g.discriminator_adam, &networks.discriminator) {
                adams.push(("discriminator_adam", adam, d.net.num_params()));
            }
        }
        for (name, adam, len) in adams {
            adam.check(len).at(format!("resume state {name}"))?;
        }
        Ok(())
    }
}

/// The method a checkpoint's metadata names: the config's (`method`) where its keys
/// agree on the guidance, else (a run older than the name, a stored config edited since)
/// the one its keys make.
fn algorithm(config: &TrainConfig) -> String {
    match config.method.as_deref().and_then(crate::methods::method) {
        Some(m) if m.guided == config.guided() => m.name.to_string(),
        _ => config.identify().to_string(),
    }
}

/// The config (with `iterations` if given) and the learner's state besides its networks
/// in `ckpt`, checked against each other and against the networks the metadata lists.
fn read_record(
    path: &Path,
    ckpt: &Checkpoint,
    iterations: Option<usize>,
) -> Result<(TrainConfig, Learned), TrainError> {
    let extra = &ckpt.meta.extra;
    if ckpt.is_policy_alone() {
        return Err(TrainError::Resume(
            "is a policy alone (`logo export`), with no learner state to go on from: resume \
             the run's own checkpoint.safetensors (a page that extends a kept run names the \
             commit that holds it)"
                .into(),
        ));
    }
    let mut config: TrainConfig = serde_json::from_value(extra["config"].clone())
        .map_err(|e| TrainError::Resume(format!("metadata config: {e}")))?;
    let learned = migrate(&extra["resume"], &config)?;
    if learned.sampler.is_none() {
        return Err(TrainError::Resume(NO_RESUME_STATE.into()));
    }
    // A run copied from another clone names files by that clone's absolute paths: they
    // are looked for under the working folder, then under each folder above the run's
    // (a run kept inside a clone finds that clone's data/).
    let above_run = path.parent().into_iter().flat_map(Path::ancestors);
    let roots = std::env::current_dir()
        .into_iter()
        .chain(above_run.map(Path::to_path_buf));
    for root in roots {
        for note in config.relocate_missing_paths(&root) {
            eprintln!("note: {note}");
        }
    }
    if let Some(n) = iterations {
        config.iterations = n;
    }
    config.validate().at("metadata config")?;
    check_config_against_meta(&ckpt.meta, &config, &learned)?;
    learned.check(&config)?;
    Ok((config, learned))
}

/// A checkpoint without the sampler's state (format 1 wrote `null` for it).
const NO_RESUME_STATE: &str = "holds no resume state (runs with rollout = \"steps\" continue \
     episodes across iterations and cannot be resumed exactly; older checkpoints lack it)";

/// A checkpoint's `resume` field, in any format it has had, as today's [`Learned`].
/// Where the format moves on, the step from the last one goes here.
fn migrate(resume: &serde_json::Value, config: &TrainConfig) -> Result<Learned, TrainError> {
    let bad = |e: serde_json::Error| TrainError::Resume(format!("metadata resume state: {e}"));
    match resume.get("format").map(serde_json::Value::as_u64) {
        None if resume.is_null() => Err(TrainError::Resume(NO_RESUME_STATE.into())),
        // Format 1 was written without its number; one that names it reads the same.
        None | Some(Some(1)) => {
            let one: FormatOne = serde_json::from_value(resume.clone()).map_err(bad)?;
            Ok(one.into_learned(config))
        }
        Some(Some(Learned::FORMAT)) => {
            let read: Versioned<Learned> = serde_json::from_value(resume.clone()).map_err(bad)?;
            Ok(read.learned)
        }
        Some(Some(newer)) if newer > Learned::FORMAT => Err(TrainError::Resume(format!(
            "metadata resume state: format {newer} is newer than this logo-rl reads (1 to {}): \
             resume it with the logo-rl that wrote it, or a later one",
            Learned::FORMAT
        ))),
        Some(_) => Err(TrainError::Resume(format!(
            "metadata resume state: format {} is not a format this logo-rl knows (1 to {})",
            resume["format"],
            Learned::FORMAT
        ))),
    }
}

impl FormatOne {
    fn into_learned(self, config: &TrainConfig) -> Learned {
        Learned {
            iteration: self.iteration,
            samples: self.samples,
            improvement: self.improvement,
            critic_adam: self.critic_adam,
            // (A schedule without `[guidance]` in the config has nothing to drive.)
            guidance: self
                .schedule
                .filter(|_| config.guidance.is_some())
                .map(|schedule| GuidanceState {
                    schedule,
                    update: self.guidance.unwrap_or_default(),
                    critic_adam: self.guidance_critic_adam.unwrap_or_default(),
                    discriminator_adam: self.discriminator_adam,
                }),
            sampler: Some(SamplerState {
                rng: self.sampler_rng,
                env_points: self.env_points,
            }),
        }
    }
}

/// The stored config must describe the stored networks (it sizes them before the
/// tensors are read), the algorithm that wrote them and the iteration reached.
fn check_config_against_meta(
    meta: &CheckpointMeta,
    config: &TrainConfig,
    learned: &Learned,
) -> Result<(), TrainError> {
    // A run older than the methods' names recorded the name they had then.
    let recorded = match config.method {
        None if meta.algorithm == crate::algorithms::name_before_the_table(config) => {
            meta.algorithm.clone()
        }
        _ => algorithm(config),
    };
    for (what, found, expected) in [
        ("env", meta.env_id.clone(), config.env.env_id()?),
        ("algorithm", meta.algorithm.clone(), recorded),
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
            return Err(TrainError::Resume(format!(
                "the metadata's {what} is {found}, its config says {expected}"
            )));
        }
    }
    if meta.iteration != learned.iteration as u64 {
        return Err(TrainError::Resume(format!(
            "the metadata's iteration is {}, its resume state says {}",
            meta.iteration, learned.iteration
        )));
    }
    Ok(())
}

impl Learned {
    /// The format checkpoints are written in; [`migrate`] reads it and every older one.
    pub const FORMAT: u64 = 2;

    /// Values a damaged or hand-edited checkpoint can get wrong, checked against the
    /// config they will run under.
    fn check(&self, config: &TrainConfig) -> Result<(), TrainError> {
        if self.samples < self.iteration {
            return Err(TrainError::Resume(format!(
                "resume state: {} samples in {} iterations (each collects at least one)",
                self.samples, self.iteration
            )));
        }
        let refused = |what: &str| Err(TrainError::Resume(format!("resume state: {what}")));
        match (&self.guidance, &config.guidance) {
            (Some(learned), Some(g)) => {
                // decay_signal reads the config's level, the schedule its own: one level.
                let (kept, wanted) = (&learned.schedule, g.schedule());
                if (kept.decay_from, kept.grow_back_to) != (wanted.decay_from, wanted.grow_back_to)
                {
                    return refused(&format!(
                        "the δ schedule's decay_from and grow-back are {:?} and {:?}, the \
                         config's {:?} and {:?}",
                        kept.decay_from, kept.grow_back_to, wanted.decay_from, wanted.grow_back_to
                    ));
                }
                learned
                    .schedule
                    .check(g.schedule().delta)
                    .at("resume state schedule")
            }
            (None, Some(_)) => refused("no δ schedule for the guidance step"),
            (Some(_), None) => refused("a guidance state, but no [guidance]"),
            (None, None) => Ok(()),
        }
    }
}

/// The engine spans recorded in a checkpoint's metadata (older checkpoints name one
/// engine, or none). A history that is there but malformed (not a list of spans, spans
/// out of order, one past the checkpoint's iteration) is an error, not a history lost.
pub fn engine_history(meta: &CheckpointMeta) -> Result<Vec<EngineSpan>, TrainError> {
    let extra = &meta.extra;
    if extra.get("engines").is_none_or(|v| v.is_null()) {
        return Ok(extra["engine"]
            .as_str()
            .map(|engine| {
                vec![EngineSpan {
                    from_iteration: 0,
                    engine: engine.to_string(),
                }]
            })
            .unwrap_or_default());
    }
    let spans: Vec<EngineSpan> = serde_json::from_value(extra["engines"].clone())
        .map_err(|e| TrainError::Resume(format!("metadata engines: {e}")))?;
    let ordered = spans.first().is_none_or(|s| s.from_iteration == 0)
        && spans
            .windows(2)
            .all(|w| w[0].from_iteration < w[1].from_iteration)
        && spans
            .iter()
            .all(|s| !s.engine.trim().is_empty() && s.from_iteration as u64 <= meta.iteration);
    if !ordered {
        return Err(TrainError::Resume(format!(
            "metadata engines: expected spans from iteration 0 on, in increasing order, none \
             past iteration {} and each naming an engine; got {}",
            meta.iteration, extra["engines"]
        )));
    }
    Ok(spans)
}

impl Networks {
    /// Every network of the run, initialised from the seed (or the policy from
    /// `init_policy`). burn draws initial weights from one process-wide generator: it is
    /// held from the seeding to the last parameter drawn, or trainers built at the same
    /// time on other threads (tests, sweeps) would interleave their draws.
    fn init(config: &TrainConfig, obs_dim: usize, act_dim: usize) -> Result<Self, TrainError> {
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
        let discriminator = match &config.guidance {
            Some(g) if g.demos.is_some() && g.step => {
                Some(discriminator_module(g, obs_dim, act_dim, &device)?)
            }
            _ => None,
        };
        let observation_norm = config
            .normalise_observations
            .then(|| ObservationStats::new(obs_dim).module(&device));
        let mut networks = Self {
            policy,
            critic,
            guidance_critic,
            discriminator,
            observation_norm,
        };
        // burn initialises parameters lazily, at their first use: draw them all now, under
        // the lock, in a fixed order (the fields').
        let _ = params_to_vec(&networks);
        // Without the guidance step (GAIL, POfD) the discriminator is drawn after the
        // rest, so that the policy and critic start as TRPO's of the same seed.
        if let Some(g) = config
            .guidance
            .as_ref()
            .filter(|g| g.demos.is_some() && !g.step)
        {
            let discriminator = discriminator_module(g, obs_dim, act_dim, &device)?;
            let _ = params_to_vec(&discriminator);
            networks.discriminator = Some(discriminator);
        }
        Ok(networks)
    }
}

type CpuDevice = burn::tensor::Device<Cpu>;

/// The policy from `init_policy` (a reference `.pt` or a logo-rl checkpoint, `logo bc`'s
/// among them; it must fit the env), or a new one of the config's sizes.
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
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_lowercase);
    let policy = match extension.as_deref() {
        Some("pt" | "pth") => load_reference_policy::<Cpu>(path, device)?,
        _ => checkpoint_policy(path, device)?,
    };
    if (policy.obs_dim(), policy.act_dim()) != (obs_dim, act_dim) {
        return Err(Invalid::Value(format!(
            "init_policy {}: obs/action dims ({}, {}) do not match {} ({obs_dim}, {act_dim})",
            path.display(),
            policy.obs_dim(),
            policy.act_dim(),
            config.env,
        ))
        .into());
    }
    Ok(policy)
}

/// The policy of a logo-rl checkpoint, for `init_policy`: one that acts on raw
/// observations (a run's standardised ones would need its statistics, which a new run
/// does not take over).
fn checkpoint_policy(path: &Path, device: &CpuDevice) -> Result<GaussianPolicy<Cpu>, TrainError> {
    let ckpt = Checkpoint::load(path)?;
    if ckpt.tensor("observation_norm.mean").is_some() {
        return Err(Invalid::Value(format!(
            "init_policy {}: this policy acts on standardised observations (its run set \
             normalise_observations), which a new run does not take over; give a policy of \
             raw observations",
            path.display()
        ))
        .into());
    }
    let hidden = ckpt.meta.networks.get("policy").ok_or_else(|| {
        Invalid::Value(format!(
            "init_policy {}: the checkpoint holds no policy network",
            path.display()
        ))
    })?;
    let config = PolicyConfig {
        obs_dim: ckpt.meta.obs_dim,
        act_dim: ckpt.meta.act_dim,
        hidden: hidden.clone(),
        log_std_init: 0.0,
    };
    Ok(ckpt.apply("policy", config.init::<Cpu>(device))?)
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
        let refused = format!("guidance.observe must be in 1..={obs_dim}, got {observe}");
        return Err(Invalid::Value(refused).into());
    }
    Ok(DiscriminatorConfig {
        observe,
        act_dim,
        hidden: g.discriminator_hidden.clone(),
        init: g.discriminator_init,
    }
    .init(device))
}

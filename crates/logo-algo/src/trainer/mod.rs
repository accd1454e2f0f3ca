//! Training a run: [`Trainer::step`] is one iteration of LOGO (Algorithm 1), written
//! once for every engine and every configured variant, in `iteration.rs`.
//!
//! A trainer is three parts and the config:
//! - the **learner** (`learner.rs`): every network and optimiser state, δ_k, the counts,
//!   on the engine. Taken off the engine it is a [`LearnerState`] (`learner_state.rs`),
//!   and a checkpoint is that value: a new run starts from [`LearnerState::initial`], a
//!   resumed one from [`LearnerState::load`], and both are made into a trainer the same
//!   way ([`Trainer::new`], [`Trainer::resume`]);
//! - the **resources** (`resources.rs`): the engine, the worker threads, the env copies
//!   and their sampler, the evaluation env;
//! - the **recorder** (`recorder.rs`; an iteration's row and checkpoints in `record.rs`):
//!   the run folder, metrics.csv, TensorBoard, and when checkpoints are due.
//!
//! Which steps of an iteration run beside which is the [`Schedule`]'s business
//! (`schedule.rs`); the arithmetic is the same under either schedule.

mod iteration;
mod learner;
mod learner_state;
mod record;
mod recorder;
mod resources;
mod schedule;

use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

use logo_data::Demonstrations;
use logo_envs::{EnvFactory, EnvSpec};
use logo_nn::{ActingPolicy, Engine, ObservationStats, Policy};

use crate::bc::{self, BcReport, InitKind};
use crate::config::TrainConfig;
use crate::dapg::DemonstrationRows;
pub use crate::error::TrainError;
use crate::error::{At, Invalid};
use crate::metrics::IterationMetrics;
use crate::run_dir::RunDir;
use learner::{Learner, check_dims};
pub use learner_state::{EngineSpan, Learned, LearnerState, Networks, engine_history};
use recorder::Recorder;
use resources::{Collected, Resources};
pub use schedule::Schedule;

pub struct Trainer<E: Engine> {
    pub config: TrainConfig,
    learner: Learner<E>,
    resources: Resources<E>,
    recorder: Recorder,
    /// Batch k+1, collected with π_{k+1} at the end of iteration k (under either
    /// schedule; the pipelined one beside the critic fits).
    next_batch: Option<Collected>,
    behaviour_cloning: Option<BcReport>,
}

impl<E: Engine> Trainer<E> {
    /// A new run on `engine` writing into `out_dir` (metrics.csv is started afresh).
    pub fn new(engine: E, config: TrainConfig, out_dir: &Path) -> Result<Self, TrainError> {
        config.validate().at("config")?;
        let run = RunDir::create(out_dir, &config)?;
        let factory = config.env.factory()?;
        let spec = factory.spec();
        let mut state = LearnerState::initial(&config, spec.obs_dim, spec.act_dim)?;
        let mut demos = DemonstrationSets::new(spec);
        let cloned = behaviour_clone(&engine, &config, &mut demos, &mut state.networks)?;
        if let Some(report) = &cloned {
            let path = run.path().join("bc.json");
            std::fs::write(&path, serde_json::to_string_pretty(report)?)
                .map_err(|e| TrainError::io(&path, e))?;
        }
        let mut trainer = Self::assemble(engine, config, run, &factory, state, &mut demos)?;
        trainer.behaviour_cloning = cloned;
        Ok(trainer)
    }

    /// What `[init] kind = "bc"` did before the first iteration (None on a resumed run).
    pub fn behaviour_cloning(&self) -> Option<&BcReport> {
        self.behaviour_cloning.as_ref()
    }

    /// Continues the run in `out_dir` from its checkpoint: load the state, check it, go
    /// on. Rows of metrics.csv after the checkpoint (a killed run's last iterations) are
    /// dropped and redone; the run then ends with the same checkpoint as one never
    /// interrupted. `iterations` extends or shortens the run.
    pub fn resume(
        engine: E,
        out_dir: &Path,
        iterations: Option<usize>,
    ) -> Result<Self, TrainError> {
        let run = RunDir::open(out_dir)?;
        run.remove_stale_temporaries()?;
        let (config, state) = LearnerState::load(&run.checkpoint_path(), iterations)?;
        let (iteration, samples) = (state.learned.iteration, state.learned.samples);
        let factory = config.env.factory()?;
        let mut demos = DemonstrationSets::new(factory.spec());
        let mut trainer = Self::assemble(engine, config, run, &factory, state, &mut demos)?;
        // metrics.csv, the clock and the best policy as of the checkpoint.
        let recorder = &mut trainer.recorder;
        let checkpoint = recorder.checkpoint_path();
        recorder
            .resume(iteration, samples)
            .at(checkpoint.display())?;
        Ok(trainer)
    }

    /// The trainer of a run of `config` from `state`, on the envs `factory` makes, with
    /// the demonstrations `demos` reads (the discriminator's, DAPG's rows).
    fn assemble(
        engine: E,
        config: TrainConfig,
        run: RunDir,
        factory: &EnvFactory,
        state: LearnerState,
        demos: &mut DemonstrationSets,
    ) -> Result<Self, TrainError> {
        let spec = factory.spec();
        let checkpoint = run.checkpoint_path();
        check_dims(&state.networks, spec.obs_dim, spec.act_dim).at(checkpoint.display())?;
        let discriminator_demos = match config.guidance.as_ref().and_then(|g| g.demos.as_ref()) {
            Some(path) => Some(demos.read(path, "guidance.demos")?),
            None => None,
        };
        let rows = match config.demonstration_rows_demos() {
            Some((key, path)) => Some(DemonstrationRows::of(&*demos.read(path, key)?, path, key)?),
            None => None,
        };
        let learner =
            Learner::from_state(&engine, &config, &state, discriminator_demos.as_deref())?;
        let mut resources = Resources::build(engine, &config, factory, state.networks, rows)?;
        if let Some(sampler) = &state.learned.sampler {
            resources
                .collector
                .restore(sampler)
                .at(checkpoint.display())?;
        }
        Ok(Self {
            config,
            learner,
            resources,
            recorder: Recorder::new(run),
            next_batch: None,
            behaviour_cloning: None,
        })
    }

    pub fn iteration(&self) -> usize {
        self.learner.iteration
    }

    pub fn done(&self) -> bool {
        self.learner.iteration >= self.config.iterations
    }

    pub fn engine(&self) -> &E {
        &self.resources.engine
    }

    /// The policy as it stands, for acting (through the observation statistics, where
    /// the run standardises observations).
    pub fn acting(&self) -> ActingPolicy {
        self.learner.acting(&self.resources.engine)
    }

    /// Lays the iterations over the threads by `schedule` (the numbers do not change).
    pub fn set_schedule(&mut self, schedule: Schedule) {
        self.resources.schedule = schedule;
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
        let k = self.learner.iteration;
        let pool = Arc::clone(&self.resources.pool);
        pool.install(|| self.iterate())
            .map_err(|e| e.at(format!("iteration {k}")))
    }

    /// The run's state after its latest iteration: what a checkpoint holds.
    fn state(&self) -> Result<LearnerState, TrainError> {
        let Resources {
            engine,
            collector,
            shapes,
            ..
        } = &self.resources;
        // Before the next batch, which the iteration has already collected.
        let sampler = match &self.next_batch {
            Some(next) => next.before.clone(),
            None => collector.state()?,
        };
        Ok(self.learner.state(engine, shapes, sampler))
    }

    /// Writes the run's state after its latest iteration to `path` (atomically).
    pub fn save_checkpoint(&self, path: &Path) -> Result<(), TrainError> {
        let engine = self.resources.engine.describe();
        let env_id = &self.resources.collector.venv.spec().id;
        self.state()?.save(path, &self.config, env_id, &engine)
    }

    /// `e`, saying what the run kept (see [`Recorder::stopped`]).
    fn stopped(&self, e: TrainError) -> TrainError {
        self.recorder.stopped(e)
    }
}

/// `[init] kind = "bc"`: the newly initialised policy cloned on the demonstrations. Where
/// the run standardises observations, the statistics start from the demonstrations'
/// observations and the clone sees them through those.
fn behaviour_clone<E: Engine>(
    engine: &E,
    config: &TrainConfig,
    demos: &mut DemonstrationSets,
    networks: &mut Networks,
) -> Result<Option<BcReport>, TrainError> {
    if config.init.kind != InitKind::Bc {
        return Ok(None);
    }
    let key = match config.init.demos {
        Some(_) => "init.demos",
        None => "guidance.demos",
    };
    let path = config
        .bc_demos()
        .ok_or_else(|| Invalid::Value(format!("{key} is not set")))?;
    let demos = demos.read(path, key)?;
    let mut obs = demos.obs.clone();
    if let Some(norm) = networks.observation_norm.as_mut() {
        let mut stats = ObservationStats::from_module(norm);
        stats.update(&obs);
        stats.normalise(&mut obs);
        *norm = stats.module(&Default::default());
    }
    let policy = Policy::from_module(engine, &networks.policy);
    let pairs = (&obs[..], &demos.actions[..]);
    let (fitted, report) =
        bc::clone_policy(engine, &policy, pairs, &config.init, config.seed, key)?;
    networks.policy = fitted.to_module(engine, networks.policy.clone());
    Ok(Some(report))
}

/// A run's demonstration datasets, each read once, however many of the run's parts use it
/// (the clone, the discriminator, DAPG's rows), and checked against the env as it is read.
struct DemonstrationSets<'a> {
    spec: &'a EnvSpec,
    read: Vec<(PathBuf, Rc<Demonstrations>)>,
}

impl<'a> DemonstrationSets<'a> {
    fn new(spec: &'a EnvSpec) -> Self {
        Self {
            spec,
            read: Vec::new(),
        }
    }

    /// The dataset at `path`, read the first time it is asked for; `key` names the config
    /// key in an error.
    fn read(&mut self, path: &Path, key: &str) -> Result<Rc<Demonstrations>, TrainError> {
        if let Some((_, demos)) = self.read.iter().find(|(p, _)| p == path) {
            return Ok(Rc::clone(demos));
        }
        let spec = self.spec;
        let demos =
            Rc::new(Demonstrations::load(path, &spec.id, spec.obs_dim, spec.act_dim).at(key)?);
        self.read.push((path.to_path_buf(), Rc::clone(&demos)));
        Ok(demos)
    }
}

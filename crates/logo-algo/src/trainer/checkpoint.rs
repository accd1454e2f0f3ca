//! Checkpoints and `--resume`: what a checkpoint holds besides the networks, how a run
//! continues from one, and the record of which engines trained a run.

use std::path::Path;

use logo_envs::{ResetPoint, RngState};
use logo_nn::flat::params_to_vec;
use logo_nn::{Checkpoint, CheckpointMeta, Engine, Policy};

use super::state::{EngineSpan, SamplerState, Trainer};
use crate::adam::Adam;
use crate::config::TrainConfig;
use crate::critic::CriticSet;
use crate::delta_schedule::DeltaSchedule;
use crate::guidance::{Guidance, GuidanceSignal};
use crate::policy_update::UpdateState;
use crate::run_dir::{RunDir, TrainError};

/// The algorithm a checkpoint's metadata names: "logo" with a guidance step, else "trpo".
fn checkpoint_algorithm(config: &TrainConfig) -> &'static str {
    if config.guidance.is_some() {
        "logo"
    } else {
        "trpo"
    }
}

/// The engine spans recorded in a checkpoint's metadata (older checkpoints name one
/// engine, or none). A history that is there but malformed (not a list of spans, spans
/// out of order, one past the checkpoint's iteration) is an error, not a history lost.
pub fn engine_history(meta: &CheckpointMeta) -> Result<Vec<EngineSpan>, String> {
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
        .map_err(|e| format!("metadata engines: {e}"))?;
    let ordered = spans.first().is_none_or(|s| s.from_iteration == 0)
        && spans
            .windows(2)
            .all(|w| w[0].from_iteration < w[1].from_iteration)
        && spans
            .iter()
            .all(|s| !s.engine.trim().is_empty() && s.from_iteration as u64 <= meta.iteration);
    if !ordered {
        return Err(format!(
            "metadata engines: expected spans from iteration 0 on, in increasing order, none \
             past iteration {} and each naming an engine; got {}",
            meta.iteration, extra["engines"]
        ));
    }
    Ok(spans)
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

/// The config (with `iterations` if given) and the resume state of `ckpt`, checked
/// against each other and against the networks the metadata lists.
fn read_resume_state(
    ckpt: &Checkpoint,
    iterations: Option<usize>,
) -> Result<(TrainConfig, ResumeState), String> {
    let extra = &ckpt.meta.extra;
    let mut config: TrainConfig = serde_json::from_value(extra["config"].clone())
        .map_err(|e| format!("metadata config: {e}"))?;
    if extra["resume"].is_null() {
        return Err(
            "holds no resume state (runs with rollout = \"steps\" continue episodes \
             across iterations and cannot be resumed exactly; older checkpoints lack it)"
                .into(),
        );
    }
    let state: ResumeState = serde_json::from_value(extra["resume"].clone())
        .map_err(|e| format!("metadata resume state: {e}"))?;
    // A run copied from another clone names files by that clone's absolute paths.
    if let Ok(here) = std::env::current_dir() {
        for note in config.relocate_missing_paths(&here) {
            eprintln!("note: {note}");
        }
    }
    if let Some(n) = iterations {
        config.iterations = n;
    }
    config
        .validate()
        .map_err(|e| format!("metadata config: {e}"))?;
    state.check(&config)?;
    check_config_against_meta(&ckpt.meta, &config, &state)?;
    Ok((config, state))
}

/// The stored config must describe the stored networks (it sizes them before the
/// tensors are read), the algorithm that wrote them and the iteration reached.
fn check_config_against_meta(
    meta: &CheckpointMeta,
    config: &TrainConfig,
    state: &ResumeState,
) -> Result<(), String> {
    for (what, found, expected) in [
        (
            "env",
            meta.env_id.clone(),
            config.env.env_id().map_err(|e| e.to_string())?,
        ),
        (
            "algorithm",
            meta.algorithm.clone(),
            checkpoint_algorithm(config).to_string(),
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
            return Err(format!(
                "the metadata's {what} is {found}, its config says {expected}"
            ));
        }
    }
    if meta.iteration != state.iteration as u64 {
        return Err(format!(
            "the metadata's iteration is {}, its resume state says {}",
            meta.iteration, state.iteration
        ));
    }
    Ok(())
}

impl ResumeState {
    /// Values a damaged or hand-edited checkpoint can get wrong, checked against the
    /// config they will run under.
    fn check(&self, config: &TrainConfig) -> Result<(), String> {
        if self.samples < self.iteration {
            return Err(format!(
                "resume state: {} samples in {} iterations (each collects at least one)",
                self.samples, self.iteration
            ));
        }
        match (&self.schedule, &config.guidance) {
            (Some(schedule), Some(g)) => schedule
                .check(g.delta0)
                .map_err(|e| format!("resume state schedule: {e}")),
            (None, Some(_)) => Err("resume state: no δ schedule for the guidance step".into()),
            _ => Ok(()),
        }
    }
}

impl<E: Engine> Trainer<E> {
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
        let bad = |what: String| -> TrainError { format!("{}: {what}", path.display()).into() };
        let (config, state) = read_resume_state(&ckpt, iterations).map_err(bad)?;
        let mut trainer = Self::build(engine, config, run)?;
        trainer.restore_networks(&ckpt, &state)?;
        trainer.check_optimiser_states().map_err(bad)?;
        trainer.restore_progress(&ckpt, &state).map_err(bad)?;
        Ok(trainer)
    }

    /// Every network and optimiser state of `ckpt`.
    fn restore_networks(
        &mut self,
        ckpt: &Checkpoint,
        state: &ResumeState,
    ) -> Result<(), TrainError> {
        let engine = &self.engine;
        self.modules.policy = ckpt.apply("policy", self.modules.policy.clone())?;
        self.policy = Policy::from_module(engine, &self.modules.policy);
        self.modules.critic = ckpt.apply("critic", self.modules.critic.clone())?;
        self.critics.env = CriticSet::new(engine, &self.config.critic, &self.modules.critic);
        self.critics.env.adam = state.critic_adam.clone();
        self.improvement = state.improvement.clone();
        let Some(g) = self.guidance.as_mut() else {
            return Ok(());
        };
        let modules = self
            .modules
            .guidance_critic
            .take()
            .expect("built with guidance");
        let modules = ckpt.apply("guidance_critic", modules)?;
        let config = self.config.guidance_critic().expect("guidance");
        let mut critic = CriticSet::new(engine, config, &modules);
        critic.adam = state.guidance_critic_adam.clone().unwrap_or_default();
        self.critics.guidance = Some(critic);
        self.modules.guidance_critic = Some(modules);
        g.schedule = state
            .schedule
            .clone()
            .expect("checked: guidance has a schedule");
        g.state = state.guidance.clone().unwrap_or_default();
        if let GuidanceSignal::Discriminator(d) = &mut g.signal {
            let module = self
                .modules
                .discriminator
                .take()
                .expect("built with a discriminator");
            let module = ckpt.apply("discriminator", module)?;
            d.net = engine.net(&module.net.dims(), &params_to_vec(&module.net));
            d.optim = state.discriminator_adam.clone().unwrap_or_default();
            self.modules.discriminator = Some(module);
        }
        Ok(())
    }

    /// Optimiser states must fit the networks they were saved with.
    fn check_optimiser_states(&self) -> Result<(), String> {
        let engine = &self.engine;
        let policy_len = self.policy.params(engine).len();
        let mut adams = vec![("improvement.adam", &self.improvement.adam, policy_len)];
        let sets = [Some(&self.critics.env), self.critics.guidance.as_ref()];
        for (name, set) in ["critic_adam", "guidance_critic_adam"]
            .into_iter()
            .zip(sets)
        {
            let Some(set) = set else { continue };
            if set.adam.len() != set.nets.len() {
                return Err(format!(
                    "resume state {name}: {} Adam states for {} critics",
                    set.adam.len(),
                    set.nets.len()
                ));
            }
            for (adam, net) in set.adam.iter().zip(&set.nets) {
                adams.push((name, adam, engine.params(net).len()));
            }
        }
        if let Some(g) = &self.guidance {
            adams.push(("guidance.adam", &g.state.adam, policy_len));
            if let GuidanceSignal::Discriminator(d) = &g.signal {
                adams.push(("discriminator_adam", &d.optim, engine.params(&d.net).len()));
            }
        }
        for (name, adam, len) in adams {
            adam.check(len)
                .map_err(|e| format!("resume state {name}: {e}"))?;
        }
        Ok(())
    }

    /// The sampler, the counts, the engine history and metrics.csv, as the checkpoint
    /// left them; metrics.csv must agree with the checkpoint's sample count.
    fn restore_progress(&mut self, ckpt: &Checkpoint, state: &ResumeState) -> Result<(), String> {
        self.collector.rng = state.sampler_rng.to_rng()?;
        self.collector
            .venv
            .restore_reset_points(&state.env_points)
            .map_err(|e| e.to_string())?;
        self.iteration = state.iteration;
        self.samples = state.samples;
        // A checkpoint from any engine or float type continues on this one.
        let mut engines = engine_history(&ckpt.meta)?;
        let now = self.engine.describe();
        if engines.last().map(|span| &span.engine) != Some(&now) {
            engines.push(EngineSpan {
                from_iteration: state.iteration,
                engine: now,
            });
        }
        self.engines = engines;
        // metrics.csv, the clock and the best policy as of the checkpoint.
        self.recorder.resume(state.iteration, state.samples)
    }

    /// Writes the run's state after its latest iteration to `path` (atomically).
    pub fn save_checkpoint(&self, path: &Path) -> Result<(), TrainError> {
        let engine = &self.engine;
        let spec = self.collector.venv.spec();
        let algorithm = checkpoint_algorithm(&self.config);
        let mut meta = CheckpointMeta::new(&spec.id, spec.obs_dim, spec.act_dim, algorithm);
        let dims = &self.policy.dims;
        meta.networks
            .insert("policy".into(), dims[1..dims.len() - 1].to_vec());
        meta.networks
            .insert("critic".into(), self.config.critic.hidden.clone());
        meta.iteration = self.iteration as u64;
        meta.seed = self.config.seed;
        meta.extra = serde_json::json!({
            "samples": self.samples,
            "engine": engine.describe(),
            "engines": self.engines,
            "config": self.config,
            "resume": self.resume_state()?,
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

    /// What `--resume` needs besides the networks; None where the envs cannot be restored
    /// exactly (mid-episode MuJoCo state also holds solver warm-starts: only between
    /// batches that leave every copy freshly reset can they be).
    fn resume_state(&self) -> Result<Option<ResumeState>, TrainError> {
        let Some(sampler) = self.sampler_state_after_iteration()? else {
            return Ok(None);
        };
        let guidance = self.guidance.as_ref();
        Ok(Some(ResumeState {
            iteration: self.iteration,
            samples: self.samples,
            sampler_rng: sampler.rng,
            env_points: sampler.env_points,
            schedule: guidance.map(|g| g.schedule.clone()),
            discriminator_adam: guidance.and_then(|g| match &g.signal {
                GuidanceSignal::Discriminator(d) => Some(d.optim.clone()),
                GuidanceSignal::Behaviour(_) => None,
            }),
            improvement: self.improvement.clone(),
            guidance: guidance.map(|g| g.state.clone()),
            critic_adam: self.critics.env.adam.clone(),
            guidance_critic_adam: self.critics.guidance.as_ref().map(|c| c.adam.clone()),
        }))
    }

    /// The sampler's state between this iteration and the next batch: before it, where
    /// the pipelined schedule has already collected it.
    fn sampler_state_after_iteration(&self) -> Result<Option<SamplerState>, TrainError> {
        match &self.next_batch {
            Some(next) => Ok(next.before.clone()),
            None => self.collector.state(),
        }
    }
}

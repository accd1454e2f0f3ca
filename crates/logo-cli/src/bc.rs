//! `logo bc`: behaviour cloning alone. The policy is fitted to a demonstration dataset by
//! maximum likelihood (`logo_algo::bc`), scored on the task from fresh initial states,
//! and written as a checkpoint that `logo eval`, `init_policy` and `logo_rl.load` read.
//! The evaluation is kept beside it (`policy.safetensors` → `policy.eval.json`, a run's
//! `eval.json` layout with the one policy "final"), so a study reads BC as it reads runs.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use burn::tensor::backend::Backend as _;
use clap::Args;
use logo_algo::bc::{self, BcReport, InitConfig};
use logo_algo::episode::SuccessRule;
use logo_algo::{Invalid, TrainConfig};
use logo_data::Demonstrations;
use logo_envs::EnvConfig;
use logo_nn::{Checkpoint, CheckpointMeta, Cpu, Engine, Policy, PolicyConfig};
use serde_json::{Value, json};

use crate::final_eval;
use logo_engine::{EngineArgs, WithEngine};

#[derive(Args)]
pub struct BcArgs {
    /// Take the env, the demonstrations (`[init] demos`, else `[guidance] demos`), the
    /// policy's sizes, the seed and the `[init]` settings from a `logo train` config.
    #[arg(long)]
    config: Option<PathBuf>,
    /// The task the policy acts in (an env id); overrides the config's.
    #[arg(long, required_unless_present = "config")]
    env: Option<String>,
    /// Demonstrations: a Minari dataset folder or a LOGO `.npy`; overrides the config's.
    #[arg(long, required_unless_present = "config")]
    demos: Option<PathBuf>,
    /// Where the checkpoint goes (default: runs/bc-<env>-seed<seed>/policy.safetensors).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Seeds the policy's initialisation and the minibatch order.
    #[arg(long)]
    seed: Option<u64>,
    /// Passes over the demonstrations (default 100).
    #[arg(long)]
    epochs: Option<usize>,
    /// Pairs per Adam step (default 64).
    #[arg(long)]
    minibatch: Option<usize>,
    /// Adam's step size (default 1e-3).
    #[arg(long)]
    learning_rate: Option<f64>,
    /// Fit the mean alone; log σ stays at its initial value.
    #[arg(long)]
    fixed_std: bool,
    /// Hidden sizes of the mean network, e.g. 128,128 (default: the config's, else
    /// 128,128).
    #[arg(long, value_delimiter = ',')]
    hidden: Option<Vec<usize>>,
    /// Episodes of the evaluation after the fit.
    #[arg(long, default_value_t = final_eval::EPISODES)]
    episodes: usize,
    /// Which evaluation episodes reached the goal: task (a sparse kind's goal, an env's
    /// own success), terminated (a task that stops at its goal) or none. Overrides the
    /// config's `success` (default: task).
    #[arg(long)]
    success: Option<SuccessRule>,
    #[command(flatten)]
    engine: EngineArgs,
}

/// One behaviour-cloning job, however it was asked for (`logo bc`, `logo_rl.bc`).
#[derive(Debug, Clone)]
pub struct BcJob {
    pub env: EnvConfig,
    pub demos: PathBuf,
    pub out: PathBuf,
    pub seed: u64,
    pub hidden: Vec<usize>,
    pub log_std_init: f64,
    pub fit: InitConfig,
    pub success: SuccessRule,
    pub episodes: usize,
}

/// What a job did: the fit, and the evaluation of the fitted policy.
pub struct BcOutcome {
    pub report: BcReport,
    pub evaluation: Value,
    pub checkpoint: PathBuf,
    /// Where the evaluation was written (`evaluation_path`).
    pub evaluation_file: PathBuf,
    pub engine: String,
}

impl BcJob {
    /// A job from the command line: the config's values (if one is given), then the flags.
    pub fn from_args(args: &BcArgs) -> Result<Self> {
        let config = args.config.as_deref().map(TrainConfig::load).transpose()?;
        let env = match (&args.env, &config) {
            (Some(id), _) => EnvConfig::named(id),
            (None, Some(c)) => c.env.clone(),
            (None, None) => anyhow::bail!("--env is required without --config"),
        };
        let demos = match (&args.demos, &config) {
            (Some(path), _) => path.clone(),
            (None, Some(c)) => c.bc_demos().map(Path::to_path_buf).with_context(|| {
                format!(
                    "{}: no demonstrations: set [init] demos or [guidance] demos, or give --demos",
                    args.config.as_ref().expect("a config").display()
                )
            })?,
            (None, None) => anyhow::bail!("--demos is required without --config"),
        };
        let mut fit = config.as_ref().map(|c| c.init.clone()).unwrap_or_default();
        fit.epochs = args.epochs.unwrap_or(fit.epochs);
        fit.minibatch = args.minibatch.unwrap_or(fit.minibatch);
        fit.learning_rate = args.learning_rate.unwrap_or(fit.learning_rate);
        fit.learn_std &= !args.fixed_std;
        // The keys named as this command's flags.
        fit.validate()
            .map_err(|e| Invalid::Value(e.message().replace("init.", "--").replace('_', "-")))?;
        anyhow::ensure!(args.episodes > 0, "--episodes must be at least 1");
        let seed = args.seed.or(config.as_ref().map(|c| c.seed)).unwrap_or(0);
        let hidden = match (&args.hidden, &config) {
            (Some(h), _) => h.clone(),
            (None, Some(c)) => c.policy_hidden.clone(),
            (None, None) => PolicyConfig::new(1, 1).hidden,
        };
        logo_algo::validate::check_widths("--hidden", &hidden)?;
        let env_id = env.env_id()?;
        let out = args.out.clone().unwrap_or_else(|| {
            PathBuf::from(format!("runs/bc-{env_id}-seed{seed}/policy.safetensors"))
        });
        Ok(Self {
            env,
            demos,
            out,
            seed,
            hidden,
            log_std_init: config.as_ref().map_or(0.0, |c| c.log_std_init),
            fit,
            success: args
                .success
                .or(config.as_ref().map(|c| c.success))
                .unwrap_or_default(),
            episodes: args.episodes,
        })
    }
}

pub fn run(args: &BcArgs) -> Result<()> {
    let job = BcJob::from_args(args)?;
    let outcome = args.engine.with(Cloning(&job))?;
    for line in outcome_lines(&job, &outcome) {
        println!("{line}");
    }
    Ok(())
}

/// What `logo bc` prints: the fit, the evaluation, the checkpoint.
pub fn outcome_lines(job: &BcJob, outcome: &BcOutcome) -> Vec<String> {
    let r = &outcome.report;
    let summary = &outcome.evaluation["mean_action"]["summary"];
    let number = |key: &str| summary[key].as_f64().unwrap_or(f64::NAN);
    let mut lines = vec![
        format!(
            "behaviour cloning on {} pairs of {} ({}): −log π(a|s) {:.3} → {:.3} in {} Adam steps",
            r.pairs,
            job.demos.display(),
            outcome.engine,
            r.loss_before,
            r.loss_after,
            r.steps
        ),
        format!(
            "evaluation, {} episodes of {} from fresh initial states: return {:.1}, dense return {:.1}, length {:.0}",
            job.episodes,
            job.env,
            number("return"),
            number("dense_return"),
            number("length"),
        ),
    ];
    lines.extend(final_eval::reached_line(summary));
    lines.push(format!("policy: {}", outcome.checkpoint.display()));
    lines.push(format!("evaluation: {}", outcome.evaluation_file.display()));
    lines
}

/// Where a BC checkpoint's evaluation goes: beside it, named after it (`policy.safetensors`
/// → `policy.eval.json`), so that it never overwrites a run folder's own `eval.json`.
pub fn evaluation_path(checkpoint: &Path) -> PathBuf {
    let stem = checkpoint
        .file_stem()
        .map_or("policy".into(), |s| s.to_string_lossy());
    checkpoint.with_file_name(format!("{stem}.eval.json"))
}

/// The job on the chosen engine.
pub struct Cloning<'a>(pub &'a BcJob);

impl WithEngine for Cloning<'_> {
    type Output = BcOutcome;
    fn run<E: Engine>(self, engine: E) -> Result<BcOutcome> {
        clone_on(&engine, self.0)
    }
}

/// Runs `job` on `engine`: fit, checkpoint, evaluation.
pub fn clone_on<E: Engine>(engine: &E, job: &BcJob) -> Result<BcOutcome> {
    let factory = job.env.factory()?;
    let spec = factory.spec().clone();
    let demos = Demonstrations::load(&job.demos, &spec.id, spec.obs_dim, spec.act_dim)
        .with_context(|| format!("demonstrations {}", job.demos.display()))?;
    let device = Default::default();
    let module = {
        Cpu::seed(&device, job.seed);
        PolicyConfig {
            obs_dim: spec.obs_dim,
            act_dim: spec.act_dim,
            hidden: job.hidden.clone(),
            log_std_init: job.log_std_init,
        }
        .init::<Cpu>(&device)
    };
    let policy = Policy::from_module(engine, &module);
    let pairs = (&demos.obs[..], &demos.actions[..]);
    let what = job.demos.display().to_string();
    let (fitted, report) = bc::clone_policy(engine, &policy, pairs, &job.fit, job.seed, &what)?;
    let module = fitted.to_module(engine, module);
    let mut meta = CheckpointMeta::new(&spec.id, spec.obs_dim, spec.act_dim, "bc");
    meta.seed = job.seed;
    meta.networks.insert("policy".into(), job.hidden.clone());
    meta.extra = json!({
        "engine": engine.describe(),
        "bc": report,
        "demos": job.demos.display().to_string(),
        "config": { "env": job.env, "success": job.success, "init": job.fit },
    });
    let mut checkpoint = Checkpoint::new(meta);
    checkpoint.insert("policy", &module);
    if let Some(dir) = job.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("{}", dir.display()))?;
    }
    checkpoint.save(&job.out)?;
    let acting = fitted.acting(engine);
    let evaluation = final_eval::report(&spec.id, &acting, job.seed, job.episodes, job.success)?;
    let evaluation_file = evaluation_path(&job.out);
    let file = job
        .out
        .file_name()
        .map(|f| f.to_string_lossy().into_owned());
    let policies = [(
        "final",
        file.as_deref().unwrap_or(""),
        0,
        evaluation.clone(),
    )];
    final_eval::write(
        &evaluation_file,
        &spec.id,
        job.seed,
        job.episodes,
        &policies,
    )?;
    Ok(BcOutcome {
        report,
        evaluation,
        checkpoint: job.out.clone(),
        evaluation_file,
        engine: engine.describe(),
    })
}

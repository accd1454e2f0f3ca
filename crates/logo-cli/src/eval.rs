//! `logo eval`: the mean-action policy of a checkpoint on the dense and the sparse env.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use logo_envs::{Env, EnvFactory, EnvOptions};
use logo_nn::{
    ActingPolicy, Checkpoint, CheckpointMeta, Cpu, Engine, GaussianPolicy, Policy, PolicyConfig,
};

use crate::engine::{EngineArgs, WithEngine};
use crate::rollout::mean_std;

#[derive(Args)]
pub struct EvalArgs {
    /// A checkpoint written by `logo train`.
    #[arg(long)]
    checkpoint: PathBuf,
    #[arg(long, default_value_t = 10)]
    episodes: usize,
    /// Env to evaluate on (default: the checkpoint's training env, dense and sparse).
    #[arg(long)]
    env: Option<String>,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// The engine the policy is loaded onto (any engine or float type loads any
    /// checkpoint); episodes act with its host copy, as training does.
    #[command(flatten)]
    engine: EngineArgs,
}

/// The checkpoint's policy, converted onto the chosen engine and copied back for acting.
struct OnEngine<'a>(&'a GaussianPolicy<Cpu>);

impl WithEngine for OnEngine<'_> {
    type Output = (ActingPolicy, String);
    fn run<E: Engine>(self, engine: E) -> Result<Self::Output> {
        let policy = Policy::from_module(&engine, self.0);
        Ok((policy.acting(&engine), engine.describe()))
    }
}

/// The policy stored in a checkpoint, and the checkpoint's metadata.
pub fn load_policy(path: &Path) -> Result<(GaussianPolicy<Cpu>, CheckpointMeta)> {
    let ckpt = Checkpoint::load(path)?;
    let meta = &ckpt.meta;
    let hidden = meta
        .networks
        .get("policy")
        .with_context(|| format!("{}: the metadata lists no policy network", path.display()))?;
    let config = PolicyConfig {
        obs_dim: meta.obs_dim,
        act_dim: meta.act_dim,
        hidden: hidden.clone(),
        log_std_init: 0.0,
    };
    let policy = ckpt.apply("policy", config.init::<Cpu>(&Default::default()))?;
    Ok((policy, ckpt.meta))
}

pub fn run(args: &EvalArgs) -> Result<()> {
    anyhow::ensure!(args.episodes > 0, "--episodes must be at least 1");
    let (policy, meta) = load_policy(&args.checkpoint)?;
    let meta = &meta;
    let (acting, engine) = args.engine.with(OnEngine(&policy))?;
    let trained_on = logo_algo::engine_history(meta)
        .iter()
        .map(|span| format!("{} from iteration {}", span.engine, span.from_iteration))
        .collect::<Vec<_>>()
        .join(", ");
    let dense_id = meta
        .env_id
        .strip_prefix("Sparse")
        .unwrap_or(&meta.env_id)
        .to_string();
    let ids = match &args.env {
        Some(id) => vec![id.clone()],
        None => vec![dense_id.clone(), format!("Sparse{dense_id}")],
    };
    println!(
        "{} ({} iteration {}, seed {}; trained on {}): mean action on {engine}, {} episodes",
        args.checkpoint.display(),
        meta.algorithm,
        meta.iteration,
        meta.seed,
        if trained_on.is_empty() {
            "an unrecorded engine"
        } else {
            &trained_on
        },
        args.episodes
    );
    for id in ids {
        // Name where the id came from: the flag, or the checkpoint's metadata.
        let source = match &args.env {
            Some(_) => format!("--env {id}"),
            None => format!("{}: env_id {id}", args.checkpoint.display()),
        };
        let mut env = EnvFactory::new(&id, &EnvOptions::default())
            .with_context(|| source)?
            .build();
        let spec = env.spec().clone();
        anyhow::ensure!(
            (spec.obs_dim, spec.act_dim) == (meta.obs_dim, meta.act_dim),
            "{id} has obs/action dims ({}, {}), the checkpoint's policy ({}, {})",
            spec.obs_dim,
            spec.act_dim,
            meta.obs_dim,
            meta.act_dim
        );
        let mut obs = vec![0.0; spec.obs_dim];
        let (mut returns, mut dense, mut lengths) = (Vec::new(), Vec::new(), Vec::new());
        for episode in 0..args.episodes {
            env.reset(Some(args.seed + episode as u64), &mut obs);
            let (mut r, mut d, mut n) = (0.0, 0.0, 0.0);
            loop {
                let action = acting.mean(&obs);
                let step = env.step(&action, &mut obs)?;
                (r, d, n) = (r + step.reward, d + step.info.dense_reward, n + 1.0);
                if step.done() {
                    break;
                }
            }
            returns.push(r);
            dense.push(d);
            lengths.push(n);
        }
        let ((rm, rs), (dm, ds), (lm, _)) =
            (mean_std(&returns), mean_std(&dense), mean_std(&lengths));
        println!(
            "{id:32} return {rm:10.2} ± {rs:8.2} | dense return {dm:10.2} ± {ds:8.2} | length {lm:.0}"
        );
    }
    Ok(())
}

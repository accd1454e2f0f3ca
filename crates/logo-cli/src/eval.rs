//! `logo eval`: the mean-action policy of a checkpoint on the dense and the sparse env.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use logo_envs::{Env, EnvFactory, EnvOptions};
use logo_nn::{Checkpoint, CheckpointMeta, Cpu, GaussianPolicy, PolicyConfig};

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
        "{} ({} iteration {}, seed {}): mean action, {} episodes",
        args.checkpoint.display(),
        meta.algorithm,
        meta.iteration,
        meta.seed,
        args.episodes
    );
    for id in ids {
        let mut env = EnvFactory::new(&id, &EnvOptions::default())
            .with_context(|| format!("--env {id}"))?
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
        let acting = policy.acting();
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

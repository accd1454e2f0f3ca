//! `logo eval`: the mean-action policy of a checkpoint on the dense and the sparse env.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use logo_envs::{Env, EnvFactory, EnvOptions};
use logo_nn::{
    ActingPolicy, Checkpoint, CheckpointMeta, Cpu, Engine, GaussianPolicy, Policy, PolicyConfig,
};

use crate::engine::{EngineArgs, WithEngine};
use crate::video::{Video, VideoArgs, record_episode};
use logo_algo::episode::{Episode, mean_std, run_episode};

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
    /// `--video OUT.mp4` records the first env's episodes (the dense one by default).
    #[command(flatten)]
    video: VideoArgs,
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
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.checkpoint.display()))?
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
    for (i, id) in ids.iter().enumerate() {
        // Name where the id came from: the flag, or the checkpoint's metadata.
        let source = match &args.env {
            Some(_) => format!("--env {id}"),
            None => format!("{}: env_id {id}", args.checkpoint.display()),
        };
        let factory = EnvFactory::new(id, &EnvOptions::default()).with_context(|| source)?;
        let mut env = factory.build();
        let spec = env.spec().clone();
        anyhow::ensure!(
            (spec.obs_dim, spec.act_dim) == (meta.obs_dim, meta.act_dim),
            "{id} has obs/action dims ({}, {}), the checkpoint's policy ({}, {})",
            spec.obs_dim,
            spec.act_dim,
            meta.obs_dim,
            meta.act_dim
        );
        let seeds = (0..args.episodes as u64).map(|episode| args.seed + episode);
        let episodes = match (&args.video.video, i) {
            (Some(path), 0) => {
                let mut video = Video::start(path, &factory, args.video.frames())?;
                let episodes = seeds
                    .enumerate()
                    .map(|(k, seed)| {
                        let label = format!("episode {} | ", k + 1);
                        record_episode(&mut video, env.as_mut(), seed, &label, |obs| {
                            acting.mean(obs)
                        })
                    })
                    .collect::<Result<Vec<_>>>()?;
                let frames = video.finish()?;
                println!("video: {} ({frames} frames of {id})", path.display());
                episodes
            }
            _ => seeds
                .map(|seed| run_episode(env.as_mut(), seed, |obs| acting.mean(obs)))
                .collect::<Result<Vec<_>, _>>()?,
        };
        println!("{id:32} {}", summary(&episodes));
    }
    Ok(())
}

/// One line for an env's evaluation: mean ± std over episodes of the returns and of how
/// far `qpos[0]` moved, the mean length and the mean action RMS. The dense locomotion
/// rewards charge the control cost on the action as given, while MuJoCo clamps it to the
/// actuator range (±1 for these envs), so an RMS well above 1 explains a negative dense
/// return from a policy that does move forward.
fn summary(episodes: &[Episode]) -> String {
    let stat = |of: fn(&Episode) -> f64| mean_std(&episodes.iter().map(of).collect::<Vec<_>>());
    let (rm, rs) = stat(|e| e.return_);
    let (dm, ds) = stat(|e| e.dense_return);
    let (lm, _) = stat(|e| e.length as f64);
    let (xm, xs) = stat(|e| e.moved);
    let (am, _) = stat(|e| e.action_rms);
    format!(
        "return {rm:10.2} ± {rs:8.2} | dense return {dm:10.2} ± {ds:8.2} | length {lm:.0} \
         | x moved {xm:8.2} ± {xs:6.2} | action RMS {am:.2}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant action of 2 on HalfCheetah (actuator range ±1): the RMS says 2, and the
    /// dense return is the distance over dt minus 0.1·‖a‖² per step on the unclamped
    /// action (6 × 4 × 0.1 = 2.4 per step), which is what makes it negative.
    #[test]
    fn an_episode_reports_distance_and_the_unclamped_action_size() {
        let mut env = EnvFactory::new("SparseHalfCheetah-v4", &EnvOptions::default())
            .unwrap()
            .build();
        let episode = run_episode(env.as_mut(), 0, |_| vec![2.0; 6]).unwrap();
        assert_eq!(episode.length, 1000);
        assert!((episode.action_rms - 2.0).abs() < 1e-12, "{episode:?}");
        let dt = 0.05;
        let expected = episode.moved / dt - 2.4 * episode.length as f64;
        assert!(
            (episode.dense_return - expected).abs() < 1e-6 * expected.abs(),
            "{episode:?}, expected dense {expected}"
        );
        assert!(episode.dense_return < 0.0, "{episode:?}");
    }
}

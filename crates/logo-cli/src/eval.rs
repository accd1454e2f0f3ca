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
        let mut episodes = EpisodeStats::default();
        for episode in 0..args.episodes {
            let seed = args.seed + episode as u64;
            episodes.push(run_episode(env.as_mut(), seed, |obs| acting.mean(obs))?);
        }
        println!("{id:32} {}", episodes.line());
    }
    Ok(())
}

/// One episode's totals.
#[derive(Debug)]
struct Episode {
    return_: f64,
    dense_return: f64,
    length: f64,
    /// `qpos[0]` at the end minus at the start.
    moved: f64,
    /// Root mean square over every action component of every step.
    action_rms: f64,
}

/// Runs one episode from `reset(seed)` to its end, acting with `act`.
fn run_episode(
    env: &mut dyn Env,
    seed: u64,
    mut act: impl FnMut(&[f64]) -> Vec<f64>,
) -> Result<Episode> {
    let mut obs = vec![0.0; env.spec().obs_dim];
    env.reset(Some(seed), &mut obs);
    let x_start = env.x_position();
    let (mut return_, mut dense_return, mut length, mut squared_action) = (0.0, 0.0, 0.0, 0.0);
    loop {
        let action = act(&obs);
        squared_action += action.iter().map(|a| a * a).sum::<f64>();
        let step = env.step(&action, &mut obs)?;
        return_ += step.reward;
        dense_return += step.info.dense_reward;
        length += 1.0;
        if step.done() {
            break;
        }
    }
    let components = length * env.spec().act_dim as f64;
    Ok(Episode {
        return_,
        dense_return,
        length,
        moved: env.x_position() - x_start,
        action_rms: (squared_action / components).sqrt(),
    })
}

/// Per-episode numbers of one env's evaluation. Beside the returns: how far `qpos[0]`
/// moved (forward distance for the locomotion envs, the cart for IDP) and the RMS of the
/// action components. The dense locomotion rewards charge the control cost on the action
/// as given, while MuJoCo clamps it to the actuator range (±1 for these envs), so an RMS
/// well above 1 explains a negative dense return from a policy that does move forward.
#[derive(Default)]
struct EpisodeStats {
    returns: Vec<f64>,
    dense: Vec<f64>,
    lengths: Vec<f64>,
    moved: Vec<f64>,
    action_rms: Vec<f64>,
}

impl EpisodeStats {
    fn push(&mut self, episode: Episode) {
        self.returns.push(episode.return_);
        self.dense.push(episode.dense_return);
        self.lengths.push(episode.length);
        self.moved.push(episode.moved);
        self.action_rms.push(episode.action_rms);
    }

    fn line(&self) -> String {
        let (rm, rs) = mean_std(&self.returns);
        let (dm, ds) = mean_std(&self.dense);
        let (lm, _) = mean_std(&self.lengths);
        let (xm, xs) = mean_std(&self.moved);
        let (am, _) = mean_std(&self.action_rms);
        format!(
            "return {rm:10.2} ± {rs:8.2} | dense return {dm:10.2} ± {ds:8.2} | length {lm:.0} \
             | x moved {xm:8.2} ± {xs:6.2} | action RMS {am:.2}"
        )
    }
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
        assert_eq!(episode.length, 1000.0);
        assert!((episode.action_rms - 2.0).abs() < 1e-12, "{episode:?}");
        let dt = 0.05;
        let expected = episode.moved / dt - 2.4 * episode.length;
        assert!(
            (episode.dense_return - expected).abs() < 1e-6 * expected.abs(),
            "{episode:?}, expected dense {expected}"
        );
        assert!(episode.dense_return < 0.0, "{episode:?}");
    }
}

//! `logo envs` and `logo rollout`: look at the environments before training on them.

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use logo_envs::{Env, EnvFactory, EnvOptions, all_env_ids};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub fn list_envs() -> Result<()> {
    println!(
        "{:32} {:>4} {:>4} {:>9}  sparse rule",
        "id", "obs", "act", "max steps"
    );
    for id in all_env_ids() {
        let factory = EnvFactory::new(&id, &EnvOptions::default())?;
        let spec = factory.spec();
        let rule = factory
            .sparse_rule()
            .map_or("-".to_string(), |r| format!("{r:?}"));
        println!(
            "{:32} {:>4} {:>4} {:>9}  {rule}",
            spec.id, spec.obs_dim, spec.act_dim, spec.max_episode_steps
        );
    }
    Ok(())
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FixedPolicy {
    /// Uniform in the actuator control range.
    Random,
    /// All-zero actions.
    Zero,
}

#[derive(Args)]
pub struct RolloutArgs {
    /// Environment id (`logo envs` lists them).
    #[arg(long, default_value = "SparseInvertedDoublePendulum-v4")]
    env: String,
    #[arg(long, default_value_t = 5)]
    episodes: usize,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    #[arg(long, value_enum, default_value_t = FixedPolicy::Random)]
    policy: FixedPolicy,
}

pub fn run(args: &RolloutArgs) -> Result<()> {
    anyhow::ensure!(args.episodes > 0, "--episodes must be at least 1");
    let factory = EnvFactory::new(&args.env, &EnvOptions::default())
        .with_context(|| format!("--env {}", args.env))?;
    let mut env = factory.build();
    let spec = env.spec().clone();
    let mut rng = ChaCha8Rng::seed_from_u64(args.seed);
    println!(
        "{} with a {} policy, seed {}",
        spec.id,
        format!("{:?}", args.policy).to_lowercase(),
        args.seed
    );
    let mut episodes = Vec::new();
    for episode in 0..args.episodes {
        let act = |_: &[f64]| -> Vec<f64> {
            (spec.action_low.iter().zip(&spec.action_high))
                .map(|(lo, hi)| match args.policy {
                    FixedPolicy::Random => rng.random_range(*lo..*hi),
                    FixedPolicy::Zero => 0.0,
                })
                .collect()
        };
        let e = run_episode(env.as_mut(), args.seed + episode as u64, act)?;
        let end = if e.terminated {
            "terminated"
        } else {
            "truncated"
        };
        println!(
            "episode {episode}: {:4} steps ({end}), return {:10.3}, dense return {:10.3}",
            e.length, e.return_, e.dense_return
        );
        episodes.push(e);
    }
    let (m, s) = mean_std(&episodes.iter().map(|e| e.return_).collect::<Vec<_>>());
    let (dm, ds) = mean_std(&episodes.iter().map(|e| e.dense_return).collect::<Vec<_>>());
    println!(
        "return {m:.3} ± {s:.3}, dense return {dm:.3} ± {ds:.3} over {} episodes",
        args.episodes
    );
    Ok(())
}

/// One episode's totals.
#[derive(Debug)]
pub struct Episode {
    pub return_: f64,
    pub dense_return: f64,
    pub length: usize,
    /// Ended by the MDP (a fall), not by the time limit.
    pub terminated: bool,
    /// `qpos[0]` at the end minus at the start: forward distance for the locomotion envs,
    /// the cart's travel for IDP.
    pub moved: f64,
    /// Root mean square over every action component of every step, as given to the env
    /// (before MuJoCo clamps it to the actuator range).
    pub action_rms: f64,
}

/// Runs one episode from `reset(seed)` to its end, acting with `act`.
pub fn run_episode(
    env: &mut dyn Env,
    seed: u64,
    mut act: impl FnMut(&[f64]) -> Vec<f64>,
) -> Result<Episode> {
    let mut obs = vec![0.0; env.spec().obs_dim];
    env.reset(Some(seed), &mut obs);
    let x_start = env.x_position();
    let (mut return_, mut dense_return, mut length, mut squared_action) = (0.0, 0.0, 0, 0.0);
    loop {
        let action = act(&obs);
        squared_action += action.iter().map(|a| a * a).sum::<f64>();
        let step = env.step(&action, &mut obs)?;
        return_ += step.reward;
        dense_return += step.info.dense_reward;
        length += 1;
        if step.done() {
            let components = (length * env.spec().act_dim) as f64;
            return Ok(Episode {
                return_,
                dense_return,
                length,
                terminated: step.terminated,
                moved: env.x_position() - x_start,
                action_rms: (squared_action / components).sqrt(),
            });
        }
    }
}

pub fn mean_std(x: &[f64]) -> (f64, f64) {
    let n = x.len().max(1) as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    (mean, var.sqrt())
}

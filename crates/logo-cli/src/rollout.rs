//! `logo envs` and `logo rollout`: look at the environments before training on them.

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use logo_envs::{EnvFactory, EnvOptions, all_env_ids};
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
    let mut obs = vec![0.0; spec.obs_dim];
    let mut action = vec![0.0; spec.act_dim];
    let (mut dense_returns, mut rewards) = (Vec::new(), Vec::new());
    println!(
        "{} with a {} policy, seed {}",
        spec.id,
        format!("{:?}", args.policy).to_lowercase(),
        args.seed
    );
    for episode in 0..args.episodes {
        env.reset(Some(args.seed + episode as u64), &mut obs);
        let (mut dense, mut reward, mut steps) = (0.0, 0.0, 0);
        loop {
            for (a, (lo, hi)) in action
                .iter_mut()
                .zip(spec.action_low.iter().zip(&spec.action_high))
            {
                *a = match args.policy {
                    FixedPolicy::Random => rng.random_range(*lo..*hi),
                    FixedPolicy::Zero => 0.0,
                };
            }
            let step = env.step(&action, &mut obs)?;
            dense += step.info.dense_reward;
            reward += step.reward;
            steps += 1;
            if step.done() {
                let end = if step.terminated {
                    "terminated"
                } else {
                    "truncated"
                };
                println!(
                    "episode {episode}: {steps:4} steps ({end}), return {reward:10.3}, dense return {dense:10.3}"
                );
                break;
            }
        }
        dense_returns.push(dense);
        rewards.push(reward);
    }
    let (m, s) = mean_std(&rewards);
    let (dm, ds) = mean_std(&dense_returns);
    println!(
        "return {m:.3} ± {s:.3}, dense return {dm:.3} ± {ds:.3} over {} episodes",
        args.episodes
    );
    Ok(())
}

pub fn mean_std(x: &[f64]) -> (f64, f64) {
    let n = x.len().max(1) as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    (mean, var.sqrt())
}

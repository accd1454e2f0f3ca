//! `logo envs` and `logo rollout`: look at the environments before training on them.

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use logo_algo::episode::run_episode_with;
use logo_stats::mean_std;

use crate::video::{Video, VideoArgs};
use logo_envs::{EnvFactory, EnvOptions, SPARSE_KINDS, all_env_ids};
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
            .map_or("-".to_string(), |r| r.describe());
        println!(
            "{:32} {:>4} {:>4} {:>9}  {rule}",
            spec.id, spec.obs_dim, spec.act_dim, spec.max_episode_steps
        );
    }
    println!("\nSparse kinds: any dense id above made sparse by a config's [env] table");
    println!("(id = \"Hopper-v4\", sparse = {{ kind = \"distance\", threshold = 2.0 }}),");
    println!("or on the command line as <id>+<kind>, e.g. Hopper-v4+distance(5):");
    for (kind, parameters, pays) in SPARSE_KINDS {
        println!("  {kind:10} {parameters:30} {pays}");
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
    /// `--video OUT.mp4` records the episodes.
    #[command(flatten)]
    video: VideoArgs,
}

pub fn run(args: &RolloutArgs) -> Result<()> {
    anyhow::ensure!(args.episodes > 0, "--episodes must be at least 1");
    let factory = EnvFactory::new(&args.env, &EnvOptions::default())
        .with_context(|| format!("--env {}", args.env))?;
    let mut env = factory.build()?;
    let spec = env.spec().clone();
    let mut video = match &args.video.video {
        Some(path) => Some(Video::start(path, &factory, args.video.frames())?),
        None => None,
    };
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
        let label = format!("episode {} | ", episode + 1);
        let e = run_episode_with(
            env.as_mut(),
            args.seed + episode as u64,
            act,
            |env, e| match video.as_mut() {
                Some(video) => video.episode_frame(env, &label, e),
                None => Ok(()),
            },
        )?;
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
    if let (Some(video), Some(path)) = (video, &args.video.video) {
        let frames = video.finish()?;
        println!("video: {} ({frames} frames)", path.display());
    }
    let (m, s) = mean_std(&episodes.iter().map(|e| e.return_).collect::<Vec<_>>());
    let (dm, ds) = mean_std(&episodes.iter().map(|e| e.dense_return).collect::<Vec<_>>());
    println!(
        "return {m:.3} ± {s:.3}, dense return {dm:.3} ± {ds:.3} over {} episodes",
        args.episodes
    );
    Ok(())
}

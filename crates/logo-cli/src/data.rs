//! `logo data`: import, inspect and record demonstration datasets (Minari layout).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use logo_data::import::{import_d4rl, import_logo_npy};
use logo_data::minari::box_space;
use logo_data::{Dataset, Episode, is_minari_dir, read_minari, write_minari};
use logo_envs::{Env, EnvFactory, EnvOptions, EnvSpec};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use crate::eval::load_policy;
use logo_stats::mean_std;

#[derive(Subcommand)]
pub enum DataCommand {
    /// Convert demonstrations from another layout into a Minari dataset folder.
    Import(ImportArgs),
    /// Print a dataset's episodes, steps, returns and dims.
    Inspect(InspectArgs),
    /// Run a checkpoint's policy and record its episodes as a Minari dataset.
    Record(RecordArgs),
}

#[derive(Clone, Copy, ValueEnum)]
enum Source {
    /// `[obs ‖ action]` rows with no episode markers (the LOGO paper's demonstrations).
    LogoNpy,
    /// Flat HDF5 with observations, actions, rewards, terminals, timeouts.
    D4rl,
}

#[derive(Args)]
pub struct ImportArgs {
    #[arg(long, value_enum)]
    from: Source,
    input: PathBuf,
    /// The env the demonstrations come from (needed for `logo-npy`: dims and reset pose).
    #[arg(long)]
    env: Option<String>,
    /// Output dataset folder.
    #[arg(long)]
    out: PathBuf,
    /// Minari dataset id written in the metadata.
    #[arg(long)]
    dataset_id: Option<String>,
}

#[derive(Args)]
pub struct InspectArgs {
    /// A Minari dataset folder (or a LOGO `.npy` array, with --env).
    path: PathBuf,
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct RecordArgs {
    #[arg(long)]
    policy: PathBuf,
    /// Env id; a sparse id stores the sparse reward, a dense id the dense one. Both
    /// returns of every episode go in the metadata either way.
    #[arg(long)]
    env: String,
    #[arg(long)]
    episodes: usize,
    /// Act with the mean action instead of sampling.
    #[arg(long)]
    deterministic: bool,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    #[arg(long)]
    out: PathBuf,
    #[arg(long)]
    dataset_id: Option<String>,
}

pub fn run(cmd: &DataCommand) -> Result<()> {
    match cmd {
        DataCommand::Import(args) => import(args),
        DataCommand::Inspect(args) => inspect(args),
        DataCommand::Record(args) => record(args),
    }
}

/// Minari metadata for an env: its id and its spaces.
fn env_metadata(dataset: &mut Dataset, env_id: &str, spec: &EnvSpec) {
    let n = spec.obs_dim;
    let meta = &mut dataset.metadata;
    meta.insert("logo_env_id".into(), env_id.into());
    meta.insert(
        "observation_space".into(),
        box_space(&vec![f64::NEG_INFINITY; n], &vec![f64::INFINITY; n]).into(),
    );
    meta.insert(
        "action_space".into(),
        box_space(&spec.action_low, &spec.action_high).into(),
    );
}

fn import(args: &ImportArgs) -> Result<()> {
    let env = match &args.env {
        Some(id) => {
            let factory = EnvFactory::new(id, &EnvOptions::default())
                .with_context(|| format!("--env {id}"))?;
            Some((id.as_str(), factory.spec().clone()))
        }
        None => None,
    };
    let mut dataset = match (args.from, &env) {
        (Source::LogoNpy, None) => {
            anyhow::bail!("--env is needed to import a LOGO .npy (dims and reset pose)")
        }
        (Source::LogoNpy, Some((id, spec))) => import_logo_npy(
            &args.input,
            id,
            spec.obs_dim,
            spec.act_dim,
            spec.max_episode_steps,
        )?,
        (Source::D4rl, _) => import_d4rl(&args.input)?,
    };
    if let Some((id, spec)) = &env {
        dataset.check_dims(&args.input, spec.obs_dim, spec.act_dim)?;
        env_metadata(&mut dataset, id, spec);
    }
    if let Some(id) = &args.dataset_id {
        dataset
            .metadata
            .insert("dataset_id".into(), id.as_str().into());
    }
    write_minari(&dataset, &args.out)?;
    println!(
        "{} -> {}: {} episodes, {} steps",
        args.input.display(),
        args.out.display(),
        dataset.episodes.len(),
        dataset.total_steps()
    );
    Ok(())
}

fn inspect(args: &InspectArgs) -> Result<()> {
    anyhow::ensure!(
        is_minari_dir(&args.path),
        "{}: not a Minari dataset folder (expected data/main_data.hdf5 inside)",
        args.path.display()
    );
    let dataset = read_minari(&args.path)?;
    let lengths: Vec<usize> = dataset.episodes.iter().map(Episode::steps).collect();
    let returns: Vec<f64> = dataset.episodes.iter().map(Episode::total_reward).collect();
    let (mean, std) = mean_std(&returns);
    let meta = &dataset.metadata;
    let dense: Option<Vec<f64>> = meta
        .get("logo_dense_returns")
        .and_then(Value::as_array)
        .map(|v| v.iter().filter_map(Value::as_f64).collect());
    let summary = json!({
        "path": args.path.display().to_string(),
        "dataset_id": meta.get("dataset_id"),
        "env_id": dataset.env_id(),
        "obs_dim": dataset.obs_dim,
        "act_dim": dataset.act_dim,
        "episodes": dataset.episodes.len(),
        "steps": dataset.total_steps(),
        "episode_lengths": lengths,
        "return_mean": mean,
        "return_std": std,
        "return_min": returns.iter().copied().fold(f64::INFINITY, f64::min),
        "return_max": returns.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        "dense_returns": dense,
        "terminated": dataset.episodes.iter().filter(|e| e.terminations.last() == Some(&true)).count(),
        "truncated": dataset.episodes.iter().filter(|e| e.truncations.last() == Some(&true)).count(),
    });
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
        return Ok(());
    }
    println!(
        "{}: {} ({})",
        args.path.display(),
        meta.get("dataset_id")
            .and_then(Value::as_str)
            .unwrap_or("?"),
        dataset.env_id().unwrap_or("env unknown")
    );
    println!(
        "  {} episodes, {} steps, obs dim {}, action dim {}",
        dataset.episodes.len(),
        dataset.total_steps(),
        dataset.obs_dim,
        dataset.act_dim
    );
    println!("  episode lengths: {lengths:?}");
    println!(
        "  return (stored rewards): {mean:.2} ± {std:.2} (min {:.2}, max {:.2})",
        summary["return_min"].as_f64().unwrap_or(f64::NAN),
        summary["return_max"].as_f64().unwrap_or(f64::NAN)
    );
    if let Some(dense) = &dense {
        let (m, s) = mean_std(dense);
        println!("  dense return (metadata): {m:.2} ± {s:.2}");
    }
    if let Some(notes) = meta.get("logo_notes").and_then(Value::as_str) {
        println!("  notes: {notes}");
    }
    Ok(())
}

/// A Minari dataset name for an env id: lower case, a sparse rule's `+kind(value)`
/// spelled with dashes (`hopper-v4-distance-5`).
fn dataset_name(env_id: &str) -> String {
    let name: String = env_id
        .to_lowercase()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' {
                c
            } else {
                '-'
            }
        })
        .collect();
    name.trim_end_matches('-').to_string()
}

/// One episode from reset `seed`, acting with `act`: the episode as a dataset stores it
/// (its sparse rewards where `sparse_rewards`, else the dense ones), its dense return and
/// its sparse return.
fn record_episode(
    env: &mut dyn Env,
    seed: u64,
    act: impl Fn(&[f64], &mut ChaCha8Rng) -> Vec<f64>,
    rng: &mut ChaCha8Rng,
    sparse_rewards: bool,
) -> Result<(Episode, f64, f64)> {
    let mut obs = vec![0.0; env.spec().obs_dim];
    env.reset(Some(seed), &mut obs);
    let mut ep = Episode {
        observations: obs.clone(),
        ..Default::default()
    };
    let (mut dense, mut sparse) = (0.0, 0.0);
    loop {
        let action = act(&obs, rng);
        let step = env.step(&action, &mut obs)?;
        dense += step.info.dense_reward;
        sparse += step.reward;
        ep.actions.extend_from_slice(&action);
        ep.observations.extend_from_slice(&obs);
        ep.rewards.push(if sparse_rewards {
            step.reward
        } else {
            step.info.dense_reward
        });
        ep.terminations.push(step.terminated);
        ep.truncations.push(step.truncated);
        if step.done() {
            return Ok((ep, dense, sparse));
        }
    }
}

/// What a recording's metadata says of where it came from: the policy, how it acted, and
/// each episode's dense and sparse return.
fn recording_metadata(
    dataset: &mut Dataset,
    args: &RecordArgs,
    meta: &logo_nn::CheckpointMeta,
    dense_returns: &[f64],
    sparse_returns: &[f64],
) {
    let m = &mut dataset.metadata;
    m.insert(
        "dataset_id".into(),
        args.dataset_id
            .clone()
            .unwrap_or_else(|| format!("logo/{}-recorded-v0", dataset_name(&args.env)))
            .into(),
    );
    m.insert(
        "logo_policy".into(),
        args.policy.display().to_string().into(),
    );
    m.insert(
        "logo_policy_algorithm".into(),
        meta.algorithm.clone().into(),
    );
    m.insert("logo_policy_iteration".into(), meta.iteration.into());
    m.insert("logo_deterministic".into(), args.deterministic.into());
    m.insert("logo_seed".into(), args.seed.into());
    m.insert("logo_dense_returns".into(), json!(dense_returns));
    m.insert("logo_sparse_returns".into(), json!(sparse_returns));
}

fn record(args: &RecordArgs) -> Result<()> {
    anyhow::ensure!(args.episodes > 0, "--episodes must be at least 1");
    let policy = load_policy(&args.policy)?;
    let meta = &policy.meta;
    // A sparse id records its own rewards; a dense one the dense rewards, with the sparse
    // returns of LOGO's rule for the task beside them.
    let sparse_requested = logo_envs::dense_id(&args.env) != args.env;
    let sparse_id = if sparse_requested {
        args.env.clone()
    } else {
        format!("Sparse{}", args.env)
    };
    let mut env = EnvFactory::new(&sparse_id, &EnvOptions::default())
        .with_context(|| format!("--env {}", args.env))?
        .build()?;
    let spec = env.spec().clone();
    anyhow::ensure!(
        (spec.obs_dim, spec.act_dim) == (meta.obs_dim, meta.act_dim),
        "{}: the policy has obs/action dims ({}, {}), {} has ({}, {})",
        args.policy.display(),
        meta.obs_dim,
        meta.act_dim,
        args.env,
        spec.obs_dim,
        spec.act_dim
    );
    let acting = policy.acting(&logo_nn::Kernels);
    let mut rng = ChaCha8Rng::seed_from_u64(args.seed);
    let mut episodes = Vec::new();
    let (mut dense_returns, mut sparse_returns) = (Vec::new(), Vec::new());
    for k in 0..args.episodes {
        let seed = args.seed * 1_000_003 + k as u64;
        let act = |obs: &[f64], rng: &mut ChaCha8Rng| {
            if args.deterministic {
                acting.mean(obs)
            } else {
                acting.sample(obs, rng)
            }
        };
        let (ep, dense, sparse) =
            record_episode(env.as_mut(), seed, act, &mut rng, sparse_requested)?;
        dense_returns.push(dense);
        sparse_returns.push(sparse);
        episodes.push(ep);
    }
    let mut dataset = Dataset {
        obs_dim: spec.obs_dim,
        act_dim: spec.act_dim,
        episodes,
        metadata: Default::default(),
    };
    env_metadata(&mut dataset, &args.env, &spec);
    recording_metadata(&mut dataset, args, meta, &dense_returns, &sparse_returns);
    write_minari(&dataset, &args.out)?;
    let (dm, ds) = mean_std(&dense_returns);
    let (sm, ss) = mean_std(&sparse_returns);
    println!(
        "{} episodes, {} steps -> {}: dense return {dm:.2} ± {ds:.2}, sparse return {sm:.2} ± {ss:.2}",
        args.episodes,
        dataset.total_steps(),
        args.out.display()
    );
    Ok(())
}

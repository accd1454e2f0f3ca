//! `logo train`: run TRPO or LOGO from a TOML config, with a progress line per iteration,
//! `metrics.csv` and checkpoints in the output folder.

use std::path::PathBuf;

use anyhow::{Context, Result};
use burn::tensor::backend::AutodiffBackend;
use clap::{Args, ValueEnum};
use logo_algo::{TrainConfig, Trainer};
use logo_nn::burn;
use logo_nn::{Cpu32Autodiff, CpuAutodiff};

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Dtype {
    /// float64 (the reference implementation's precision)
    F64,
    F32,
}

#[derive(Args)]
pub struct TrainArgs {
    /// TOML config, e.g. configs/logo/inverted_double_pendulum.toml
    #[arg(long)]
    config: PathBuf,
    /// Overrides the config's seed.
    #[arg(long)]
    seed: Option<u64>,
    /// Overrides the config's number of iterations.
    #[arg(long)]
    iterations: Option<usize>,
    /// Stop (and write the checkpoint) at the first evaluation whose dense return reaches
    /// this: the behaviour-policy pipeline, e.g. a dense TRPO run stopped at LOGO's
    /// behaviour level, then `logo data record`.
    #[arg(long)]
    stop_at_return: Option<f64>,
    /// Output folder (default: runs/<config name>-seed<seed>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Overrides the config's worker threads.
    #[arg(long)]
    threads: Option<usize>,
    #[arg(long, value_enum, default_value_t = Dtype::F64)]
    dtype: Dtype,
}

pub fn run(args: &TrainArgs) -> Result<()> {
    let mut config = TrainConfig::load(&args.config)?;
    if let Some(seed) = args.seed {
        config.seed = seed;
    }
    if let Some(target) = args.stop_at_return {
        anyhow::ensure!(
            target.is_finite(),
            "--stop-at-return must be a finite number"
        );
    }
    if let Some(iterations) = args.iterations {
        anyhow::ensure!(iterations > 0, "--iterations must be at least 1");
        config.iterations = iterations;
    }
    if let Some(threads) = args.threads {
        anyhow::ensure!(threads > 0, "--threads must be at least 1");
        config.threads = threads;
    }
    let name = args
        .config
        .file_stem()
        .map_or("run".into(), |s| s.to_string_lossy().into_owned());
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("runs/{name}-seed{}", config.seed)));
    match args.dtype {
        Dtype::F64 => train::<CpuAutodiff>(config, out, args.stop_at_return),
        Dtype::F32 => train::<Cpu32Autodiff>(config, out, args.stop_at_return),
    }
}

fn train<B: AutodiffBackend>(
    config: TrainConfig,
    out: PathBuf,
    stop_at_return: Option<f64>,
) -> Result<()> {
    let algorithm = if config.guidance.is_some() {
        "LOGO"
    } else {
        "TRPO"
    };
    println!(
        "{algorithm} on {} (eval: {}), {} iterations x {} samples, seed {}, {} envs on {} threads -> {}",
        config.env,
        config.eval_env_id(),
        config.iterations,
        config.samples_per_iter,
        config.seed,
        config.num_envs,
        config.threads,
        out.display()
    );
    let mut trainer = Trainer::<B>::new(config, &out).map_err(|e| anyhow::anyhow!("{e}"))?;
    let total = trainer.config.iterations;
    let mut best = (f64::NEG_INFINITY, 0);
    let mut last = None;
    while !trainer.done() {
        let m = trainer
            .step()
            .map_err(|e| anyhow::anyhow!("{e}"))
            .context(format!("iteration {}", trainer.iteration()))?;
        if m.eval_dense_return > best.0 {
            best = (m.eval_dense_return, m.iteration);
        }
        let per_iter = m.wall_s / (m.iteration + 1) as f64;
        println!(
            "[{:>4}/{total}] samples {:>9} | sparse {:>9.2} | eval dense {:>9.2} | kl {:.4} | δk {:.3e} | {:.2} s/it, ETA {:.0} s",
            m.iteration + 1,
            m.samples,
            m.train_sparse_return,
            m.eval_dense_return,
            m.kl,
            m.delta_k,
            per_iter,
            per_iter * (total - m.iteration - 1) as f64
        );
        let reached = stop_at_return.is_some_and(|target| m.eval_dense_return >= target);
        last = Some(m);
        if reached {
            let path = out.join("checkpoint.safetensors");
            trainer
                .save_checkpoint(&path)
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            println!(
                "reached --stop-at-return {}: stopped, policy in {}",
                stop_at_return.unwrap_or_default(),
                path.display()
            );
            break;
        }
    }
    let last = last.expect("at least one iteration");
    println!(
        "done in {:.1} s: final eval dense return {:.1}, best {:.1} at iteration {}; {} and {}",
        last.wall_s,
        last.eval_dense_return,
        best.0,
        best.1 + 1,
        out.join("metrics.csv").display(),
        out.join("checkpoint.safetensors").display()
    );
    Ok(())
}

//! `logo bench iteration`: where a training iteration of a config goes on this machine.
//!
//! Runs the config for a few iterations under the sequential schedule (one step at a
//! time, so each step's time and FLOPs are its own), then again under the pipelined one
//! (the default), from the same seed; prints each step's median seconds and GFLOPs, both
//! schedules' seconds per iteration, and two floors beside them:
//!
//! - physics: `samples_per_iter` env steps at this machine's single-thread raw `mj_step`
//!   rate (`logo bench envs`), spread over the run's threads;
//! - compute: the iteration's FLOPs (the kernels' matrix products and contractions,
//!   counted from their shapes) at the GEMM's one-thread rate on a 256-row block
//!   (`logo bench nn`), spread over the run's threads.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use logo_algo::{IterationMetrics, Schedule, TrainConfig, Trainer};

use logo_nn::{Engine, flops};
use serde::Serialize;

use super::envs::single_thread_rates;
use super::nn::block_products;
use logo_engine::{Dtype, EngineArgs, WithEngine};
use logo_stats::median;

#[derive(Args)]
pub struct IterationBenchArgs {
    /// The training config to measure, e.g. configs/logo/hopper.toml.
    #[arg(long)]
    config: PathBuf,
    /// Iterations per schedule.
    #[arg(long, default_value_t = 4)]
    iterations: usize,
    /// Leading iterations left out of the medians (start-up, first allocations).
    #[arg(long, default_value_t = 1)]
    skip: usize,
    /// Overrides the config's worker threads.
    #[arg(long)]
    threads: Option<usize>,
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    engine: EngineArgs,
}

/// A step's timing column in `metrics.csv`.
type Column = fn(&IterationMetrics) -> f64;

/// The steps of an iteration as `metrics.csv` times them and `logo_nn::flops` counts
/// them: (label, timing column).
const PHASES: [(&str, Column); 7] = [
    ("sampling", |m| m.t_sampling),
    ("advantages", |m| m.t_advantages),
    ("improvement step", |m| m.t_policy_step),
    ("guidance step", |m| m.t_guidance),
    ("discriminator", |m| m.t_discriminator),
    ("critic fits", |m| m.t_critics),
    ("evaluation", |m| m.t_evaluation),
];

#[derive(Serialize)]
struct Phase {
    phase: &'static str,
    seconds: f64,
    gflop: f64,
}

#[derive(Serialize)]
struct Report {
    config: String,
    engine: String,
    threads: usize,
    samples_per_iter: usize,
    phases: Vec<Phase>,
    sequential_s: f64,
    pipelined_s: f64,
    raw_env_steps_per_s: f64,
    physics_floor_s: f64,
    gemm_gflops_one_thread: f64,
    compute_floor_s: f64,
    /// Pipelined iteration ÷ physics floor.
    ratio_physics: f64,
    /// Pipelined iteration ÷ (physics + compute floors).
    ratio_floors: f64,
}

/// The rows of one run and the FLOPs of each of its iterations.
struct Measured {
    engine: String,
    rows: Vec<IterationMetrics>,
    flops: Vec<BTreeMap<&'static str, u64>>,
}

struct Run {
    config: TrainConfig,
    schedule: Schedule,
}

impl WithEngine for Run {
    type Output = Measured;
    fn run<E: Engine>(self, engine: E) -> Result<Measured> {
        let dir = std::env::temp_dir().join(format!(
            "logo-bench-iteration-{}-{:?}",
            std::process::id(),
            self.schedule
        ));
        let _ = std::fs::remove_dir_all(&dir);
        let mut trainer = Trainer::new(engine, self.config, &dir)?;
        trainer.set_schedule(self.schedule);
        let engine = trainer.engine().describe();
        flops::enable(true);
        flops::take();
        let (mut rows, mut counts) = (Vec::new(), Vec::new());
        while !trainer.done() {
            rows.push(trainer.step()?);
            counts.push(flops::take());
        }
        flops::enable(false);
        drop(trainer);
        let _ = std::fs::remove_dir_all(&dir);
        Ok(Measured {
            engine,
            rows,
            flops: counts,
        })
    }
}

/// The benched config, with the bench's iterations and threads.
fn bench_config(args: &IterationBenchArgs) -> Result<TrainConfig> {
    let mut config = TrainConfig::load(&args.config)?;
    config.iterations = args.iterations;
    if let Some(threads) = args.threads {
        anyhow::ensure!(threads > 0, "--threads must be at least 1");
        config.threads = threads;
    }
    Ok(config)
}

pub fn run(args: &IterationBenchArgs) -> Result<()> {
    anyhow::ensure!(
        args.iterations > args.skip,
        "--iterations must be more than --skip"
    );
    let config = bench_config(args)?;
    let engine = args.engine.for_config(&config);
    let run = |schedule| {
        engine.with(Run {
            config: config.clone(),
            schedule,
        })
    };
    let sequential = run(Schedule::Sequential)?;
    let pipelined = run(Schedule::Pipelined)?;

    let factory = config
        .env
        .factory()
        .with_context(|| format!("{}: env", args.config.display()))?;
    let raw = single_thread_rates(&factory, 5_000, 5)?.raw_env_steps_per_s;
    let gemm = match engine.dtype() {
        Dtype::F64 => block_products::<f64>(7),
        Dtype::F32 => block_products::<f32>(7),
    };
    let gemm_rate = median(&gemm.iter().map(|g| g.gflops).collect::<Vec<_>>());

    let kept = |m: &Measured| m.rows[args.skip..].to_vec();
    let per_iteration = |rows: &[IterationMetrics]| {
        median(
            &rows
                .windows(2)
                .map(|w| w[1].wall_s - w[0].wall_s)
                .collect::<Vec<_>>(),
        )
    };
    let phases: Vec<Phase> = PHASES
        .iter()
        .map(|&(phase, column)| Phase {
            phase,
            seconds: median(&kept(&sequential).iter().map(column).collect::<Vec<_>>()),
            gflop: median(
                &sequential.flops[args.skip..]
                    .iter()
                    .map(|f| f.get(phase).copied().unwrap_or(0) as f64 / 1e9)
                    .collect::<Vec<_>>(),
            ),
        })
        .collect();
    let total_gflop: f64 = phases.iter().map(|p| p.gflop).sum();
    let threads = config.threads as f64;
    let physics_floor_s = config.samples_per_iter as f64 / raw / threads;
    let compute_floor_s = total_gflop / gemm_rate / threads;
    let pipelined_s = per_iteration(&pipelined.rows[args.skip.saturating_sub(1)..]);
    let report = Report {
        config: args.config.display().to_string(),
        engine: pipelined.engine.clone(),
        threads: config.threads,
        samples_per_iter: config.samples_per_iter,
        phases,
        sequential_s: per_iteration(&sequential.rows[args.skip.saturating_sub(1)..]),
        pipelined_s,
        raw_env_steps_per_s: raw,
        physics_floor_s,
        gemm_gflops_one_thread: gemm_rate,
        compute_floor_s,
        ratio_physics: pipelined_s / physics_floor_s,
        ratio_floors: pipelined_s / (physics_floor_s + compute_floor_s),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print(&report, args);
    }
    Ok(())
}

fn print(r: &Report, args: &IterationBenchArgs) {
    println!(
        "{} on {}, {} threads, {} samples per iteration; medians of iterations {}..{}",
        r.config,
        r.engine,
        r.threads,
        r.samples_per_iter,
        args.skip,
        args.iterations - 1
    );
    println!(
        "{:18} {:>12} {:>8} {:>10}",
        "step (sequential)", "seconds", "GFLOP", "GFLOP/s"
    );
    for p in &r.phases {
        println!(
            "{:18} {:>12.3} {:>8.1} {:>10.1}",
            p.phase,
            p.seconds,
            p.gflop,
            if p.seconds > 0.0 {
                p.gflop / p.seconds
            } else {
                0.0
            }
        );
    }
    println!(
        "iteration: {:.2} s sequential, {:.2} s pipelined",
        r.sequential_s, r.pipelined_s
    );
    println!(
        "physics floor: {} steps / {:.0} raw env steps/s / {} threads = {:.2} s",
        r.samples_per_iter, r.raw_env_steps_per_s, r.threads, r.physics_floor_s
    );
    println!(
        "compute floor: {:.1} GFLOP / {:.1} GFLOP/s (GEMM, one thread) / {} threads = {:.2} s",
        r.phases.iter().map(|p| p.gflop).sum::<f64>(),
        r.gemm_gflops_one_thread,
        r.threads,
        r.compute_floor_s
    );
    println!(
        "pipelined iteration / physics floor = {:.2}; / (physics + compute floors) = {:.2}",
        r.ratio_physics, r.ratio_floors
    );
}

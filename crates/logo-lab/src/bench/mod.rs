//! `logo bench`: where the time goes, on the machine at hand (docs/benchmarks.md records
//! the figures and the commands).

mod envs;
mod iteration;
mod nn;

use anyhow::Result;
use clap::Subcommand;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Env steps/s vs a raw mj_step loop (single thread), and the vectorised throughput.
    Envs(envs::EnvBenchArgs),
    /// Policy latency, forward+backward and F·v at a training batch, float64 and float32.
    Nn(nn::NnBenchArgs),
    /// Per-phase medians of a training iteration, its FLOPs, and the physics and compute
    /// floors beside it.
    Iteration(iteration::IterationBenchArgs),
}

pub fn run(cmd: &BenchCommand) -> Result<()> {
    match cmd {
        BenchCommand::Envs(args) => envs::run(args),
        BenchCommand::Nn(args) => nn::run(args),
        BenchCommand::Iteration(args) => iteration::run(args),
    }
}

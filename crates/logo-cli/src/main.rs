//! `logo`: the one command of logo-rl.

mod bench;
mod bench_nn;
mod rollout;
mod train;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "logo",
    version,
    about = "LOGO: reinforcement learning under sparse rewards with offline guidance"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the environment ids with their dimensions.
    Envs,
    /// Train TRPO or LOGO from a TOML config (configs/).
    Train(train::TrainArgs),
    /// Run episodes with a fixed (random or zero) policy and print dense and sparse returns.
    Rollout(rollout::RolloutArgs),
    /// Measure throughput (see docs/benchmarks.md).
    #[command(subcommand)]
    Bench(bench::BenchCommand),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Envs => rollout::list_envs(),
        Command::Rollout(args) => rollout::run(&args),
        Command::Train(args) => train::run(&args),
        Command::Bench(cmd) => bench::run(&cmd),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

//! What a sweep runs: its arguments, the runs (configuration × seed) it plans, and
//! each run's folder, state and `logo train` command.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use anyhow::{Context, Result, bail, ensure};
use clap::Args;
use logo_algo::TrainConfig;
use logo_nn::Checkpoint;
use serde::{Deserialize, Serialize};

use logo_engine::EngineArgs;

#[derive(Args)]
pub struct SweepArgs {
    /// Training configs (TOML).
    #[arg(required = true)]
    pub(crate) configs: Vec<PathBuf>,
    /// Seeds: a range `0..5` (5 excluded), `0..=4`, a list `0,2,7`, or one seed.
    #[arg(long, default_value = "0..5")]
    pub(crate) seeds: String,
    /// The sweep's folder.
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Runs at a time (local mode).
    #[arg(long, default_value_t = 1)]
    pub(crate) jobs: usize,
    /// Threads for all runs together (default: the machine's cores), split evenly
    /// between the jobs; each Slurm task gets this many CPUs divided by --jobs.
    #[arg(long)]
    pub(crate) threads: Option<usize>,
    /// Overrides every config's number of iterations.
    #[arg(long)]
    pub(crate) iterations: Option<usize>,
    /// Write a Slurm job array (`<out>/sweep.sbatch`) instead of running locally.
    #[arg(long)]
    pub(crate) slurm: bool,
    /// With --slurm: submit it with `sbatch`.
    #[arg(long, requires = "slurm")]
    pub(crate) submit: bool,
    /// With --slurm: the partition (`#SBATCH --partition`).
    #[arg(long, requires = "slurm")]
    pub(crate) partition: Option<String>,
    /// With --slurm: each task's time limit (`#SBATCH --time`, e.g. 04:00:00).
    #[arg(long, requires = "slurm")]
    pub(crate) time: Option<String>,
    /// Seconds between progress lines (local mode).
    #[arg(long, default_value_t = 30)]
    pub(crate) progress_every: u64,
    #[command(flatten)]
    pub(crate) engine: EngineArgs,
}

/// One run of a sweep: everything a `logo train` process needs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSpec {
    pub name: String,
    pub config: PathBuf,
    pub seed: u64,
    pub dir: PathBuf,
    /// The run's length: `--iterations`, else the config's.
    pub iterations: usize,
    /// `--threads` and RAYON_NUM_THREADS of the process.
    pub threads: usize,
    /// Engine flags passed on to `logo train`.
    pub engine_args: Vec<String>,
}

/// Where a run stands on disk.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunState {
    /// No checkpoint: start (afresh).
    New,
    /// A checkpoint before the last iteration: `--resume`.
    Interrupted(usize),
    /// A checkpoint at the last iteration.
    Done,
}

/// The seeds of `--seeds`.
pub fn parse_seeds(text: &str) -> Result<Vec<u64>> {
    let bad = || {
        format!(
            "--seeds {text:?}: expected a range like 0..5 or 0..=4, a list like 0,2,7, or one seed"
        )
    };
    let seeds: Vec<u64> = if let Some((a, b)) = text.split_once("..=") {
        let (a, b): (u64, u64) = (
            a.trim().parse().with_context(bad)?,
            b.trim().parse().with_context(bad)?,
        );
        (a..=b).collect()
    } else if let Some((a, b)) = text.split_once("..") {
        let (a, b): (u64, u64) = (
            a.trim().parse().with_context(bad)?,
            b.trim().parse().with_context(bad)?,
        );
        (a..b).collect()
    } else {
        text.split(',')
            .map(|s| s.trim().parse::<u64>().with_context(bad))
            .collect::<Result<_>>()?
    };
    ensure!(!seeds.is_empty(), "--seeds {text:?} selects no seed");
    let mut unique = seeds.clone();
    unique.sort_unstable();
    unique.dedup();
    ensure!(
        unique.len() == seeds.len(),
        "--seeds {text:?} repeats a seed"
    );
    Ok(seeds)
}

/// Each config's run name: its stem, or `<parent>-<stem>` where stems collide.
fn run_names(configs: &[PathBuf]) -> Result<Vec<String>> {
    let stem = |p: &Path| p.file_stem().map(|s| s.to_string_lossy().into_owned());
    let parent = |p: &Path| {
        p.parent()
            .and_then(|d| d.file_name())
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let names: Vec<String> = configs
        .iter()
        .map(|c| {
            let s = stem(c).with_context(|| format!("{}: not a file name", c.display()))?;
            let shared = configs
                .iter()
                .filter(|o| stem(o).as_deref() == Some(&s))
                .count()
                > 1;
            Ok(if shared {
                format!("{}-{s}", parent(c))
            } else {
                s
            })
        })
        .collect::<Result<_>>()?;
    for (i, n) in names.iter().enumerate() {
        if names[..i].contains(n) {
            bail!("two configs would share the run folder {n:?}: give them different names");
        }
    }
    Ok(names)
}

/// The runs of a sweep, checking every config first (a bad one stops the sweep before
/// anything runs, naming the file and the key).
pub fn plan(args: &SweepArgs) -> Result<Vec<RunSpec>> {
    ensure!(args.jobs >= 1, "--jobs must be at least 1");
    if let Some(i) = args.iterations {
        ensure!(i >= 1, "--iterations must be at least 1");
    }
    let seeds = parse_seeds(&args.seeds)?;
    let total_threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    ensure!(total_threads >= 1, "--threads must be at least 1");
    let threads = (total_threads / args.jobs).max(1);
    let names = run_names(&args.configs)?;
    let mut runs = Vec::new();
    for (config, name) in args.configs.iter().zip(names) {
        let loaded = TrainConfig::load(config)?;
        let config = std::path::absolute(config)?;
        for &seed in &seeds {
            runs.push(RunSpec {
                dir: std::path::absolute(args.out.join(&name).join(format!("seed{seed}")))?,
                name: name.clone(),
                config: config.clone(),
                seed,
                iterations: args.iterations.unwrap_or(loaded.iterations),
                threads,
                engine_args: args.engine.to_args(),
            });
        }
    }
    Ok(runs)
}

impl RunSpec {
    pub fn checkpoint(&self) -> PathBuf {
        self.dir.join(logo_algo::run_dir::CHECKPOINT)
    }

    pub fn log(&self) -> PathBuf {
        self.dir.join("train.log")
    }

    /// Where the run stands: from its checkpoint's iteration.
    pub fn state(&self) -> Result<RunState> {
        let path = self.checkpoint();
        if !path.exists() {
            return Ok(RunState::New);
        }
        let iteration = Checkpoint::load(&path)?.meta.iteration as usize;
        Ok(if iteration >= self.iterations {
            RunState::Done
        } else {
            RunState::Interrupted(iteration)
        })
    }

    /// Iterations finished so far (rows of metrics.csv), for the progress line.
    pub(super) fn rows(&self) -> usize {
        std::fs::read_to_string(self.dir.join("metrics.csv"))
            .map_or(0, |t| t.lines().count().saturating_sub(1))
    }

    /// The `logo train` command that starts or resumes this run.
    pub fn command(&self, logo: &Path, state: RunState) -> Command {
        let mut cmd = Command::new(logo);
        cmd.arg("train");
        match state {
            RunState::Interrupted(_) => {
                cmd.arg("--resume").arg(&self.dir);
            }
            _ => {
                cmd.arg("--config")
                    .arg(&self.config)
                    .arg("--seed")
                    .arg(self.seed.to_string())
                    .arg("--out")
                    .arg(&self.dir)
                    .arg("--threads")
                    .arg(self.threads.to_string());
            }
        }
        cmd.arg("--iterations")
            .arg(self.iterations.to_string())
            .args(&self.engine_args)
            .env("RAYON_NUM_THREADS", self.threads.to_string());
        cmd
    }

    /// Starts (or resumes) the run as a child process logging into `train.log`; `None`
    /// when it is already done.
    pub fn spawn(&self, logo: &Path) -> Result<Option<Child>> {
        let state = self.state()?;
        if state == RunState::Done {
            return Ok(None);
        }
        std::fs::create_dir_all(&self.dir).with_context(|| format!("{}", self.dir.display()))?;
        let log = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(self.log())
            .with_context(|| format!("{}", self.log().display()))?;
        let child = self
            .command(logo, state)
            .stdout(log.try_clone()?)
            .stderr(log)
            .stdin(Stdio::null())
            .spawn()
            .with_context(|| format!("starting {}", logo.display()))?;
        Ok(Some(child))
    }

    pub(super) fn label(&self) -> String {
        format!("{}/seed{}", self.name, self.seed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_parse_as_ranges_and_lists() {
        assert_eq!(parse_seeds("0..5").unwrap(), vec![0, 1, 2, 3, 4]);
        assert_eq!(parse_seeds("2..=4").unwrap(), vec![2, 3, 4]);
        assert_eq!(parse_seeds("0, 2,7").unwrap(), vec![0, 2, 7]);
        assert_eq!(parse_seeds("9").unwrap(), vec![9]);
        for bad in ["", "a..3", "5..5", "1,1", "-1", "0..x"] {
            assert!(parse_seeds(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn run_names_are_stems_unless_two_configs_share_one() {
        let names = run_names(&[
            PathBuf::from("configs/logo/hopper.toml"),
            PathBuf::from("configs/trpo/hopper.toml"),
            PathBuf::from("configs/logo/walker2d.toml"),
        ])
        .unwrap();
        assert_eq!(names, ["logo-hopper", "trpo-hopper", "walker2d"]);
        let same = run_names(&[PathBuf::from("a/x.toml"), PathBuf::from("a/x.toml")]);
        assert!(same.is_err());
    }
}

//! `logo sweep`: configurations × seeds, each run a `logo train` process in
//! `<out>/<name>/seed<N>/` (config, metrics, checkpoint, `train.log`). Run again, it skips
//! finished runs and resumes interrupted ones. Locally it runs `--jobs` at a time with a
//! progress line; with `--slurm` it writes (and with `--submit` submits) a Slurm job array,
//! one task per run, whose tasks do the same skip-or-resume.
//!
//! `<name>` is the config file's stem, or `<parent>-<stem>` when two configs of the sweep
//! share a stem (`configs/logo/hopper.toml` and `configs/trpo/hopper.toml` give
//! `logo-hopper` and `trpo-hopper`).

mod plan;
mod slurm;

use std::path::PathBuf;
use std::process::{Child, ExitStatus};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail, ensure};
use clap::Args;

use plan::{RunSpec, plan};
pub use plan::{SweepArgs, parse_seeds};

/// What happened to each run of a local sweep.
enum Outcome {
    Skipped,
    Finished,
    Failed(String),
}

pub fn run(args: &SweepArgs) -> Result<()> {
    let runs = plan(args)?;
    std::fs::create_dir_all(&args.out).with_context(|| format!("{}", args.out.display()))?;
    let logo = std::env::current_exe().context("the path of this logo binary")?;
    if args.slurm {
        return slurm::write_array(args, &runs, &logo);
    }
    println!(
        "sweep: {} runs ({} configs x {} seeds) in {}, {} at a time, {} threads each",
        runs.len(),
        args.configs.len(),
        runs.len() / args.configs.len(),
        args.out.display(),
        args.jobs,
        runs[0].threads
    );
    let started = Instant::now();
    let mut pending: Vec<usize> = (0..runs.len()).rev().collect();
    let mut running: Vec<(usize, Child)> = Vec::new();
    // Rows each run had when this invocation started it: the ETA counts only rows made here.
    let mut rows_at_start: Vec<Option<usize>> = vec![None; runs.len()];
    let mut outcomes: Vec<Option<Outcome>> = (0..runs.len()).map(|_| None).collect();
    let mut last_progress = Instant::now();
    loop {
        while running.len() < args.jobs {
            let Some(i) = pending.pop() else { break };
            let spec = &runs[i];
            match spec.spawn(&logo) {
                Ok(None) => outcomes[i] = Some(Outcome::Skipped),
                Ok(Some(child)) => {
                    println!(
                        "[sweep] started {} ({})",
                        spec.label(),
                        spec.log().display()
                    );
                    rows_at_start[i] = Some(spec.rows());
                    running.push((i, child));
                }
                Err(e) => {
                    println!("[sweep] FAILED to start {}: {e:#}", spec.label());
                    outcomes[i] = Some(Outcome::Failed(format!("{e:#}")));
                }
            }
        }
        if running.is_empty() && pending.is_empty() {
            break;
        }
        let mut k = 0;
        while k < running.len() {
            let (i, child) = &mut running[k];
            match child.try_wait()? {
                Some(status) => {
                    let i = *i;
                    outcomes[i] = Some(finished(&runs[i], status));
                    running.remove(k);
                }
                None => k += 1,
            }
        }
        if last_progress.elapsed() >= Duration::from_secs(args.progress_every.max(1)) {
            last_progress = Instant::now();
            println!(
                "{}",
                progress(&runs, &outcomes, &rows_at_start, &running, started)
            );
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    summary(&runs, &outcomes, started)
}

/// The outcome of a finished child, and its line.
fn finished(spec: &RunSpec, status: ExitStatus) -> Outcome {
    if status.success() {
        println!("[sweep] finished {}", spec.label());
        Outcome::Finished
    } else {
        let why = format!("{status}; log: {}", spec.log().display());
        println!("[sweep] FAILED {}: {why}", spec.label());
        Outcome::Failed(why)
    }
}

/// "3/10 runs done, 2 running (a/seed3 120/500, b/seed0 80/500), 0 failed, ETA 4m 10s":
/// the ETA from the iterations done in this invocation per second, over the iterations
/// left.
fn progress(
    runs: &[RunSpec],
    outcomes: &[Option<Outcome>],
    rows_at_start: &[Option<usize>],
    running: &[(usize, Child)],
    started: Instant,
) -> String {
    let done = outcomes
        .iter()
        .filter(|o| matches!(o, Some(Outcome::Finished | Outcome::Skipped)))
        .count();
    let failed = outcomes
        .iter()
        .filter(|o| matches!(o, Some(Outcome::Failed(_))))
        .count();
    // Each run's metrics read once: the ETA and the running runs' places share them.
    let rows: Vec<usize> = runs.iter().map(RunSpec::rows).collect();
    let (made, left) = made_and_left(runs.iter().enumerate().map(|(i, spec)| RunProgress {
        rows: rows[i].min(spec.iterations),
        iterations: spec.iterations,
        at_start: rows_at_start[i],
        open: outcomes[i].is_none(),
    }));
    let elapsed = started.elapsed().as_secs_f64();
    let eta = if made > 0 {
        let seconds = elapsed / made as f64 * left as f64;
        format!(
            "ETA {}m {:02}s",
            (seconds / 60.0) as u64,
            seconds as u64 % 60
        )
    } else {
        "ETA unknown".into()
    };
    let mut where_running = running
        .iter()
        .map(|(i, _)| {
            let spec = &runs[*i];
            format!("{} {}/{}", spec.label(), rows[*i], spec.iterations)
        })
        .collect::<Vec<_>>()
        .join(", ");
    if !where_running.is_empty() {
        where_running = format!(" ({where_running})");
    }
    format!(
        "[sweep] {done}/{} runs done, {} running{where_running}, {failed} failed, {eta} ({:.0} s elapsed)",
        runs.len(),
        running.len(),
        elapsed
    )
}

/// One run as the ETA sees it.
struct RunProgress {
    /// Iterations in its metrics now.
    rows: usize,
    iterations: usize,
    /// Iterations it had when this invocation started it; None if it was not started here.
    at_start: Option<usize>,
    /// Neither finished, skipped nor failed.
    open: bool,
}

/// Iterations made by this invocation, and iterations still to make. What a resumed run
/// had made before it was started here is not this invocation's speed: counting it made
/// a sweep resumed near the end of two runs promise minutes for hours of work.
fn made_and_left(runs: impl IntoIterator<Item = RunProgress>) -> (usize, usize) {
    let (mut made, mut left) = (0, 0);
    for run in runs {
        if let Some(at_start) = run.at_start {
            made += run.rows.saturating_sub(at_start);
        }
        if run.open {
            left += run.iterations.saturating_sub(run.rows);
        }
    }
    (made, left)
}

fn summary(runs: &[RunSpec], outcomes: &[Option<Outcome>], started: Instant) -> Result<()> {
    let mut failed = Vec::new();
    let (mut finished, mut skipped) = (0, 0);
    for (spec, outcome) in runs.iter().zip(outcomes) {
        match outcome {
            Some(Outcome::Finished) => finished += 1,
            Some(Outcome::Skipped) => skipped += 1,
            Some(Outcome::Failed(why)) => failed.push(format!("{}: {why}", spec.label())),
            None => failed.push(format!("{}: never ran", spec.label())),
        }
    }
    println!(
        "sweep: {finished} finished, {skipped} already done, {} failed in {:.0} s",
        failed.len(),
        started.elapsed().as_secs_f64()
    );
    if !failed.is_empty() {
        bail!("{} runs failed:\n  {}", failed.len(), failed.join("\n  "));
    }
    Ok(())
}

/// `logo sweep-task PLAN INDEX`: one run of a written plan (a Slurm array task),
/// started or resumed, in the foreground.
#[derive(Args)]
pub struct TaskArgs {
    plan: PathBuf,
    index: usize,
}

pub fn run_task(args: &TaskArgs) -> Result<()> {
    let text =
        std::fs::read_to_string(&args.plan).with_context(|| format!("{}", args.plan.display()))?;
    let runs: Vec<RunSpec> = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a sweep plan", args.plan.display()))?;
    let spec = runs.get(args.index).with_context(|| {
        format!(
            "{}: task {} of a plan of {} runs",
            args.plan.display(),
            args.index,
            runs.len()
        )
    })?;
    let logo = std::env::current_exe().context("the path of this logo binary")?;
    let Some(mut child) = spec.spawn(&logo)? else {
        println!("{} is done already", spec.label());
        return Ok(());
    };
    let status = child.wait()?;
    ensure!(
        status.success(),
        "{} failed ({status}); log: {}",
        spec.label(),
        spec.log().display()
    );
    println!("{} finished", spec.label());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(rows: usize, at_start: Option<usize>, open: bool) -> RunProgress {
        RunProgress {
            rows,
            iterations: 500,
            at_start,
            open,
        }
    }

    #[test]
    fn the_eta_counts_only_iterations_made_by_this_invocation() {
        let (made, left) = made_and_left([
            run(500, Some(450), false), // resumed at 450, finished here: 50 made
            run(500, None, false),      // finished before: skipped
            run(50, Some(0), true),     // started here: 50 made, 450 left
            run(0, None, true),         // pending: 500 left
        ]);
        assert_eq!((made, left), (100, 950));
    }
}

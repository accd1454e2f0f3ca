//! `logo sweep --slurm`: the sweep as a Slurm job array. One array task per run; each
//! task runs `logo sweep-task <plan> $SLURM_ARRAY_TASK_ID`, which starts the run or
//! resumes it from its checkpoint, so a preempted and requeued task (`--requeue`) carries
//! on where it stopped. The folder layout is the local sweep's.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, ensure};

use super::plan::{RunSpec, SweepArgs};

/// Writes `<out>/sweep-plan.json` and `<out>/sweep.sbatch`; submits it with `--submit`.
pub fn write_array(args: &SweepArgs, runs: &[RunSpec], logo: &Path) -> Result<()> {
    let out = std::path::absolute(&args.out)?;
    let plan = out.join("sweep-plan.json");
    std::fs::write(&plan, serde_json::to_string_pretty(runs)?)
        .with_context(|| format!("{}", plan.display()))?;
    let logs = out.join("slurm");
    std::fs::create_dir_all(&logs).with_context(|| format!("{}", logs.display()))?;
    let script = out.join("sweep.sbatch");
    std::fs::write(&script, sbatch_script(args, runs, logo, &plan, &logs))
        .with_context(|| format!("{}", script.display()))?;
    println!(
        "sweep: {} runs as a Slurm job array: {} (plan {})",
        runs.len(),
        script.display(),
        plan.display()
    );
    if !args.submit {
        println!("submit it with: sbatch {}", script.display());
        return Ok(());
    }
    let output = Command::new("sbatch")
        .arg("--parsable")
        .arg(&script)
        .output()
        .context("running sbatch (is Slurm installed and its controller up?)")?;
    ensure!(
        output.status.success(),
        "sbatch {} failed: {}",
        script.display(),
        String::from_utf8_lossy(&output.stderr).trim()
    );
    let job = String::from_utf8_lossy(&output.stdout).trim().to_string();
    println!(
        "submitted job array {job}: watch it with `squeue -j {job}`; logs in {}",
        logs.display()
    );
    Ok(())
}

/// The job array: one task per run, `--jobs` of them at a time (`%`), each with the
/// run's threads as CPUs, requeued on preemption.
pub fn sbatch_script(
    args: &SweepArgs,
    runs: &[RunSpec],
    logo: &Path,
    plan: &Path,
    logs: &Path,
) -> String {
    let mut lines = vec![
        "#!/bin/bash".to_string(),
        "# Written by `logo sweep --slurm`: one array task per run of the plan.".to_string(),
        "#SBATCH --job-name=logo-sweep".to_string(),
        format!("#SBATCH --array=0-{}%{}", runs.len() - 1, args.jobs),
        format!("#SBATCH --cpus-per-task={}", runs[0].threads),
        format!("#SBATCH --output={}/%A_%a.out", logs.display()),
        "#SBATCH --open-mode=append".to_string(),
        "#SBATCH --requeue".to_string(),
    ];
    if let Some(p) = &args.partition {
        lines.push(format!("#SBATCH --partition={p}"));
    }
    if let Some(t) = &args.time {
        lines.push(format!("#SBATCH --time={t}"));
    }
    lines.push("set -euo pipefail".to_string());
    lines.push(format!(
        "exec {:?} sweep-task {:?} \"$SLURM_ARRAY_TASK_ID\"",
        logo.display().to_string(),
        plan.display().to_string()
    ));
    lines.join("\n") + "\n"
}

//! `logo sweep --slurm --submit` against a real single-node Slurm cluster
//! (`scripts/slurm-cluster.sh`: slurm-wlm and munge from Debian, slurmctld and slurmd on
//! this machine): a 3-task job array of short training runs, waited for with `squeue`,
//! every run folder checked, the daemons stopped at the end.
//!
//! It needs root (to install and start the daemons). Where that is not possible it is
//! skipped, unless LOGO_REQUIRE_SLURM is set (CI sets it), which makes that a failure.

use logo_testkit::Tiny;
use std::path::PathBuf;
use std::process::Command;
use std::time::{Duration, Instant};

fn repo() -> PathBuf {
    logo_testkit::workspace()
}

fn cluster(action: &str) -> std::process::Output {
    Command::new(repo().join("scripts/slurm-cluster.sh"))
        .arg(action)
        .output()
        .unwrap()
}

/// Stops the daemons when the test ends, passed or failed.
struct Daemons;

impl Drop for Daemons {
    fn drop(&mut self) {
        cluster("stop");
    }
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

#[test]
fn a_sweep_runs_as_a_slurm_job_array() {
    let required = std::env::var_os("LOGO_REQUIRE_SLURM").is_some();
    if !is_root() {
        assert!(
            !required,
            "LOGO_REQUIRE_SLURM is set but this test needs root"
        );
        eprintln!("skipped: starting Slurm's daemons needs root");
        return;
    }
    let started = cluster("start");
    if !started.status.success() {
        let why = String::from_utf8_lossy(&started.stderr);
        assert!(!required, "scripts/slurm-cluster.sh start failed: {why}");
        eprintln!("skipped: no Slurm cluster: {why}");
        return;
    }
    let _daemons = Daemons;

    let dir = std::env::temp_dir().join(format!("logo-slurm-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let config = Tiny::trpo().write(&dir.join("tiny.toml"));
    let out = dir.join("sweep");
    let submitted = Command::new(env!("CARGO_BIN_EXE_logo"))
        .args([
            "sweep",
            config.to_str().unwrap(),
            "--seeds",
            "0..3",
            "--jobs",
            "3",
        ])
        .args([
            "--threads",
            "3",
            "--out",
            out.to_str().unwrap(),
            "--slurm",
            "--submit",
        ])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&submitted.stdout);
    assert!(
        submitted.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&submitted.stderr)
    );
    let job = stdout
        .split("submitted job array ")
        .nth(1)
        .and_then(|rest| rest.split(':').next())
        .unwrap_or_else(|| panic!("no job id in: {stdout}"))
        .trim()
        .to_string();

    // Wait until squeue no longer lists any task of the array.
    let deadline = Instant::now() + Duration::from_secs(300);
    loop {
        let queue = Command::new("squeue")
            .args(["-h", "-j", &job])
            .output()
            .unwrap();
        if String::from_utf8_lossy(&queue.stdout).trim().is_empty() {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "job {job} still queued after 300 s"
        );
        std::thread::sleep(Duration::from_millis(500));
    }

    // Every task completed, and every run folder holds the whole run.
    let jobs = Command::new("scontrol")
        .args(["show", "job", &job])
        .output()
        .unwrap();
    let jobs = String::from_utf8_lossy(&jobs.stdout);
    assert_eq!(jobs.matches("JobState=COMPLETED").count(), 3, "{jobs}");
    for seed in 0..3 {
        let run = out.join("tiny").join(format!("seed{seed}"));
        let metrics = std::fs::read_to_string(run.join("metrics.csv")).unwrap();
        assert_eq!(
            metrics.lines().count(),
            3,
            "{}: a header and 2 rows",
            run.display()
        );
        assert!(run.join("checkpoint.safetensors").is_file());
        let log = std::fs::read_to_string(run.join("train.log")).unwrap();
        assert!(log.contains("done in"), "{}: {log}", run.display());
    }
    let script = std::fs::read_to_string(out.join("sweep.sbatch")).unwrap();
    assert!(script.contains("#SBATCH --array=0-2%3") && script.contains("#SBATCH --requeue"));
}

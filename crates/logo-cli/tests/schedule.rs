//! The pipelined schedule computes exactly what the sequential one does, at one thread
//! and at two, and a pipelined run killed (SIGKILL) at any moment resumes to the same
//! final checkpoint and metrics as one never interrupted, on its own float type.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use logo_nn::Checkpoint;
use logo_testkit::{Tiny, metrics_without_timings, scratch};

fn logo() -> Command {
    Command::new(env!("CARGO_BIN_EXE_logo"))
}

/// Sparse IDP LOGO at a small size; `variant` adds tables (minibatched kinds draw from
/// the random streams of both the policy steps and the critic fits).
fn config(dir: &Path, variant: &str) -> PathBuf {
    Tiny::logo()
        .lbfgs(4)
        .with("iterations = 6\nsamples_per_iter = 400\nnum_envs = 3\neval_steps = 120")
        .with("checkpoint_every = 2\nseed = 5\n[guidance]\nwarmup = 1")
        .with(variant)
        .write(&dir.join("config.toml"))
}

const PPO_ADAM: &str = r#"
[improvement]
kind = "ppo-clip"
epochs = 2
minibatch = 64
[guidance.critic]
hidden = [16, 16]
fit = { method = "adam", epochs = 2, minibatch = 64 }
"#;

fn train(config: &Path, out: &Path, extra: &[&str]) {
    let status = logo()
        .args(["train", "--config", config.to_str().unwrap()])
        .args(["--out", out.to_str().unwrap()])
        .args(extra)
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(
        status.success(),
        "logo train {extra:?} into {}",
        out.display()
    );
}

/// The final checkpoint: every tensor's values, and the metadata with the run's thread
/// count left out (it is in the config it records).
fn checkpoint(dir: &Path) -> (Vec<(String, Vec<f64>)>, serde_json::Value) {
    let ckpt = Checkpoint::load(&dir.join("checkpoint.safetensors")).unwrap();
    let tensors = ckpt
        .tensor_names()
        .map(|name| (name.to_string(), ckpt.tensor(name).unwrap().1.to_vec()))
        .collect();
    let mut meta = serde_json::to_value(&ckpt.meta).unwrap();
    meta["extra"]["config"]
        .as_object_mut()
        .unwrap()
        .remove("threads");
    (tensors, meta)
}

fn same_bits(a: &[(String, Vec<f64>)], b: &[(String, Vec<f64>)]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|((na, va), (nb, vb))| {
            na == nb
                && va.len() == vb.len()
                && va.iter().zip(vb).all(|(x, y)| x.to_bits() == y.to_bits())
        })
}

fn check_schedules(name: &str, variant: &str) {
    let dir = scratch(name);
    let config = config(&dir, variant);
    let runs = [
        ("sequential", "1"),
        ("sequential", "2"),
        ("pipelined", "1"),
        ("pipelined", "2"),
    ];
    let outs: Vec<PathBuf> = runs
        .iter()
        .map(|(schedule, threads)| {
            let out = dir.join(format!("{schedule}-{threads}"));
            train(
                &config,
                &out,
                &["--schedule", schedule, "--threads", threads],
            );
            out
        })
        .collect();
    let (reference, reference_meta) = checkpoint(&outs[0]);
    assert_eq!(
        metrics_without_timings(&outs[0]).len(),
        7,
        "a header and 6 rows"
    );
    for (out, run) in outs.iter().zip(&runs).skip(1) {
        assert_eq!(
            metrics_without_timings(out),
            metrics_without_timings(&outs[0]),
            "{name}: {run:?}"
        );
        let (tensors, meta) = checkpoint(out);
        assert!(same_bits(&tensors, &reference), "{name}: {run:?} tensors");
        assert_eq!(meta, reference_meta, "{name}: {run:?} metadata");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_pipelined_schedule_gives_the_sequential_ones_bits_at_one_and_two_threads() {
    check_schedules("logo", "");
}

#[test]
fn so_it_does_where_the_policy_steps_and_critic_fits_draw_random_streams() {
    check_schedules("ppo-adam", PPO_ADAM);
}

/// Rows written to `dir`'s metrics.csv so far.
fn rows_written(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("metrics.csv"))
        .map_or(0, |csv| csv.lines().count().saturating_sub(1))
}

#[test]
fn a_pipelined_run_killed_at_any_moment_resumes_to_the_same_end() {
    let dir = scratch("kill");
    let config = config(&dir, "");
    let text = std::fs::read_to_string(&config)
        .unwrap()
        .replace("iterations = 6", "iterations = 14");
    std::fs::write(&config, text).unwrap();
    let whole = dir.join("whole");
    train(&config, &whole, &[]);
    let expected = (metrics_without_timings(&whole), checkpoint(&whole));

    // Kill once the run has written `rows` rows, `delay` later: before the first
    // checkpoint, right after one, mid-iteration while the next batch is sampled beside
    // the critic fits, and so on.
    let (mut killed_mid_run, mut resumed) = (0, 0);
    for (i, (rows, delay_ms)) in [(0, 5), (2, 0), (3, 1), (5, 7), (8, 3), (11, 12)]
        .into_iter()
        .enumerate()
    {
        let out = dir.join(format!("killed-{i}"));
        let mut child = logo()
            .args(["train", "--config", config.to_str().unwrap()])
            .args(["--out", out.to_str().unwrap()])
            .stdout(Stdio::null())
            .spawn()
            .unwrap();
        while rows_written(&out) < rows && child.try_wait().unwrap().is_none() {
            std::thread::sleep(Duration::from_millis(1));
        }
        std::thread::sleep(Duration::from_millis(delay_ms));
        child.kill().unwrap(); // SIGKILL
        if !child.wait().unwrap().success() {
            killed_mid_run += 1;
        }
        // What a user (or `logo sweep`) does next: resume where a checkpoint was written,
        // start afresh where none was.
        if out.join("checkpoint.safetensors").exists() {
            let status = logo()
                .args(["train", "--resume", out.to_str().unwrap()])
                .stdout(Stdio::null())
                .status()
                .unwrap();
            assert!(status.success(), "resume after a kill at row {rows}");
            resumed += 1;
        } else {
            train(&config, &out, &[]);
        }
        let (got_rows, (tensors, meta)) = (metrics_without_timings(&out), checkpoint(&out));
        assert_eq!(got_rows, expected.0, "killed after row {rows}");
        assert!(
            same_bits(&tensors, &expected.1.0),
            "killed after row {rows}"
        );
        assert_eq!(meta, expected.1.1, "killed after row {rows}");
    }
    assert!(
        killed_mid_run >= 5 && resumed >= 4,
        "of 6 kills {killed_mid_run} hit the run while it ran, {resumed} after a checkpoint"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_resume_without_engine_flags_keeps_the_runs_float_type() {
    // A float32 run stopped after 4 iterations and resumed with no engine flag ends as
    // the same run never stopped: it does not slip into the float64 default.
    let dir = scratch("float32");
    let config = config(&dir, "");
    let (whole, parts) = (dir.join("whole"), dir.join("parts"));
    train(&config, &whole, &["--dtype", "f32", "--no-tensorboard"]);
    let four = ["--dtype", "f32", "--iterations", "4", "--no-tensorboard"];
    train(&config, &parts, &four);
    let resumed = logo()
        .args(["train", "--resume", parts.to_str().unwrap()])
        .args(["--iterations", "6"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&resumed.stdout);
    assert!(resumed.status.success(), "{stdout}");
    assert!(stdout.contains("continuing on kernels f32"), "{stdout}");
    assert_eq!(
        metrics_without_timings(&parts),
        metrics_without_timings(&whole)
    );
    // A flag still chooses another engine, and then nothing is said of the old one.
    let again = logo()
        .args(["train", "--resume", parts.to_str().unwrap()])
        .args(["--iterations", "7", "--dtype", "f64"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&again.stdout);
    assert!(
        again.status.success()
            && !stdout.contains("continuing on")
            && stdout.contains("kernels f64"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

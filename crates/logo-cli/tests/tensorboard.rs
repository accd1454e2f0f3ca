//! A run's TensorBoard event file, read by TensorBoard's own reader (Python's
//! `tensorboard` package in the test venv, `tests/python/tensorboard_events.py`): every
//! numeric metrics.csv column as a scalar with the samples as its step and the same
//! values (as float32), the config as text; after a kill and a resume, the same again,
//! with no step twice.

use logo_testkit::{Tiny, python};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

type Scalars = BTreeMap<String, Vec<(f64, f64)>>;

/// What TensorBoard reads in `run`: the scalars by tag, and the text summaries.
fn read_events(python: &Path, run: &Path) -> (Scalars, BTreeMap<String, Vec<String>>) {
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/tensorboard_events.py");
    let out = Command::new(python).arg(script).arg(run).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let scalars = json["scalars"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(tag, points)| {
            let points = points
                .as_array()
                .unwrap()
                .iter()
                .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
                .collect();
            (tag.clone(), points)
        })
        .collect();
    let text = serde_json::from_value(json["text"].clone()).unwrap();
    (scalars, text)
}

/// metrics.csv's numeric columns: column → [(samples, value)] over the rows where the
/// value is a finite number.
fn metrics(run: &Path) -> Scalars {
    let mut reader = csv::Reader::from_path(run.join("metrics.csv")).unwrap();
    let headers = reader.headers().unwrap().clone();
    let samples_at = headers.iter().position(|h| h == "samples").unwrap();
    let mut columns = Scalars::new();
    for record in reader.records() {
        let record = record.unwrap();
        let samples: f64 = record[samples_at].parse().unwrap();
        for (name, field) in headers.iter().zip(record.iter()) {
            if let Ok(v) = field.parse::<f64>()
                && v.is_finite()
            {
                columns
                    .entry(name.to_string())
                    .or_default()
                    .push((samples, v));
            }
        }
    }
    columns
}

/// The event file holds metrics.csv's rows; `killed`: all of them but perhaps the last,
/// which a kill can catch written to metrics.csv and not yet to the event file.
fn check(python: &Path, run: &Path, killed: bool) {
    let (scalars, text) = read_events(python, run);
    let expected = metrics(run);
    assert_eq!(
        scalars.keys().collect::<Vec<_>>(),
        expected.keys().collect::<Vec<_>>(),
        "one scalar per numeric column"
    );
    for (tag, points) in &expected {
        let got = &scalars[tag];
        let short = points.len() - got.len().min(points.len());
        assert!(
            got.len() <= points.len() && short <= usize::from(killed),
            "{tag}: {} points for {} rows (a point per row, none twice)",
            got.len(),
            points.len()
        );
        for ((gs, gv), (s, v)) in got.iter().zip(points) {
            assert_eq!(gs, s, "{tag}: the step is the sample count");
            assert_eq!(*gv, *v as f32 as f64, "{tag} at {s}");
        }
    }
    let config = std::fs::read_to_string(run.join("config.toml")).unwrap();
    assert_eq!(text["config"], vec![config]);
}

#[test]
fn tensorboard_reads_the_runs_metrics_also_after_a_kill_and_a_resume() {
    let Some(python) = python() else { return };
    let dir = std::env::temp_dir().join(format!("logo-tensorboard-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let config = Tiny::logo()
        .lbfgs(4)
        .with("iterations = 12\nsamples_per_iter = 1000\nnum_envs = 3\neval_every = 2")
        .with("checkpoint_every = 4\n[guidance]\nwarmup = 1")
        .write(&dir.join("tiny.toml"));
    let run = dir.join("run");
    let logo = || Command::new(env!("CARGO_BIN_EXE_logo"));
    let mut child = logo()
        .args(["train", "--config", config.to_str().unwrap()])
        .args(["--out", run.to_str().unwrap()])
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    // Killed after 6 rows: the checkpoint is iteration 4's, rows 4 and 5 are redone.
    let rows = || {
        std::fs::read_to_string(run.join("metrics.csv"))
            .map_or(0, |t| t.lines().count().saturating_sub(1))
    };
    while rows() < 6 && child.try_wait().unwrap().is_none() {
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    assert!(
        !child.wait().unwrap().success(),
        "the run was killed mid-way"
    );
    check(&python, &run, true);
    let resumed = logo()
        .args(["train", "--resume", run.to_str().unwrap()])
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(resumed.success());
    let files: Vec<_> = std::fs::read_dir(&run)
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            name.starts_with("events.out.tfevents.").then_some(name)
        })
        .collect();
    assert_eq!(files.len(), 1, "one event file: {files:?}");
    check(&python, &run, false);
    assert_eq!(metrics(&run)["iteration"].len(), 12);

    // --no-tensorboard writes none.
    let plain = dir.join("plain");
    let status = logo()
        .args([
            "train",
            "--config",
            config.to_str().unwrap(),
            "--iterations",
            "1",
        ])
        .args(["--out", plain.to_str().unwrap(), "--no-tensorboard"])
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    assert!(!std::fs::read_dir(&plain).unwrap().any(|e| {
        e.unwrap()
            .file_name()
            .to_string_lossy()
            .contains("tfevents")
    }));
    std::fs::remove_dir_all(&dir).unwrap();
}

//! The LOGO reference's BC policies import with the right sizes, and the imported network
//! computes what an independent reader of the same file computes
//! (`tests/python/torch_policy_forward.py`: zipfile + pickle + numpy, no torch, no Rust).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use logo_nn::flat::{from_f64, to_f64};
use logo_nn::{Cpu, load_reference_policy};
use logo_testkit::python;

fn repo() -> PathBuf {
    logo_testkit::workspace()
}

/// The reference data lives beside the checkout (`../shared`), as on CI.
fn reference_dir() -> Option<PathBuf> {
    let dir = repo().join("../shared/reference/logo-demos");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipped: {} is not there", dir.display());
        None
    }
}

#[test]
fn reference_bc_policies_match_an_independent_reader() {
    let (Some(dir), Some(python)) = (reference_dir(), python()) else {
        return;
    };
    let device = Default::default();
    for (env, obs_dim, act_dim) in [
        ("hopper", 11, 3),
        ("walker2d", 17, 6),
        ("halfcheetah", 17, 6),
        ("inverted_double_pendulum", 11, 1),
    ] {
        let path = dir.join(format!("{env}_bc_policy.pt"));
        let policy = load_reference_policy::<Cpu>(&path, &device).unwrap();
        assert_eq!(
            (policy.obs_dim(), policy.act_dim()),
            (obs_dim, act_dim),
            "{env}"
        );

        let rows = 16;
        let obs: Vec<f64> = (0..rows * obs_dim)
            .map(|k| 1.5 * ((k as f64) * 0.37).sin())
            .collect();
        let ours = to_f64(policy.mean_action(from_f64(&obs, [rows, obs_dim], &device)));
        let ours_log_std = to_f64(policy.log_std.val());

        let json_rows: Vec<Vec<f64>> = obs.chunks(obs_dim).map(<[f64]>::to_vec).collect();
        let mut child = Command::new(&python)
            .arg(repo().join("tests/python/torch_policy_forward.py"))
            .arg(&path)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        child
            .stdin
            .take()
            .unwrap()
            .write_all(serde_json::to_string(&json_rows).unwrap().as_bytes())
            .unwrap();
        let out = child.wait_with_output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let theirs: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let theirs_mean: Vec<f64> = theirs["mean"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|r| r.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()))
            .collect();
        let theirs_log_std: Vec<f64> = theirs["log_std"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(ours_log_std, theirs_log_std, "{env}: log_std");
        let worst = ours
            .iter()
            .zip(&theirs_mean)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "{env}: mean actions differ by {worst:e}");
        assert_eq!(ours.len(), theirs_mean.len());
    }
}

#[test]
fn a_file_that_is_not_a_policy_is_a_clear_error() {
    let device = Default::default();
    let missing =
        load_reference_policy::<Cpu>(Path::new("/nonexistent/policy.pt"), &device).unwrap_err();
    assert!(
        missing.to_string().contains("/nonexistent/policy.pt"),
        "{missing}"
    );
    let dir = std::env::temp_dir().join(format!("logo-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let junk = dir.join("junk.pt");
    std::fs::write(&junk, b"PK\x03\x04 definitely not a zip archive").unwrap();
    let err = load_reference_policy::<Cpu>(&junk, &device).unwrap_err();
    assert!(err.to_string().contains("junk.pt"), "{err}");
}

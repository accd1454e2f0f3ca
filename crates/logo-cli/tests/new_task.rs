//! `scripts/experiments/new_task.sh` on a tiny budget: a dense task to LOGO against TRPO on
//! its sparse version, every step's output where docs/new-task.md says.

use std::path::Path;
use std::process::Command;

#[test]
fn new_task_script_goes_from_a_dense_task_to_logo_and_trpo_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = std::env::temp_dir().join(format!("logo-new-task-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let script = root.join("scripts/experiments/new_task.sh");
    let run = || {
        Command::new("bash")
            .arg(&script)
            // A negative target (as Reacher's) is a value, not a flag; IDP's first
            // iteration reaches it.
            .args(["InvertedDoublePendulum-v4", "distance(0.05)", "-30"])
            .current_dir(&root)
            .env("LOGO", env!("CARGO_BIN_EXE_logo"))
            .env("OUT", &out)
            .envs([
                ("BEHAVIOUR_ITERATIONS", "3"),
                ("BEHAVIOUR_SAMPLES", "500"),
                ("EPISODES", "3"),
                ("ITERATIONS", "2"),
                ("SAMPLES", "500"),
                ("SEEDS", "0..2"),
                ("WARMUP", "0"),
                ("DELTA0", "0.2"),
                ("LOG_STD", "-0.5"),
            ])
            .output()
            .unwrap()
    };
    let first = run();
    let stderr = String::from_utf8_lossy(&first.stderr);
    assert!(first.status.success(), "{stderr}");
    // Each step prints its command.
    for step in ["train --config", "data record", "sweep", "summary", "plot"] {
        assert!(stderr.contains(step), "no `{step}` in: {stderr}");
    }
    for file in [
        "behaviour/checkpoint.safetensors",
        "demos/data/metadata.json",
        "runs/logo/seed0/metrics.csv",
        "runs/logo/seed1/eval.json",
        "runs/trpo/seed1/metrics.csv",
        "curves.png",
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    // The demonstrations were recorded on the sparse task the runs train on.
    let metadata = std::fs::read_to_string(out.join("demos/data/metadata.json")).unwrap();
    assert!(
        metadata.contains("InvertedDoublePendulum-v4+distance(0.05)"),
        "{metadata}"
    );
    let config = std::fs::read_to_string(out.join("configs/logo.toml")).unwrap();
    assert!(
        config.contains("sparse = { kind = \"distance\", threshold = 0.05 }"),
        "{config}"
    );
    assert!(config.contains("log_std_init = -0.5"), "{config}");
    let trpo = std::fs::read_to_string(out.join("configs/trpo.toml")).unwrap();
    assert!(trpo.contains("log_std_init = -0.5"), "{trpo}");
    let stdout = String::from_utf8_lossy(&first.stdout);
    assert!(stdout.contains("reached --stop-at-return -30"), "{stdout}");
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        summary.starts_with("| configuration") && summary.contains("| logo |"),
        "{summary}"
    );
    // The LOGO runs trained on the sparse kind, guided (δ_k above 0).
    let metrics = std::fs::read_to_string(out.join("runs/logo/seed0/metrics.csv")).unwrap();
    let header: Vec<&str> = metrics.lines().next().unwrap().split(',').collect();
    let delta = header.iter().position(|c| *c == "delta_k").unwrap();
    let first_row: Vec<&str> = metrics.lines().nth(1).unwrap().split(',').collect();
    assert!(first_row[delta].parse::<f64>().unwrap() > 0.0);
    // Run again: every step is found done and skipped.
    let again = run();
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{stderr}");
    assert!(!stderr.contains("train --config") && !stderr.contains("data record"));
    assert!(String::from_utf8_lossy(&again.stdout).contains("4 already done"));
    // Bad arguments: a usage error, before anything runs.
    let bad = Command::new("bash")
        .arg(&script)
        .args(["Hopper-v4", "distance(far)", "100"])
        .env("OUT", out.join("bad"))
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("number of metres"));
    assert!(!out.join("bad").exists());
    // Going on in the same folder with another rule is refused, not mixed in.
    let other = Command::new("bash")
        .arg(&script)
        .args(["InvertedDoublePendulum-v4", "delayed", "30"])
        .env("LOGO", env!("CARGO_BIN_EXE_logo"))
        .env("OUT", &out)
        .output()
        .unwrap();
    assert_eq!(other.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&other.stderr).contains("give another OUT"));
    std::fs::remove_dir_all(&out).unwrap();
}

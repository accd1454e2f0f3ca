//! Golden runs: the reference-faithful LOGO configs train to the same numbers as the
//! binary that wrote `tests/golden/` (commit 463789f, whose training code is that of
//! every kept paper-scale run: `git diff ac77080 463789f -- crates/logo-algo
//! crates/logo-nn crates/logo-envs` is empty). Sparse IDP for 6 iterations and sparse
//! Hopper for 3, in float64 and float32: every `metrics.csv` column of the golden run but
//! the timings (columns added since may follow), and every tensor of the final checkpoint
//! bit for bit (as SHA-256 digests of their values).
//! Refactors of the trainer, the envs or the engines must keep these; a change that is
//! meant to change the numbers rewrites the fixtures with `LOGO_GOLDEN_WRITE=1` and says
//! so in its commit.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use logo_nn::Checkpoint;
use sha2::{Digest, Sha256};

fn root() -> PathBuf {
    logo_testkit::workspace()
}

/// A CSV's columns by name, each with its values as written.
fn columns(csv: &str) -> Vec<(String, Vec<String>)> {
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    (0..rows[0].len())
        .map(|c| {
            let values = rows[1..].iter().map(|r| r[c].to_string()).collect();
            (rows[0][c].to_string(), values)
        })
        .collect()
}

/// One line per tensor of the final checkpoint: name, length, SHA-256 of its values'
/// little-endian bits.
fn tensors(dir: &Path) -> String {
    let ckpt = Checkpoint::load(&dir.join("checkpoint.safetensors")).unwrap();
    let mut out = String::new();
    for name in ckpt.tensor_names() {
        let values = ckpt.tensor(name).unwrap().1;
        let mut hash = Sha256::new();
        for v in values {
            hash.update(v.to_bits().to_le_bytes());
        }
        writeln!(out, "{name} {} {}", values.len(), hex(hash)).unwrap();
    }
    out
}

/// A SHA-256 digest in lowercase hex.
fn hex(hash: Sha256) -> String {
    hash.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// Trains `config` into a scratch folder (with `--dtype` where `dtype` names one); its
/// metrics (timings removed) and tensors.
fn train(name: &str, config: &str, iterations: &str, dtype: Option<&str>) -> (String, String) {
    let out = std::env::temp_dir().join(format!("logo-golden-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let status = Command::new(env!("CARGO_BIN_EXE_logo"))
        .current_dir(root())
        .args(["train", "--config", config, "--iterations", iterations])
        .args(dtype.iter().flat_map(|dtype| ["--dtype", dtype]))
        .args(["--no-tensorboard", "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "{name}: logo train failed");
    let metrics = logo_testkit::metrics_without_timings(&out)
        .into_iter()
        .map(|row| row + "\n")
        .collect();
    let tensors = tensors(&out);
    std::fs::remove_dir_all(&out).unwrap();
    (metrics, tensors)
}

fn check(name: &str, config: &str, iterations: &str, dtype: Option<&str>) {
    check_against(name, name, config, iterations, dtype);
}

/// Trains `config` as `name` and compares it with the golden run `fixture`.
fn check_against(fixture: &str, name: &str, config: &str, iterations: &str, dtype: Option<&str>) {
    let (metrics, tensors) = train(name, config, iterations, dtype);
    // Only a fixture's own run writes it: a variant checked against it must not.
    let write = std::env::var_os("LOGO_GOLDEN_WRITE").is_some() && fixture == name;
    let fixture = root().join("tests/golden").join(fixture);
    if write {
        std::fs::create_dir_all(&fixture).unwrap();
        std::fs::write(fixture.join("metrics.csv"), &metrics).unwrap();
        std::fs::write(fixture.join("tensors.txt"), &tensors).unwrap();
        return;
    }
    let read = |file: &str| {
        std::fs::read_to_string(fixture.join(file))
            .unwrap_or_else(|e| panic!("{}: {e}", fixture.join(file).display()))
    };
    let (got, want) = (columns(&metrics), columns(&read("metrics.csv")));
    for (column, values) in &want {
        let ours = got
            .iter()
            .find(|(c, _)| c == column)
            .unwrap_or_else(|| panic!("{name}: metrics.csv has no column {column}"));
        assert_eq!(
            &ours.1, values,
            "{name}: column {column} differs from the golden run"
        );
    }
    assert_eq!(
        tensors,
        read("tensors.txt"),
        "{name}: final checkpoint's tensors"
    );
}

#[test]
fn sparse_idp_six_iterations_float64() {
    check(
        "idp-f64",
        "configs/logo/inverted_double_pendulum.toml",
        "6",
        Some("f64"),
    );
}

#[test]
fn sparse_idp_six_iterations_float32() {
    check(
        "idp-f32",
        "configs/logo/inverted_double_pendulum.toml",
        "6",
        Some("f32"),
    );
}

#[test]
fn sparse_hopper_three_iterations_float64() {
    check("hopper-f64", "configs/logo/hopper.toml", "3", Some("f64"));
}

#[test]
fn sparse_hopper_three_iterations_float32() {
    check("hopper-f32", "configs/logo/hopper.toml", "3", Some("f32"));
}

/// PPO-Clip (with its KL stop), PPO-Penalty and the critics' Adam fit on sparse IDP for 5
/// iterations (`tests/golden/idp-ppo.toml`). Its fixture was written by the binary of
/// 12f567c, whose metrics and tensors on this config equal 463789f's.
#[test]
fn first_order_kinds_five_iterations_float64() {
    check("idp-ppo-f64", "tests/golden/idp-ppo.toml", "5", Some("f64"));
}

/// A config's `dtype` chooses the float type where no `--dtype` flag does, and the flag
/// wins over it: each trains exactly as the golden run of its type.
#[test]
fn a_configs_dtype_trains_as_the_flag() {
    let (dir, text) = shipped_config("dtype", "configs/logo/inverted_double_pendulum.toml");
    let config = dir.join("f32.toml");
    std::fs::write(&config, format!("dtype = \"f32\"\n{text}")).unwrap();
    let config = config.to_str().unwrap();
    check_against("idp-f32", "dtype-f32", config, "6", None);
    check_against("idp-f64", "dtype-f32-flag-f64", config, "6", Some("f64"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A scratch folder for variants of a shipped config, and that config's text with its
/// data paths made absolute (the variants are written elsewhere than configs/).
fn shipped_config(name: &str, config: &str) -> (PathBuf, String) {
    let dir =
        std::env::temp_dir().join(format!("logo-golden-{}-{name}-config", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(root().join(config))
        .unwrap()
        .replace("../../data/", &format!("{}/data/", root().display()));
    (dir, text)
}

/// `eval_initial_states = "fresh"` evaluates from new initial states each iteration on a
/// stream of its own: every training column and every tensor stay the golden run's, and
/// the evaluation columns change.
#[test]
fn fresh_evaluation_states_leave_training_as_it_was() {
    let (dir, text) = shipped_config("fresh", "configs/logo/inverted_double_pendulum.toml");
    let config = dir.join("fresh.toml");
    std::fs::write(&config, format!("eval_initial_states = \"fresh\"\n{text}")).unwrap();
    let (metrics, tensors) = train("fresh", config.to_str().unwrap(), "6", Some("f64"));
    std::fs::remove_dir_all(&dir).unwrap();
    let fixture = root().join("tests/golden/idp-f64");
    let golden = std::fs::read_to_string(fixture.join("metrics.csv")).unwrap();
    let (got, want) = (columns(&metrics), columns(&golden));
    for (column, values) in &want {
        let ours = &got.iter().find(|(c, _)| c == column).unwrap().1;
        if column.starts_with("eval_") {
            assert_ne!(
                ours, values,
                "{column}: the fresh states evaluated the same"
            );
        } else {
            assert_eq!(
                ours, values,
                "{column} changed with the evaluation's states"
            );
        }
    }
    let golden_tensors = std::fs::read_to_string(fixture.join("tensors.txt")).unwrap();
    assert_eq!(tensors, golden_tensors);
}

/// `clip_actions = true` on sparse Hopper: MuJoCo clamps controls to their range and the
/// sparse reward ignores the action, so one iteration with the actions clipped before the
/// env (sampled and evaluated alike) trains exactly as without: every tensor, and every
/// column but the dense returns, whose control cost is charged on the action as given,
/// and the evaluation's action RMS. The training batch's dense return is higher, by the
/// out-of-range part of the control cost.
#[test]
fn clipping_actions_changes_no_sparse_training() {
    let (dir, text) = shipped_config("clip", "configs/logo/hopper.toml");
    let text = text.replace("samples_per_iter = 20000", "samples_per_iter = 4000");
    let (plain, clipped) = (dir.join("plain.toml"), dir.join("clipped.toml"));
    std::fs::write(&plain, &text).unwrap();
    std::fs::write(&clipped, format!("clip_actions = true\n{text}")).unwrap();
    let (a, a_tensors) = train("clip-off", plain.to_str().unwrap(), "1", Some("f64"));
    let (b, b_tensors) = train("clip-on", clipped.to_str().unwrap(), "1", Some("f64"));
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(a_tensors, b_tensors, "the checkpoints differ");
    let (a, b) = (columns(&a), columns(&b));
    for ((column, values), (_, others)) in a.iter().zip(&b) {
        let number = |v: &[String]| v[0].parse::<f64>().unwrap();
        // The mean action after one iteration stays in range here (the evaluation's
        // clipping is tested in logo-algo's rollout.rs): its columns may stay equal.
        if column == "train_dense_return" {
            let (x, y) = (number(values), number(others));
            assert!(
                y > x,
                "{column}: clipped actions cost less: {x} unclipped, {y} clipped"
            );
        } else if column == "eval_dense_return" {
            let (x, y) = (number(values), number(others));
            assert!(y >= x, "{column}: {x} unclipped, {y} clipped");
        } else if column == "eval_action_rms" {
            let (x, y) = (number(values), number(others));
            assert!(y <= x, "{column}: {x} unclipped, {y} clipped");
        } else {
            assert_eq!(values, others, "{column} changed with clip_actions");
        }
    }
}

/// The LOGO ids' rules given as config kinds (`[env]` with `id` and `sparse`) train to the
/// golden runs of the `Sparse<id>` names, row for row and tensor for tensor.
#[test]
fn sparse_kinds_in_the_config_train_as_the_logo_ids() {
    let cases = [
        (
            "idp-f64",
            "configs/logo/inverted_double_pendulum.toml",
            "InvertedDoublePendulum-v4",
            "{ kind = \"delayed\" }",
            "6",
        ),
        (
            "hopper-f64",
            "configs/logo/hopper.toml",
            "Hopper-v4",
            "{ kind = \"distance\", threshold = 2.0 }",
            "3",
        ),
    ];
    for (fixture, shipped, id, sparse, iterations) in cases {
        let name = format!("{fixture}-kind");
        let (dir, text) = shipped_config(&name, shipped);
        let table = logo_testkit::with_env_table(&text, id, sparse)
            .unwrap_or_else(|| panic!("{shipped} has no env line"));
        let config = dir.join("kind.toml");
        std::fs::write(&config, table).unwrap();
        check_against(
            fixture,
            &name,
            config.to_str().unwrap(),
            iterations,
            Some("f64"),
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// One kept run of each checkpoint family (`tests/fixtures/kept-runs/`, where they moved
/// from `docs/results/` when the docs kept policies alone): every algorithm, step kind,
/// critic kind, float type and env form a kept checkpoint has, and the older config
/// layouts among them.
const KEPT_FAMILIES: &[&str] = &[
    "paper-scale/hopper/hopper/seed0",
    "paper-scale/hopper/hopper_ppo_cdq_skip_rewardless/seed2",
    "halfcheetah-fall/halfcheetah/seed1",
    "hc-reference-exact/seed3",
    "fisher-damping/walker2d_reference_fisher/seed0",
    "new-task/ant/runs-sigma1/logo/seed2",
    "new-task/reacher/runs/logo/seed2",
    "new-task/reacher/runs/trpo/seed0",
];

/// Where each kept family's run is after one more iteration: `logo train --resume` on a
/// copy of it; the line names the run and the iteration reached, then two SHA-256s: of
/// the new checkpoint's samples and tensors (recorded on fd906cb, before the learner
/// state's format got its number), and of its learner state besides the networks
/// (`extra.resume`, format 2, recorded on the commit after 32de645): the δ schedule's
/// window, the optimisers' moments and the sampler's position, which one iteration's
/// tensors need not show.
fn resume_digest(kept: &str) -> String {
    let from = root().join("tests/fixtures/kept-runs").join(kept);
    let dir = std::env::temp_dir().join(format!(
        "logo-golden-{}-resume-{}",
        std::process::id(),
        kept.replace('/', "-")
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for file in ["checkpoint.safetensors", "metrics.csv", "config.toml"] {
        std::fs::copy(from.join(file), dir.join(file))
            .unwrap_or_else(|e| panic!("{kept}/{file}: {e}"));
    }
    let before = Checkpoint::load(&dir.join("checkpoint.safetensors")).unwrap();
    let next = before.meta.iteration + 1;
    let status = Command::new(env!("CARGO_BIN_EXE_logo"))
        .current_dir(root())
        .args([
            "train",
            "--no-tensorboard",
            "--iterations",
            &next.to_string(),
        ])
        .arg("--resume")
        .arg(&dir)
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "{kept}: logo train --resume failed");
    let after = Checkpoint::load(&dir.join("checkpoint.safetensors")).unwrap();
    assert_eq!(after.meta.iteration, next, "{kept}");
    let mut networks = Sha256::new();
    networks.update(after.meta.extra["samples"].to_string());
    networks.update(tensors(&dir));
    let mut state = Sha256::new();
    state.update(after.meta.extra["resume"].to_string());
    std::fs::remove_dir_all(&dir).unwrap();
    format!("{kept} {next} {} {}\n", hex(networks), hex(state))
}

/// Every kept checkpoint family resumes exactly as it did when the digests were recorded
/// (commit fd906cb, before the learner state's format got a version): however the
/// checkpoint format moves on, old checkpoints read through its migration and go on
/// bit for bit.
#[test]
fn kept_checkpoint_families_resume_to_their_recorded_digests() {
    let got: String = KEPT_FAMILIES
        .iter()
        .map(|kept| resume_digest(kept))
        .collect();
    let fixture = root().join("tests/golden/resume-digests.txt");
    if std::env::var_os("LOGO_GOLDEN_WRITE").is_some() {
        std::fs::write(&fixture, &got).unwrap();
        return;
    }
    let want =
        std::fs::read_to_string(&fixture).unwrap_or_else(|e| panic!("{}: {e}", fixture.display()));
    for (got, want) in got.lines().zip(want.lines()) {
        assert_eq!(got, want, "a kept run resumed to another digest");
    }
    assert_eq!(
        got.lines().count(),
        want.lines().count(),
        "{}",
        fixture.display()
    );
}

/// The Figure 1 baselines, recorded before the trainer's seams moved (issue of one table
/// of methods; fixtures written with the training code of 60a6047): GAIL, POfD, BC-TRPO and DAPG
/// as the shipped configs make them (`configs/<method>/inverted_double_pendulum.toml`,
/// the Figure 1 runs' form) train to their golden metrics and tensors in 3 iterations,
/// and a run stopped after 2 and resumed (`logo train --resume`) ends on the same tensors
/// and rows as the unbroken one.
const FIGURE_ONE_BASELINES: [&str; 4] = ["gail", "pofd", "bc-trpo", "dapg"];

#[test]
fn figure_one_baselines_train_and_resume_to_their_golden_runs() {
    for method in FIGURE_ONE_BASELINES {
        let config = format!("configs/{method}/inverted_double_pendulum.toml");
        let fixture = format!("idp-{method}-f64");
        check(&fixture, &config, "3", Some("f64"));
        if std::env::var_os("LOGO_GOLDEN_WRITE").is_none() {
            check_resumed(&fixture, &config, "2", "3");
        }
    }
}

/// The same four made by `logo compare` (`algorithms::configure`) from the new-task
/// template, as the suite's baseline runs are: sparse Hopper, 2 iterations, with
/// observation statistics, ten discriminator steps and `kl_limit`.
#[test]
fn suite_baselines_as_logo_compare_makes_them_train_to_their_golden_runs() {
    let template = root().join("configs/templates/new_task.toml");
    let base = logo_algo::TrainConfig::load(&template).unwrap();
    let dir = std::env::temp_dir().join(format!("logo-golden-{}-suite", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for method in FIGURE_ONE_BASELINES {
        let made = logo_algo::algorithms::configure(&base, method).unwrap();
        let config = dir.join(format!("{method}.toml"));
        std::fs::write(&config, made.to_toml().unwrap()).unwrap();
        let config = config.to_str().unwrap();
        check(&format!("new-task-{method}-f64"), config, "2", Some("f64"));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `config` trained for `first` iterations, then resumed to `last`: the rows and tensors
/// of the golden run `fixture` (which ran `last` unbroken).
fn check_resumed(fixture: &str, config: &str, first: &str, last: &str) {
    let out = std::env::temp_dir().join(format!(
        "logo-golden-{}-{fixture}-resumed",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&out);
    let logo = |args: &[&str]| {
        let status = Command::new(env!("CARGO_BIN_EXE_logo"))
            .current_dir(root())
            .args(args)
            .args(["--no-tensorboard", "--dtype", "f64"])
            .stdout(Stdio::null())
            .status()
            .unwrap();
        assert!(status.success(), "{fixture}: logo {args:?} failed");
    };
    let dir = out.to_str().unwrap();
    logo(&[
        "train",
        "--config",
        config,
        "--iterations",
        first,
        "--out",
        dir,
    ]);
    logo(&["train", "--resume", dir, "--iterations", last]);
    let metrics: String = logo_testkit::metrics_without_timings(&out)
        .into_iter()
        .map(|row| row + "\n")
        .collect();
    let tensors = tensors(&out);
    std::fs::remove_dir_all(&out).unwrap();
    let golden = root().join("tests/golden").join(fixture);
    let want = std::fs::read_to_string(golden.join("metrics.csv")).unwrap();
    for (column, values) in &columns(&want) {
        let got = columns(&metrics);
        let ours = &got.iter().find(|(c, _)| c == column).unwrap().1;
        assert_eq!(ours, values, "{fixture} resumed: column {column}");
    }
    let want = std::fs::read_to_string(golden.join("tensors.txt")).unwrap();
    assert_eq!(
        tensors, want,
        "{fixture} resumed: final checkpoint's tensors"
    );
}

//! The `logo` binary as a user meets it.

use logo_testkit::{
    Logo, TINY_LOGO_TEXT as TINY, metrics_without_timings, one_line_error as stderr_line, scratch,
    write_demos_npy as write_npy,
};
use std::path::{Path, PathBuf};
use std::process::Command;

fn cli() -> Logo {
    Logo::new(env!("CARGO_BIN_EXE_logo"))
}

/// `logo train` on `config`, expected to fail: its one-line error.
fn train_error(config: &Path, out: &Path) -> String {
    cli().train_error(config, out)
}

/// A scratch folder with the tiny LOGO config and its demonstrations; the config's path.
fn tiny_run(name: &str) -> (PathBuf, PathBuf) {
    let dir = scratch(name);
    write_npy(&dir.join("demos.npy"), 40, 12);
    let config = dir.join("tiny.toml");
    std::fs::write(&config, TINY).unwrap();
    (dir, config)
}

/// `config` with its `env = ...` line replaced by an `[env]` table of `id` and `sparse`.
fn env_table(config: &str, id: &str, sparse: &str) -> String {
    logo_testkit::with_env_table(config, id, sparse).expect("the config has an env line")
}

#[test]
fn config_errors_name_the_file_and_the_key() {
    let dir = scratch("config");
    write_npy(&dir.join("demos.npy"), 20, 12);
    let cases = [
        (
            TINY.replace("iterations = 2", "iterations = 2\nbogus_key = 1"),
            "bogus_key",
        ),
        (
            TINY.replace("samples_per_iter = 300", "samples_per_iter = \"many\""),
            "samples_per_iter",
        ),
        (TINY.replace("demos.npy", "missing.npy"), "guidance.demos"),
        (TINY.replace("num_envs = 4", "num_envs = 0"), "num_envs"),
        (
            TINY.replace("num_envs = 4", "num_envs = 4\ndtype = \"f16\""),
            "unknown variant `f16`, expected `f64` or `f32`",
        ),
        (
            TINY.replace(
                "[guidance]",
                "[improvement]\nfisher_fraction = 1.5\n[guidance]",
            ),
            "improvement.fisher_fraction",
        ),
        // A field of another policy-update kind, and one of another critic fit.
        (
            TINY.replace(
                "[guidance]",
                "[improvement]\nkind = \"ppo-clip\"\ndamping = 0.1\n[guidance]",
            ),
            "damping",
        ),
        (
            TINY.replace("iterations = 3 }", "iterations = 3, epochs = 2 }"),
            "epochs",
        ),
        // A policy file of raw observations cannot act through a run's statistics.
        (
            TINY.replace(
                "num_envs = 4",
                "num_envs = 4\nnormalise_observations = true\ninit_policy = \"demos.npy\"",
            ),
            "normalise_observations: init_policy is a policy of raw observations",
        ),
        (
            TINY.replace("num_envs = 4", "num_envs = 4\neval_episodes = 0"),
            "eval_episodes must be at least 1",
        ),
        (
            TINY.replace("num_envs = 4", "num_envs = 4\nsuccess = \"always\""),
            "unknown variant `always`, expected one of `task`, `terminated`, `none`",
        ),
        (
            TINY.replace(
                "warmup = 0",
                "warmup = 0\n[guidance.update]\nkind = \"ppo-clip\"\nepochs = 0",
            ),
            "guidance.update.epochs",
        ),
        // The env as a table: an unknown sparse kind, a missing parameter, a rule on an
        // id that is sparse already, an id that is not one.
        (
            env_table(TINY, "InvertedDoublePendulum-v4", "{ kind = \"walk\" }"),
            "unknown sparse kind \"walk\"",
        ),
        (
            env_table(
                TINY,
                "InvertedDoublePendulum-v4",
                "{ kind = \"goal\", radius = 0.1 }",
            ),
            "only Reacher and Pusher",
        ),
        (
            env_table(TINY, "InvertedDoublePendulum-v4", "{ kind = \"distance\" }"),
            "needs `threshold`",
        ),
        (
            env_table(
                TINY,
                "SparseInvertedDoublePendulum-v4",
                "{ kind = \"delayed\" }",
            ),
            "env: invalid option: SparseInvertedDoublePendulum-v4 is already sparse",
        ),
        (
            env_table(TINY, "Pendulum-v4", "{ kind = \"delayed\" }"),
            "env: unknown environment id \"Pendulum-v4\"",
        ),
        (
            TINY.replace("iterations = 2", "iterations = 2\neval_env = \"Ant-v3\""),
            "eval_env: unknown environment id",
        ),
        (
            TINY.replace("iterations = 2", "iterations = 2\neval_env = \"Ant-v4\""),
            "eval_env Ant-v4 does not have the dims of env",
        ),
    ];
    for (i, (text, key)) in cases.iter().enumerate() {
        let path = dir.join(format!("case{i}.toml"));
        std::fs::write(&path, text).unwrap();
        let err = train_error(&path, &dir.join("out"));
        assert!(
            err.contains(&format!("case{i}.toml")) && err.contains(key),
            "{err}"
        );
    }
    // Demonstrations whose width does not match the env's obs + action dims.
    write_npy(&dir.join("demos.npy"), 20, 9);
    let path = dir.join("dims.toml");
    std::fs::write(&path, TINY).unwrap();
    let err = train_error(&path, &dir.join("out"));
    assert!(
        err.contains("guidance.demos") && err.contains("demos.npy") && err.contains("9 columns"),
        "{err}"
    );
}

#[test]
fn a_tiny_logo_run_writes_metrics_and_a_checkpoint_and_is_reproducible() {
    let (dir, config) = tiny_run("train");
    let run = |name: &str| {
        let out_dir = dir.join(name);
        let stdout = cli().train(&config, &out_dir, &["--seed", "3"]);
        assert!(
            stdout.contains("[   2/2]")
                && stdout.contains("final eval dense return")
                && out_dir.join("best.safetensors").is_file()
                && out_dir.join("eval.json").is_file(),
            "{stdout}"
        );
        assert!(out_dir.join("checkpoint.safetensors").is_file());
        out_dir
    };
    let (a, b) = (run("a"), run("b"));
    // The checkpoint evaluates.
    let ckpt = dir.join("a/checkpoint.safetensors");
    let stdout = cli().succeed(&[
        "eval",
        "--checkpoint",
        ckpt.to_str().unwrap(),
        "--episodes",
        "2",
    ]);
    let text = stdout;
    assert!(
        text.contains("SparseInvertedDoublePendulum-v4") && text.contains("dense return"),
        "{text}"
    );
    // Sampled actions are seeded (the same --seed, the same episodes); --split-at adds a
    // line per env, and a mark that is not a positive distance is refused.
    let ckpt = ckpt.to_str().unwrap();
    let sampled = || {
        let args = [
            "--episodes",
            "2",
            "--sample",
            "--seed",
            "5",
            "--split-at",
            "0.01",
        ];
        cli().succeed(&[&["eval", "--checkpoint", ckpt][..], &args].concat())
    };
    let (first, again) = (sampled(), sampled());
    assert_eq!(first, again);
    assert!(
        first.contains("sampled actions") && first.contains("0.01 m reached in"),
        "{first}"
    );
    let bad = stderr_line(&cli().run(&["eval", "--checkpoint", ckpt, "--split-at", "0"]));
    assert!(bad.contains("--split-at must be a positive"), "{bad}");
    let a_csv = std::fs::read_to_string(a.join("metrics.csv")).unwrap();
    let header: Vec<&str> = a_csv.lines().next().unwrap().split(',').collect();
    for col in [
        "iteration",
        "samples",
        "wall_s",
        "train_sparse_return",
        "eval_dense_return",
        "kl",
        "delta_k",
    ] {
        assert!(header.contains(&col), "metrics.csv lacks {col}: {header:?}");
    }
    assert_eq!(
        a_csv.lines().count(),
        3,
        "a header and one row per iteration"
    );
    // Same seed, same numbers (everything but the timings).
    assert_eq!(metrics_without_timings(&a), metrics_without_timings(&b));
}

/// The best policy and the end-of-run evaluation: best.safetensors is the checkpoint of
/// the latest iteration whose evaluation of the task's own return reached its highest
/// value; eval.json evaluates it and the final policy over 20 fresh episodes, as `logo
/// eval --json` does; a run stopped and resumed ends with the same files' numbers.
#[test]
fn a_run_keeps_its_best_policy_and_ends_with_eval_json() {
    let (dir, config) = tiny_run("best");
    let train = |out: &Path, iterations: &str, resume: bool| {
        if resume {
            let out = out.to_str().unwrap();
            cli().succeed(&["train", "--resume", out, "--iterations", iterations])
        } else {
            cli().train(&config, out, &["--seed", "1", "--iterations", iterations])
        }
    };
    let whole = dir.join("whole");
    let stdout = train(&whole, "4", false);
    assert!(stdout.contains("best policy (iteration"), "{stdout}");
    let csv = std::fs::read_to_string(whole.join("metrics.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column = header.iter().position(|h| *h == "eval_return").unwrap();
    let returns: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(column).unwrap().parse().unwrap())
        .collect();
    let top = returns.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let last_top = returns.iter().rposition(|&r| r == top).unwrap() + 1;
    let best = logo_nn::Checkpoint::load(&whole.join("best.safetensors")).unwrap();
    assert_eq!(best.meta.iteration, last_top as u64, "{returns:?}");

    let eval: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("eval.json")).unwrap()).unwrap();
    assert_eq!(eval["episodes"], 20);
    for policy in ["final", "best"] {
        for acting in ["mean_action", "clipped"] {
            let episodes = eval["policies"][policy][acting]["episodes"]
                .as_array()
                .unwrap();
            assert_eq!(episodes.len(), 20, "{policy} {acting}");
            assert!(episodes[0]["dense_return"].as_f64().unwrap().is_finite());
        }
    }
    assert_eq!(eval["policies"]["best"]["iteration"], last_top);
    let json = cli().succeed(&[
        "eval",
        "--checkpoint",
        whole.join("best.safetensors").to_str().unwrap(),
        "--json",
        "--episodes",
        "20",
    ]);
    let alone: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(
        alone["mean_action"],
        eval["policies"]["best"]["mean_action"]
    );
    assert_eq!(alone["clipped"], eval["policies"]["best"]["clipped"]);

    // Stopped after 2 iterations and resumed to 4: the same best and the same eval.json.
    let parts = dir.join("parts");
    train(&parts, "2", false);
    train(&parts, "4", true);
    let file = |run: &Path, name: &str| std::fs::read(run.join(name)).unwrap();
    let tensors = |run: &Path| {
        let c = logo_nn::Checkpoint::load(&run.join("best.safetensors")).unwrap();
        let names: Vec<String> = c.tensor_names().map(String::from).collect();
        let values: Vec<Vec<f64>> = names
            .iter()
            .map(|n| c.tensor(n).unwrap().1.to_vec())
            .collect();
        (c.meta.iteration, names, values)
    };
    assert_eq!(tensors(&parts), tensors(&whole));
    let policies = |run: &Path| {
        let v: serde_json::Value = serde_json::from_slice(&file(run, "eval.json")).unwrap();
        v["policies"].clone()
    };
    assert_eq!(policies(&parts), policies(&whole));
}

/// `normalise_observations`: the statistics count every observation collected, travel
/// with the checkpoint (a resumed run ends where an uninterrupted one does), and `logo
/// eval` acts through them as the run's own end-of-run evaluation did.
#[test]
fn observation_statistics_round_trip_through_checkpoints_and_eval() {
    let (dir, _) = tiny_run("obs-norm");
    let config = dir.join("norm.toml");
    let text = TINY.replace(
        "iterations = 2",
        "iterations = 3\nnormalise_observations = true",
    );
    std::fs::write(&config, text).unwrap();
    let (whole, parts) = (dir.join("whole"), dir.join("parts"));
    cli().train(&config, &whole, &["--no-tensorboard"]);
    cli().train(&config, &parts, &["--iterations", "2", "--no-tensorboard"]);
    cli().succeed(&[
        "train",
        "--resume",
        parts.to_str().unwrap(),
        "--iterations",
        "3",
        "--no-tensorboard",
    ]);
    let ckpt = logo_nn::Checkpoint::load(&whole.join("checkpoint.safetensors")).unwrap();
    let count = ckpt.tensor("observation_norm.count").unwrap().1[0];
    assert_eq!(count, ckpt.meta.extra["samples"].as_f64().unwrap());
    let var = ckpt.tensor("observation_norm.var").unwrap().1;
    // (IDP's last three observations are always 0: their variance is 0.)
    assert!(
        var.iter().all(|v| *v >= 0.0) && var[..8].iter().all(|v| *v > 0.0 && *v != 1.0),
        "{var:?}"
    );
    let again = logo_nn::Checkpoint::load(&parts.join("checkpoint.safetensors")).unwrap();
    for name in ckpt.tensor_names() {
        assert_eq!(ckpt.tensor(name), again.tensor(name), "{name}");
    }
    let json = cli().succeed(&[
        "eval",
        "--checkpoint",
        whole.join("checkpoint.safetensors").to_str().unwrap(),
        "--json",
    ]);
    let alone: serde_json::Value = serde_json::from_str(&json).unwrap();
    let eval: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("eval.json")).unwrap()).unwrap();
    assert_eq!(
        alone["mean_action"],
        eval["policies"]["final"]["mean_action"]
    );
}

/// A run whose task return never leaves 0 (a sparse goal out of reach) keeps its latest
/// policy as the best, not iteration 1's: ties go to the policy that trained longer.
#[test]
fn a_run_that_never_earns_keeps_its_latest_policy_as_best() {
    let dir = scratch("never-earns");
    let trpo = TINY
        .split("[guidance]")
        .next()
        .unwrap()
        .replace("iterations = 2", "iterations = 3");
    let config = dir.join("unreachable.toml");
    let text = env_table(
        &trpo,
        "Hopper-v4",
        "{ kind = \"distance\", threshold = 1000 }",
    );
    std::fs::write(&config, text).unwrap();
    let out = dir.join("run");
    cli().train(&config, &out, &["--no-tensorboard"]);
    let csv = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column = header.iter().position(|h| *h == "eval_return").unwrap();
    let returns: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(column).unwrap())
        .collect();
    assert_eq!(returns, ["0.0"; 3], "the goal was reached");
    let best = logo_nn::Checkpoint::load(&out.join("best.safetensors")).unwrap();
    assert_eq!(best.meta.iteration, 3);
}

#[test]
fn a_missing_checkpoint_is_a_one_line_error() {
    let err = stderr_line(&cli().run(&["eval", "--checkpoint", "/nonexistent/ckpt.safetensors"]));
    assert!(err.contains("/nonexistent/ckpt.safetensors"), "{err}");
}

#[test]
fn an_os_error_is_said_once_with_its_path() {
    for args in [
        &["eval", "--checkpoint", "/nonexistent/ckpt.safetensors"][..],
        &[
            "data",
            "import",
            "--from",
            "d4rl",
            "/nonexistent/d4rl.hdf5",
            "--out",
            "/tmp/x",
        ],
    ] {
        let err = stderr_line(&cli().run(args));
        assert!(
            err.contains("/nonexistent/") && err.matches("os error 2").count() == 1,
            "{err}"
        );
    }
}

#[test]
fn an_error_names_the_checkpoint_not_a_flag_the_user_did_not_give() {
    let (dir, config) = tiny_run("blame");
    let run = dir.join("run");
    cli().succeed(&[
        "train",
        "--config",
        config.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
    ]);
    let path = run.join("checkpoint.safetensors");
    let mut ckpt = logo_nn::Checkpoint::load(&path).unwrap();
    ckpt.meta.env_id = "Teapot-v1".into();
    ckpt.save(&path).unwrap();
    let err = stderr_line(&cli().run(&["eval", "--checkpoint", path.to_str().unwrap()]));
    assert!(
        err.contains("checkpoint.safetensors: env_id Teapot-v1") && !err.contains("--env"),
        "{err}"
    );
}

#[test]
fn zero_episodes_is_an_error_not_a_meaningless_mean() {
    let err = stderr_line(&cli().run(&["rollout", "--episodes", "0"]));
    assert_eq!(err, "error: --episodes must be at least 1");
}

#[test]
fn unknown_env_ids_are_one_line_errors() {
    let err = stderr_line(&cli().run(&["rollout", "--env", "Hopper-v9"]));
    assert!(
        err.contains("Hopper-v9") && err.contains("known ids"),
        "{err}"
    );
}

#[test]
fn the_behaviour_pipeline_stops_at_a_return_then_records_and_inspects() {
    let (dir, config) = tiny_run("behaviour");
    // Any evaluation reaches -1e9: the run stops after its first iteration.
    let out_dir = dir.join("run");
    let stdout = cli().succeed(&[
        "train",
        "--config",
        config.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--stop-at-return=-1e9",
    ]);
    assert!(stdout.contains("reached --stop-at-return"), "{stdout}");
    let csv = std::fs::read_to_string(out_dir.join("metrics.csv")).unwrap();
    assert_eq!(csv.lines().count(), 2, "stopped after one iteration: {csv}");

    let ckpt = out_dir.join("checkpoint.safetensors");
    let rec = dir.join("recorded");
    cli().succeed(&[
        "data",
        "record",
        "--policy",
        ckpt.to_str().unwrap(),
        "--env",
        "InvertedDoublePendulum-v4",
        "--episodes",
        "3",
        "--out",
        rec.to_str().unwrap(),
    ]);
    let stdout = cli().succeed(&["data", "inspect", rec.to_str().unwrap(), "--json"]);
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(summary["episodes"], 3);
    assert_eq!(summary["env_id"], "InvertedDoublePendulum-v4");
    let dense = summary["dense_returns"].as_array().unwrap();
    let lengths = summary["episode_lengths"].as_array().unwrap();
    assert_eq!(dense.len(), 3);
    // Dense IDP rewards are at most ~9.35 per step; the stored rewards are the dense ones.
    let total: f64 = dense.iter().map(|v| v.as_f64().unwrap()).sum();
    let mean = summary["return_mean"].as_f64().unwrap();
    assert!((total / 3.0 - mean).abs() < 1e-9, "{total} vs {mean}");
    assert!(lengths.iter().all(|l| l.as_u64().unwrap() >= 1));

    // Inspecting something that is not a dataset is a one-line error.
    let err =
        stderr_line(&cli().run(&["data", "inspect", dir.join("demos.npy").to_str().unwrap()]));
    assert!(err.contains("not a Minari dataset folder"), "{err}");
}

#[test]
fn resume_extends_a_finished_run_and_says_when_there_is_nothing_to_do() {
    let (dir, config) = tiny_run("resume");
    let run_dir = dir.join("run");
    let run = dir.join("run").to_str().unwrap().to_string();
    cli().succeed(&["train", "--config", config.to_str().unwrap(), "--out", &run]);
    // As if the first two iterations had taken a week: the resumed run's speed and ETA
    // must come from its own iterations, not from that.
    let metrics = run_dir.join("metrics.csv");
    let csv = std::fs::read_to_string(&metrics).unwrap();
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    let wall = header.split(',').position(|c| c == "wall_s").unwrap();
    let mut slow = vec![header.to_string()];
    for line in lines {
        let mut cells: Vec<&str> = line.split(',').collect();
        cells[wall] = "604800";
        slow.push(cells.join(","));
    }
    std::fs::write(&metrics, slow.join("\n") + "\n").unwrap();
    let stdout = cli().succeed(&["train", "--resume", &run, "--iterations", "3"]);
    let progress = stdout
        .lines()
        .find(|l| l.starts_with("[   3/3]"))
        .unwrap_or_else(|| panic!("no progress line for iteration 3: {stdout}"));
    assert!(stdout.contains("resuming"), "{stdout}");
    let per_iter: f64 = progress
        .split(" s/it")
        .next()
        .and_then(|head| head.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no s/it in {progress}"));
    assert!(
        per_iter < 600.0,
        "s/it counts earlier invocations: {progress}"
    );
    let csv = std::fs::read_to_string(run_dir.join("metrics.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    let out = cli().run(&["train", "--resume", &run]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("nothing to do"));
    // A folder without a checkpoint: one clear line.
    let err = stderr_line(&cli().run(&["train", "--resume", dir.to_str().unwrap()]));
    assert!(err.contains("checkpoint.safetensors"), "{err}");
}

#[test]
#[cfg(unix)]
fn output_into_a_closed_pipe_ends_quietly() {
    use std::io::{BufRead, BufReader};
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    // `logo train … | head -1`: the reader goes away after a line; the run must end by
    // SIGPIPE as Unix tools do, not with a panic and its backtrace.
    let (dir, config) = tiny_run("closed-pipe");
    let config = config.to_str().unwrap().to_string();
    let text = std::fs::read_to_string(&config)
        .unwrap()
        .replace("iterations = 2", "iterations = 200");
    std::fs::write(&config, text).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_logo"))
        .args(["train", "--config", &config, "--out"])
        .arg(dir.join("run"))
        .arg("--no-tensorboard")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    // The reading end is dropped here.
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.signal(), Some(13), "{first}{stderr}");
}

#[test]
fn a_run_folder_in_training_is_refused_to_a_second_process() {
    let (dir, config) = tiny_run("locked");
    let run = dir.join("run");
    let (config, run_arg) = (config.to_str().unwrap(), run.to_str().unwrap());
    let mut first = Command::new(env!("CARGO_BIN_EXE_logo"))
        .args([
            "train",
            "--config",
            config,
            "--out",
            run_arg,
            "--iterations",
            "100000",
        ])
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // The first process writes its pid into the lock it holds.
    let lock = run.join("run.lock");
    let start = std::time::Instant::now();
    while std::fs::read_to_string(&lock).map_or(true, |t| t.trim().is_empty()) {
        assert!(start.elapsed().as_secs() < 60, "no lock after 60 s");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let second = cli().run(&["train", "--config", config, "--out", run_arg]);
    let running = first.try_wait().unwrap().is_none();
    first.kill().unwrap();
    first.wait().unwrap();
    assert!(running, "the first run ended before the second started");
    let err = stderr_line(&second);
    assert!(
        err.contains(&format!("being trained by process {}", first.id())),
        "{err}"
    );
    // The first run's files are untouched by the refused second: its config stands.
    let stored = std::fs::read_to_string(run.join("config.toml")).unwrap();
    assert!(stored.contains("iterations = 100000"), "{stored}");
}

#[test]
fn inspect_works_on_every_shipped_dataset() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let mut inspected = 0;
    for group in ["logo", "behaviour"] {
        for entry in std::fs::read_dir(data.join(group)).unwrap() {
            let path = entry.unwrap().path();
            let stdout = cli().succeed(&["data", "inspect", path.to_str().unwrap(), "--json"]);
            let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
            assert!(
                summary["steps"].as_u64().unwrap() > 100,
                "{}",
                path.display()
            );
            inspected += 1;
        }
    }
    assert_eq!(inspected, 5, "four LOGO sets and the Hopper behaviour set");
}

/// A `--dtype` given over a config's `dtype` is what the run trains in, and what its
/// stored config says.
#[test]
fn a_dtype_flag_over_the_configs_is_written_into_the_run() {
    let (dir, _) = tiny_run("dtype-over-config");
    let config = dir.join("f32.toml");
    std::fs::write(
        &config,
        TINY.replace("num_envs = 4", "num_envs = 4\ndtype = \"f32\""),
    )
    .unwrap();
    let run = dir.join("run");
    let (config, out) = (config.to_str().unwrap(), run.to_str().unwrap());
    let stdout = cli().succeed(&["train", "--config", config, "--dtype", "f64", "--out", out]);
    assert!(stdout.contains("kernels f64"), "{stdout}");
    let stored = std::fs::read_to_string(run.join("config.toml")).unwrap();
    assert!(stored.contains("dtype = \"f64\""), "{stored}");
}

#[test]
fn a_checkpoint_from_one_engine_resumes_and_evaluates_on_another() {
    let (dir, config) = tiny_run("cross-engine");
    let run = dir.join("run").to_str().unwrap().to_string();
    let checkpoint = dir.join("run/checkpoint.safetensors");
    let checkpoint = checkpoint.to_str().unwrap();
    // float32 kernels → burn ndarray float64 → evaluated on burn ndarray float32.
    let f32_run = ["--config", config.to_str().unwrap(), "--out", &run];
    cli().succeed(&[&["train", "--dtype", "f32"][..], &f32_run[..]].concat());
    let stdout = cli().succeed(&[
        "train",
        "--resume",
        &run,
        "--iterations",
        "3",
        "--engine",
        "burn",
    ]);
    assert!(stdout.contains("[   3/3]"), "{stdout}");
    let stdout = cli().succeed(&[
        "eval",
        "--checkpoint",
        checkpoint,
        "--episodes",
        "1",
        "--backend",
        "ndarray",
        "--dtype",
        "f32",
    ]);
    assert!(
        stdout
            .contains("trained on kernels f32 from iteration 0, burn ndarray f64 from iteration 2")
            && stdout.contains("mean action on burn ndarray f32"),
        "{stdout}"
    );
    // With no engine flag, on the engine the run last trained on (burn ndarray f64):
    // float32 rounding of the weights moves the returns by little (the same seed, the
    // same episode).
    let on_f64 = cli().succeed(&["eval", "--checkpoint", checkpoint, "--episodes", "1"]);
    assert!(
        on_f64.contains("mean action on burn ndarray f64"),
        "{on_f64}"
    );
    let dense = |s: &str| -> f64 {
        let line = s
            .lines()
            .find(|l| l.starts_with("InvertedDoublePendulum"))
            .unwrap();
        let after = line.split("dense return").nth(1).unwrap();
        after.split_whitespace().next().unwrap().parse().unwrap()
    };
    let (a, b) = (dense(&stdout), dense(&on_f64));
    assert!((a - b).abs() <= 1e-3 * b.abs().max(1.0), "f32 {a}, f64 {b}");
}

/// A run on a sparse kind that is not LOGO's rule: its checkpoint names the env as
/// `<id>+<rule>`, which `logo eval` rebuilds, and `--resume` goes on from it.
#[test]
fn a_sparse_kind_of_the_config_is_evaluated_and_resumed_as_trained() {
    let (dir, _) = tiny_run("kind");
    let config = dir.join("kind.toml");
    let sparse = "{ kind = \"distance\", threshold = 0.5 }";
    std::fs::write(
        &config,
        env_table(TINY, "InvertedDoublePendulum-v4", sparse),
    )
    .unwrap();
    let run = dir.join("run").to_str().unwrap().to_string();
    let stdout = cli().succeed(&["train", "--config", config.to_str().unwrap(), "--out", &run]);
    assert!(
        stdout.contains("InvertedDoublePendulum-v4 (sparse: distance(0.5))"),
        "{stdout}"
    );
    let written = std::fs::read_to_string(dir.join("run/config.toml")).unwrap();
    assert!(written.contains("kind = \"distance\""), "{written}");
    let checkpoint = dir.join("run/checkpoint.safetensors");
    let stdout = cli().succeed(&[
        "eval",
        "--checkpoint",
        checkpoint.to_str().unwrap(),
        "--episodes",
        "2",
    ]);
    assert!(
        stdout.contains("InvertedDoublePendulum-v4+distance(0.5)"),
        "{stdout}"
    );
    // eval.json's numbers for this policy: on the env the run evaluated on; its initial
    // states are the run's, so --seed is refused rather than ignored.
    let ckpt = checkpoint.to_str().unwrap();
    let report: serde_json::Value =
        serde_json::from_str(&cli().succeed(&["eval", "--checkpoint", ckpt, "--json"])).unwrap();
    assert_eq!(report["env"], "InvertedDoublePendulum-v4+distance(0.5)");
    let out = cli().run(&["eval", "--checkpoint", ckpt, "--json", "--seed", "3"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("'--seed <SEED>'"),
        "{err}"
    );
    cli().succeed(&["train", "--resume", &run, "--iterations", "3"]);
    let rows = std::fs::read_to_string(dir.join("run/metrics.csv")).unwrap();
    assert_eq!(rows.lines().count(), 4, "{rows}");
    // The same env named by its id, written otherwise than the env writes it: the run
    // records it as the env names itself, and resumes.
    let named = dir.join("named.toml");
    let text = TINY.replace(
        "SparseInvertedDoublePendulum-v4",
        "InvertedDoublePendulum-v4+distance(0.50)",
    );
    std::fs::write(&named, text).unwrap();
    let run = dir.join("named").to_str().unwrap().to_string();
    cli().succeed(&["train", "--config", named.to_str().unwrap(), "--out", &run]);
    cli().succeed(&["train", "--resume", &run, "--iterations", "3"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn print_config_fills_every_default_and_trains_as_the_config_does() {
    let (dir, config) = tiny_run("print-config");
    let printed = cli().succeed(&[
        "train",
        "--config",
        config.to_str().unwrap(),
        "--print-config",
        "--seed",
        "4",
    ]);
    let table: toml::Table = printed.parse().unwrap_or_else(|e| panic!("{printed}: {e}"));
    // Defaults the file left out, the flag laid over it, the guidance step's own tables.
    assert_eq!(table["seed"].as_integer(), Some(4), "{printed}");
    assert_eq!(table["gamma"].as_float(), Some(0.99), "{printed}");
    assert_eq!(table["dtype"].as_str(), Some("f64"), "{printed}");
    let guidance = table["guidance"].as_table().unwrap();
    assert_eq!(
        guidance["discriminator_steps"].as_integer(),
        Some(1),
        "{printed}"
    );
    assert_eq!(
        guidance["update"]["kind"].as_str(),
        Some("trpo"),
        "{printed}"
    );
    assert!(guidance.contains_key("critic"), "{printed}");
    // Nothing was trained, and the printed config trains to the same numbers.
    assert!(!Path::new("runs/tiny-seed4").exists());
    let resolved = dir.join("resolved.toml");
    std::fs::write(&resolved, &printed).unwrap();
    let train = |config: &Path, name: &str| {
        let out = dir.join(name);
        cli().succeed(&[
            "train",
            "--config",
            config.to_str().unwrap(),
            "--seed",
            "4",
            "--out",
            out.to_str().unwrap(),
            "--no-tensorboard",
        ]);
        metrics_without_timings(&out)
    };
    assert_eq!(
        train(&config, "from-file"),
        train(&resolved, "from-printed")
    );
}

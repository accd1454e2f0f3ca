//! The one-line errors of 45 bad inputs, word for word: `tests/golden/error-messages.txt`
//! holds each case's line as `logo` printed it (its scratch folder written `<dir>`).
//! Written before the errors became typed, so that the types change no message; a change
//! meant to reword one rewrites the file with `LOGO_GOLDEN_WRITE=1` and says so.

use std::path::Path;

use logo_testkit::{
    Logo, TINY_LOGO_TEXT as TINY, one_line_error, scratch, workspace, write_demos_npy as write_npy,
};

/// A bad config: its name and its text (TINY with one mistake).
fn config_cases() -> Vec<(&'static str, String)> {
    let at = |anchor: &str, added: &str| TINY.replacen(anchor, &format!("{anchor}\n{added}"), 1);
    let env = |id: &str, sparse: &str| {
        logo_testkit::with_env_table(TINY, id, sparse).expect("TINY has an env line")
    };
    vec![
        ("unknown-key", at("iterations = 2", "bogus_key = 1")),
        (
            "wrong-type",
            TINY.replace("samples_per_iter = 300", "samples_per_iter = \"many\""),
        ),
        ("missing-key", TINY.replace("iterations = 2\n", "")),
        ("missing-demos", TINY.replace("demos.npy", "missing.npy")),
        (
            "num-envs-zero",
            TINY.replace("num_envs = 4", "num_envs = 0"),
        ),
        (
            "hidden-zero",
            TINY.replace("policy_hidden = [16, 16]", "policy_hidden = [16, 0]"),
        ),
        ("gamma-nan", at("num_envs = 4", "gamma = nan")),
        (
            "eval-episodes-zero",
            at("num_envs = 4", "eval_episodes = 0"),
        ),
        (
            "fisher-fraction",
            at("eval_steps = 100", "[improvement]\nfisher_fraction = 1.5"),
        ),
        (
            "kl-limit",
            at("eval_steps = 100", "[improvement]\nkl_limit = -1.0"),
        ),
        (
            "ppo-damping",
            at(
                "eval_steps = 100",
                "[improvement]\nkind = \"ppo-clip\"\ndamping = 0.1",
            ),
        ),
        (
            "ppo-clip",
            at(
                "eval_steps = 100",
                "[improvement]\nkind = \"ppo-clip\"\nclip_epsilon = 1.5",
            ),
        ),
        (
            "ppo-epochs",
            at(
                "warmup = 0",
                "[guidance.update]\nkind = \"ppo-clip\"\nepochs = 0",
            ),
        ),
        (
            "ppo-penalty",
            at(
                "eval_steps = 100",
                "[improvement]\nkind = \"ppo-penalty\"\nbeta_init = -1.0",
            ),
        ),
        (
            "npg-step",
            at(
                "eval_steps = 100",
                "[improvement]\nkind = \"npg\"\ncg_iters = 0",
            ),
        ),
        (
            "critic-subsample",
            TINY.replace("iterations = 3 }", "iterations = 3, subsample = 0 }"),
        ),
        (
            "critic-fit-field",
            TINY.replace("iterations = 3 }", "iterations = 3, epochs = 2 }"),
        ),
        (
            "delta0-negative",
            TINY.replace("delta0 = 0.2", "delta0 = -0.2"),
        ),
        (
            "alpha-above-one",
            TINY.replace("alpha = 0.9", "alpha = 1.5"),
        ),
        ("observe-zero", at("warmup = 0", "observe = 0")),
        (
            "reward-negative",
            at("eval_steps = 100", "[reward]\nenv = -1.0"),
        ),
        (
            "bc-epochs",
            at("eval_steps = 100", "[init]\nkind = \"bc\"\nepochs = 0"),
        ),
        (
            "dapg-lambda",
            at(
                "eval_steps = 100",
                "[demonstration_rows]\nlambda0 = -1.0\nlambda1 = 0.95",
            ),
        ),
        (
            "algorithm-unknown",
            at("eval_steps = 100", "[algorithm]\nname = \"nope\""),
        ),
        (
            "init-policy-missing",
            at("num_envs = 4", "init_policy = \"nothing.pt\""),
        ),
        (
            "sparse-kind",
            env("InvertedDoublePendulum-v4", "{ kind = \"walk\" }"),
        ),
        (
            "sparse-goal",
            env(
                "InvertedDoublePendulum-v4",
                "{ kind = \"goal\", radius = 0.1 }",
            ),
        ),
        (
            "sparse-threshold",
            env("InvertedDoublePendulum-v4", "{ kind = \"distance\" }"),
        ),
        (
            "sparse-negative",
            env("Hopper-v4", "{ kind = \"distance\", threshold = -1.0 }"),
        ),
        (
            "already-sparse",
            env("SparseInvertedDoublePendulum-v4", "{ kind = \"delayed\" }"),
        ),
        ("unknown-id", env("Pendulum-v4", "{ kind = \"delayed\" }")),
        (
            "sparse-suffix",
            TINY.replace(
                "\"SparseInvertedDoublePendulum-v4\"",
                "\"Hopper-v4+distance(x)\"",
            ),
        ),
        (
            "eval-env-dims",
            at("iterations = 2", "eval_env = \"Ant-v4\""),
        ),
        (
            "clip-normalise",
            at(
                "num_envs = 4",
                "normalise_observations = true\ninit_policy = \"demos.npy\"",
            ),
        ),
    ]
}

/// Every case's line, `name: message`, with the scratch folder written `<dir>`.
fn messages() -> String {
    let logo = Logo::new(env!("CARGO_BIN_EXE_logo"));
    let dir = scratch("messages");
    let text = |p: &Path| p.to_str().expect("a UTF-8 path").to_string();
    write_npy(&dir.join("demos.npy"), 40, 12);
    let mut lines = Vec::new();
    let mut record = |name: &str, args: Vec<String>| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let line = one_line_error(&logo.run(&args)).replace(&text(&dir), "<dir>");
        lines.push(format!("{name}: {line}"));
    };
    for (name, config) in config_cases() {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, config).unwrap();
        let out = text(&dir.join(format!("out-{name}")));
        record(
            name,
            vec![
                "train".into(),
                "--config".into(),
                text(&path),
                "--out".into(),
                out,
            ],
        );
    }
    // Files that are not what they should be.
    let train = |config: &str, out: &str| {
        vec![
            "train".into(),
            "--config".into(),
            text(&dir.join(config)),
            "--out".into(),
            text(&dir.join(out)),
        ]
    };
    std::fs::write(dir.join("tiny.toml"), TINY).unwrap();
    record("config-missing", train("absent.toml", "out-absent"));
    std::fs::write(dir.join("config-not-toml.toml"), "env = [").unwrap();
    record(
        "config-not-toml",
        train("config-not-toml.toml", "out-not-toml"),
    );
    let sub = |name: &str, file: &str, write: &dyn Fn(&Path)| {
        let folder = dir.join(name);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join("tiny.toml"), TINY).unwrap();
        write(&folder.join(file));
        folder
    };
    sub("npy-garbage", "demos.npy", &|p| {
        std::fs::write(p, b"not an npy file").unwrap()
    });
    record(
        "npy-garbage",
        train("npy-garbage/tiny.toml", "out-npy-garbage"),
    );
    sub("npy-width", "demos.npy", &|p| write_npy(p, 20, 9));
    record("npy-width", train("npy-width/tiny.toml", "out-npy-width"));
    sub("npy-nan", "demos.npy", &|p| {
        logo_data::write_npy(p, &[2, 12], &[f64::NAN; 24]).unwrap()
    });
    record("npy-nan", train("npy-nan/tiny.toml", "out-npy-nan"));
    // A folder holding a run already, and resumes of what is not a run.
    let held = sub("held", "checkpoint.safetensors", &|p| {
        std::fs::write(p, b"x").unwrap()
    });
    record("out-holds-a-run", train("tiny.toml", "held"));
    let _ = held;
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    record(
        "resume-empty",
        vec!["train".into(), "--resume".into(), text(&empty)],
    );
    let corrupt = sub("corrupt", "checkpoint.safetensors", &|p| {
        std::fs::write(p, b"not a safetensors file").unwrap()
    });
    record(
        "resume-corrupt",
        vec!["train".into(), "--resume".into(), text(&corrupt)],
    );
    // A real run whose config.toml was edited after it: the resume state no longer fits.
    let run = dir.join("edited");
    logo.train(&dir.join("tiny.toml"), &run, &["--iterations", "1"]);
    // Its resume state said to be of a newer format (the same length, so the header's
    // size still holds).
    let checkpoint = run.join("checkpoint.safetensors");
    let bytes = std::fs::read(&checkpoint).unwrap();
    let (from, to) = (br#"\"format\":2"#, br#"\"format\":9"#);
    let at = bytes
        .windows(from.len())
        .position(|w| w == from)
        .expect("a format-2 state");
    let mut edited = bytes.clone();
    edited[at..at + from.len()].copy_from_slice(to);
    std::fs::write(&checkpoint, edited).unwrap();
    record(
        "resume-edited",
        vec![
            "train".into(),
            "--resume".into(),
            text(&run),
            "--iterations".into(),
            "2".into(),
        ],
    );
    record(
        "eval-missing",
        vec![
            "eval".into(),
            "--checkpoint".into(),
            text(&dir.join("none.safetensors")),
        ],
    );
    record(
        "eval-corrupt",
        vec![
            "eval".into(),
            "--checkpoint".into(),
            text(&corrupt.join("checkpoint.safetensors")),
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
    lines.join("\n") + "\n"
}

#[test]
fn bad_input_prints_the_recorded_one_line_errors() {
    let golden = workspace().join("tests/golden/error-messages.txt");
    let got = messages();
    if std::env::var_os("LOGO_GOLDEN_WRITE").is_some() {
        std::fs::write(&golden, &got).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&golden).expect("tests/golden/error-messages.txt");
    for (w, g) in want.lines().zip(got.lines()) {
        assert_eq!(
            w, g,
            "a message changed (LOGO_GOLDEN_WRITE=1 rewrites the file)"
        );
    }
    assert_eq!(
        want.lines().count(),
        got.lines().count(),
        "cases were added or removed"
    );
}

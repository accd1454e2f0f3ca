//! Generated corruptions of what a run reads back: its checkpoint and its metrics.csv on
//! `--resume`, and the TOML config of a new run. Each must end in an error or in a run
//! that works; never a panic. CI runs `PROPTEST_CASES` cases each (64 unless set).

#[path = "../../logo-data/tests/common/corrupt.rs"]
mod corrupt;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use corrupt::{apply, config, mutation, no_panic};
use logo_algo::{TrainConfig, Trainer};
use logo_nn::Kernels;
use proptest::prelude::*;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("logo-algo-fuzz-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn config_text() -> String {
    let demos =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/logo/inverted_double_pendulum");
    format!(
        r#"env = "SparseInvertedDoublePendulum-v4"
iterations = 2
samples_per_iter = 200
num_envs = 2
threads = 1
policy_hidden = [8, 8]
eval_steps = 50
checkpoint_every = 2
seed = 5
max_kl = 0.01
log_std_init = 0.0
[critic]
hidden = [8, 8]
fit = {{ method = "lbfgs", iterations = 3 }}
[guidance]
demos = {:?}
delta0 = 0.2
alpha = 0.9
warmup = 1
discriminator_hidden = [8, 8]
"#,
        demos.to_str().unwrap()
    )
}

/// A finished 2-iteration LOGO run to corrupt copies of (made once).
fn finished_run() -> &'static PathBuf {
    static RUN: OnceLock<PathBuf> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = scratch("source");
        let path = dir.join("config.toml");
        std::fs::write(&path, config_text()).unwrap();
        let run = dir.join("run");
        let mut trainer = Trainer::new(Kernels, TrainConfig::load(&path).unwrap(), &run).unwrap();
        while !trainer.done() {
            trainer.step().unwrap();
        }
        run
    })
}

/// A copy of the finished run with `file` corrupted.
fn corrupted_copy(case: &str, file: &str, mutations: &[corrupt::Mutation]) -> PathBuf {
    let source = finished_run();
    let dir = scratch(case);
    for entry in std::fs::read_dir(source).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), dir.join(entry.file_name())).unwrap();
    }
    let bytes = std::fs::read(source.join(file)).unwrap();
    std::fs::write(dir.join(file), apply(&bytes, mutations)).unwrap();
    dir
}

/// Resumes `dir` for one more iteration; an accepted resume must then train, or stop on
/// the non-finite check (a weight corrupted to 1e308 is a number, and overflows in the
/// first critic fit) with metrics.csv left as it was.
fn resume_and_step(dir: &Path) -> Result<(), TestCaseError> {
    let resumed = no_panic("Trainer::resume", || Trainer::resume(Kernels, dir, Some(3)))?;
    if let Ok(mut trainer) = resumed {
        prop_assert_eq!(trainer.iteration(), 2);
        if let Err(e) = no_panic("step", || trainer.step())? {
            let e = e.to_string();
            prop_assert!(e.contains("non-finite") && e.contains("is kept"), "{}", e);
            return Ok(());
        }
        let csv = std::fs::read_to_string(dir.join("metrics.csv")).unwrap();
        let iterations: Vec<&str> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap())
            .collect();
        prop_assert_eq!(iterations, vec!["0", "1", "2"]);
    }
    Ok(())
}

/// Replaces the `nth` number of `text` by `value`.
fn replace_number(text: &str, nth: usize, value: &str) -> String {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit() && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric());
        if starts {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    let (start, end) = spans[nth % spans.len()];
    format!("{}{value}{}", &text[..start], &text[end..])
}

const VALUES: [&str; 12] = [
    "0",
    "-1",
    "1e308",
    "nan",
    "inf",
    "-inf",
    "18446744073709551615",
    "9223372036854775807",
    "4294967296",
    "0.0",
    "\"x\"",
    "[]",
];

proptest! {
    #![proptest_config(config())]

    #[test]
    fn checkpoints_on_resume(mutations in prop::collection::vec(mutation(), 1..4)) {
        let dir = corrupted_copy("checkpoint", "checkpoint.safetensors", &mutations);
        resume_and_step(&dir)?;
    }

    #[test]
    fn metrics_on_resume(mutations in prop::collection::vec(mutation(), 1..4)) {
        let dir = corrupted_copy("metrics", "metrics.csv", &mutations);
        resume_and_step(&dir)?;
    }

    #[test]
    fn configs(edits in prop::collection::vec((0usize..64, 0usize..VALUES.len()), 1..3)) {
        let mut text = config_text();
        for (nth, value) in edits {
            text = replace_number(&text, nth, VALUES[value]);
        }
        let dir = scratch("config");
        let path = dir.join("config.toml");
        std::fs::write(&path, &text).unwrap();
        if let Ok(config) = no_panic("TrainConfig::load", || TrainConfig::load(&path))? {
            // Accepted: it must build (a run's sizes are bounded, so this cannot exhaust
            // memory) and its error, if any, must be one.
            let _ = no_panic("Trainer::new", || Trainer::new(Kernels, config, &dir.join("run")))?;
        }
    }
}

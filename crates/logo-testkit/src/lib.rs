//! What logo-rl's tests share, so that each test file holds only its own checks:
//! the repository root, the project venv's Python, scratch folders, and the `logo`
//! binary run as a user runs it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub fn workspace() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    root.canonicalize().unwrap_or(root)
}

/// The project venv's Python (`./scripts/setup.sh` makes it). Where it is missing the
/// calling test is skipped (None), unless `LOGO_REQUIRE_PYTHON` is set, as
/// `scripts/test.sh` sets it: then a missing venv fails the test.
pub fn python() -> Option<PathBuf> {
    let python = workspace().join(".venv/bin/python");
    if python.exists() {
        return Some(python);
    }
    assert!(
        std::env::var_os("LOGO_REQUIRE_PYTHON").is_none(),
        "LOGO_REQUIRE_PYTHON is set but {} is missing: run ./scripts/setup.sh",
        python.display()
    );
    eprintln!("skipped: no {} (run ./scripts/setup.sh)", python.display());
    None
}

/// A new, empty folder of its own under the system's temporary folder, named after
/// `name` (made by `tempfile`, so that parallel tests and processes never share one).
/// It is kept after the test, for a failure to be looked at; tests that pass remove it.
pub fn scratch(name: &str) -> PathBuf {
    tempfile::Builder::new()
        .prefix(&format!("logo-{name}-"))
        .tempdir()
        .expect("a scratch folder under the temporary folder")
        .keep()
}

/// The `logo` binary under test (`Logo::new(env!("CARGO_BIN_EXE_logo"))`).
pub struct Logo {
    binary: PathBuf,
}

impl Logo {
    pub fn new(binary: impl Into<PathBuf>) -> Self {
        Self {
            binary: binary.into(),
        }
    }

    /// A command running the binary, to add arguments, environment and a folder to.
    pub fn command(&self) -> Command {
        Command::new(&self.binary)
    }

    /// `logo args`, whatever its outcome.
    pub fn run(&self, args: &[&str]) -> Output {
        self.command()
            .args(args)
            .output()
            .expect("the logo binary runs")
    }

    /// `logo args`, expected to succeed: its standard output.
    pub fn succeed(&self, args: &[&str]) -> String {
        let out = self.run(args);
        assert!(
            out.status.success(),
            "logo {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    }
}

/// `config` (a `logo train` config's text) with its `env = ...` line replaced by an
/// `[env]` table of `id` and `sparse` (a TOML inline table such as `{ kind = "delayed" }`);
/// None where the config has no such line.
pub fn with_env_table(config: &str, id: &str, sparse: &str) -> Option<String> {
    let kept: Vec<&str> = config
        .lines()
        .filter(|line| !line.starts_with("env = "))
        .collect();
    (kept.len() < config.lines().count()).then(|| {
        format!(
            "{}\n[env]\nid = \"{id}\"\nsparse = {sparse}\n",
            kept.join("\n")
        )
    })
}

/// The one-line error of a command expected to fail (the project's promise for bad
/// input: one line naming what to fix, and a non-zero exit).
pub fn one_line_error(out: &Output) -> String {
    assert!(
        !out.status.success(),
        "expected a failure; stdout: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    let err = String::from_utf8_lossy(&out.stderr).trim().to_string();
    assert_eq!(err.lines().count(), 1, "one line, got: {err}");
    err
}

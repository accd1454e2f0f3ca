//! What logo-rl's tests share, so that each test file holds only its own checks:
//! the repository root, the project venv's Python, scratch folders, the `logo` binary
//! run as a user runs it, and tiny configs ([`Tiny`]).

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

    /// `logo train --config config --out out` and `more` arguments, expected to succeed:
    /// its standard output.
    pub fn train(&self, config: &Path, out: &Path, more: &[&str]) -> String {
        self.succeed(&[&train_args(config, out)[..], more].concat())
    }

    /// `logo train --config config --out out`, expected to fail: its one-line error.
    pub fn train_error(&self, config: &Path, out: &Path) -> String {
        one_line_error(&self.run(&train_args(config, out)))
    }
}

fn train_args<'a>(config: &'a Path, out: &'a Path) -> [&'a str; 5] {
    [
        "train",
        "--config",
        config.to_str().expect("a UTF-8 path"),
        "--out",
        out.to_str().expect("a UTF-8 path"),
    ]
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

/// A tiny LOGO run's config as text, its demonstrations `demos.npy` beside it (write them
/// with [`write_demos_npy`], 12 columns for IDP): sparse IDP, 2 iterations of 300
/// samples, 16 × 16 networks; tests edit the text to make one mistake or change one key.
pub const TINY_LOGO_TEXT: &str = r#"
env = "SparseInvertedDoublePendulum-v4"
iterations = 2
samples_per_iter = 300
num_envs = 4
policy_hidden = [16, 16]
eval_steps = 100
[critic]
hidden = [16, 16]
fit = { method = "lbfgs", iterations = 3 }
[guidance]
demos = "demos.npy"
delta0 = 0.2
alpha = 0.9
warmup = 0
"#;

/// A LOGO `.npy` of `rows` × `cols` small values (rows of observation ‖ action).
pub fn write_demos_npy(path: &Path, rows: usize, cols: usize) {
    let data: Vec<f64> = (0..rows * cols)
        .map(|k| (k as f64 * 0.1).sin() * 0.5)
        .collect();
    logo_data::write_npy(path, &[rows, cols], &data).expect("a writable .npy path");
}

/// A tiny run's config: sparse IDP at sizes a test trains in seconds (2 iterations of 300
/// samples, 16 × 16 networks, 100 evaluation steps), TRPO unless [`Tiny::logo`] adds
/// LOGO's guidance. Tests change what they vary with [`Tiny::set`] or [`Tiny::with`].
#[derive(Clone, Debug)]
pub struct Tiny(toml::Table);

impl Tiny {
    /// TRPO on sparse IDP.
    pub fn trpo() -> Self {
        Self(toml::toml! {
            env = "SparseInvertedDoublePendulum-v4"
            iterations = 2
            samples_per_iter = 300
            policy_hidden = [16, 16]
            eval_steps = 100
            [critic]
            hidden = [16, 16]
        })
    }

    /// LOGO on sparse IDP, guided by the project's IDP demonstrations (δ_0 = 0.2,
    /// α = 0.9, no warm-up).
    pub fn logo() -> Self {
        let demos = workspace().join("data/logo/inverted_double_pendulum");
        Self::trpo()
            .set("guidance.demos", demos.to_str().expect("a UTF-8 path"))
            .set("guidance.delta0", 0.2)
            .set("guidance.alpha", 0.9)
            .set("guidance.warmup", 0)
    }

    /// `key` (dotted for a table's: `critic.fit.iterations`) set to `value`.
    pub fn set(mut self, key: &str, value: impl Into<toml::Value>) -> Self {
        let (tables, last) = match key.rsplit_once('.') {
            Some((tables, last)) => (tables.split('.').collect(), last),
            None => (Vec::new(), key),
        };
        let mut table = &mut self.0;
        for name in tables {
            table = table
                .entry(name)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .unwrap_or_else(|| panic!("{name} of {key} is not a table"));
        }
        table.insert(last.to_string(), value.into());
        self
    }

    /// The critic fitted by `iterations` of L-BFGS.
    pub fn lbfgs(self, iterations: i64) -> Self {
        self.set("critic.fit.method", "lbfgs")
            .set("critic.fit.iterations", iterations)
    }

    /// Every key of the TOML `text` set (tables merged key by key).
    pub fn with(mut self, text: &str) -> Self {
        fn merge(into: &mut toml::Table, from: toml::Table) {
            for (key, value) in from {
                match (into.get_mut(&key), value) {
                    (Some(toml::Value::Table(old)), toml::Value::Table(new)) => merge(old, new),
                    (_, value) => {
                        into.insert(key, value);
                    }
                }
            }
        }
        let table: toml::Table = text.parse().unwrap_or_else(|e| panic!("{text}: {e}"));
        merge(&mut self.0, table);
        self
    }

    /// The config's TOML text.
    pub fn text(&self) -> String {
        toml::to_string(&self.0).expect("a TOML table")
    }

    /// Writes the config to `path`, which it returns.
    pub fn write(&self, path: &Path) -> PathBuf {
        std::fs::write(path, self.text()).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        path.to_path_buf()
    }
}

/// The rows of `dir`'s metrics.csv (its header first) without the timing columns,
/// `wall_s` and `t_*`: what two runs of the same numbers write alike.
pub fn metrics_without_timings(dir: &Path) -> Vec<String> {
    let path = dir.join("metrics.csv");
    let csv = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header: Vec<&str> = csv
        .lines()
        .next()
        .unwrap_or_else(|| panic!("{}: empty", path.display()))
        .split(',')
        .collect();
    csv.lines()
        .map(|line| {
            line.split(',')
                .zip(&header)
                .filter(|(_, h)| **h != "wall_s" && !h.starts_with("t_"))
                .map(|(v, _)| v)
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect()
}

/// The largest |a − b| over the largest |b|: how far `a` is from `b`, at `b`'s scale.
pub fn max_relative_error(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs() / scale))
}

#[cfg(test)]
mod tests {
    use super::Tiny;

    #[test]
    fn tiny_configs_set_keys_at_any_depth_and_merge_text() {
        let text = Tiny::logo()
            .lbfgs(3)
            .set("iterations", 5)
            .with("seed = 7\n[critic]\nhidden = [8]\n")
            .text();
        let table: toml::Table = text.parse().unwrap();
        assert_eq!(table["iterations"].as_integer(), Some(5));
        assert_eq!(table["seed"].as_integer(), Some(7));
        assert_eq!(table["critic"]["fit"]["iterations"].as_integer(), Some(3));
        assert_eq!(table["critic"]["hidden"].as_array().unwrap().len(), 1);
        assert_eq!(table["guidance"]["delta0"].as_float(), Some(0.2));
        assert!(
            table["guidance"]["demos"]
                .as_str()
                .unwrap()
                .ends_with("inverted_double_pendulum")
        );
    }
}

//! `logo_rl.train`'s Rust side: the job of `logo train`, its lines handed to a Python
//! callable, Ctrl-C honoured between iterations (the run keeps a checkpoint there).

use std::path::PathBuf;
use std::sync::Arc;

use clap::ValueEnum;
use logo_algo::bc::{InitConfig, InitKind};
use logo_algo::episode::SuccessRule;
use logo_algo::{Schedule, TrainConfig};
use logo_cli::bc::BcJob;
use logo_cli::train::{Console, Job, Start, run_dir_for_config, run_job};
use logo_engine::{BackendKind, Dtype, EngineArgs, EngineKind};
use logo_envs::{EnvConfig, EnvMaker, EnvSpec};
use pyo3::prelude::*;

use crate::errors::{Kind, config_error, logo_error, raised, value_error};
use crate::python_env::{PyEnvMaker, Raised};

/// Lines go to `say` (a Python callable). Python's pending signals are checked after each
/// iteration; Ctrl-C (KeyboardInterrupt), there or inside `say`, or any exception `say`
/// raises, stops the run once its checkpoint is written, and is raised again to the caller.
struct PythonConsole {
    say: Py<PyAny>,
    raised: Option<PyErr>,
}

impl Console for PythonConsole {
    fn say(&mut self, line: &str) {
        if self.raised.is_some() {
            // Stopping: the lines that remain go where the caller can still see them.
            eprintln!("{}", crate::errors::in_python_words(line));
            return;
        }
        let line = crate::errors::in_python_words(line);
        if let Err(e) = Python::attach(|py| self.say.call1(py, (line,))) {
            self.raised = Some(e);
        }
    }

    fn go_on(&mut self) -> anyhow::Result<()> {
        if self.raised.is_none() {
            self.raised = Python::attach(|py| py.check_signals()).err();
        }
        match &self.raised {
            None => Ok(()),
            Some(e) => Err(anyhow::anyhow!("interrupted ({e})")),
        }
    }
}

fn choice<T: ValueEnum>(key: &str, value: Option<&str>) -> PyResult<Option<T>> {
    value
        .map(|text| {
            T::from_str(text, true).map_err(|_| {
                let names: Vec<String> = T::value_variants()
                    .iter()
                    .filter_map(|v| v.to_possible_value())
                    .map(|p| p.get_name().to_string())
                    .collect();
                value_error(format!(
                    "{key}={text:?}: expected one of {}",
                    names.join(", ")
                ))
            })
        })
        .transpose()
}

/// The config `table_json` (a JSON object of a config's keys) names, read as
/// `TrainConfig::load_with` reads a file: from `path` with the table laid over it, or the
/// table alone (`origin` names it in errors, relative paths are taken from `base`).
fn config(path: Option<PathBuf>, table_json: &str, base: PathBuf) -> PyResult<TrainConfig> {
    let mut json: serde_json::Value =
        serde_json::from_str(table_json).map_err(|e| value_error(format!("config keys: {e}")))?;
    // A top-level None takes the key out of the config (guidance=None: TRPO alone).
    let mut removed = Vec::new();
    if let Some(map) = json.as_object_mut() {
        map.retain(|key, value| {
            if value.is_null() {
                removed.push(key.clone());
            }
            !value.is_null()
        });
    }
    let removed: Vec<&str> = removed.iter().map(String::as_str).collect();
    let table: toml::Table = toml::Value::try_from(json)
        .ok()
        .and_then(|v| v.as_table().cloned())
        .ok_or_else(|| value_error("config keys: a TOML table (no None values) was expected"))?;
    match &path {
        Some(path) => TrainConfig::load_edited(path, table.clone(), &removed).map_err(|e| {
            // Where the file alone is a good config, the call's keyword arguments are what
            // is wrong: say so, rather than blame the file.
            if (table.is_empty() && removed.is_empty()) || TrainConfig::load(path).is_err() {
                return config_error(&e, e.to_string());
            }
            let keys: Vec<&str> = table
                .keys()
                .map(String::as_str)
                .chain(removed.iter().copied())
                .collect();
            let message = format!(
                "the keyword arguments ({}) laid over {}: {}",
                keys.join(", "),
                path.display(),
                e.message
            );
            config_error(&e, message)
        }),
        None => TrainConfig::from_table(table, &PathBuf::from("<config dict>"), &base)
            .map_err(|e| config_error(&e, e.to_string())),
    }
}

/// Runs `logo train` in this process, with the GIL released, and returns the run folder.
/// `config` and `table_json` make a new run (see [`config`]); `resume` continues one.
/// `env`: a Python env's maker and its spec ([`SpecArg`]), registered under its id for the
/// run; the first exception it raises is raised again here.
#[pyfunction]
#[pyo3(signature = (
    *, say, config = None, table_json = "{}", base = PathBuf::from("."), out = None,
    resume = None, iterations = None, engine = None, backend = None, dtype = None,
    tensorboard = true, env = None
))]
#[allow(clippy::too_many_arguments)]
pub fn train(
    py: Python<'_>,
    say: Py<PyAny>,
    config: Option<PathBuf>,
    table_json: &str,
    base: PathBuf,
    out: Option<PathBuf>,
    resume: Option<PathBuf>,
    iterations: Option<usize>,
    engine: Option<&str>,
    backend: Option<&str>,
    dtype: Option<&str>,
    tensorboard: bool,
    env: Option<(Py<PyAny>, SpecArg)>,
) -> PyResult<PathBuf> {
    let engine = EngineArgs {
        engine: choice::<EngineKind>("engine", engine)?,
        backend: choice::<BackendKind>("backend", backend)?,
        dtype: choice::<Dtype>("dtype", dtype)?,
    };
    // First: the config names the env by its id.
    let raised = Raised::default();
    let _registered = env
        .map(|(make, spec)| register(make, spec, raised.clone()))
        .transpose()?;
    let start = match resume {
        Some(dir) => Start::Resume(dir, iterations),
        None => {
            let name = config.clone();
            let config = self::config(config, table_json, base)?;
            let out = out.unwrap_or_else(|| run_dir_for(name, config.seed));
            Start::New(Box::new(config), out)
        }
    };
    let job = Job {
        start,
        stop: None,
        schedule: Schedule::Pipelined,
        tensorboard,
        video_every: None,
    };
    let mut console = PythonConsole { say, raised: None };
    let result = py.detach(|| run_job(job, &engine, &mut console));
    match (result, console.raised.or_else(|| raised.take())) {
        (_, Some(raised)) => Err(raised),
        (Ok(dir), None) => Ok(dir),
        (Err(e), None) => Err(logo_error(&e)),
    }
}

/// A config file's keys as JSON, read as `logo train` reads the file: a file that is not
/// there, or not TOML, raises the same error (naming the file and the line) with or
/// without `env=`.
#[pyfunction]
pub fn config_keys(path: PathBuf) -> PyResult<String> {
    let table = TrainConfig::read_table(&path).map_err(|e| config_error(&e, e.to_string()))?;
    serde_json::to_string(&table).map_err(|e| value_error(format!("{}: {e}", path.display())))
}

/// `logo train`'s default run folder, `runs/<config name>-seed<seed>` (`run` for a dict),
/// for Python too (the list-of-trajectories demos are written into it before training).
#[pyfunction]
#[pyo3(signature = (config, seed))]
pub fn run_dir_for(config: Option<PathBuf>, seed: u64) -> PathBuf {
    run_dir_for_config(config.as_deref().unwrap_or("run".as_ref()), seed)
}

/// A Python env's registration, dropped when the call ends whichever way it ends.
struct Registered(Arc<dyn EnvMaker>);

impl Drop for Registered {
    fn drop(&mut self) {
        logo_envs::unregister_external(&self.0);
    }
}

/// What the Rust side needs of a Python env (`logo_rl.custom.prepare`'s dict).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct SpecArg {
    id: String,
    obs_dim: usize,
    act_dim: usize,
    action_low: Vec<f64>,
    action_high: Vec<f64>,
    max_episode_steps: usize,
    dt: f64,
}

/// Registers a Python env's maker under its spec's id.
fn register(make: Py<PyAny>, spec: SpecArg, raised: Raised) -> PyResult<Registered> {
    if spec.action_low.len() != spec.act_dim || spec.action_high.len() != spec.act_dim {
        return Err(value_error(format!(
            "{}: action bounds of {} and {} values for {} actions",
            spec.id,
            spec.action_low.len(),
            spec.action_high.len(),
            spec.act_dim
        )));
    }
    let spec = EnvSpec {
        id: spec.id,
        obs_dim: spec.obs_dim,
        act_dim: spec.act_dim,
        action_low: spec.action_low,
        action_high: spec.action_high,
        max_episode_steps: spec.max_episode_steps,
        frame_skip: 1,
        dt: spec.dt,
    };
    let maker: Arc<dyn EnvMaker> = Arc::new(PyEnvMaker { make, spec, raised });
    logo_envs::register_external(maker.clone()).map_err(|e| value_error(e.to_string()))?;
    Ok(Registered(maker))
}

/// `logo bc` in this process, with the GIL released: fits, writes the checkpoint `out`,
/// evaluates. `env_id` names the task (a logo-rl id, or a Python env's, registered for the
/// call from `env`). Returns the checkpoint's path and, as JSON, the fit's report, the
/// evaluation (as `eval.json` holds one policy's) and the engine.
#[pyfunction]
#[pyo3(signature = (
    *, env_id, demos, out, seed, epochs, minibatch, learning_rate, learn_std, hidden,
    episodes, success = "task", engine = None, backend = None, dtype = None, env = None
))]
#[allow(clippy::too_many_arguments)]
pub fn bc(
    py: Python<'_>,
    env_id: String,
    demos: PathBuf,
    out: PathBuf,
    seed: u64,
    epochs: usize,
    minibatch: usize,
    learning_rate: f64,
    learn_std: bool,
    hidden: Vec<usize>,
    episodes: usize,
    success: &str,
    engine: Option<&str>,
    backend: Option<&str>,
    dtype: Option<&str>,
    env: Option<(Py<PyAny>, SpecArg)>,
) -> PyResult<(PathBuf, String)> {
    let success: SuccessRule = success
        .parse()
        .map_err(|e: String| value_error(format!("success={e}")))?;
    let engine = EngineArgs {
        engine: choice::<EngineKind>("engine", engine)?,
        backend: choice::<BackendKind>("backend", backend)?,
        dtype: choice::<Dtype>("dtype", dtype)?,
    };
    let fit = InitConfig {
        kind: InitKind::Bc,
        demos: None,
        epochs,
        minibatch,
        learning_rate,
        learn_std,
    };
    // The keys named as this function's keyword arguments.
    fit.validate()
        .map_err(|e| raised(Kind::Value, e.message().replace("init.", "")))?;
    logo_algo::validate::check_widths("hidden", &hidden)
        .map_err(|e| raised(Kind::Value, e.to_string()))?;
    if episodes == 0 {
        return Err(value_error("episodes must be at least 1"));
    }
    let raised = Raised::default();
    let _registered = env
        .map(|(make, spec)| register(make, spec, raised.clone()))
        .transpose()?;
    let job = BcJob {
        env: EnvConfig::named(&env_id),
        demos,
        out,
        seed,
        hidden,
        log_std_init: 0.0,
        fit,
        success,
        episodes,
    };
    let result = py.detach(|| engine.with(logo_cli::bc::Cloning(&job)));
    match (result, raised.take()) {
        (_, Some(raised)) => Err(raised),
        (Err(e), None) => Err(logo_error(&e)),
        (Ok(outcome), None) => {
            let json = serde_json::json!({
                "report": outcome.report,
                "evaluation": outcome.evaluation,
                "evaluation_file": outcome.evaluation_file,
                "engine": outcome.engine,
            });
            Ok((outcome.checkpoint, json.to_string()))
        }
    }
}

/// The config (as [`config`] reads it) made into algorithm `name` by its own keys
/// (`logo compare`'s configs), as TOML text.
#[pyfunction]
#[pyo3(signature = (*, name, config = None, table_json = "{}", base = PathBuf::from(".")))]
pub fn configure(
    name: &str,
    config: Option<PathBuf>,
    table_json: &str,
    base: PathBuf,
) -> PyResult<String> {
    let origin = config.clone();
    let loaded = self::config(config, table_json, base)?;
    let made = logo_algo::algorithms::configure(&loaded, name).map_err(|e| {
        let origin = origin.map_or("<config dict>".into(), |p| p.display().to_string());
        crate::errors::invalid(&e, format!("{origin}: as {name}: {e}"))
    })?;
    made.to_toml()
        .map_err(|e| crate::errors::LogoError::new_err(e.to_string()))
}

/// The numeric columns of a run's `metrics.csv`, in file order (what `compare`'s
/// `metric` may name).
#[pyfunction]
pub fn metric_columns() -> Vec<String> {
    logo_algo::IterationMetrics::numeric_columns()
}

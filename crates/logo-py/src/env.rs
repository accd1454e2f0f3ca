//! One env of `logo envs` for Python: `logo_rl.envs.LogoEnv` wraps it as a Gymnasium env.

use logo_envs::render::{Look, Renderer};
use logo_envs::{Env, EnvFactory, EnvOptions};
use numpy::{IntoPyArray, PyArray1, PyArray3, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::errors::{env_error, render_error, value_error};

/// Every id `RustEnv` takes by name (`logo envs`): the dense tasks, then LOGO's sparse ones.
#[pyfunction]
pub fn env_ids() -> Vec<String> {
    logo_envs::all_env_ids()
}

/// The time limit Gymnasium registers an id's task with (1000; Reacher 50, Pusher 100),
/// without loading its model.
#[pyfunction]
pub fn time_limit(id: &str) -> PyResult<usize> {
    logo_envs::time_limit(id).map_err(env_error)
}

/// The factory of a Rust env for Python. A `python:` id names an env a training run
/// registered: its copies are the trainer's, and from Python it is used as itself.
/// `max_episode_steps`: `None` for the limit Gymnasium registers the task with.
pub(crate) fn factory(id: &str, max_episode_steps: Option<usize>) -> PyResult<EnvFactory> {
    if id.starts_with(logo_envs::EXTERNAL_PREFIX) {
        return Err(value_error(format!(
            "{id}: a Python env is used as itself from Python, not through logo_rl's Rust envs"
        )));
    }
    if max_episode_steps == Some(0) {
        return Err(value_error("max_episode_steps must be at least 1"));
    }
    let options = EnvOptions {
        max_episode_steps,
        ..EnvOptions::default()
    };
    EnvFactory::new(id, &options).map_err(env_error)
}

/// A Rust env: `f64` observations and actions, the project's own seeded reset stream.
/// Not shared between threads (it may hold an OpenGL context for rendering).
#[pyclass(unsendable, module = "logo_rl._logo_rl")]
pub struct RustEnv {
    factory: EnvFactory,
    env: Box<dyn Env>,
    obs: Vec<f64>,
    renderer: Option<Renderer>,
}

fn f64s<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyArray1<f64>> {
    values.to_vec().into_pyarray(py)
}

#[pymethods]
impl RustEnv {
    /// `id`: any id of `logo envs`, also `<dense id>+<rule>` (`Hopper-v4+distance(5)`).
    #[new]
    #[pyo3(signature = (id, max_episode_steps = None))]
    fn new(id: &str, max_episode_steps: Option<usize>) -> PyResult<Self> {
        let factory = factory(id, max_episode_steps)?;
        let env = factory.build().map_err(env_error)?;
        let obs = vec![0.0; factory.spec().obs_dim];
        Ok(Self {
            factory,
            env,
            obs,
            renderer: None,
        })
    }

    #[getter]
    fn id(&self) -> String {
        self.factory.spec().id.clone()
    }
    #[getter]
    fn obs_dim(&self) -> usize {
        self.factory.spec().obs_dim
    }
    #[getter]
    fn act_dim(&self) -> usize {
        self.factory.spec().act_dim
    }
    #[getter]
    fn action_low<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        f64s(py, &self.factory.spec().action_low)
    }
    #[getter]
    fn action_high<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        f64s(py, &self.factory.spec().action_high)
    }
    #[getter]
    fn max_episode_steps(&self) -> usize {
        self.factory.spec().max_episode_steps
    }
    /// Seconds of simulated time per step.
    #[getter]
    fn dt(&self) -> f64 {
        self.factory.spec().dt
    }
    /// The sparse rule, as `logo envs` writes it (None for a dense env).
    #[getter]
    fn sparse(&self) -> Option<String> {
        self.factory.sparse_rule().map(|rule| rule.describe())
    }

    /// Starts an episode; `seed` reseeds the env's own ChaCha8 reset stream.
    #[pyo3(signature = (seed = None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>) -> Bound<'py, PyArray1<f64>> {
        self.env.reset(seed, &mut self.obs);
        f64s(py, &self.obs)
    }

    /// `(obs, reward, terminated, truncated, dense_reward, x_position, goal_distance)`,
    /// the last `None` for a task without a target.
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        f64,
        bool,
        bool,
        f64,
        f64,
        Option<f64>,
        Option<bool>,
    )> {
        let action = action.as_slice().map_err(|e| value_error(e.to_string()))?;
        let step = self.env.step(action, &mut self.obs).map_err(env_error)?;
        Ok((
            f64s(py, &self.obs),
            step.reward,
            step.terminated,
            step.truncated,
            step.info.dense_reward,
            step.info.x_position,
            step.info.goal_distance,
            step.info.success,
        ))
    }

    /// Overwrites the joint state (Gymnasium's `set_state`) and returns the observation.
    fn set_state<'py>(
        &mut self,
        py: Python<'py>,
        qpos: PyReadonlyArray1<'py, f64>,
        qvel: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let not_contiguous = |e: numpy::AsSliceError| value_error(e.to_string());
        let (qpos, qvel) = (
            qpos.as_slice().map_err(not_contiguous)?,
            qvel.as_slice().map_err(not_contiguous)?,
        );
        self.env
            .set_state(qpos, qvel, &mut self.obs)
            .map_err(|e| value_error(e.to_string()))?;
        Ok(f64s(py, &self.obs))
    }

    /// `(qpos, qvel)` now.
    fn state<'py>(
        &self,
        py: Python<'py>,
    ) -> (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>) {
        let (qpos, qvel) = self.env.state();
        (f64s(py, qpos), f64s(py, qvel))
    }

    /// The frame of the current state: `[height, width, 3]` RGB bytes, offscreen (EGL),
    /// with the camera `logo eval --video` uses.
    fn render<'py>(
        &mut self,
        py: Python<'py>,
        width: u32,
        height: u32,
    ) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let stale = self
            .renderer
            .as_ref()
            .is_some_and(|r| r.size() != (width, height));
        if self.renderer.is_none() || stale {
            let renderer = Renderer::new(&self.factory, width, height, Look::Full);
            self.renderer = Some(renderer.map_err(render_error)?);
        }
        let renderer = self.renderer.as_mut().expect("made above");
        let (qpos, qvel) = self.env.state();
        let frame = renderer.render(qpos, qvel).map_err(render_error)?;
        let shape = [height as usize, width as usize, 3];
        let array = frame.to_vec().into_pyarray(py);
        array.reshape(shape)
    }
}

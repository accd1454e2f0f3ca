//! N copies of one Rust env for Python (`logo_rl.vector.LogoVectorEnv`), stepped on Rust
//! threads with the GIL released: logo-rl's own `VecEnv`, as the trainer's sampler uses it.

use logo_envs::VecEnv;
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::env::factory;
use crate::errors::{env_error, value_error};

/// Not shared between Python threads; each step runs on the env's own worker threads.
#[pyclass(unsendable, module = "logo_rl._logo_rl")]
pub struct RustVecEnv {
    venv: VecEnv,
}

type Arrays<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
);

fn rows<'py>(py: Python<'py>, values: &[f64], width: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = values.len() / width;
    values.to_vec().into_pyarray(py).reshape([n, width])
}

#[pymethods]
impl RustVecEnv {
    /// `num_envs` copies of `id` on `threads` threads; copy i first reset with seed `seed + i`.
    #[new]
    #[pyo3(signature = (id, num_envs, threads, seed = 0, max_episode_steps = None))]
    fn new(
        id: &str,
        num_envs: usize,
        threads: usize,
        seed: u64,
        max_episode_steps: Option<usize>,
    ) -> PyResult<Self> {
        let factory = factory(id, max_episode_steps)?;
        let venv = VecEnv::new(&factory, num_envs, threads, seed).map_err(env_error)?;
        Ok(Self { venv })
    }

    #[getter]
    fn num_envs(&self) -> usize {
        self.venv.num_envs()
    }
    #[getter]
    fn id(&self) -> String {
        self.venv.spec().id.clone()
    }
    #[getter]
    fn obs_dim(&self) -> usize {
        self.venv.spec().obs_dim
    }
    #[getter]
    fn action_low<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.venv.spec().action_low.clone().into_pyarray(py)
    }
    #[getter]
    fn action_high<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.venv.spec().action_high.clone().into_pyarray(py)
    }

    /// Resets every copy: copy i with seed `seed + i`, or each continuing its own stream.
    #[pyo3(signature = (seed = None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        match seed {
            Some(seed) => {
                self.venv.reset(seed);
            }
            None => {
                let copies = vec![(); self.venv.num_envs()];
                self.venv
                    .map_copies(copies, |env, obs, ()| {
                        env.reset(None, obs);
                        Ok(())
                    })
                    .map_err(env_error)?;
            }
        }
        rows(py, self.venv.obs(), self.venv.spec().obs_dim)
    }

    /// Steps every copy (`actions`: `[num_envs, act_dim]`); a copy whose episode ends is
    /// reset on the spot. `(obs, reward, terminated, truncated, dense_reward, x_position,
    /// final_obs)`, `final_obs` meaningful where the episode ended.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Arrays<'py>> {
        let (n, act_dim) = (self.venv.num_envs(), self.venv.spec().act_dim);
        if actions.shape() != [n, act_dim] {
            return Err(value_error(format!(
                "actions of shape {:?}; {} x {n} takes [{n}, {act_dim}]",
                actions.shape(),
                self.venv.spec().id
            )));
        }
        // A copy: Python may write the array while the GIL is released.
        let actions = actions
            .as_slice()
            .map_err(|e| value_error(e.to_string()))?
            .to_vec();
        let venv = &mut self.venv;
        let out = py
            .detach(|| venv.step(&actions).cloned())
            .map_err(env_error)?;
        let obs_dim = self.venv.spec().obs_dim;
        let column = |f: fn(&logo_envs::Step) -> f64| out.steps.iter().map(f).collect::<Vec<_>>();
        let flag = |f: fn(&logo_envs::Step) -> bool| out.steps.iter().map(f).collect::<Vec<_>>();
        Ok((
            rows(py, &out.obs, obs_dim)?,
            column(|s| s.reward).into_pyarray(py),
            flag(|s| s.terminated).into_pyarray(py),
            flag(|s| s.truncated).into_pyarray(py),
            column(|s| s.info.dense_reward).into_pyarray(py),
            column(|s| s.info.x_position).into_pyarray(py),
            rows(py, &out.final_obs, obs_dim)?,
        ))
    }
}

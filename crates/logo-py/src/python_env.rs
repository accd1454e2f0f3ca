//! A user's Gymnasium env as a Rust [`Env`]: the trainer's sampler and evaluations step it
//! through this, holding the GIL only around its `reset` and `step`. The env comes wrapped
//! in `logo_rl.custom._Adapter`, which hands back float64 arrays and checks their shapes;
//! the first exception the env raises is kept, so that `logo_rl.train` raises it again
//! with its own traceback once the trainer has stopped.

use std::sync::{Arc, Mutex, PoisonError};

use logo_envs::{Env, EnvError, EnvMaker, EnvSpec, ResetPoint, Step, StepInfo};
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;

/// The first exception any copy raised, shared by a maker and its envs.
#[derive(Clone, Default)]
pub struct Raised(Arc<Mutex<Option<PyErr>>>);

impl Raised {
    /// Keeps `e` (where none is kept yet) and gives the trainer its message.
    fn keep(&self, env: &str, what: &str, e: PyErr) -> EnvError {
        let message = format!("{what} raised {e}");
        let mut slot = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        slot.get_or_insert(e);
        EnvError::External {
            env: env.to_string(),
            message,
        }
    }

    pub fn take(&self) -> Option<PyErr> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner).take()
    }
}

/// Builds copies by calling `make` (a Python callable returning an `_Adapter`).
pub struct PyEnvMaker {
    pub make: Py<PyAny>,
    pub spec: EnvSpec,
    pub raised: Raised,
}

impl EnvMaker for PyEnvMaker {
    fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    fn build(&self) -> Result<Box<dyn Env>, EnvError> {
        let adapter = Python::attach(|py| self.make.call0(py))
            .map_err(|e| self.raised.keep(&self.spec.id, "making the env", e))?;
        Ok(Box::new(PyEnv {
            adapter,
            spec: self.spec.clone(),
            raised: self.raised.clone(),
            failed: None,
            x: 0.0,
        }))
    }
}

struct PyEnv {
    adapter: Py<PyAny>,
    spec: EnvSpec,
    raised: Raised,
    /// A reset that raised: the next step reports it (`Env::reset` cannot fail).
    failed: Option<EnvError>,
    /// The env's `info["x_position"]` after the last step or reset (0 where it has none).
    x: f64,
}

impl Drop for PyEnv {
    /// Closes the user's env (its renderer, its devices), as Gymnasium's `close`.
    fn drop(&mut self) {
        Python::attach(|py| {
            if let Err(e) = self.adapter.call_method0(py, "close") {
                self.raised.keep(&self.spec.id, "close", e);
            }
        });
    }
}

fn copy_into(array: &Bound<'_, PyAny>, obs: &mut [f64]) -> PyResult<()> {
    let array: PyReadonlyArray1<'_, f64> = array.extract()?;
    obs.copy_from_slice(array.as_slice()?);
    Ok(())
}

impl Env for PyEnv {
    fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    fn reset(&mut self, seed: Option<u64>, obs: &mut [f64]) {
        let result = Python::attach(|py| -> PyResult<f64> {
            let out = self.adapter.call_method1(py, "reset", (seed,))?;
            let (array, x): (Bound<'_, PyAny>, f64) = out.extract(py)?;
            copy_into(&array, obs)?;
            Ok(x)
        });
        match result {
            Ok(x) => {
                self.x = x;
                self.failed = None;
            }
            Err(e) => {
                obs.fill(f64::NAN);
                self.failed = Some(self.raised.keep(&self.spec.id, "reset", e));
            }
        }
    }

    fn step(&mut self, action: &[f64], obs: &mut [f64]) -> Result<Step, EnvError> {
        if let Some(failed) = self.failed.take() {
            return Err(failed);
        }
        let result = Python::attach(|py| -> PyResult<Step> {
            let action = action.to_vec().into_pyarray(py);
            let out = self.adapter.call_method1(py, "step", (action,))?;
            let (array, reward, terminated, truncated, dense_reward, x, success): (
                Bound<'_, PyAny>,
                f64,
                bool,
                bool,
                f64,
                f64,
                Option<bool>,
            ) = out.extract(py)?;
            copy_into(&array, obs)?;
            self.x = x;
            Ok(Step {
                reward,
                terminated,
                truncated,
                info: StepInfo {
                    dense_reward,
                    x_position: x,
                    goal_distance: None,
                    success,
                },
            })
        });
        result.map_err(|e| self.raised.keep(&self.spec.id, "step", e))
    }

    /// The env's `info["x_position"]` (0 where it gives none).
    fn x_position(&self) -> f64 {
        self.x
    }

    /// A new episode (a Python env's state cannot be taken), reporting a reset that raised.
    fn restore_reset_point(&mut self, _: &ResetPoint, obs: &mut [f64]) -> Result<(), EnvError> {
        self.reset(None, obs);
        match self.failed.take() {
            Some(failed) => Err(failed),
            None => Ok(()),
        }
    }
}

//! A checkpoint's policy for Python (`logo_rl.load`): the mean net on the same host
//! kernels `logo eval` acts with, so that its actions are `logo eval`'s.

use std::path::PathBuf;

use logo_nn::{ActingPolicy, Kernels};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::errors::{logo_error, value_error};

#[pyclass(frozen, module = "logo_rl._logo_rl")]
pub struct Policy {
    acting: ActingPolicy,
    #[pyo3(get)]
    path: PathBuf,
    /// The env it was trained on, as its checkpoint names it.
    #[pyo3(get)]
    env_id: String,
    #[pyo3(get)]
    obs_dim: usize,
    #[pyo3(get)]
    act_dim: usize,
    /// Iterations trained when it was saved.
    #[pyo3(get)]
    iteration: u64,
    #[pyo3(get)]
    algorithm: String,
    #[pyo3(get)]
    seed: u64,
}

#[pymethods]
impl Policy {
    #[new]
    fn new(path: PathBuf) -> PyResult<Self> {
        let stored = logo_cli::eval::load_policy(&path).map_err(|e| logo_error(&e))?;
        let acting = stored.acting(&Kernels);
        let meta = stored.meta;
        Ok(Self {
            acting,
            path,
            env_id: meta.env_id,
            obs_dim: meta.obs_dim,
            act_dim: meta.act_dim,
            iteration: meta.iteration,
            algorithm: meta.algorithm,
            seed: meta.seed,
        })
    }

    /// μ(s) for each row of `obs` (`[rows, obs_dim]`, float64).
    fn mean<'py>(
        &self,
        py: Python<'py>,
        obs: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let shape = obs.shape();
        let (rows, width) = (shape[0], shape[1]);
        if width != self.obs_dim {
            return Err(value_error(format!(
                "observations of {width} values; the policy of {} ({}) takes {}",
                self.env_id,
                self.path.display(),
                self.obs_dim
            )));
        }
        // A copy: Python may write the array while the GIL is released.
        let obs = obs
            .as_slice()
            .map_err(|e| value_error(e.to_string()))?
            .to_vec();
        if let Some(i) = obs.iter().position(|v| !v.is_finite()) {
            return Err(value_error(format!(
                "observation row {} has a non-finite value {} at index {}",
                i / width,
                obs[i],
                i % width
            )));
        }
        let means = py.detach(|| self.acting.mean(&obs));
        means.into_pyarray(py).reshape([rows, self.act_dim])
    }

    /// The observation statistics the policy sees through, `(mean, var)`, or None where
    /// its run did not standardise observations.
    #[getter]
    #[allow(clippy::type_complexity)]
    fn observation_norm<'py>(
        &self,
        py: Python<'py>,
    ) -> Option<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
        self.acting.observation_norm().map(|stats| {
            (
                stats.mean.clone().into_pyarray(py),
                stats.var.clone().into_pyarray(py),
            )
        })
    }

    /// log σ, one per action.
    #[getter]
    fn log_std<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.acting.log_std().to_vec().into_pyarray(py)
    }

    /// The mean net's layers, first to last, as `(weight [out, in], bias [out])`: a torch
    /// `nn.Linear`'s layout; tanh between them.
    #[allow(clippy::type_complexity)]
    fn layers<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Vec<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>)>> {
        let net = self.acting.mean_net();
        let mut offset = 0;
        let mut layers = Vec::new();
        for pair in net.dims.windows(2) {
            let (fan_in, fan_out) = (pair[0], pair[1]);
            // Stored as [in, out] row-major: transposed into [out, in].
            let w = &net.params[offset..offset + fan_in * fan_out];
            let mut weight = vec![0.0; fan_in * fan_out];
            for i in 0..fan_in {
                for o in 0..fan_out {
                    weight[o * fan_in + i] = w[i * fan_out + o];
                }
            }
            offset += fan_in * fan_out;
            let bias = net.params[offset..offset + fan_out].to_vec();
            offset += fan_out;
            let weight = weight.into_pyarray(py).reshape([fan_out, fan_in])?;
            layers.push((weight, bias.into_pyarray(py)));
        }
        Ok(layers)
    }
}

//! `logo_rl._logo_rl`: the Rust half of the `logo_rl` Python package (its Python half is
//! `python/logo_rl/`). It hands Python the envs of `logo envs` ([`env::RustEnv`]), the
//! trainer of `logo train` ([`train::train`]) and the policies of checkpoints
//! ([`policy::Policy`]); everything they compute is the Rust crates' own.

use pyo3::prelude::*;

mod env;
mod errors;
mod minari;
mod policy;
mod presets;
mod python_env;
mod train;
mod vector;

use errors::LogoError;

#[pymodule]
fn _logo_rl(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<env::RustEnv>()?;
    m.add_class::<policy::Policy>()?;
    m.add_class::<vector::RustVecEnv>()?;
    m.add_function(wrap_pyfunction!(env::env_ids, m)?)?;
    m.add_function(wrap_pyfunction!(env::time_limit, m)?)?;
    m.add_function(wrap_pyfunction!(train::train, m)?)?;
    m.add_function(wrap_pyfunction!(train::bc, m)?)?;
    m.add_function(wrap_pyfunction!(train::configure, m)?)?;
    m.add_function(wrap_pyfunction!(train::metric_columns, m)?)?;
    m.add_function(wrap_pyfunction!(train::run_dir_for, m)?)?;
    m.add_function(wrap_pyfunction!(train::config_keys, m)?)?;
    m.add_function(wrap_pyfunction!(minari::write_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(minari::read_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(presets::presets, m)?)?;
    m.add_function(wrap_pyfunction!(presets::preset_text, m)?)?;
    m.add_function(wrap_pyfunction!(presets::preset_data, m)?)?;
    m.add_function(wrap_pyfunction!(presets::methods, m)?)?;
    m.add("LogoError", m.py().get_type::<LogoError>())?;
    m.add("MUJOCO_VERSION", "3.17.0")?;
    m.add("EXTERNAL_PREFIX", logo_envs::EXTERNAL_PREFIX)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

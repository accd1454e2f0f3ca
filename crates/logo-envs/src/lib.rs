//! Gymnasium-exact MuJoCo environments for logo-rl.
//!
//! - [`Env`]: the interface every environment implements (reset, step, seeded noise).
//! - [`MujocoEnv`]: the generic MuJoCo stepping loop; a new MJCF model needs only a
//!   [`Task`] (observation, reward, termination, reset noise), see `hopper.rs` for one.
//! - The four LOGO tasks in their Gymnasium `-v4` and `-v5` forms, and [`SparseReward`]:
//!   any of them made sparse by a [`SparseRule`] (a config's [`EnvConfig`]), LOGO's own
//!   versions under their old names (`SparseHopper-v4`, ...).
//! - [`VecEnv`]: N copies on worker threads, one `MjData` each over a shared `MjModel`.
//! - [`EnvMaker`]: an env the caller brings (a Python env), built by id like the others.
//!
//! This crate knows nothing of neural networks: observations and actions are `f64` slices.

mod env;
mod env_config;
mod external;
mod half_cheetah;
mod hopper;
mod inverted_double_pendulum;
mod mujoco_env;
mod registry;
mod sparse;
mod vec_env;
mod walker2d;

#[cfg(feature = "render")]
pub mod render;

pub use env::{
    Env, EnvError, EnvSpec, ResetPoint, RngState, Step, StepInfo, Version, clip_to_range,
};
pub use env_config::EnvConfig;
pub use external::{EXTERNAL_PREFIX, EnvMaker, register_external, unregister_external};
pub use half_cheetah::HalfCheetah;
pub use hopper::Hopper;
pub use inverted_double_pendulum::InvertedDoublePendulum;
pub use mujoco_env::{Data, MujocoEnv, ResetNoise, Task, models_dir};
pub use registry::{
    BASE_ENV_IDS, EnvFactory, EnvOptions, all_env_ids, canonical_id, dense_id, make, sparse_id,
};
pub use sparse::{SPARSE_KINDS, SparseReward, SparseRule};
pub use vec_env::{VecEnv, VecStep};
pub use walker2d::Walker2d;

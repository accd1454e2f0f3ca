//! Gymnasium-exact MuJoCo environments for logo-rl.
//!
//! - [`Env`]: the interface every environment implements (reset, step, seeded noise).
//! - [`MujocoEnv`]: the generic MuJoCo stepping loop; a new MJCF model needs only a
//!   [`Task`] (observation, reward, termination, reset noise), see `hopper.rs` for one.
//! - Gymnasium's eleven MuJoCo tasks in their `-v4` and `-v5` forms (Pusher `-v5` only),
//!   and [`SparseReward`]:
//!   any of them made sparse by a [`SparseRule`] (a config's [`EnvConfig`]), LOGO's own
//!   four under their old names (`SparseHopper-v4`, ...).
//! - [`VecEnv`]: N copies on worker threads, one `MjData` each over a shared `MjModel`.
//! - [`EnvMaker`]: an env the caller brings (a Python env), built by id like the others.
//!
//! This crate knows nothing of neural networks: observations and actions are `f64` slices.

mod ant;
mod env;
mod env_config;
mod external;
mod half_cheetah;
mod hopper;
mod humanoid;
mod inverted_double_pendulum;
mod inverted_pendulum;
mod mujoco_env;
mod numpy_sum;
mod pusher;
mod reacher;
mod registry;
mod sparse;
mod swimmer;
mod vec_env;
mod walker2d;

#[cfg(feature = "render")]
pub mod render;

pub use ant::Ant;
pub use env::{
    Env, EnvError, EnvSpec, ResetPoint, RngState, Step, StepInfo, Version, clip_to_range,
};
pub use env_config::{EnvConfig, EnvKeyError};
pub use external::{EXTERNAL_PREFIX, EnvMaker, register_external, unregister_external};
pub use half_cheetah::HalfCheetah;
pub use hopper::Hopper;
pub use humanoid::{Humanoid, HumanoidStandup};
pub use inverted_double_pendulum::InvertedDoublePendulum;
pub use inverted_pendulum::InvertedPendulum;
pub use mujoco_env::{BeforeStep, Data, MujocoEnv, ResetNoise, Task, models_dir};
pub use pusher::Pusher;
pub use reacher::Reacher;
pub use registry::{
    BASE_ENV_IDS, EnvFactory, EnvOptions, all_env_ids, canonical_id, dense_id, make, sparse_id,
    time_limit,
};
pub use sparse::{RuleError, SPARSE_KINDS, SparseReward, SparseRule};
pub use swimmer::Swimmer;
pub use vec_env::{VecEnv, VecStep};
pub use walker2d::Walker2d;

//! LOGO and its variants, readable top to bottom: `trainer.rs` is the loop of one
//! iteration, each step a function of its own file, each variant a configuration.
//!
//! | file | the paper's name |
//! | --- | --- |
//! | `rollout.rs` | collect (s, a, r, s') ~ π_k: whole episodes, at least `samples_per_iter` steps |
//! | `gae.rs` | generalised advantage estimation |
//! | `critic.rs` | the critic kinds (`single`, `twin-min` = clipped double-Q) and their fits (`lbfgs.rs`, `adam.rs`) |
//! | `policy_update/` | the policy-update kinds: `trpo`, `clip-in-trpo`, `ppo-clip`, `ppo-penalty` |
//! | `guidance.rs` | LOGO: discriminator D, r_C = −log D (or log π_b − log π_k), the δ_k schedule |
//! | `trainer.rs` | the iteration, evaluation, checkpoints |
//! | `metrics.rs`, `run_dir.rs` | `metrics.csv` and the run's folder |
//! | `config.rs` | the TOML config |

pub mod adam;
pub mod config;
pub mod critic;
pub mod gae;
pub mod guidance;
pub mod lbfgs;
pub mod metrics;
pub mod more_thuente;
pub mod policy_update;
pub mod rollout;
pub mod run_dir;
pub mod trainer;

pub use config::{ConfigError, TrainConfig};
pub use metrics::IterationMetrics;
pub use trainer::{EngineSpan, Trainer, engine_history};

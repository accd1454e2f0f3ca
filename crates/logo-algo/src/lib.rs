//! TRPO and LOGO, readable top to bottom: `trainer.rs` is the loop of one iteration,
//! each step a function of its own file.
//!
//! | file | the paper's name |
//! | --- | --- |
//! | `rollout.rs` | collect (s, a, r, s') ~ π_k: whole episodes, at least `samples_per_iter` steps |
//! | `gae.rs` | generalised advantage estimation |
//! | `critic.rs` | fitting V by L-BFGS on MSE + L2 (`lbfgs.rs`) |
//! | `trpo.rs` | the policy step: CG on F·v, step size from δ, backtracking line search |
//! | `guidance.rs` | LOGO: discriminator D, r_C = −log D (or log π_b − log π_k), the δ_k schedule |
//! | `trainer.rs` | the iteration, evaluation, metrics, checkpoints |

pub mod config;
pub mod critic;
pub mod gae;
pub mod guidance;
pub mod lbfgs;
pub mod rollout;
pub mod trainer;
pub mod trpo;

pub use config::{ConfigError, TrainConfig};
pub use trainer::{IterationMetrics, Trainer};

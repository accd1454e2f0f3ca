//! LOGO and its variants, readable top to bottom: `trainer/iteration.rs` is one
//! iteration, each step a function of its own file, each variant a configuration.
//!
//! | file | the paper's name |
//! | --- | --- |
//! | `bc.rs` | behaviour cloning: `[init] kind = "bc"` and `logo bc` |
//! | `sampler.rs` | collect (s, a, r, s') ~ π_k: whole episodes, at least `samples_per_iter` steps |
//! | `gae.rs` | generalised advantage estimation |
//! | `critic.rs` | the critic kinds (`single`, `twin-min` = clipped double-Q) and their fits (`lbfgs.rs`, `adam.rs`) |
//! | `policy_update/` | the policy-update kinds: `trpo`, `npg`, `clip-in-trpo`, `ppo-clip`, `ppo-penalty` |
//! | `dapg.rs` | DAPG's demonstration rows in the improvement step, weighted λ0·λ1^k·max Â |
//! | `guidance.rs` | LOGO's guidance step: r_C = −log D (or log π_b − log π_k), the step with KL ≈ δ_k |
//! | `delta_schedule.rs` | the δ_k schedule |
//! | `discriminator.rs` | the discriminator D and its training |
//! | `episode.rs` | one episode of a fixed policy; the evaluation |
//! | `streams.rs` | the table of random streams |
//! | `trainer/` | the iteration (`iteration.rs`) over the learner (`learner.rs`), its resources (`resources.rs`) and its recorder (`recorder.rs`, and `record.rs`: an iteration's metrics row and checkpoints); the learner's state, which a checkpoint is (`learner_state.rs`) |
//! | `metrics.rs`, `run_dir.rs`, `tensorboard.rs` | `metrics.csv`, TensorBoard's event file and the run's folder |
//! | `config.rs`, `validate.rs` | the TOML config, and the checks its tables share |
//! | `methods.rs` | the table of methods: one entry each, read by everything that lists or makes one |
//! | `algorithms.rs`, `presets.rs` | `logo algorithms`, `logo compare`'s methods; `[algorithm] name`: the keys that make each method, under a config's own |

pub mod adam;
pub mod algorithms;
pub mod bc;
pub mod config;
pub mod critic;
pub mod dapg;
pub mod delta_schedule;
pub mod discriminator;
pub mod episode;
pub mod error;
pub mod gae;
pub mod guidance;
pub mod lbfgs;
pub mod methods;
pub mod metrics;
pub mod more_thuente;
pub mod policy_update;
pub mod presets;
pub mod run_dir;
pub mod sampler;
pub mod streams;
pub mod tensorboard;
pub mod trainer;
pub mod validate;

pub use config::{ConfigError, ConfigErrorKind, Dtype, EvalInitialStates, TrainConfig};
pub use error::{At, Invalid, TrainError};
pub use metrics::IterationMetrics;
pub use trainer::{EngineSpan, Learned, LearnerState, Schedule, Trainer, engine_history};

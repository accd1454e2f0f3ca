//! Networks and losses of LOGO and its variants, written once in burn and generic over
//! the backend, and the engines they run on:
//!
//! - networks ([`mlp`], [`policy`], [`critic`], [`discriminator`]): burn modules, with the
//!   reference's initialisation; checkpoints ([`checkpoint`]) and the reference's BC
//!   policies ([`torch_import`]) read and write them;
//! - [`loss`]: every loss, over network outputs, with burn's autodiff for its gradient;
//! - [`engine`]: the seam: what algorithms need from a network (trace, Jᵀ·u, the
//!   Gauss–Newton product, flat parameters), implemented by the hand-tuned CPU
//!   [`kernels`] and by burn on any backend;
//! - [`fisher`]: the policy's Fisher-vector product over an engine, conjugate gradient.

pub mod checkpoint;
pub mod critic;
pub mod discriminator;
pub mod engine;
pub mod fisher;
pub mod flat;
pub mod flops;
pub mod kernels;
pub mod loss;
pub mod mlp;
pub mod observation_norm;
pub mod policy;
pub mod torch_import;

pub use burn;

pub use checkpoint::{Checkpoint, CheckpointError, CheckpointMeta};
pub use critic::{ValueNet, ValueNetConfig};
pub use discriminator::{Discriminator, DiscriminatorConfig, DiscriminatorInit};
pub use engine::{BurnEngine, Engine, Kernels};
pub use fisher::{FisherKind, FisherOperator, conjugate_gradient};
pub use mlp::{Mlp, MlpConfig};
pub use observation_norm::{DamagedStats, ObservationNorm, ObservationStats};
pub use policy::{ActingPolicy, GaussianPolicy, Policy, PolicyConfig};
pub use torch_import::{ImportError, load_reference_policy};

/// ndarray, float64: the reference implementation's precision.
pub type Cpu = burn::backend::NdArray<f64>;
pub type CpuAutodiff = burn::backend::Autodiff<Cpu>;
/// ndarray, float32.
pub type Cpu32 = burn::backend::NdArray<f32>;
pub type Cpu32Autodiff = burn::backend::Autodiff<Cpu32>;

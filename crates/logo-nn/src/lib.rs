//! Networks and losses of LOGO and its variants, written once in burn and generic over
//! the backend; the natural-gradient pieces (flat parameters, KL, F·v, conjugate gradient);
//! checkpoints; import of the LOGO reference's PyTorch BC policies.
//!
//! The default backend is ndarray in float64, the reference implementation's precision
//! ([`Cpu`], [`CpuAutodiff`]); float32 is [`Cpu32`], [`Cpu32Autodiff`].

pub mod checkpoint;
pub mod critic;
pub mod discriminator;
pub mod fisher;
pub mod flat;
pub mod gemm;
pub mod host;
pub mod mlp;
pub mod policy;
pub mod torch_import;

pub use burn;

pub use checkpoint::{Checkpoint, CheckpointError, CheckpointMeta};
pub use critic::{TwinCritic, ValueNet, ValueNetConfig};
pub use discriminator::{Discriminator, DiscriminatorConfig};
pub use fisher::{FisherVectorProduct, conjugate_gradient, mean_kl};
pub use host::{HostMlp, HostTrace, OutputSensitivities};
pub use mlp::{Mlp, MlpConfig};
pub use policy::{ActingPolicy, GaussianPolicy, PolicyConfig};
pub use torch_import::{ImportError, load_reference_policy};

/// ndarray, float64: the default (the reference implementation computes in float64).
pub type Cpu = burn::backend::NdArray<f64>;
pub type CpuAutodiff = burn::backend::Autodiff<Cpu>;
/// ndarray, float32.
pub type Cpu32 = burn::backend::NdArray<f32>;
pub type Cpu32Autodiff = burn::backend::Autodiff<Cpu32>;

//! The hand-tuned CPU kernels under the kernels engine ([`crate::engine::Kernels`]): an
//! MLP's forward pass, reverse product and Gauss–Newton product on plain host buffers,
//! the GEMM they are made of, and a vectorised tanh. They compute what the burn
//! definition in [`crate::mlp`] defines; `tests/kernels.rs` holds them to it.

pub mod float;
pub mod gemm;
pub mod mlp;
pub mod tanh;

pub use float::KernelFloat;
pub use mlp::{HostMlp, HostTrace, OutputSensitivities};

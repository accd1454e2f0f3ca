//! The one seam between the mathematics and the machine.
//!
//! The algorithms need four things from a network (an MLP of [`crate::mlp`]): a forward
//! trace over a batch, the reverse product Jᵀ·u, the Gauss–Newton product Jᵀ·W·J·v that
//! F·v is made of, and its parameters as one flat vector. An [`Engine`] provides them;
//! everything above it (losses, policy updates, critics, the discriminator) is written
//! once against this trait and runs on either engine:
//!
//! - [`Kernels`]: the hand-tuned CPU path (`crate::kernels`), the default;
//! - [`BurnEngine`]: burn tensor ops on any burn backend (ndarray, wgpu, …).
//!
//! The engine is a value chosen once, where the trainer is built. Batch columns and
//! network outputs are burn tensors on the engine's backend [`Engine::B`], where the
//! losses of [`crate::loss`] run (with autodiff for their gradients with respect to the
//! outputs); only flat parameter and direction vectors cross to the host.

mod burn_engine;
mod kernels;
mod seam;

pub use burn_engine::BurnEngine;
pub use kernels::{HostRows, Kernels};
pub use seam::{Device, Engine, select_rows};

//! Networks for logo-rl (work in progress).
pub use burn;

//! The float types the kernels compute in.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Mul, MulAssign, Sub};

/// A float the kernels run on: float64 (the default, the reference's precision) or,
/// with a tanh of its own, float32.
pub trait KernelFloat:
    Copy
    + Debug
    + Default
    + PartialEq
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + AddAssign
    + MulAssign
{
    const ZERO: Self;
    const ONE: Self;
    /// "f64" or "f32".
    const NAME: &'static str;
    /// tanh of every value, in place (the hidden layers' activation).
    fn tanh_in_place(values: &mut [Self]);
    fn from_f64(x: f64) -> Self;
    fn to_f64(self) -> f64;
}

impl KernelFloat for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const NAME: &'static str = "f64";
    fn tanh_in_place(values: &mut [Self]) {
        super::tanh::tanh_f64_in_place(values)
    }
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
}

impl KernelFloat for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const NAME: &'static str = "f32";
    fn tanh_in_place(values: &mut [Self]) {
        super::tanh::tanh_f32_in_place(values)
    }
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
}

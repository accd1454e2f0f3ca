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
    /// tanh of every value, in place (the hidden layers' activation).
    fn tanh_in_place(values: &mut [Self]);
}

impl KernelFloat for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    fn tanh_in_place(values: &mut [Self]) {
        super::tanh::tanh_f64_in_place(values)
    }
}

//! Observation normalisation: the running mean and variance of every observation a run
//! has collected, and the standardisation its networks see their inputs through,
//! (s − mean) / √(var + 1e-8) clipped to ±10 (Stable-Baselines3's `VecNormalize`
//! defaults). On a task whose observations differ in scale by orders of magnitude
//! (MountainCar: position within ±1.2, velocity within ±0.07) a network at its initial
//! weights barely sees the small ones.
//!
//! - [`ObservationStats`]: the statistics on the host, as a run updates them and acting
//!   applies them;
//! - [`ObservationNorm`]: the same as a burn module of three tensors, so that a
//!   checkpoint writes and reads them with the networks (`observation_norm.count`,
//!   `.mean`, `.var`).

use burn::module::{Module, Param};
use burn::tensor::{Tensor, TensorData, backend::Backend};

use crate::flat::to_f64;

/// Added to the variance before the square root: a constant observation stays finite.
const EPSILON: f64 = 1e-8;
/// Standardised observations are clipped to ±this.
const CLIP: f64 = 10.0;

/// Count, mean and (population) variance of the observations seen so far.
#[derive(Debug, Clone, PartialEq)]
pub struct ObservationStats {
    pub count: f64,
    pub mean: Vec<f64>,
    pub var: Vec<f64>,
}

impl ObservationStats {
    /// Nothing seen yet: the identity (mean 0, variance 1).
    pub fn new(obs_dim: usize) -> Self {
        Self {
            count: 0.0,
            mean: vec![0.0; obs_dim],
            var: vec![1.0; obs_dim],
        }
    }

    pub fn obs_dim(&self) -> usize {
        self.mean.len()
    }

    /// Takes in `rows` (row-major observations): the batch's moments merged with the
    /// running ones (Chan, Golub and LeVeque's pairwise update).
    pub fn update(&mut self, rows: &[f64]) {
        let dim = self.obs_dim();
        let n = (rows.len() / dim) as f64;
        if n == 0.0 {
            return;
        }
        let mut batch_mean = vec![0.0; dim];
        for row in rows.chunks_exact(dim) {
            batch_mean.iter_mut().zip(row).for_each(|(m, x)| *m += x);
        }
        batch_mean.iter_mut().for_each(|m| *m /= n);
        let mut batch_m2 = vec![0.0; dim];
        for row in rows.chunks_exact(dim) {
            for ((s, x), m) in batch_m2.iter_mut().zip(row).zip(&batch_mean) {
                *s += (x - m) * (x - m);
            }
        }
        if self.count == 0.0 {
            self.mean = batch_mean;
            self.var = batch_m2.iter().map(|s| s / n).collect();
            self.count = n;
            return;
        }
        let total = self.count + n;
        for i in 0..dim {
            let delta = batch_mean[i] - self.mean[i];
            let m2 =
                self.var[i] * self.count + batch_m2[i] + delta * delta * self.count * n / total;
            self.mean[i] += delta * n / total;
            self.var[i] = m2 / total;
        }
        self.count = total;
    }

    /// Standardises `rows` (row-major observations) in place.
    pub fn normalise(&self, rows: &mut [f64]) {
        let scale: Vec<f64> = self
            .var
            .iter()
            .map(|v| 1.0 / (v + EPSILON).sqrt())
            .collect();
        for row in rows.chunks_exact_mut(self.obs_dim()) {
            for ((x, m), s) in row.iter_mut().zip(&self.mean).zip(&scale) {
                *x = ((*x - m) * s).clamp(-CLIP, CLIP);
            }
        }
    }

    /// Every value finite, the variances non-negative (a damaged checkpoint's may not be).
    pub fn check(&self) -> Result<(), DamagedStats> {
        let finite = self.count.is_finite() && self.count >= 0.0;
        let values = self.mean.iter().chain(&self.var).all(|v| v.is_finite());
        if !(finite && values && self.var.iter().all(|v| *v >= 0.0)) {
            return Err(DamagedStats(self.clone()));
        }
        Ok(())
    }

    /// As a module, for a checkpoint.
    pub fn module<B: Backend>(&self, device: &B::Device) -> ObservationNorm<B> {
        let tensor = |values: &[f64]| {
            Param::from_tensor(Tensor::from_data(
                TensorData::new(values.to_vec(), [values.len()]),
                device,
            ))
        };
        ObservationNorm {
            count: tensor(&[self.count]),
            mean: tensor(&self.mean),
            var: tensor(&self.var),
        }
    }

    /// From a module read from a checkpoint.
    pub fn from_module<B: Backend>(module: &ObservationNorm<B>) -> Self {
        Self {
            count: to_f64(module.count.val())[0],
            mean: to_f64(module.mean.val()),
            var: to_f64(module.var.val()),
        }
    }
}

/// [`ObservationStats`] as a burn module: what a checkpoint holds.
#[derive(Module, Debug)]
pub struct ObservationNorm<B: Backend> {
    pub count: Param<Tensor<B, 1>>,
    pub mean: Param<Tensor<B, 1>>,
    pub var: Param<Tensor<B, 1>>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merged_batches_give_the_moments_of_all_rows() {
        let rows: Vec<f64> = (0..60)
            .map(|i| ((i * 37) % 11) as f64 * 0.5 - 1.0)
            .collect();
        let mut stats = ObservationStats::new(3);
        for part in rows.chunks(3 * 7) {
            stats.update(part);
        }
        for d in 0..3 {
            let column: Vec<f64> = rows.iter().skip(d).step_by(3).copied().collect();
            let mean = column.iter().sum::<f64>() / 20.0;
            let var = column.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 20.0;
            assert!((stats.mean[d] - mean).abs() < 1e-12);
            assert!((stats.var[d] - var).abs() < 1e-12);
        }
        assert_eq!(stats.count, 20.0);
    }

    #[test]
    fn standardised_rows_are_clipped_and_a_fresh_norm_is_the_identity() {
        let mut rows = vec![0.3, -2.0];
        ObservationStats::new(2).normalise(&mut rows);
        assert!((rows[0] - 0.3).abs() < 1e-7 && (rows[1] + 2.0).abs() < 1e-7);
        let stats = ObservationStats {
            count: 5.0,
            mean: vec![1.0, 0.0],
            var: vec![4.0, 1e-6],
        };
        let mut rows = vec![5.0, 1.0];
        stats.normalise(&mut rows);
        assert!((rows[0] - 2.0).abs() < 1e-8);
        assert_eq!(rows[1], 10.0);
    }
}

/// Statistics [`ObservationStats::check`] refuses (read from a damaged checkpoint).
#[derive(Debug, Clone, thiserror::Error)]
#[error(
    "observation_norm: expected a count ≥ 0, finite means and variances ≥ 0; got count {}, \
     mean {:?}, var {:?}",
    .0.count,
    .0.mean,
    .0.var
)]
pub struct DamagedStats(pub ObservationStats);

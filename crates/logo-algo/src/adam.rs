//! Adam on a flat parameter vector, and epochs of minibatch Adam: the first-order
//! optimiser of the discriminator, of the PPO policy-update kinds and of the critics'
//! `adam` fit. Written out rather than burn's optimizer so that its state is plain
//! vectors a checkpoint holds (for `logo train --resume`).

use crate::error::Invalid;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Adam with PyTorch's defaults: β = (0.9, 0.999), ε = 1e-8 outside the square root.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Adam {
    pub m: Vec<f64>,
    pub v: Vec<f64>,
    pub t: u64,
}

impl Adam {
    /// Moments restored from a checkpoint must be fresh (empty) or fit `len` parameters,
    /// with finite values and v ≥ 0: [`Adam::step`] would otherwise reset them silently.
    pub fn check(&self, len: usize) -> Result<(), Invalid> {
        if self.m.len() != self.v.len() || !(self.m.is_empty() || self.m.len() == len) {
            return Err(format!(
                "Adam moments of lengths {} and {}, expected {len} (or none)",
                self.m.len(),
                self.v.len()
            )
            .into());
        }
        if self.m.iter().any(|x| !x.is_finite())
            || self.v.iter().any(|x| !(x.is_finite() && *x >= 0.0))
        {
            return Err("Adam moments hold a non-finite or negative value".into());
        }
        Ok(())
    }

    pub fn step(&mut self, theta: &mut [f64], grad: &[f64], lr: f64) {
        const B1: f64 = 0.9;
        const B2: f64 = 0.999;
        const EPS: f64 = 1e-8;
        if self.m.len() != theta.len() {
            (self.m, self.v) = (vec![0.0; theta.len()], vec![0.0; theta.len()]);
        }
        self.t += 1;
        let (c1, c2) = (1.0 - B1.powi(self.t as i32), 1.0 - B2.powi(self.t as i32));
        for (((x, g), m), v) in theta.iter_mut().zip(grad).zip(&mut self.m).zip(&mut self.v) {
            *m = B1 * *m + (1.0 - B1) * g;
            *v = B2 * *v + (1.0 - B2) * g * g;
            *x -= lr * (*m / c1) / ((*v / c2).sqrt() + EPS);
        }
    }
}

/// Epochs over a batch in shuffled minibatches, one Adam step each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdamEpochs {
    pub epochs: usize,
    pub minibatch: usize,
    pub learning_rate: f64,
    /// The gradient is scaled down to this Euclidean norm when longer (`None`: never).
    pub max_grad_norm: Option<f64>,
}

impl AdamEpochs {
    /// One epoch's minibatches: `order` shuffled in place and cut into chunks. The order
    /// is kept from epoch to epoch (each epoch shuffles the last one's permutation), so
    /// the same generator gives the same minibatches as the runs before this was split.
    pub fn minibatches<'a>(
        &self,
        order: &'a mut [usize],
        rng: &mut ChaCha8Rng,
    ) -> std::slice::Chunks<'a, usize> {
        order.shuffle(rng);
        order.chunks(self.minibatch.max(1))
    }

    /// One Adam step down `grad` (the gradient of a loss to minimise), scaled to
    /// `max_grad_norm` first when longer.
    pub fn step(&self, adam: &mut Adam, theta: &mut [f64], mut grad: Vec<f64>) {
        if let Some(max) = self.max_grad_norm {
            let norm = grad.iter().map(|g| g * g).sum::<f64>().sqrt();
            if norm > max {
                grad.iter_mut().for_each(|g| *g *= max / norm);
            }
        }
        adam.step(theta, &grad, self.learning_rate);
    }

    /// Every epoch over `rows` rows, without a stop: `gradient(indices, theta)` is the
    /// minibatch's gradient at `theta` (the critics' `adam` fit).
    pub fn run(
        &self,
        adam: &mut Adam,
        theta: &mut [f64],
        rows: usize,
        rng: &mut ChaCha8Rng,
        mut gradient: impl FnMut(&[usize], &[f64]) -> Vec<f64>,
    ) {
        let mut order: Vec<usize> = (0..rows).collect();
        for _ in 0..self.epochs {
            for minibatch in self.minibatches(&mut order, rng) {
                let grad = gradient(minibatch, theta);
                self.step(adam, theta, grad);
            }
        }
    }
}

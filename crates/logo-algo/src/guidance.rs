//! LOGO's guidance: the offline signal r_C and the KL bound δ_k of the guidance step.

use std::collections::VecDeque;

use burn::module::AutodiffModule;
use burn::tensor::Tensor;
use burn::tensor::backend::{AutodiffBackend, Backend};
use logo_data::Demonstrations;
use logo_nn::discriminator::softplus;
use logo_nn::flat::{from_f64, grads_to_vec, params_to_vec, to_f64, vec_to_params};
use logo_nn::{Discriminator, DiscriminatorConfig, GaussianPolicy};
use serde::{Deserialize, Serialize};

/// δ_k: starts at δ_0; after the warm-up (iterations > K_δ, 0-based) it shrinks by α each
/// time the batch's mean sparse return beats the mean of the previous (up to) 10, down
/// to a floor of 5e-7; guidance stops once δ_k is at the floor (LOGO-FACTS).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeltaSchedule {
    pub delta: f64,
    pub alpha: f64,
    pub warmup: usize,
    window: VecDeque<f64>,
}

pub const DELTA_FLOOR: f64 = 5e-7;
const WINDOW: usize = 10;

impl DeltaSchedule {
    pub fn new(delta0: f64, alpha: f64, warmup: usize) -> Self {
        Self {
            delta: delta0,
            alpha,
            warmup,
            window: VecDeque::new(),
        }
    }

    /// Feeds iteration `iteration`'s mean sparse training return.
    pub fn update(&mut self, iteration: usize, sparse_return: f64) {
        if iteration > self.warmup && !self.window.is_empty() {
            let previous = self.window.iter().sum::<f64>() / self.window.len() as f64;
            if sparse_return > previous {
                self.delta = (self.alpha * self.delta).max(DELTA_FLOOR);
            }
        }
        if self.window.len() == WINDOW {
            self.window.pop_front();
        }
        self.window.push_back(sparse_return);
    }

    /// Whether the guidance step still runs (the reference's test: δ_k > 6e-7).
    pub fn guidance_on(&self) -> bool {
        self.delta > 6e-7
    }
}

/// D(s, a) = P(the pair came from the policy), trained by one full-batch Adam step per
/// iteration on BCE: policy pairs labelled 1, demonstration pairs 0 (the loss is the sum
/// of the two means, as the reference's GAIL-style code writes it).
/// Adam (PyTorch's defaults: β = (0.9, 0.999), ε = 1e-8 outside the square root) on a
/// flat parameter vector. Written out rather than burn's optimizer so that its state is
/// three plain vectors a checkpoint can hold (for `logo train --resume`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Adam {
    pub m: Vec<f64>,
    pub v: Vec<f64>,
    pub t: u64,
}

impl Adam {
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

pub struct DiscriminatorTrainer<B: AutodiffBackend> {
    pub disc: Discriminator<B>,
    pub optim: Adam,
    lr: f64,
    demo_obs: Tensor<B, 2>,
    demo_actions: Tensor<B, 2>,
}

impl<B: AutodiffBackend> DiscriminatorTrainer<B> {
    pub fn new(
        config: &DiscriminatorConfig,
        demos: &Demonstrations,
        lr: f64,
        device: &B::Device,
    ) -> Self {
        let rows = demos.len();
        Self {
            disc: config.init(device),
            // PyTorch's Adam defaults (burn's epsilon default is 1e-5).
            optim: Adam::default(),
            lr,
            demo_obs: from_f64(&demos.obs, [rows, demos.obs_dim], device),
            demo_actions: from_f64(&demos.actions, [rows, demos.act_dim], device),
        }
    }

    /// r_C = −log D(s, a) for each pair (higher where the pair looks like the demos).
    pub fn rewards(
        &self,
        obs: Tensor<B::InnerBackend, 2>,
        actions: Tensor<B::InnerBackend, 2>,
    ) -> Vec<f64> {
        to_f64(self.disc.valid().guidance_reward(obs, actions))
    }

    /// One Adam step; returns the loss before it.
    pub fn update(&mut self, obs: Tensor<B, 2>, actions: Tensor<B, 2>) -> f64 {
        let policy_logits = self.disc.logits(obs, actions);
        let demo_logits = self
            .disc
            .logits(self.demo_obs.clone(), self.demo_actions.clone());
        // BCE(label 1) = softplus(−z); BCE(label 0) = softplus(z).
        let loss = softplus(policy_logits.neg()).mean() + softplus(demo_logits).mean();
        let value = to_f64(loss.clone().inner())[0];
        let grad = grads_to_vec(&self.disc, &loss.backward());
        let mut theta = params_to_vec(&self.disc);
        self.optim.step(&mut theta, &grad, self.lr);
        self.disc = vec_to_params(self.disc.clone(), &theta);
        value
    }
}

/// r_C = −C = log π_b(a|s) − log π_k(a|s) when the behaviour policy is known.
pub fn behaviour_rewards<B: Backend>(
    behaviour: &GaussianPolicy<B>,
    logp_k: &Tensor<B, 1>,
    obs: &Tensor<B, 2>,
    actions: &Tensor<B, 2>,
) -> Vec<f64> {
    to_f64(behaviour.log_prob(obs.clone(), actions.clone()) - logp_k.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delta_shrinks_only_after_warmup_and_only_on_improvement() {
        let mut s = DeltaSchedule::new(0.2, 0.9, 5);
        for i in 0..=5 {
            s.update(i, i as f64); // improving, but within the warm-up
        }
        assert_eq!(s.delta, 0.2);
        s.update(6, 100.0);
        assert!((s.delta - 0.18).abs() < 1e-15);
        s.update(7, 0.0); // worse than the window's mean
        assert!((s.delta - 0.18).abs() < 1e-15);
        // A sparse return that stays 0 never shrinks δ.
        let mut zero = DeltaSchedule::new(0.01, 0.95, 0);
        for i in 0..50 {
            zero.update(i, 0.0);
        }
        assert_eq!(zero.delta, 0.01);
        // The floor, and guidance off there.
        let mut fast = DeltaSchedule::new(1e-6, 0.1, 0);
        for i in 0..5 {
            fast.update(i, i as f64);
        }
        assert_eq!(fast.delta, DELTA_FLOOR);
        assert!(!fast.guidance_on());
    }
}

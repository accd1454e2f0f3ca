//! LOGO's guidance: the offline signal r_C and the KL bound δ_k of the guidance step.

use std::collections::VecDeque;

use burn::module::AutodiffModule;
use burn::tensor::Tensor;
use burn::tensor::backend::{AutodiffBackend, Backend};
use logo_data::Demonstrations;
use logo_nn::discriminator::softplus;
use logo_nn::flat::{from_f64, grads_to_vec, params_to_vec, to_f64, vec_to_params};
use logo_nn::host::is_host_backend;
use logo_nn::{Discriminator, DiscriminatorConfig, GaussianPolicy, HostMlp};
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
    /// The demonstrations as the discriminator's host input rows (host path only).
    demo_inputs: Option<Vec<f64>>,
}

/// The discriminator's input rows `[obs[..observe] ‖ action]` of row-major pairs.
fn censored_inputs(obs: &[f64], actions: &[f64], act_dim: usize, observe: usize) -> Vec<f64> {
    let obs_dim = obs.len() / (actions.len() / act_dim).max(1);
    obs.chunks_exact(obs_dim)
        .zip(actions.chunks_exact(act_dim))
        .flat_map(|(o, a)| o[..observe].iter().chain(a).copied())
        .collect()
}

/// log(1 + eˣ) without overflow.
fn softplus_f64(x: f64) -> f64 {
    x.max(0.0) + (-x.abs()).exp().ln_1p()
}

/// 1 / (1 + e⁻ˣ) without overflow.
fn sigmoid_f64(x: f64) -> f64 {
    if x >= 0.0 {
        1.0 / (1.0 + (-x).exp())
    } else {
        let e = x.exp();
        e / (1.0 + e)
    }
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
            demo_inputs: is_host_backend::<B::InnerBackend>().then(|| {
                censored_inputs(&demos.obs, &demos.actions, demos.act_dim, config.observe)
            }),
        }
    }

    /// r_C = −log D(s, a) for each pair (higher where the pair looks like the demos).
    pub fn rewards(
        &self,
        obs: Tensor<B::InnerBackend, 2>,
        actions: Tensor<B::InnerBackend, 2>,
    ) -> Vec<f64> {
        if is_host_backend::<B::InnerBackend>() {
            let inputs = self.host_inputs(&to_f64(obs), &to_f64(actions));
            let net = HostMlp::from_mlp(&self.disc.net);
            return net
                .forward(&inputs)
                .iter()
                .map(|l| softplus_f64(-l))
                .collect();
        }
        to_f64(self.disc.valid().guidance_reward(obs, actions))
    }

    /// One Adam step on the BCE loss (policy pairs labelled 1, demonstration pairs 0);
    /// returns the loss before the step. On the default CPU backend the loss and its
    /// gradient run on host buffers (`logo_nn::host`), elsewhere through burn's autodiff.
    pub fn update(&mut self, obs: Tensor<B, 2>, actions: Tensor<B, 2>) -> f64 {
        if is_host_backend::<B::InnerBackend>() {
            self.update_host(&to_f64(obs), &to_f64(actions))
        } else {
            self.update_burn(obs, actions)
        }
    }

    fn update_burn(&mut self, obs: Tensor<B, 2>, actions: Tensor<B, 2>) -> f64 {
        let policy_logits = self.disc.logits(obs, actions);
        let demo_logits = self
            .disc
            .logits(self.demo_obs.clone(), self.demo_actions.clone());
        let loss = softplus(policy_logits.neg()).mean() + softplus(demo_logits).mean();
        let value = to_f64(loss.clone().inner())[0];
        let grad = grads_to_vec(&self.disc, &loss.backward());
        self.adam_step(&grad);
        value
    }

    fn host_inputs(&self, obs: &[f64], actions: &[f64]) -> Vec<f64> {
        censored_inputs(obs, actions, self.demo_actions.dims()[1], self.disc.observe)
    }

    /// As [`Self::update_burn`]: d/dl softplus(−l) = −σ(−l), d/dl softplus(l) = σ(l).
    fn update_host(&mut self, obs: &[f64], actions: &[f64]) -> f64 {
        let net = HostMlp::from_mlp(&self.disc.net);
        let demo_inputs = self
            .demo_inputs
            .as_deref()
            .expect("made by new() on the host backend");
        let mut value = 0.0;
        let mut grad = vec![0.0; net.num_params()];
        for (inputs, label_policy) in [
            (&self.host_inputs(obs, actions)[..], true),
            (demo_inputs, false),
        ] {
            let trace = net.trace(inputs);
            let logits = trace.output();
            let n = logits.len() as f64;
            let sign = if label_policy { -1.0 } else { 1.0 };
            value += logits.iter().map(|l| softplus_f64(sign * l)).sum::<f64>() / n;
            let upstream: Vec<f64> = logits
                .iter()
                .map(|l| sign * sigmoid_f64(sign * l) / n)
                .collect();
            grad.iter_mut()
                .zip(net.vjp(&trace, &upstream))
                .for_each(|(g, d)| *g += d);
        }
        self.adam_step(&grad);
        value
    }

    fn adam_step(&mut self, grad: &[f64]) {
        let mut theta = params_to_vec(&self.disc);
        self.optim.step(&mut theta, grad, self.lr);
        self.disc = vec_to_params(self.disc.clone(), &theta);
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

    /// The host path's loss, gradient step and rewards against burn's autodiff path, on a
    /// censored discriminator (observe < obs_dim) away from its initialisation.
    #[test]
    fn host_and_burn_discriminator_updates_agree() {
        use logo_nn::CpuAutodiff;
        use rand::{Rng, SeedableRng};
        let device = Default::default();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
        let mut random =
            |n: usize| -> Vec<f64> { (0..n).map(|_| rng.random_range(-1.5..1.5)).collect() };
        let demos = Demonstrations {
            obs_dim: 5,
            act_dim: 2,
            obs: random(30 * 5),
            actions: random(30 * 2),
            source: "test".into(),
        };
        let config = DiscriminatorConfig {
            observe: 3,
            act_dim: 2,
            hidden: vec![8, 8],
        };
        let mut burn = DiscriminatorTrainer::<CpuAutodiff>::new(&config, &demos, 1e-2, &device);
        let theta: Vec<f64> = random(params_to_vec(&burn.disc).len());
        burn.disc = vec_to_params(burn.disc, &theta);
        let mut host = DiscriminatorTrainer::<CpuAutodiff>::new(&config, &demos, 1e-2, &device);
        host.disc = vec_to_params(host.disc, &theta);
        let (obs, actions) = (random(50 * 5), random(50 * 2));
        for _ in 0..3 {
            let a = burn.update_burn(
                from_f64(&obs, [50, 5], &device),
                from_f64(&actions, [50, 2], &device),
            );
            let b = host.update_host(&obs, &actions);
            assert!((a - b).abs() < 1e-12, "loss {a} vs {b}");
        }
        let (pb, ph) = (params_to_vec(&burn.disc), params_to_vec(&host.disc));
        let err = pb
            .iter()
            .zip(&ph)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(err < 1e-10, "parameters differ by {err:e} after 3 steps");
        assert_ne!(pb, theta, "the steps moved the parameters");
        let inner = |v: &[f64], c| from_f64::<logo_nn::Cpu, 2>(v, [50, c], &device);
        let rb = to_f64(
            burn.disc
                .valid()
                .guidance_reward(inner(&obs, 5), inner(&actions, 2)),
        );
        let rh = host.rewards(inner(&obs, 5), inner(&actions, 2));
        let err = rb
            .iter()
            .zip(&rh)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(err < 1e-12, "rewards differ by {err:e}");
    }

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

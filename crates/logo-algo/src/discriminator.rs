//! LOGO's discriminator D(s, a) and its training (the reference's GAIL-style BCE step).

use burn::tensor::Tensor;
use logo_data::Demonstrations;
use logo_nn::flat::{params_to_vec, vec_to_params};
use logo_nn::loss::{binary_cross_entropy, guidance_reward, value_and_grad};
use logo_nn::{Discriminator, Engine, ObservationStats};

use crate::adam::Adam;

/// The discriminator's input rows `[obs[..observe] ‖ action]` of row-major pairs.
pub fn censored_inputs(obs: &[f64], actions: &[f64], act_dim: usize, observe: usize) -> Vec<f64> {
    let obs_dim = obs.len() / (actions.len() / act_dim).max(1);
    obs.chunks_exact(obs_dim)
        .zip(actions.chunks_exact(act_dim))
        .flat_map(|(o, a)| o[..observe].iter().chain(a).copied())
        .collect()
}

/// LOGO's discriminator on an engine: D(s, a) = σ(logit), the probability that a pair
/// came from the policy. Trained by `discriminator_steps` full-batch Adam steps per
/// iteration (the reference: one) at `discriminator_lr` (the reference: 3e-4) on binary
/// cross-entropy, policy pairs labelled 1 and demonstration pairs 0 (the loss is the sum
/// of the two means, as the reference's GAIL-style code writes it).
pub struct DiscriminatorTrainer<E: Engine> {
    dims: Vec<usize>,
    pub net: E::Net,
    pub observe: usize,
    pub act_dim: usize,
    pub optim: Adam,
    lr: f64,
    /// Full-batch Adam steps per iteration (the reference takes 1).
    steps: usize,
    /// The demonstrations as input rows, uploaded once (again when the observation
    /// statistics change).
    demo_rows: E::Rows,
    /// The demonstrations as recorded: `[obs ‖ action]` is made from them anew when the
    /// observations are standardised.
    demos: Demonstrations,
}

impl<E: Engine> DiscriminatorTrainer<E> {
    pub fn new<B: burn::tensor::backend::Backend>(
        engine: &E,
        module: &Discriminator<B>,
        demos: &Demonstrations,
        lr: f64,
        steps: usize,
    ) -> Self {
        let dims = module.net.dims();
        let inputs = censored_inputs(&demos.obs, &demos.actions, demos.act_dim, module.observe);
        Self {
            net: engine.net(&dims, &params_to_vec(&module.net)),
            demo_rows: engine.rows(&inputs, dims[0]),
            demos: demos.clone(),
            dims,
            observe: module.observe,
            act_dim: demos.act_dim,
            optim: Adam::default(),
            lr,
            steps,
        }
    }

    /// `template` with this discriminator's parameters (for checkpoints).
    pub fn to_module<B: burn::tensor::backend::Backend>(
        &self,
        engine: &E,
        template: Discriminator<B>,
    ) -> Discriminator<B> {
        let net = vec_to_params(template.net, &engine.params(&self.net));
        Discriminator { net, ..template }
    }

    /// The demonstrations' observations seen through `stats` from now on.
    pub fn standardise_demos(&mut self, engine: &E, stats: &ObservationStats) {
        let mut obs = self.demos.obs.clone();
        stats.normalise(&mut obs);
        let inputs = censored_inputs(&obs, &self.demos.actions, self.act_dim, self.observe);
        self.demo_rows = engine.rows(&inputs, self.dims[0]);
    }

    /// The batch's pairs as this discriminator's input rows, uploaded once per iteration
    /// for [`Self::rewards`] and [`Self::update`].
    pub fn inputs(&self, engine: &E, obs: &[f64], actions: &[f64]) -> E::Rows {
        engine.rows(
            &censored_inputs(obs, actions, self.act_dim, self.observe),
            self.dims[0],
        )
    }

    /// r_C = −log D(s, a) for each pair (higher where the pair looks like the demos).
    pub fn rewards(&self, engine: &E, inputs: &E::Rows) -> Vec<f64> {
        engine.download(guidance_reward(logits(engine.forward(&self.net, inputs))))
    }

    /// The iteration's Adam steps on the BCE loss; returns the loss before the first.
    pub fn update(&mut self, engine: &E, policy_inputs: &E::Rows) -> f64 {
        let before = self.step(engine, policy_inputs);
        for _ in 1..self.steps {
            self.step(engine, policy_inputs);
        }
        // A non-finite parameter reports as a non-finite loss (the trainer stops on it).
        let finite = engine.params(&self.net).iter().all(|v| v.is_finite());
        if finite { before } else { f64::NAN }
    }

    /// One Adam step on the BCE loss; returns the loss before the step.
    fn step(&mut self, engine: &E, policy_inputs: &E::Rows) -> f64 {
        let mut value = 0.0;
        let mut grad = vec![0.0; engine.params(&self.net).len()];
        for (rows, label_one) in [(policy_inputs, true), (&self.demo_rows, false)] {
            let trace = engine.trace(&self.net, rows);
            let (loss, d_logits) = value_and_grad(engine.output(&trace), |out| {
                binary_cross_entropy(logits(out), label_one)
            });
            value += engine.download(loss)[0];
            let part = engine.vjp(&self.net, &trace, d_logits);
            grad.iter_mut().zip(part).for_each(|(g, d)| *g += d);
        }
        let mut theta = engine.params(&self.net);
        self.optim.step(&mut theta, &grad, self.lr);
        self.net = engine.net(&self.dims, &theta);
        value
    }
}

/// A one-column network output as one value per row.
fn logits<B: burn::tensor::backend::Backend>(out: Tensor<B, 2>) -> Tensor<B, 1> {
    out.squeeze_dim::<1>(1)
}

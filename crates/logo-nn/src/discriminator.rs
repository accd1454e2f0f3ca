//! LOGO's discriminator D(s, a): the probability that a pair came from the policy rather
//! than the demonstrations. In the censored-observation setting it sees only the first
//! `observe` observation dimensions.

use burn::module::Module;
use burn::tensor::{Tensor, backend::Backend};
use serde::{Deserialize, Serialize};

use crate::mlp::{Mlp, MlpConfig};

/// How the discriminator's output layer starts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiscriminatorInit {
    /// The LOGO reference's: weights ×0.1, bias 0 (`models/mlp_discriminator.py`), so
    /// D starts near ½ on every pair.
    #[default]
    Reference,
    /// PyTorch's default for a linear layer, U(±1/√fan_in) (what this port used before).
    Uniform,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiscriminatorConfig {
    /// Observation dimensions the discriminator sees: `obs[..observe]`.
    pub observe: usize,
    pub act_dim: usize,
    pub hidden: Vec<usize>,
    pub init: DiscriminatorInit,
}

impl DiscriminatorConfig {
    pub fn new(observe: usize, act_dim: usize) -> Self {
        Self {
            observe,
            act_dim,
            hidden: vec![128, 128],
            init: DiscriminatorInit::Reference,
        }
    }

    pub fn init<B: Backend>(&self, device: &B::Device) -> Discriminator<B> {
        let net = MlpConfig {
            input: self.observe + self.act_dim,
            hidden: self.hidden.clone(),
            output: 1,
            output_scale: match self.init {
                DiscriminatorInit::Reference => Some(0.1),
                DiscriminatorInit::Uniform => None,
            },
        };
        Discriminator {
            net: net.init(device),
            observe: self.observe,
        }
    }
}

#[derive(Module, Debug)]
pub struct Discriminator<B: Backend> {
    pub net: Mlp<B>,
    pub observe: usize,
}

impl<B: Backend> Discriminator<B> {
    /// The pre-sigmoid logit for each row of `[obs ‖ action]` (full observations in; the
    /// censoring happens here).
    pub fn logits(&self, obs: Tensor<B, 2>, actions: Tensor<B, 2>) -> Tensor<B, 1> {
        let rows = obs.dims()[0];
        let seen = obs.slice([0..rows, 0..self.observe]);
        self.net
            .forward(Tensor::cat(vec![seen, actions], 1))
            .squeeze_dim::<1>(1)
    }
}

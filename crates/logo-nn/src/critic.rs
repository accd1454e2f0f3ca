//! The state-value network V(s): its definition. How many of them a reward stream uses
//! (one, or two for clipped double-Q) is the critic kind of `logo_algo::critic`.

use burn::module::Module;
use burn::tensor::{Tensor, backend::Backend};
use serde::{Deserialize, Serialize};

use crate::mlp::{Mlp, MlpConfig};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ValueNetConfig {
    pub obs_dim: usize,
    /// The reference: 128-128, tanh.
    pub hidden: Vec<usize>,
}

impl ValueNetConfig {
    pub fn new(obs_dim: usize) -> Self {
        Self {
            obs_dim,
            hidden: vec![128, 128],
        }
    }

    pub fn net(&self) -> MlpConfig {
        MlpConfig {
            input: self.obs_dim,
            hidden: self.hidden.clone(),
            output: 1,
            output_scale: Some(0.1),
        }
    }

    pub fn init<B: Backend>(&self, device: &B::Device) -> ValueNet<B> {
        ValueNet {
            net: self.net().init(device),
        }
    }
}

/// V(s).
#[derive(Module, Debug)]
pub struct ValueNet<B: Backend> {
    pub net: Mlp<B>,
}

impl<B: Backend> ValueNet<B> {
    /// One value per row of `obs`.
    pub fn forward(&self, obs: Tensor<B, 2>) -> Tensor<B, 1> {
        self.net.forward(obs).squeeze_dim::<1>(1)
    }
}

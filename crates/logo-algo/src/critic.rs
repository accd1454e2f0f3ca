//! The critic of one reward stream, as a configuration: `single` (LOGO's one value net)
//! or `twin-min` (the seed paper's clipped double-Q: two value nets fitted to the same
//! returns, the baseline min(V1, V2)). Each net is fitted by L-BFGS on MSE + l2·‖θ‖²
//! (the reference: 25 iterations, l2 = 1e-3) or by epochs of minibatch Adam, a config
//! choice (`[critic.fit] method = "lbfgs" | "adam"`).

use crate::error::Invalid;
use burn::tensor::Tensor;
use logo_nn::flat::dot;
use logo_nn::loss::{mse, value_and_grad};
use logo_nn::{Engine, ValueNet, ValueNetConfig};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::adam::{Adam, AdamEpochs};
use crate::lbfgs::{self, LineSearch};
use crate::validate::{
    MAX_SAMPLES_PER_ITER, check_count, check_fraction, check_positive, check_widths,
};

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CriticKind {
    /// One value net (LOGO).
    #[default]
    Single,
    /// Two value nets fitted to the same returns; the baseline is their minimum.
    TwinMin,
}

/// `[critic]` (or `[guidance.critic]`); a key left out takes its value from
/// [`CriticConfig::default`]: the reference's one 128-128 value net fitted by L-BFGS.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CriticConfig {
    pub kind: CriticKind,
    /// Hidden sizes of each value net (tanh). The reference: 128-128.
    pub hidden: Vec<usize>,
    pub fit: CriticFit,
}

impl Default for CriticConfig {
    fn default() -> Self {
        Self {
            kind: CriticKind::Single,
            hidden: vec![128, 128],
            fit: CriticFit::default(),
        }
    }
}

/// How each value net is fitted to its returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "method", rename_all = "kebab-case")]
pub enum CriticFit {
    /// L-BFGS on the whole batch (the reference's `fmin_l_bfgs_b(maxiter=25)`).
    Lbfgs(LbfgsFit),
    /// Epochs of minibatch Adam, as PPO implementations fit their value function.
    Adam(AdamFit),
}

impl Default for CriticFit {
    fn default() -> Self {
        Self::Lbfgs(LbfgsFit::default())
    }
}

/// A key left out takes its value from [`LbfgsFit::default`]: the reference's 25
/// iterations with l2 = 1e-3 on the whole batch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LbfgsFit {
    pub iterations: usize,
    pub l2: f64,
    /// "backtracking" (the default) or "strong-wolfe" (the reference's SciPy L-BFGS-B).
    pub line_search: LineSearch,
    /// The fraction of the batch's rows each fit sees, drawn afresh every iteration
    /// without replacement (1, the default: the whole batch, as the reference). A cost
    /// lever: the fit's arithmetic scales with it.
    #[serde(skip_serializing_if = "is_whole_batch")]
    pub subsample: f64,
}

// serde's skip_serializing_if passes a reference.
fn is_whole_batch(fraction: &f64) -> bool {
    *fraction == 1.0
}

impl Default for LbfgsFit {
    fn default() -> Self {
        Self {
            iterations: 25,
            l2: 1e-3,
            line_search: LineSearch::Backtracking,
            subsample: 1.0,
        }
    }
}

/// A key left out takes its value from [`AdamFit::default`]: the PPO paper's MuJoCo
/// settings (10 epochs, minibatch 64, Adam lr 3e-4), and the reference's l2.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AdamFit {
    pub epochs: usize,
    pub minibatch: usize,
    pub learning_rate: f64,
    pub l2: f64,
}

impl Default for AdamFit {
    fn default() -> Self {
        Self {
            epochs: 10,
            minibatch: 64,
            learning_rate: 3e-4,
            l2: LbfgsFit::default().l2,
        }
    }
}

impl CriticConfig {
    /// What a config file cannot be trusted to hold; `table` names where it is.
    pub fn validate(&self, table: &str) -> Result<(), Invalid> {
        check_widths(&format!("{table}.hidden"), &self.hidden)?;
        match &self.fit {
            CriticFit::Lbfgs(fit) => {
                check_count(&format!("{table}.fit.iterations"), fit.iterations, 100_000)?;
                check_fraction(&format!("{table}.fit.subsample"), fit.subsample)?;
                check_positive(&format!("{table}.fit.l2"), fit.l2, true)
            }
            CriticFit::Adam(fit) => {
                check_count(&format!("{table}.fit.epochs"), fit.epochs, 10_000)?;
                check_count(
                    &format!("{table}.fit.minibatch"),
                    fit.minibatch,
                    MAX_SAMPLES_PER_ITER,
                )?;
                check_positive(
                    &format!("{table}.fit.learning_rate"),
                    fit.learning_rate,
                    false,
                )?;
                check_positive(&format!("{table}.fit.l2"), fit.l2, true)
            }
        }
    }

    /// How many value nets the kind has.
    pub fn num_nets(&self) -> usize {
        match self.kind {
            CriticKind::Single => 1,
            CriticKind::TwinMin => 2,
        }
    }

    /// The value net of this critic for `obs_dim` observations.
    pub fn net(&self, obs_dim: usize) -> ValueNetConfig {
        ValueNetConfig {
            obs_dim,
            hidden: self.hidden.clone(),
        }
    }
}

/// The value nets of one reward stream, on an engine.
pub struct CriticSet<E: Engine> {
    pub config: CriticConfig,
    dims: Vec<usize>,
    pub nets: Vec<E::Net>,
    /// Each net's Adam moments (the `adam` fit; carried over between iterations).
    pub adam: Vec<Adam>,
}

impl<E: Engine> CriticSet<E> {
    /// The set of `config.kind` with the parameters of `modules` (one per net).
    pub fn new<B: burn::tensor::backend::Backend>(
        engine: &E,
        config: &CriticConfig,
        modules: &[ValueNet<B>],
    ) -> Self {
        assert_eq!(modules.len(), config.num_nets(), "one module per value net");
        let dims = modules[0].net.dims();
        Self {
            config: config.clone(),
            nets: modules
                .iter()
                .map(|m| engine.net(&dims, &logo_nn::flat::params_to_vec(m)))
                .collect(),
            adam: vec![Adam::default(); modules.len()],
            dims,
        }
    }

    /// `templates` with the nets' parameters (for checkpoints).
    pub fn to_modules<B: burn::tensor::backend::Backend>(
        &self,
        engine: &E,
        templates: &[ValueNet<B>],
    ) -> Vec<ValueNet<B>> {
        self.nets
            .iter()
            .zip(templates)
            .map(|(net, t)| logo_nn::flat::vec_to_params(t.clone(), &engine.params(net)))
            .collect()
    }

    /// The baseline V(s) of each row: the (minimum over the) value net(s).
    pub fn values(&self, engine: &E, obs: &E::Rows) -> Vec<f64> {
        self.nets
            .iter()
            .map(|net| engine.download(engine.forward(net, obs)))
            .reduce(|a, b| a.iter().zip(&b).map(|(x, y)| x.min(*y)).collect())
            .expect("a critic has at least one net")
    }

    /// Fits every net to `returns` (`[rows]`); the mean of their final losses.
    pub fn fit(&mut self, engine: &E, obs: &E::Rows, returns: &[f64], rng: &mut ChaCha8Rng) -> f64 {
        let targets = engine.upload(returns, [returns.len(), 1]);
        // One subset for every net of the set (`[critic.fit] subsample`).
        let subset = match &self.config.fit {
            CriticFit::Lbfgs(fit) if fit.subsample < 1.0 => {
                let rows = returns.len();
                let keep = ((fit.subsample * rows as f64).round() as usize).clamp(1, rows);
                let mut indices = rand::seq::index::sample(rng, rows, keep).into_vec();
                indices.sort_unstable(); // memory order, for the products' caches
                Some((
                    engine.select(obs, &indices),
                    logo_nn::engine::select_rows(&targets, &indices),
                ))
            }
            _ => None,
        };
        let mut total = 0.0;
        for (net, adam) in self.nets.iter_mut().zip(&mut self.adam) {
            let theta0 = engine.params(net);
            let (theta, loss) = match &self.config.fit {
                CriticFit::Lbfgs(fit) => {
                    let (obs, targets) = match &subset {
                        Some((rows, targets)) => (rows, targets),
                        None => (obs, &targets),
                    };
                    let mut objective =
                        ValueObjective::new(engine, &self.dims, obs, targets, fit.l2);
                    let result =
                        lbfgs::minimize(&mut objective, theta0, fit.iterations, fit.line_search);
                    (result.x, result.loss)
                }
                CriticFit::Adam(fit) => {
                    let epochs = AdamEpochs {
                        epochs: fit.epochs,
                        minibatch: fit.minibatch,
                        learning_rate: fit.learning_rate,
                        max_grad_norm: None,
                    };
                    let mut theta = theta0;
                    let rows = engine.num_rows(obs);
                    epochs.run(adam, &mut theta, rows, rng, |indices, theta| {
                        let minibatch = engine.select(obs, indices);
                        let minibatch_targets = logo_nn::engine::select_rows(&targets, indices);
                        let mut objective = ValueObjective::new(
                            engine,
                            &self.dims,
                            &minibatch,
                            &minibatch_targets,
                            fit.l2,
                        );
                        lbfgs::Objective::loss(&mut objective, theta);
                        lbfgs::Objective::gradient(&mut objective)
                    });
                    let loss = ValueObjective::new(engine, &self.dims, obs, &targets, fit.l2)
                        .value(&theta);
                    (theta, loss)
                }
            };
            *net = engine.net(&self.dims, &theta);
            // A non-finite parameter reports as a non-finite loss (the trainer stops on it).
            total += if theta.iter().all(|v| v.is_finite()) {
                loss
            } else {
                f64::NAN
            };
        }
        total / self.nets.len() as f64
    }
}

/// MSE(V(obs), targets) + l2·‖θ‖² of a value net with parameters θ, as an L-BFGS
/// objective: the loss is a forward pass and the MSE's gradient with respect to the
/// values; the parameter gradient is the engine's reverse pass over that trace (so a
/// rejected line-search point costs only its forward pass).
pub struct ValueObjective<'a, E: Engine> {
    engine: &'a E,
    dims: &'a [usize],
    obs: &'a E::Rows,
    targets: &'a Tensor<E::B, 2>,
    l2: f64,
    /// The latest loss's point, for the gradient.
    last: Option<Evaluated<E>>,
}

/// θ, its net and trace, and ∂MSE/∂values there.
struct Evaluated<E: Engine> {
    theta: Vec<f64>,
    net: E::Net,
    trace: E::Trace,
    d_values: Tensor<E::B, 2>,
}

impl<'a, E: Engine> ValueObjective<'a, E> {
    pub fn new(
        engine: &'a E,
        dims: &'a [usize],
        obs: &'a E::Rows,
        targets: &'a Tensor<E::B, 2>,
        l2: f64,
    ) -> Self {
        Self {
            engine,
            dims,
            obs,
            targets,
            l2,
            last: None,
        }
    }

    /// The loss at θ alone.
    pub fn value(&self, theta: &[f64]) -> f64 {
        let net = self.engine.net(self.dims, theta);
        let values = self.engine.forward(&net, self.obs);
        self.engine.download(mse(values, self.targets.clone()))[0] + self.l2 * dot(theta, theta)
    }
}

impl<E: Engine> lbfgs::Objective for ValueObjective<'_, E> {
    fn loss(&mut self, theta: &[f64]) -> f64 {
        let net = self.engine.net(self.dims, theta);
        let trace = self.engine.trace(&net, self.obs);
        let targets = burn::tensor::Tensor::from_inner(self.targets.clone());
        let (mse_value, d_values) =
            value_and_grad(self.engine.output(&trace), |values| mse(values, targets));
        let mse_value = self.engine.download(mse_value)[0];
        self.last = Some(Evaluated {
            theta: theta.to_vec(),
            net,
            trace,
            d_values,
        });
        mse_value + self.l2 * dot(theta, theta)
    }

    fn gradient(&mut self) -> Vec<f64> {
        let Evaluated {
            theta,
            net,
            trace,
            d_values,
        } = self.last.take().expect("gradient() follows loss()");
        let mut grad = self.engine.vjp(&net, &trace, d_values);
        grad.iter_mut()
            .zip(&theta)
            .for_each(|(g, t)| *g += 2.0 * self.l2 * t);
        grad
    }
}

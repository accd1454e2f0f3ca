//! Behaviour cloning: the Gaussian policy fitted to demonstration pairs (s, a) by maximum
//! likelihood, −mean log π(a|s), with epochs of minibatch Adam. It is `[init] kind =
//! "bc"` (BC-TRPO and DAPG start from it) and `logo bc` (BC alone, as a baseline).
//!
//! With `learn_std = false` the log σ stays where it started and only the mean is
//! fitted (then the loss is a weighted squared error, as DAPG's code fits its BC).

use crate::error::{Invalid, TrainError};
use std::path::PathBuf;

use burn::tensor::Tensor;
use logo_nn::loss::{gaussian_log_prob, value_and_grad2};
use logo_nn::{Engine, Policy};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::adam::{Adam, AdamEpochs};

/// `[init]`: where a run's policy starts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InitConfig {
    /// `"random"` (the seed's initialisation) or `"bc"` (that, then behaviour cloning
    /// on `demos`).
    pub kind: InitKind,
    /// The demonstrations to clone (a Minari dataset folder or a LOGO `.npy`); default:
    /// `[guidance] demos`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub demos: Option<PathBuf>,
    /// Passes over the demonstrations.
    pub epochs: usize,
    /// Pairs per Adam step (DAPG's code: 64).
    pub minibatch: usize,
    /// Adam's step size (DAPG's code: 1e-3).
    pub learning_rate: f64,
    /// Fit log σ too (maximum likelihood of the whole Gaussian); false: the mean alone.
    pub learn_std: bool,
}

impl Default for InitConfig {
    fn default() -> Self {
        Self {
            kind: InitKind::Random,
            demos: None,
            epochs: 100,
            minibatch: 64,
            learning_rate: 1e-3,
            learn_std: true,
        }
    }
}

/// `[init] kind`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InitKind {
    #[default]
    Random,
    Bc,
}

impl InitConfig {
    /// The seed's initialisation alone (a stored config leaves `[init]` out then).
    pub fn is_random(&self) -> bool {
        self.kind == InitKind::Random
    }

    /// The values a file can get wrong; the message names the key.
    pub fn validate(&self) -> Result<(), Invalid> {
        if self.epochs == 0 {
            return Err("init.epochs must be at least 1".into());
        }
        if self.minibatch == 0 {
            return Err("init.minibatch must be at least 1".into());
        }
        if !(self.learning_rate.is_finite() && self.learning_rate > 0.0) {
            return Err(format!(
                "init.learning_rate must be a positive number, got {}",
                self.learning_rate
            )
            .into());
        }
        Ok(())
    }
}

/// What a fit did: the loss (−mean log π(a|s) over every pair) before and after, and
/// the Adam steps taken.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BcReport {
    pub pairs: usize,
    pub loss_before: f64,
    pub loss_after: f64,
    pub steps: usize,
}

/// The random stream of a run's behaviour cloning (minibatch shuffles): apart from the
/// iterations' streams and the evaluations' (`streams.rs`).
pub fn generator(seed: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(crate::streams::EVALUATION_STREAMS - 1);
    rng
}

/// −mean log π(a|s) of `means` and `log_std` over the rows: BC's loss, on any backend.
fn negative_log_likelihood<B: burn::tensor::backend::Backend>(
    means: Tensor<B, 2>,
    log_std: Tensor<B, 1>,
    actions: Tensor<B, 2>,
) -> Tensor<B, 1> {
    gaussian_log_prob(means, log_std, actions).mean().neg()
}

/// `policy` cloned on the pairs (`obs` as the networks see them) with the BC stream of
/// `seed`: [`fit`], and an error naming `what` (the demonstrations) if it left a
/// non-finite parameter. What `logo bc` and `[init] kind = "bc"` both run.
pub fn clone_policy<E: Engine>(
    engine: &E,
    policy: &Policy<E>,
    (obs, actions): (&[f64], &[f64]),
    config: &InitConfig,
    seed: u64,
    what: &str,
) -> Result<(Policy<E>, BcReport), TrainError> {
    let mut rng = generator(seed);
    let (fitted, report) = fit(engine, policy, obs, actions, config, &mut rng);
    if !fitted.is_finite(engine) {
        return Err(TrainError::NonFinite(format!(
            "behaviour cloning on {what} left a non-finite parameter (try a smaller learning \
             rate)"
        )));
    }
    Ok((fitted, report))
}

/// `policy` fitted to the pairs (`obs` and `actions`, row-major, as the networks see
/// them) by `config`'s epochs of minibatch Adam.
pub fn fit<E: Engine>(
    engine: &E,
    policy: &Policy<E>,
    obs: &[f64],
    actions: &[f64],
    config: &InitConfig,
    rng: &mut ChaCha8Rng,
) -> (Policy<E>, BcReport) {
    let act_dim = policy.act_dim();
    let pairs = actions.len() / act_dim;
    let obs_dim = obs.len() / pairs.max(1);
    let all_obs = engine.rows(obs, obs_dim);
    let all_actions: Tensor<E::B, 2> = engine.upload(actions, [pairs, act_dim]);
    let loss = |p: &Policy<E>| {
        let value = negative_log_likelihood(
            p.means(engine, &all_obs),
            p.log_std_tensor(engine),
            all_actions.clone(),
        );
        engine.download(value)[0]
    };
    let loss_before = loss(policy);
    let epochs = AdamEpochs {
        epochs: config.epochs,
        minibatch: config.minibatch,
        learning_rate: config.learning_rate,
        max_grad_norm: None,
    };
    let mut theta = policy.params(engine);
    let mut steps = 0;
    epochs.run(
        &mut Adam::default(),
        &mut theta,
        pairs,
        rng,
        |rows, theta| {
            steps += 1;
            let current = policy.with_params(engine, theta);
            let obs = engine.select(&all_obs, rows);
            let actions = logo_nn::engine::select_rows(&all_actions, rows);
            let trace = engine.trace(&current.mean, &obs);
            let (_, d_means, d_log_std) = value_and_grad2(
                engine.output(&trace),
                current.log_std_tensor(engine),
                |means, log_std| {
                    let actions = Tensor::from_inner(actions.clone());
                    negative_log_likelihood(means, log_std, actions)
                },
            );
            let mut grad = engine.vjp(&current.mean, &trace, d_means);
            if config.learn_std {
                grad.extend(engine.download(d_log_std));
            } else {
                grad.extend(std::iter::repeat_n(0.0, act_dim));
            }
            grad
        },
    );
    let fitted = policy.with_params(engine, &theta);
    let report = BcReport {
        pairs,
        loss_before,
        loss_after: loss(&fitted),
        steps,
    };
    (fitted, report)
}

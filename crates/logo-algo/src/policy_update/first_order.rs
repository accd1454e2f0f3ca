//! Epochs of minibatch Adam on a surrogate: the loop both first-order kinds (`ppo-clip`,
//! `ppo-penalty`) run, written out with PPO-Clip's KL stop where it acts. PPO-Penalty's
//! β follows the epochs, in `ppo_penalty::update`.

use logo_nn::{Engine, Policy};
use rand_chacha::ChaCha8Rng;

use super::objective::{StepBatch, Surrogate, anchor, evaluate, evaluate_means, gradient};
use super::stats::{StopReason, UpdateStats};
use crate::adam::{Adam, AdamEpochs};

/// What a first-order kind ascends, how, and when it stops.
pub(super) struct Ascent {
    pub surrogate: Surrogate,
    pub epochs: AdamEpochs,
    /// A minibatch whose mean KL from the starting policy exceeds this stops the epochs
    /// before its step (as Stable-Baselines3's `target_kl`, with the exact Gaussian KL).
    pub kl_bound: Option<f64>,
}

/// Ascends the surrogate from `policy` by epochs of minibatch Adam.
pub(super) fn minibatch_ascent<E: Engine>(
    ascent: &Ascent,
    engine: &E,
    policy: &Policy<E>,
    batch: &StepBatch<E>,
    adam: &mut Adam,
    rng: &mut ChaCha8Rng,
) -> (Policy<E>, UpdateStats) {
    let (surrogate, epochs) = (ascent.surrogate, &ascent.epochs);
    let trace = engine.trace(&policy.mean, &batch.obs);
    let start = anchor(engine, policy, &trace);
    let (before, _) = evaluate_means(
        engine,
        surrogate,
        policy,
        start.means.clone(),
        batch,
        &start,
    );
    let theta0 = policy.params(engine);
    let mut theta = theta0.clone();
    let mut order: Vec<usize> = (0..batch.rows).collect();
    let (mut epochs_begun, mut steps, mut stop) = (0, 0, StopReason::MaxEpochs);
    'epochs: for _ in 0..epochs.epochs {
        epochs_begun += 1;
        for indices in epochs.minibatches(&mut order, rng) {
            let current = policy.with_params(engine, &theta);
            let minibatch = batch.select(engine, indices);
            let minibatch_start = start.select(indices);
            let trace = engine.trace(&current.mean, &minibatch.obs);
            // PPO-Clip's early stop: a minibatch already too far from the start ends the
            // epochs before its step.
            if let Some(bound) = ascent.kl_bound {
                let means = engine.output(&trace);
                let (_, kl) = evaluate_means(
                    engine,
                    surrogate,
                    &current,
                    means,
                    &minibatch,
                    &minibatch_start,
                );
                if kl > bound {
                    stop = StopReason::KlBound;
                    break 'epochs;
                }
            }
            let (_, grad) = gradient(
                engine,
                surrogate,
                &current,
                &trace,
                &minibatch,
                &minibatch_start,
            );
            // Adam minimises, so it is given the gradient of −surrogate.
            epochs.step(adam, &mut theta, grad.iter().map(|g| -g).collect());
            steps += 1;
        }
    }
    let moved = policy.with_params(engine, &theta);
    let (after, kl) = evaluate(engine, surrogate, &moved, batch, &start);
    let step_norm = theta
        .iter()
        .zip(&theta0)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt();
    let stats = UpdateStats {
        kl,
        step_norm,
        improvement: after - before,
        steps: steps as f64,
        epochs: epochs_begun,
        stop,
        beta: 0.0,
    };
    (moved, stats)
}

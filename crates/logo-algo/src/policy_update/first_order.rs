//! Epochs of minibatch Adam on a surrogate: the loop both first-order kinds (`ppo-clip`,
//! `ppo-penalty`) run, with their surrogate and stopping rule as arguments.

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
    let Ascent {
        surrogate,
        epochs,
        kl_bound,
    } = ascent;
    let (surrogate, kl_bound) = (*surrogate, *kl_bound);
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
    let run = epochs.run(adam, &mut theta, batch.rows, rng, |indices, theta| {
        let current = policy.with_params(engine, theta);
        let minibatch = batch.select(engine, indices);
        let minibatch_start = start.select(indices);
        let trace = engine.trace(&current.mean, &minibatch.obs);
        if let Some(bound) = kl_bound {
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
                return None;
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
        Some(grad.iter().map(|g| -g).collect()) // Adam minimises −surrogate
    });
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
        steps: run.steps as f64,
        epochs: run.epochs,
        stop: if run.stopped_early {
            StopReason::KlBound
        } else {
            StopReason::MaxEpochs
        },
        beta: 0.0,
    };
    (moved, stats)
}

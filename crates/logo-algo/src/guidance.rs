//! LOGO's guidance step (Algorithm 1, lines 4-9 and 13-14): the offline signal r_C, and a
//! second policy step on the same batch, π_{k+½} → π_{k+1}, with KL ≈ δ_k and every
//! ratio against π_k. Its parts live in files of their own: the δ_k schedule
//! (`delta_schedule.rs`) and the discriminator (`discriminator.rs`).

use burn::tensor::Tensor;
use logo_nn::{Engine, ObservationStats, Policy};
use rand_chacha::ChaCha8Rng;

use crate::delta_schedule::DeltaSchedule;
use crate::discriminator::DiscriminatorTrainer;
use crate::policy_update::{PolicyUpdateConfig, StepBatch, UpdateState, UpdateStats};
use crate::sampler::Batch;

/// Where r_C comes from.
pub enum GuidanceSignal<E: Engine> {
    /// r_C = −log D(s, a), D trained on the demonstrations (the paper's unknown π_b).
    Discriminator(DiscriminatorTrainer<E>),
    /// r_C = log π_b(a|s) − log π_k(a|s) (a known behaviour policy).
    Behaviour(Policy<E>),
}

/// LOGO's guidance: its signal, δ_k, and its policy-update kind and state.
pub struct Guidance<E: Engine> {
    pub signal: GuidanceSignal<E>,
    pub schedule: DeltaSchedule,
    pub update: PolicyUpdateConfig,
    pub state: UpdateState,
}

/// One batch's guidance reward, and the discriminator's inputs its update reuses.
pub struct GuidanceReward<E: Engine> {
    pub rewards: Vec<f64>,
    pub discriminator_inputs: Option<E::Rows>,
}

impl<E: Engine> Guidance<E> {
    /// r_C for every pair of `batch` (`data` is the same batch on the engine): −log D from
    /// the discriminator as the previous iteration left it, or log π_b − log π_k from a
    /// known behaviour policy.
    pub fn rewards(&self, engine: &E, batch: &Batch, data: &StepBatch<E>) -> GuidanceReward<E> {
        match &self.signal {
            GuidanceSignal::Discriminator(d) => {
                let inputs = d.inputs(engine, &batch.obs, &batch.actions);
                GuidanceReward {
                    rewards: d.rewards(engine, &inputs),
                    discriminator_inputs: Some(inputs),
                }
            }
            GuidanceSignal::Behaviour(pi_b) => GuidanceReward {
                rewards: behaviour_rewards(engine, pi_b, &data.obs, &data.actions, &data.logp_old),
                discriminator_inputs: None,
            },
        }
    }

    /// r_C = −log D(s, a) for every pair of `batch` where the signal is a discriminator
    /// (for `[reward]`'s mix: GAIL, POfD); None with a known behaviour policy.
    pub fn discriminator_rewards(&self, engine: &E, batch: &Batch) -> Option<GuidanceReward<E>> {
        let GuidanceSignal::Discriminator(d) = &self.signal else {
            return None;
        };
        let inputs = d.inputs(engine, &batch.obs, &batch.actions);
        Some(GuidanceReward {
            rewards: d.rewards(engine, &inputs),
            discriminator_inputs: Some(inputs),
        })
    }

    /// The guidance step from `policy` (π_{k+½}) on `data` with the guidance advantages.
    pub fn step(
        &mut self,
        engine: &E,
        policy: &Policy<E>,
        data: &StepBatch<E>,
        advantages: Tensor<E::B, 1>,
        rng: &mut ChaCha8Rng,
    ) -> (Policy<E>, UpdateStats) {
        self.update.update(
            engine,
            policy,
            &data.with_advantages(advantages),
            self.schedule.delta,
            &mut self.state,
            rng,
        )
    }

    /// From now on the discriminator sees the demonstrations' observations through
    /// `stats`, as the batch's are (`normalise_observations`).
    pub fn observe_through(&mut self, engine: &E, stats: &ObservationStats) {
        if let GuidanceSignal::Discriminator(d) = &mut self.signal {
            d.standardise_demos(engine, stats);
        }
    }

    /// One discriminator update on the batch's pairs (policy 1, demonstrations 0): its
    /// loss, or None where there is no discriminator or no inputs this iteration.
    pub fn train_discriminator(&mut self, engine: &E, inputs: Option<&E::Rows>) -> Option<f64> {
        match (&mut self.signal, inputs) {
            (GuidanceSignal::Discriminator(d), Some(inputs)) => Some(d.update(engine, inputs)),
            _ => None,
        }
    }
}

/// r_C = −C = log π_b(a|s) − log π_k(a|s) when the behaviour policy is known.
pub fn behaviour_rewards<E: Engine>(
    engine: &E,
    behaviour: &Policy<E>,
    obs: &E::Rows,
    actions: &Tensor<E::B, 2>,
    logp_k: &Tensor<E::B, 1>,
) -> Vec<f64> {
    engine.download(behaviour.log_prob(engine, obs, actions) - logp_k.clone())
}

//! The end of an iteration: its row of metrics.csv from what the steps produced, and the
//! checkpoints the recorder says are due. Recording only: nothing here changes the
//! learner.

use logo_nn::Engine;

use super::Trainer;
use super::iteration::{GuidanceStream, Later, finite};
use super::learner::CriticFits;
use crate::episode::Evaluation;
use crate::error::TrainError;
use crate::metrics::IterationMetrics;
use crate::sampler::Batch;

impl<E: Engine> Trainer<E> {
    /// Iteration `k`'s row of metrics.csv, and its checkpoint when one is due.
    pub(super) fn record(
        &mut self,
        k: usize,
        timed: IterationMetrics,
        batch: &Batch,
        stream: Option<&GuidanceStream<E>>,
        later: Later,
    ) -> Result<IterationMetrics, TrainError> {
        check_critic_fits(&later.fits, stream.is_some()).map_err(|e| self.stopped(e))?;
        let row = self.metrics_row(k, timed, batch, stream, &later);
        let every = self.config.checkpoint_every;
        let due = self
            .recorder
            .append(&row, self.learner.iteration, self.done(), every)?;
        self.next_batch = later.next;
        if let Some(eval_return) = due.best {
            self.save_checkpoint(&self.recorder.best_path())?;
            self.recorder.best_saved(eval_return);
        }
        if due.checkpoint {
            self.save_checkpoint(&self.recorder.checkpoint_path())?;
            self.recorder.checkpoint_saved(self.learner.iteration);
        }
        Ok(row)
    }

    /// The metrics.csv row of iteration `k` (the timings of steps 1-3 and δ_k are in
    /// `timed`).
    fn metrics_row(
        &self,
        k: usize,
        timed: IterationMetrics,
        batch: &Batch,
        stream: Option<&GuidanceStream<E>>,
        later: &Later,
    ) -> IterationMetrics {
        let Later {
            steps,
            fits,
            evaluation,
            t_evaluation,
            ..
        } = later;
        let eval = |of: fn(&Evaluation) -> f64| evaluation.as_ref().map_or(f64::NAN, of);
        let mut row = IterationMetrics {
            iteration: k,
            samples: self.learner.samples,
            wall_s: self.recorder.wall_s(),
            episodes: batch.episode_returns.len(),
            train_sparse_return: batch.mean_return(),
            train_dense_return: batch.mean_dense_return(),
            train_success: batch.success_rate(self.config.success).unwrap_or(f64::NAN),
            eval_dense_return: eval(|e| e.dense_return),
            eval_return: eval(|e| e.return_),
            eval_moved: eval(|e| e.moved),
            eval_action_rms: eval(|e| e.action_rms),
            eval_success: eval(|e| e.success.unwrap_or(f64::NAN)),
            guidance_reward: stream.map_or(f64::NAN, |s| s.mean_reward),
            mean_log_std: self.learner.policy.log_std.iter().sum::<f64>()
                / self.learner.policy.act_dim() as f64,
            critic_loss: fits.env_loss,
            guidance_critic_loss: fits.guidance_loss,
            disc_loss: steps.disc_loss.unwrap_or(f64::NAN),
            t_critics: fits.seconds,
            t_policy_step: steps.t_policy_step,
            t_guidance: steps.t_guidance,
            t_discriminator: steps.t_discriminator,
            t_evaluation: *t_evaluation,
            ..timed
        };
        row.improvement(&steps.improvement);
        row.guidance(steps.guidance.as_ref());
        row
    }
}

/// Step 7's check: a critic fit that left a non-finite loss stops the run.
fn check_critic_fits(fits: &CriticFits, guidance: bool) -> Result<(), TrainError> {
    finite(
        fits.env_loss.is_finite(),
        "the critic fit",
        "env critic's parameters or loss",
    )?;
    if guidance {
        finite(
            fits.guidance_loss.is_finite(),
            "the critic fit",
            "guidance critic's parameters or loss",
        )?;
    }
    Ok(())
}

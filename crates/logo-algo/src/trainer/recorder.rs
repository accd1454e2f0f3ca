//! What a run leaves in its folder as it goes: metrics.csv, TensorBoard's events, the
//! run's clock, and which checkpoints each iteration makes due (the best policy's, and
//! every `checkpoint_every` iterations'). The recorder decides when; the trainer writes
//! what, since only it holds the learner's state.

use std::path::{Path, PathBuf};
use std::time::Instant;

use logo_nn::Checkpoint;

use crate::error::TrainError;
use crate::metrics::IterationMetrics;
use crate::run_dir::RunDir;
use crate::tensorboard::EventWriter;

pub(super) struct Recorder {
    run: RunDir,
    /// TensorBoard's event file, once [`Recorder::write_tensorboard`] opened it.
    events: Option<EventWriter>,
    started: Instant,
    /// Wall seconds of the iterations before a resume.
    wall_offset: f64,
    /// The iteration count of the last checkpoint written (or resumed from).
    saved_at: Option<usize>,
    /// The highest evaluation return of the trained task so far, whose policy is in
    /// `best.safetensors`.
    best_return: Option<f64>,
}

/// The checkpoints an iteration's row makes due.
pub(super) struct Due {
    /// The best policy so far, with its return: the latest to reach the highest
    /// evaluation of the trained task's own return (sparse on a sparse task; the dense
    /// one is for reporting, and a user with a sparse task has none). Ties go to the
    /// later policy, which has trained longer: a run that never earns anything keeps
    /// its latest policy, not iteration 1's.
    pub(super) best: Option<f64>,
    pub(super) checkpoint: bool,
}

impl Recorder {
    pub(super) fn new(run: RunDir) -> Self {
        Self {
            run,
            events: None,
            started: Instant::now(),
            wall_offset: 0.0,
            saved_at: None,
            best_return: None,
        }
    }

    pub(super) fn path(&self) -> &Path {
        self.run.path()
    }

    pub(super) fn checkpoint_path(&self) -> PathBuf {
        self.run.checkpoint_path()
    }

    pub(super) fn best_path(&self) -> PathBuf {
        self.run.best_path()
    }

    /// Seconds the run has trained, earlier invocations included.
    pub(super) fn wall_s(&self) -> f64 {
        self.wall_offset + self.started.elapsed().as_secs_f64()
    }

    /// From now on, every row also goes to a TensorBoard event file (written anew from
    /// the rows metrics.csv holds, so a resumed run's curves continue without the redone
    /// iterations twice), flushed each iteration.
    pub(super) fn write_tensorboard(&mut self, config_toml: &str) -> Result<(), TrainError> {
        let rows = self.run.read_metrics()?;
        self.events = Some(EventWriter::create(self.run.path(), config_toml, &rows)?);
        Ok(())
    }

    /// Appends `row` (after which the run has done `iterations`, and is `done` or not) and
    /// says which checkpoints are due (one every `checkpoint_every` iterations, and the
    /// last). The best policy is written before the periodic
    /// checkpoint, which then vouches for it: a resume recomputes the best from the rows
    /// the checkpoint keeps.
    pub(super) fn append(
        &mut self,
        row: &IterationMetrics,
        iterations: usize,
        done: bool,
        checkpoint_every: usize,
    ) -> Result<Due, TrainError> {
        self.run.append(row)?;
        if let Some(events) = self.events.as_mut() {
            events.append(row)?;
        }
        let best =
            row.eval_return.is_finite() && self.best_return.is_none_or(|b| row.eval_return >= b);
        Ok(Due {
            best: best.then_some(row.eval_return),
            checkpoint: iterations.is_multiple_of(checkpoint_every) || done,
        })
    }

    /// The best policy of return `eval_return` is written.
    pub(super) fn best_saved(&mut self, eval_return: f64) {
        self.best_return = Some(eval_return);
    }

    /// The checkpoint after `iterations` is written.
    pub(super) fn checkpoint_saved(&mut self, iterations: usize) {
        self.saved_at = Some(iterations);
    }

    /// The folder as a checkpoint after `iterations` (with `samples`) left it: the rows of
    /// metrics.csv after it are dropped (they are redone), the clock goes on from the last
    /// row kept, the best return is the kept rows' highest, and a best policy from a
    /// later iteration is removed (the redone iterations write it again if they earn it).
    pub(super) fn resume(&mut self, iterations: usize, samples: usize) -> Result<(), TrainError> {
        self.saved_at = Some(iterations);
        let metrics = self.run.metrics_path();
        let rows = self.run.read_metrics()?;
        if let Some(row) = rows.get(iterations.wrapping_sub(1))
            && row.samples != samples
        {
            return Err(TrainError::Resume(format!(
                "resume state: {samples} samples after iteration {iterations}, but {} says {} \
                 (not this checkpoint's metrics)",
                metrics.display(),
                row.samples
            )));
        }
        let kept = self.run.keep_metrics_before(iterations)?;
        self.wall_offset = kept.last().map_or(0.0, |row| row.wall_s);
        // Rows from before the column existed have no evaluation return.
        self.best_return = kept
            .iter()
            .map(|row| row.eval_return)
            .filter(|r| r.is_finite())
            .reduce(f64::max);
        let best = self.run.best_path();
        if best.is_file() {
            let later =
                Checkpoint::load(&best).map_or(true, |b| b.meta.iteration > iterations as u64);
            if later {
                std::fs::remove_file(&best).map_err(|e| TrainError::io(&best, e))?;
            }
        }
        Ok(())
    }

    /// `e`, saying what the run kept: metrics.csv and the checkpoint stay as the last good
    /// iteration left them.
    pub(super) fn stopped(&self, e: TrainError) -> TrainError {
        let kept = match self.saved_at {
            Some(at) => format!("the checkpoint of iteration {at} is kept"),
            None => "no checkpoint had been written yet".to_string(),
        };
        TrainError::Stopped {
            source: Box::new(e),
            kept: format!("{kept} in {}", self.path().display()),
        }
    }
}

/// Seconds between laps, for the per-phase times.
pub(super) struct Stopwatch(Instant);

impl Stopwatch {
    pub(super) fn start() -> Self {
        Self(Instant::now())
    }

    /// Seconds since the start or the previous lap.
    pub(super) fn lap(&mut self) -> f64 {
        let now = Instant::now();
        let seconds = (now - self.0).as_secs_f64();
        self.0 = now;
        seconds
    }
}

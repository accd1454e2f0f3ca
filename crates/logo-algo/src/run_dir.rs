//! A run's folder: `config.toml` (the config as run), `metrics.csv` (one row per
//! iteration), `checkpoint.safetensors` (networks plus the resume state) and `run.lock`,
//! which the process training the run holds locked so that no second process (another
//! sweep over the same folder, a requeued Slurm task whose first copy still runs)
//! trains it at the same time and interleaves their files.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

use crate::config::TrainConfig;
use crate::metrics::IterationMetrics;

pub use crate::error::TrainError;

pub struct RunDir {
    path: PathBuf,
    /// Held (locked) for as long as this value lives; the OS releases it when the
    /// process ends, however it ends. None where the filesystem has no locks.
    _lock: Option<File>,
}

/// The checkpoint's file name inside a run folder.
pub const CHECKPOINT: &str = "checkpoint.safetensors";
/// Beside it: the policy (a whole checkpoint) of the run's best evaluation.
pub const BEST: &str = "best.safetensors";

/// An I/O error on `path`, with the path in it.
fn io(path: &Path) -> impl Fn(std::io::Error) -> TrainError + '_ {
    move |e| TrainError::io(path, e)
}

/// A CSV error on `path` (a bad row, a failed write), with the path in it.
fn csv_at(path: &Path) -> impl Fn(csv::Error) -> TrainError + '_ {
    move |source| TrainError::Csv {
        path: path.to_path_buf(),
        source,
    }
}

impl RunDir {
    /// A new run in `path` (created if needed): writes `config.toml` and an empty
    /// `metrics.csv`.
    /// A folder that already holds a run's checkpoint is refused: starting afresh there
    /// would leave the old checkpoint for a later `--resume` to continue under the new
    /// config.
    pub fn create(path: &Path, config: &TrainConfig) -> Result<Self, TrainError> {
        std::fs::create_dir_all(path).map_err(io(path))?;
        let dir = Self::lock(path)?;
        if dir.checkpoint_path().exists() {
            return Err(TrainError::Busy(format!(
                "{} already holds a run (checkpoint.safetensors): continue it with --resume, \
                 or choose another --out",
                path.display()
            )));
        }
        dir.remove_stale_temporaries()?;
        let config_path = path.join("config.toml");
        std::fs::write(&config_path, toml::to_string(config)?).map_err(io(&config_path))?;
        let metrics = dir.metrics_path();
        File::create(&metrics).map_err(io(&metrics))?;
        Ok(dir)
    }

    /// An existing run's folder, to resume: it must hold a checkpoint, and no other
    /// process may be training it (see [`RunDir::lock`]).
    pub fn open(path: &Path) -> Result<Self, TrainError> {
        let checkpoint = path.join(CHECKPOINT);
        if !checkpoint.is_file() {
            let missing = std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "no such checkpoint: nothing to resume here",
            );
            return Err(TrainError::io(checkpoint, missing));
        }
        Self::lock(path)
    }

    /// The folder `path`, locked for this process: refused while another process holds
    /// it (the error names that process).
    fn lock(path: &Path) -> Result<Self, TrainError> {
        let lock_path = path.join("run.lock");
        let mut lock = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&lock_path)
            .map_err(io(&lock_path))?;
        let held = match lock.try_lock() {
            Ok(()) => true,
            Err(TryLockError::WouldBlock) => {
                let mut holder = String::new();
                let _ = lock.read_to_string(&mut holder);
                let holder = match holder.trim() {
                    "" => "another process".to_string(),
                    pid => format!("process {pid}"),
                };
                return Err(TrainError::Busy(format!(
                    "{} is being trained by {holder} (it holds {}); wait for it to end, or \
                     stop it, before training this run",
                    path.display(),
                    lock_path.display()
                )));
            }
            // Some cluster filesystems are mounted without locks: train unguarded, and
            // say so, rather than refuse every run there.
            Err(TryLockError::Error(e)) if e.kind() == std::io::ErrorKind::Unsupported => {
                eprintln!(
                    "warning: {}: this filesystem has no file locks; nothing stops a second \
                     process from training this run at the same time",
                    lock_path.display()
                );
                false
            }
            Err(TryLockError::Error(e)) => return Err(TrainError::io(lock_path, e)),
        };
        if held {
            // The holder's pid, for the message a second process gets.
            let pid = std::process::id();
            lock.set_len(0)
                .and_then(|()| lock.rewind())
                .and_then(|()| writeln!(lock, "{pid}"))
                .map_err(io(&lock_path))?;
        }
        Ok(Self {
            path: path.to_path_buf(),
            _lock: held.then_some(lock),
        })
    }

    /// Removes `checkpoint.tmp.<pid>` files left by checkpoint writes that were killed
    /// before their rename (the checkpoint itself is only ever replaced whole).
    pub fn remove_stale_temporaries(&self) -> Result<(), TrainError> {
        let Ok(entries) = std::fs::read_dir(&self.path) else {
            return Ok(());
        };
        for entry in entries.flatten() {
            let name = entry.file_name();
            if name.to_string_lossy().starts_with("checkpoint.tmp.") {
                std::fs::remove_file(entry.path()).map_err(io(&entry.path()))?;
            }
        }
        Ok(())
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn checkpoint_path(&self) -> PathBuf {
        self.path.join(CHECKPOINT)
    }

    /// The policy with the highest evaluation return of the trained task so far.
    pub fn best_path(&self) -> PathBuf {
        self.path.join(BEST)
    }

    pub fn metrics_path(&self) -> PathBuf {
        self.path.join("metrics.csv")
    }

    /// Appends one row (the header first, into an empty file).
    pub fn append(&self, row: &IterationMetrics) -> Result<(), TrainError> {
        let path = self.metrics_path();
        let file = OpenOptions::new()
            .append(true)
            .create(true)
            .open(&path)
            .map_err(io(&path))?;
        let empty = file.metadata().map_err(io(&path))?.len() == 0;
        let mut writer = csv::WriterBuilder::new()
            .has_headers(empty)
            .from_writer(file);
        writer.serialize(row).map_err(csv_at(&path))?;
        writer.flush().map_err(io(&path))?;
        Ok(())
    }

    /// Every row of `metrics.csv` (an error names the file and the line of a bad row).
    pub fn read_metrics(&self) -> Result<Vec<IterationMetrics>, TrainError> {
        let path = self.metrics_path();
        let mut reader = csv::Reader::from_path(&path).map_err(csv_at(&path))?;
        reader
            .deserialize()
            .map(|row| row.map_err(csv_at(&path)))
            .collect()
    }

    /// Keeps the rows of the iterations before `iteration` (a resumed run redoes the
    /// rest), rewritten atomically; returns them. Rows must be the iterations 0, 1, …
    /// in order: anything else means the file is not this checkpoint's run.
    pub fn keep_metrics_before(
        &self,
        iteration: usize,
    ) -> Result<Vec<IterationMetrics>, TrainError> {
        let path = self.metrics_path();
        let rows = self.read_metrics()?;
        let kept: Vec<IterationMetrics> = rows
            .into_iter()
            .take_while(|r| r.iteration < iteration)
            .collect();
        if let Some((i, row)) = kept.iter().enumerate().find(|(i, r)| r.iteration != *i) {
            let refused = format!(
                "row {} is iteration {}, expected {i}: not the rows of this run",
                i + 1,
                row.iteration
            );
            return Err(TrainError::Resume(refused).at(path.display()));
        }
        if kept.len() < iteration {
            let refused = format!(
                "holds {} iterations, the checkpoint {iteration}: rows are missing",
                kept.len()
            );
            return Err(TrainError::Resume(refused).at(path.display()));
        }
        let tmp = path.with_extension(format!("csv.tmp.{}", std::process::id()));
        {
            let mut writer = csv::Writer::from_path(&tmp).map_err(csv_at(&tmp))?;
            for row in &kept {
                writer.serialize(row).map_err(csv_at(&tmp))?;
            }
            writer.flush().map_err(io(&tmp))?;
        }
        if kept.is_empty() {
            File::create(&tmp).map_err(io(&tmp))?;
        }
        std::fs::rename(&tmp, &path).map_err(io(&path))?;
        Ok(kept)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_folder_is_trained_by_one_process_at_a_time() {
        let dir = std::env::temp_dir().join(format!("logo-run-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let first = RunDir::lock(&dir).unwrap();
        // A second open file description conflicts like a second process would.
        let refused = RunDir::lock(&dir)
            .err()
            .expect("the folder is locked")
            .to_string();
        assert!(
            refused.contains(&format!("process {}", std::process::id()))
                && refused.contains("run.lock"),
            "{refused}"
        );
        drop(first);
        let again = RunDir::lock(&dir).expect("released when the holder is dropped");
        drop(again);
        // Resuming needs a checkpoint, and says so before it leaves a lock file behind.
        let empty = dir.join("empty");
        std::fs::create_dir_all(&empty).unwrap();
        let missing = RunDir::open(&empty).err().unwrap().to_string();
        assert!(
            missing.contains("checkpoint.safetensors: no such checkpoint"),
            "{missing}"
        );
        assert!(!empty.join("run.lock").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

//! A run's folder: `config.toml` (the config as run), `metrics.csv` (one row per
//! iteration) and `checkpoint.safetensors` (networks plus the resume state).

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

use crate::config::TrainConfig;
use crate::metrics::IterationMetrics;

/// Anything that stops a run, as one message naming its cause.
pub type TrainError = Box<dyn std::error::Error + Send + Sync>;

pub struct RunDir {
    path: PathBuf,
}

/// `what` failed on `path`: the error with the path in it.
fn at(path: &Path, e: impl std::fmt::Display) -> TrainError {
    format!("{}: {e}", path.display()).into()
}

impl RunDir {
    /// A new run in `path` (created if needed): writes `config.toml` and an empty
    /// `metrics.csv`.
    /// A folder that already holds a run's checkpoint is refused: starting afresh there
    /// would leave the old checkpoint for a later `--resume` to continue under the new
    /// config.
    pub fn create(path: &Path, config: &TrainConfig) -> Result<Self, TrainError> {
        std::fs::create_dir_all(path).map_err(|e| at(path, e))?;
        let dir = Self::open(path);
        if dir.checkpoint_path().exists() {
            return Err(format!(
                "{} already holds a run (checkpoint.safetensors): continue it with --resume, \
                 or choose another --out",
                path.display()
            )
            .into());
        }
        dir.remove_stale_temporaries()?;
        let config_path = path.join("config.toml");
        std::fs::write(&config_path, toml::to_string(config)?).map_err(|e| at(&config_path, e))?;
        let metrics = dir.metrics_path();
        File::create(&metrics).map_err(|e| at(&metrics, e))?;
        Ok(dir)
    }

    /// An existing run's folder.
    pub fn open(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
        }
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
                std::fs::remove_file(entry.path()).map_err(|e| at(&entry.path(), e))?;
            }
        }
        Ok(())
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn checkpoint_path(&self) -> PathBuf {
        self.path.join("checkpoint.safetensors")
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
            .map_err(|e| at(&path, e))?;
        let empty = file.metadata().map_err(|e| at(&path, e))?.len() == 0;
        let mut writer = csv::WriterBuilder::new()
            .has_headers(empty)
            .from_writer(file);
        writer.serialize(row).map_err(|e| at(&path, e))?;
        writer.flush().map_err(|e| at(&path, e))?;
        Ok(())
    }

    /// Every row of `metrics.csv` (an error names the file and the line of a bad row).
    pub fn read_metrics(&self) -> Result<Vec<IterationMetrics>, TrainError> {
        let path = self.metrics_path();
        let mut reader = csv::Reader::from_path(&path).map_err(|e| at(&path, e))?;
        reader
            .deserialize()
            .map(|row| row.map_err(|e| at(&path, e)))
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
            return Err(at(
                &path,
                format!(
                    "row {} is iteration {}, expected {i}: not the rows of this run",
                    i + 1,
                    row.iteration
                ),
            ));
        }
        if kept.len() < iteration {
            return Err(at(
                &path,
                format!(
                    "holds {} iterations, the checkpoint {iteration}: rows are missing",
                    kept.len()
                ),
            ));
        }
        let tmp = path.with_extension(format!("csv.tmp.{}", std::process::id()));
        {
            let mut writer = csv::Writer::from_path(&tmp).map_err(|e| at(&tmp, e))?;
            for row in &kept {
                writer.serialize(row).map_err(|e| at(&tmp, e))?;
            }
            writer.flush().map_err(|e| at(&tmp, e))?;
        }
        if kept.is_empty() {
            File::create(&tmp).map_err(|e| at(&tmp, e))?;
        }
        std::fs::rename(&tmp, &path).map_err(|e| at(&path, e))?;
        Ok(kept)
    }
}

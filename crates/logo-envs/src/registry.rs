//! Environment ids and the factory that builds any number of copies over one loaded model.

use std::fmt;
use std::sync::Arc;

use mujoco_rs::prelude::MjModel;

use crate::env::{Env, EnvError, EnvSpec, Version};
use crate::mujoco_env::{MujocoEnv, Task, load_model};
use crate::sparse::{SparseReward, SparseRule};
use crate::{HalfCheetah, Hopper, InvertedDoublePendulum, Walker2d};

/// The dense environments; each also exists as `Sparse<id>` (e.g. `SparseHopper-v4`).
pub const BASE_ENV_IDS: [&str; 8] = [
    "Hopper-v4",
    "Hopper-v5",
    "Walker2d-v4",
    "Walker2d-v5",
    "HalfCheetah-v4",
    "HalfCheetah-v5",
    "InvertedDoublePendulum-v4",
    "InvertedDoublePendulum-v5",
];

/// Every id [`make`] accepts: the dense ones, then their sparse versions.
pub fn all_env_ids() -> Vec<String> {
    let dense = BASE_ENV_IDS.iter().map(|id| id.to_string());
    let sparse = BASE_ENV_IDS.iter().map(|id| format!("Sparse{id}"));
    dense.chain(sparse).collect()
}

/// Options every env id takes.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvOptions {
    /// Gymnasium registers all four tasks with 1000.
    pub max_episode_steps: usize,
    /// Overrides the sparse distance threshold (2.0 Hopper/Walker2d, 20.0 HalfCheetah).
    pub sparse_threshold: Option<f64>,
}

impl Default for EnvOptions {
    fn default() -> Self {
        Self {
            max_episode_steps: 1000,
            sparse_threshold: None,
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum Kind {
    Hopper,
    Walker2d,
    HalfCheetah,
    InvertedDoublePendulum,
}

/// Builds copies of one env id over a model loaded once (`MjModel` is shared, read-only).
#[derive(Clone)]
pub struct EnvFactory {
    kind: Kind,
    version: Version,
    sparse: Option<SparseRule>,
    model: Arc<MjModel>,
    options: EnvOptions,
    spec: EnvSpec,
}

impl fmt::Debug for EnvFactory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("EnvFactory")
            .field("id", &self.spec.id)
            .field("options", &self.options)
            .finish()
    }
}

fn unknown(id: &str) -> EnvError {
    EnvError::UnknownId(id.to_string(), all_env_ids().join(", "))
}

impl EnvFactory {
    pub fn new(id: &str, options: &EnvOptions) -> Result<Self, EnvError> {
        let (sparse, base) = match id.strip_prefix("Sparse") {
            Some(base) => (true, base),
            None => (false, id),
        };
        let (name, version) = base.rsplit_once('-').ok_or_else(|| unknown(id))?;
        let version = match version {
            "v4" => Version::V4,
            "v5" => Version::V5,
            _ => return Err(unknown(id)),
        };
        let (kind, default_threshold) = match name {
            "Hopper" => (Kind::Hopper, Some(2.0)),
            "Walker2d" => (Kind::Walker2d, Some(2.0)),
            "HalfCheetah" => (Kind::HalfCheetah, Some(20.0)),
            "InvertedDoublePendulum" => (Kind::InvertedDoublePendulum, None),
            _ => return Err(unknown(id)),
        };
        if options.max_episode_steps == 0 {
            return Err(EnvError::InvalidOption(
                "max_episode_steps must be at least 1".into(),
            ));
        }
        if let Some(t) = options.sparse_threshold
            && !t.is_finite()
        {
            return Err(EnvError::InvalidOption(format!(
                "sparse_threshold must be finite, got {t}"
            )));
        }
        let sparse = sparse.then(|| match default_threshold {
            Some(default) => SparseRule::Distance {
                threshold: options.sparse_threshold.unwrap_or(default),
            },
            None => SparseRule::EpisodeLump,
        });
        let model_file = match kind {
            Kind::Hopper => Hopper { version }.model_file(),
            Kind::Walker2d => Walker2d { version }.model_file(),
            Kind::HalfCheetah => HalfCheetah { version }.model_file(),
            Kind::InvertedDoublePendulum => InvertedDoublePendulum { version }.model_file(),
        };
        let model = load_model(model_file)?;
        let spec = build_env(kind, version, sparse, &model, options.max_episode_steps)
            .spec()
            .clone();
        Ok(Self {
            kind,
            version,
            sparse,
            model,
            options: options.clone(),
            spec,
        })
    }

    pub fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    /// The sparse rule, if this id is a sparse one.
    pub fn sparse_rule(&self) -> Option<SparseRule> {
        self.sparse
    }

    /// One new env (own `MjData`, own noise generator) over the shared model.
    pub fn build(&self) -> Box<dyn Env> {
        build_env(
            self.kind,
            self.version,
            self.sparse,
            &self.model,
            self.options.max_episode_steps,
        )
    }

    /// The loaded model, for code that steps MuJoCo directly (the raw-step benchmark).
    pub fn model(&self) -> &Arc<MjModel> {
        &self.model
    }
}

/// One env by id with default options: `make("SparseHopper-v4")`.
pub fn make(id: &str) -> Result<Box<dyn Env>, EnvError> {
    Ok(EnvFactory::new(id, &EnvOptions::default())?.build())
}

fn build_env(
    kind: Kind,
    version: Version,
    sparse: Option<SparseRule>,
    model: &Arc<MjModel>,
    max_episode_steps: usize,
) -> Box<dyn Env> {
    fn finish<T: Task>(env: MujocoEnv<T>, sparse: Option<SparseRule>) -> Box<dyn Env> {
        match sparse {
            Some(rule) => Box::new(SparseReward::new(env, rule)),
            None => Box::new(env),
        }
    }
    let (model, steps) = (model.clone(), max_episode_steps);
    match kind {
        Kind::Hopper => finish(
            MujocoEnv::with_model(Hopper { version }, model, steps),
            sparse,
        ),
        Kind::Walker2d => finish(
            MujocoEnv::with_model(Walker2d { version }, model, steps),
            sparse,
        ),
        Kind::HalfCheetah => finish(
            MujocoEnv::with_model(HalfCheetah { version }, model, steps),
            sparse,
        ),
        Kind::InvertedDoublePendulum => finish(
            MujocoEnv::with_model(InvertedDoublePendulum { version }, model, steps),
            sparse,
        ),
    }
}

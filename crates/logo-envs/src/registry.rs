//! Environment ids and the factory that builds any number of copies over one loaded model.

use std::fmt;
use std::sync::Arc;

use mujoco_rs::prelude::MjModel;

use crate::env::{Env, EnvError, EnvSpec, Version};
use crate::external::{EnvMaker, external};
use crate::mujoco_env::{MujocoEnv, Task, load_model};
use crate::sparse::{SparseReward, SparseRule};
use crate::{HalfCheetah, Hopper, InvertedDoublePendulum, Walker2d};

/// The dense environments. Each also exists as `Sparse<id>` (e.g. `SparseHopper-v4`),
/// with LOGO's rule for that task, and as `<id>+<rule>` with any [`SparseRule`]
/// (`Hopper-v4+distance(5)`, `HalfCheetah-v4+delayed`).
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

/// Every id [`make`] accepts by name: the dense ones, then their LOGO sparse versions.
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
    /// Makes a dense id's reward sparse by this rule (a config's `[env.sparse]`).
    pub sparse: Option<SparseRule>,
}

impl Default for EnvOptions {
    fn default() -> Self {
        Self {
            max_episode_steps: 1000,
            sparse: None,
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

/// Builds copies of one env id over a model loaded once (`MjModel` is shared, read-only),
/// or by the maker of an external env (`python:<name>`, see [`crate::register_external`]).
#[derive(Clone)]
pub struct EnvFactory {
    source: Source,
    options: EnvOptions,
    spec: EnvSpec,
}

#[derive(Clone)]
enum Source {
    Mujoco {
        kind: Kind,
        version: Version,
        sparse: Option<SparseRule>,
        model: Arc<MjModel>,
    },
    External(Arc<dyn EnvMaker>),
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

/// An id's task, version and sparse rule (`Sparse<id>`: the task's LOGO rule;
/// `<id>+<rule>`: that rule; else dense).
fn parse_id(id: &str) -> Result<(Kind, Version, Option<SparseRule>), EnvError> {
    let (base, rule) = match (id.strip_prefix("Sparse"), id.split_once('+')) {
        (Some(base), None) => (base, Some(None)),
        (None, Some((base, rule))) => {
            let rule = SparseRule::parse(rule)
                .map_err(|e| EnvError::InvalidOption(format!("{id}: {e}")))?;
            (base, Some(Some(rule)))
        }
        (None, None) => (id, None),
        (Some(_), Some(_)) => return Err(unknown(id)),
    };
    let (name, version) = base.rsplit_once('-').ok_or_else(|| unknown(id))?;
    let version = match version {
        "v4" => Version::V4,
        "v5" => Version::V5,
        _ => return Err(unknown(id)),
    };
    let kind = match name {
        "Hopper" => Kind::Hopper,
        "Walker2d" => Kind::Walker2d,
        "HalfCheetah" => Kind::HalfCheetah,
        "InvertedDoublePendulum" => Kind::InvertedDoublePendulum,
        _ => return Err(unknown(id)),
    };
    let rule = rule.map(|named| named.unwrap_or_else(|| kind.logo_rule()));
    Ok((kind, version, rule))
}

impl Kind {
    /// The sparse rule of LOGO's version of the task (its `Sparse<id>`).
    fn logo_rule(self) -> SparseRule {
        match self {
            Kind::Hopper | Kind::Walker2d => SparseRule::Distance { threshold: 2.0 },
            Kind::HalfCheetah => SparseRule::Distance { threshold: 20.0 },
            Kind::InvertedDoublePendulum => SparseRule::Delayed,
        }
    }
}

/// The id the env built from `id` reports: `id` itself, with a sparse rule written as
/// [`sparse_id`] writes it (`Hopper-v4+distance(2)` is LOGO's rule, `SparseHopper-v4`;
/// `Hopper-v4+distance(5.0)` is `Hopper-v4+distance(5)`), so that a config naming an
/// env either way matches its checkpoints.
pub fn canonical_id(id: &str) -> Result<String, EnvError> {
    if let Some(maker) = external(id) {
        return maker.map(|m| m.spec().id.clone());
    }
    let (kind, _, rule) = parse_id(id)?;
    Ok(match rule {
        Some(rule) => sparse_name(dense_id(id), kind, rule),
        None => id.to_string(),
    })
}

/// The dense task of any id: `Hopper-v4` for `SparseHopper-v4` and `Hopper-v4+delayed`.
pub fn dense_id(id: &str) -> &str {
    let id = id.strip_prefix("Sparse").unwrap_or(id);
    id.split_once('+').map_or(id, |(base, _)| base)
}

/// The id of a dense task made sparse by `rule`: `Sparse<id>` where the rule is LOGO's
/// for that task (so that a config's kind and the old name run and record alike), else
/// `<id>+<rule>`.
pub fn sparse_id(dense: &str, rule: SparseRule) -> Result<String, EnvError> {
    if external(dense).is_some() {
        return Err(EnvError::InvalidOption(format!(
            "{dense}: a sparse kind of a Python env is a wrapper in Python (logo_rl.SparseReward)"
        )));
    }
    let (kind, _, named) = parse_id(dense)?;
    if named.is_some() {
        return Err(EnvError::InvalidOption(format!(
            "{dense} is already sparse"
        )));
    }
    rule.validate().map_err(EnvError::InvalidOption)?;
    Ok(sparse_name(dense, kind, rule))
}

fn sparse_name(dense: &str, kind: Kind, rule: SparseRule) -> String {
    if kind.logo_rule() == rule {
        format!("Sparse{dense}")
    } else {
        format!("{dense}+{}", rule.describe())
    }
}

impl EnvFactory {
    pub fn new(id: &str, options: &EnvOptions) -> Result<Self, EnvError> {
        if let Some(maker) = external(id) {
            return Self::external(maker?, options);
        }
        let (kind, version, named_rule) = parse_id(id)?;
        if options.max_episode_steps == 0 {
            return Err(EnvError::InvalidOption(
                "max_episode_steps must be at least 1".into(),
            ));
        }
        let sparse = match (named_rule, options.sparse) {
            (Some(_), Some(_)) => {
                return Err(EnvError::InvalidOption(format!(
                    "{id} is already sparse; give the dense id {} with the sparse rule",
                    dense_id(id)
                )));
            }
            (named, chosen) => named.or(chosen),
        };
        if let Some(rule) = &sparse {
            rule.validate().map_err(EnvError::InvalidOption)?;
        }
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
            source: Source::Mujoco {
                kind,
                version,
                sparse,
                model,
            },
            options: options.clone(),
            spec,
        })
    }

    fn external(maker: Arc<dyn EnvMaker>, options: &EnvOptions) -> Result<Self, EnvError> {
        let spec = maker.spec().clone();
        if options.sparse.is_some() {
            return Err(EnvError::InvalidOption(format!(
                "{}: a sparse kind of a Python env is a wrapper in Python (logo_rl.SparseReward)",
                spec.id
            )));
        }
        Ok(Self {
            source: Source::External(maker),
            options: options.clone(),
            spec,
        })
    }

    pub fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    /// The sparse rule, if the env is a sparse one of this crate's.
    pub fn sparse_rule(&self) -> Option<SparseRule> {
        match &self.source {
            Source::Mujoco { sparse, .. } => *sparse,
            Source::External(_) => None,
        }
    }

    /// One new env (own `MjData`, own noise generator) over the shared model; an
    /// external env's maker may fail.
    pub fn build(&self) -> Result<Box<dyn Env>, EnvError> {
        match &self.source {
            Source::Mujoco {
                kind,
                version,
                sparse,
                model,
            } => Ok(build_env(
                *kind,
                *version,
                *sparse,
                model,
                self.options.max_episode_steps,
            )),
            Source::External(maker) => maker.build(),
        }
    }

    /// The loaded model, for code that steps or draws MuJoCo directly (the raw-step
    /// benchmark, the renderer); an error for an external env.
    pub fn model(&self) -> Result<&Arc<MjModel>, EnvError> {
        match &self.source {
            Source::Mujoco { model, .. } => Ok(model),
            Source::External(_) => Err(EnvError::InvalidOption(format!(
                "{} is a Python env: no MuJoCo model of logo-rl's to draw or step",
                self.spec.id
            ))),
        }
    }
}

/// One env by id with default options: `make("SparseHopper-v4")`.
pub fn make(id: &str) -> Result<Box<dyn Env>, EnvError> {
    EnvFactory::new(id, &EnvOptions::default())?.build()
}

fn build_env(
    kind: Kind,
    version: Version,
    sparse: Option<SparseRule>,
    model: &Arc<MjModel>,
    max_episode_steps: usize,
) -> Box<dyn Env> {
    fn finish<T: Task>(env: MujocoEnv<T>, kind: Kind, sparse: Option<SparseRule>) -> Box<dyn Env> {
        match sparse {
            Some(rule) => {
                let id = sparse_name(&env.spec().id, kind, rule);
                Box::new(SparseReward::new(env, rule, id))
            }
            None => Box::new(env),
        }
    }
    let (model, steps) = (model.clone(), max_episode_steps);
    match kind {
        Kind::Hopper => finish(
            MujocoEnv::with_model(Hopper { version }, model, steps),
            kind,
            sparse,
        ),
        Kind::Walker2d => finish(
            MujocoEnv::with_model(Walker2d { version }, model, steps),
            kind,
            sparse,
        ),
        Kind::HalfCheetah => finish(
            MujocoEnv::with_model(HalfCheetah { version }, model, steps),
            kind,
            sparse,
        ),
        Kind::InvertedDoublePendulum => finish(
            MujocoEnv::with_model(InvertedDoublePendulum { version }, model, steps),
            kind,
            sparse,
        ),
    }
}

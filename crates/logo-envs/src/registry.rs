//! Environment ids and the factory that builds any number of copies over one loaded model.

use std::fmt;
use std::sync::Arc;

use mujoco_rs::prelude::MjModel;

use crate::env::{Env, EnvError, EnvSpec, Version};
use crate::external::{EnvMaker, external};
use crate::mujoco_env::{MujocoEnv, Task, load_model};
use crate::sparse::{SparseReward, SparseRule};
use crate::{
    Ant, HalfCheetah, Hopper, Humanoid, HumanoidStandup, InvertedDoublePendulum, InvertedPendulum,
    Pusher, Reacher, Swimmer, Walker2d,
};

/// The dense environments: Gymnasium 1.4.0's eleven MuJoCo tasks, `-v4` and `-v5`
/// (Pusher only `-v5`: Gymnasium refuses `Pusher-v4` under MuJoCo 3). Each is made sparse
/// as `<id>+<rule>` with any [`SparseRule`] (`Ant-v4+distance(5)`, `HalfCheetah-v4+delayed`);
/// LOGO's four tasks also as `Sparse<id>` (e.g. `SparseHopper-v4`), with LOGO's rule.
pub const BASE_ENV_IDS: [&str; 21] = [
    "Hopper-v4",
    "Hopper-v5",
    "Walker2d-v4",
    "Walker2d-v5",
    "HalfCheetah-v4",
    "HalfCheetah-v5",
    "InvertedDoublePendulum-v4",
    "InvertedDoublePendulum-v5",
    "Ant-v4",
    "Ant-v5",
    "Humanoid-v4",
    "Humanoid-v5",
    "HumanoidStandup-v4",
    "HumanoidStandup-v5",
    "InvertedPendulum-v4",
    "InvertedPendulum-v5",
    "Pusher-v5",
    "Reacher-v4",
    "Reacher-v5",
    "Swimmer-v4",
    "Swimmer-v5",
];

/// Every id [`make`] accepts by name: the dense ones, then LOGO's sparse versions.
pub fn all_env_ids() -> Vec<String> {
    let dense = BASE_ENV_IDS.iter().map(|id| id.to_string());
    let sparse = BASE_ENV_IDS
        .iter()
        .filter(|id| parse_id(id).is_ok_and(|(kind, ..)| kind.logo_rule().is_some()))
        .map(|id| format!("Sparse{id}"));
    dense.chain(sparse).collect()
}

/// Options every env id takes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EnvOptions {
    /// Steps after which an episode is truncated; `None`: the limit Gymnasium registers
    /// the task with (1000; Reacher 50, Pusher 100).
    pub max_episode_steps: Option<usize>,
    /// Makes a dense id's reward sparse by this rule (a config's `[env.sparse]`).
    pub sparse: Option<SparseRule>,
}

#[derive(Debug, Clone, Copy)]
enum Kind {
    Hopper,
    Walker2d,
    HalfCheetah,
    InvertedDoublePendulum,
    Ant,
    Humanoid,
    HumanoidStandup,
    InvertedPendulum,
    Pusher,
    Reacher,
    Swimmer,
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
        "Ant" => Kind::Ant,
        "Humanoid" => Kind::Humanoid,
        "HumanoidStandup" => Kind::HumanoidStandup,
        "InvertedPendulum" => Kind::InvertedPendulum,
        "Pusher" if version == Version::V4 => {
            return Err(EnvError::InvalidOption(format!(
                "{id}: Gymnasium 1.4.0 refuses Pusher-v4 under MuJoCo 3, so there is no \
                 reference to match it to; use Pusher-v5"
            )));
        }
        "Pusher" => Kind::Pusher,
        "Reacher" => Kind::Reacher,
        "Swimmer" => Kind::Swimmer,
        _ => return Err(unknown(id)),
    };
    let rule = match rule {
        None => None,
        Some(Some(named)) => {
            check_rule(id, kind, named)?;
            Some(named)
        }
        Some(None) => Some(kind.logo_rule().ok_or_else(|| {
            EnvError::InvalidOption(format!(
                "{id}: LOGO has no sparse version of {name}; give the dense id {base} with \
                 an [env.sparse] kind (`logo envs` lists them), e.g. {base}+{}",
                kind.suggested_rule()
            ))
        })?),
    };
    Ok((kind, version, rule))
}

impl Kind {
    /// The sparse rule of LOGO's version of the task (its `Sparse<id>`); the tasks LOGO
    /// did not use have none.
    fn logo_rule(self) -> Option<SparseRule> {
        match self {
            Kind::Hopper | Kind::Walker2d => Some(SparseRule::Distance { threshold: 2.0 }),
            Kind::HalfCheetah => Some(SparseRule::Distance { threshold: 20.0 }),
            Kind::InvertedDoublePendulum => Some(SparseRule::Delayed),
            _ => None,
        }
    }

    /// A kind that fits the task, for error messages: a target to reach, the episode's
    /// return for the tasks not about moving along x, else a distance.
    fn suggested_rule(self) -> &'static str {
        match self {
            Kind::Reacher => "goal(0.02)",
            Kind::Pusher => "goal(0.08)",
            Kind::InvertedPendulum | Kind::InvertedDoublePendulum | Kind::HumanoidStandup => {
                "delayed"
            }
            _ => "distance(5)",
        }
    }

    /// Whether the task reports a goal distance (what the goal kind pays on).
    fn has_goal(self) -> bool {
        matches!(self, Kind::Reacher | Kind::Pusher)
    }

    /// The task as the MuJoCo loop runs it.
    fn task(self, version: Version) -> Box<dyn Task> {
        match self {
            Kind::Hopper => Box::new(Hopper { version }),
            Kind::Walker2d => Box::new(Walker2d { version }),
            Kind::HalfCheetah => Box::new(HalfCheetah { version }),
            Kind::InvertedDoublePendulum => Box::new(InvertedDoublePendulum { version }),
            Kind::Ant => Box::new(Ant { version }),
            Kind::Humanoid => Box::new(Humanoid { version }),
            Kind::HumanoidStandup => Box::new(HumanoidStandup { version }),
            Kind::InvertedPendulum => Box::new(InvertedPendulum { version }),
            Kind::Pusher => Box::new(Pusher),
            Kind::Reacher => Box::new(Reacher { version }),
            Kind::Swimmer => Box::new(Swimmer { version }),
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
    check_rule(dense, kind, rule)?;
    Ok(sparse_name(dense, kind, rule))
}

/// A rule's parameters, and whether the task can pay it (the goal kind needs a target).
fn check_rule(id: &str, kind: Kind, rule: SparseRule) -> Result<(), EnvError> {
    rule.validate()
        .map_err(|e| EnvError::InvalidOption(e.to_string()))?;
    if matches!(rule, SparseRule::Goal { .. }) && !kind.has_goal() {
        return Err(EnvError::InvalidOption(format!(
            "{id}: the goal kind pays for reaching a target, and only Reacher and Pusher have \
             one; use distance or delayed"
        )));
    }
    Ok(())
}

fn sparse_name(dense: &str, kind: Kind, rule: SparseRule) -> String {
    if kind.logo_rule() == Some(rule) {
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
        if options.max_episode_steps == Some(0) {
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
        if let Some(rule) = sparse {
            check_rule(id, kind, rule)?;
        }
        let model = load_model(kind.task(version).model_file())?;
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

/// The time limit Gymnasium registers `id`'s task with (1000; Reacher 50, Pusher 100),
/// without loading its model; an error for an unknown id.
pub fn time_limit(id: &str) -> Result<usize, EnvError> {
    let (kind, version, _) = parse_id(id)?;
    Ok(kind.task(version).max_episode_steps())
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
    max_episode_steps: Option<usize>,
) -> Box<dyn Env> {
    let task = kind.task(version);
    let steps = max_episode_steps.unwrap_or_else(|| task.max_episode_steps());
    let env = MujocoEnv::with_model(task, model.clone(), steps);
    match sparse {
        Some(rule) => {
            let id = sparse_name(&env.spec().id, kind, rule);
            Box::new(SparseReward::new(env, rule, id))
        }
        None => Box::new(env),
    }
}

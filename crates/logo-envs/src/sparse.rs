//! LOGO's sparse-reward versions of the tasks (see `docs/reference.md`): the agent is paid
//! only for having gone far, or only once per episode. The dense reward stays in
//! [`StepInfo::dense_reward`] so evaluation can report both. A config chooses the rule
//! by its kind (`[env.sparse] kind = "distance"`); the `Sparse<id>` ids are the tasks'
//! LOGO rules under their old names.

use serde::{Deserialize, Serialize};

use crate::env::{Env, EnvError, EnvSpec, ResetPoint, Step};

/// How the sparse reward is paid: a config's `[env.sparse]` table, `kind` naming the rule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RuleTable", into = "RuleTable")]
pub enum SparseRule {
    /// +1 on every step where `x − x_init > threshold` (x_init: x at the episode's start),
    /// else 0. LOGO's Hopper and Walker2d use 2.0, HalfCheetah 20.0. (The LOGO code pays
    /// on every step spent past the threshold, not once; its published curves follow the
    /// code.)
    Distance { threshold: f64 },
    /// The dense rewards accumulated and paid in one lump on the episode's last step
    /// (termination or time limit); 0 on every other step. LOGO's InvertedDoublePendulum.
    Delayed,
    /// +1 on every step where the task's goal distance (Reacher: fingertip to target;
    /// Pusher: object to goal; both in the plane of the table) is below `radius`, else 0.
    Goal { radius: f64 },
}

/// Each kind, its parameters and what it pays, for `logo envs` and error messages.
pub const SPARSE_KINDS: [(&str, &str, &str); 3] = [
    (
        "distance",
        "threshold (metres along x)",
        "+1 on every step once x has moved past the threshold from the episode's start",
    ),
    (
        "delayed",
        "-",
        "the episode's dense return, paid once on its last step",
    ),
    (
        "goal",
        "radius (metres, in the plane)",
        "+1 on every step the fingertip (Reacher) or object (Pusher) is within the radius of its target",
    ),
];

/// The table as written: each kind's parameters are checked by hand, so that a
/// parameter given to a kind without it is an error too (serde's tagged enums let it by).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RuleTable {
    kind: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    threshold: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    radius: Option<f64>,
}

/// What a sparse rule's table or `describe` form can get wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RuleError {
    #[error("kind {kind:?} needs `{param}`")]
    Needs {
        kind: &'static str,
        param: &'static str,
    },
    #[error("kind {kind:?} takes `{param}`, not `{other}`")]
    Takes {
        kind: &'static str,
        param: &'static str,
        other: &'static str,
    },
    #[error("kind {0:?} takes no `threshold` or `radius`")]
    TakesNone(&'static str),
    #[error("unknown sparse kind {0:?}; the kinds are {kinds}", kinds = kind_names())]
    UnknownKind(String),
    #[error("sparse.{param} must be a positive number of metres, got {value}")]
    NotPositive { param: &'static str, value: f64 },
    #[error("{EXPECTED_FORM}")]
    Unclosed,
    #[error("unknown sparse kind {0:?}: {EXPECTED_FORM}")]
    UnknownForm(String),
    #[error("{what} {value:?} is not a number")]
    NotANumber { what: &'static str, value: String },
}

/// The forms [`SparseRule::parse`] reads.
const EXPECTED_FORM: &str = "expected distance(<metres>), delayed or goal(<metres>)";

fn kind_names() -> String {
    let known: Vec<&str> = SPARSE_KINDS.iter().map(|k| k.0).collect();
    known.join(", ")
}

impl TryFrom<RuleTable> for SparseRule {
    type Error = RuleError;
    fn try_from(table: RuleTable) -> Result<Self, RuleError> {
        use RuleError::{Needs, Takes, TakesNone};
        let rule = match (table.kind.as_str(), table.threshold, table.radius) {
            ("distance", Some(threshold), None) => Self::Distance { threshold },
            ("distance", None, _) => {
                return Err(Needs {
                    kind: "distance",
                    param: "threshold",
                });
            }
            ("distance", _, Some(_)) => {
                return Err(Takes {
                    kind: "distance",
                    param: "threshold",
                    other: "radius",
                });
            }
            ("delayed", None, None) => Self::Delayed,
            ("delayed", ..) => return Err(TakesNone("delayed")),
            ("goal", None, Some(radius)) => Self::Goal { radius },
            ("goal", _, None) => {
                return Err(Needs {
                    kind: "goal",
                    param: "radius",
                });
            }
            ("goal", Some(_), _) => {
                return Err(Takes {
                    kind: "goal",
                    param: "radius",
                    other: "threshold",
                });
            }
            (kind, ..) => return Err(RuleError::UnknownKind(kind.to_string())),
        };
        rule.validate()?;
        Ok(rule)
    }
}

impl From<SparseRule> for RuleTable {
    fn from(rule: SparseRule) -> Self {
        let (kind, threshold, radius) = match rule {
            SparseRule::Distance { threshold } => ("distance", Some(threshold), None),
            SparseRule::Delayed => ("delayed", None, None),
            SparseRule::Goal { radius } => ("goal", None, Some(radius)),
        };
        Self {
            kind: kind.into(),
            threshold,
            radius,
        }
    }
}

impl SparseRule {
    /// What a file can get wrong that serde cannot see.
    pub fn validate(&self) -> Result<(), RuleError> {
        let (param, value) = match *self {
            Self::Distance { threshold } => ("threshold", threshold),
            Self::Goal { radius } => ("radius", radius),
            Self::Delayed => return Ok(()),
        };
        match value.is_finite() && value > 0.0 {
            true => Ok(()),
            false => Err(RuleError::NotPositive { param, value }),
        }
    }

    /// The kind as a config names it, with its parameter: `distance(2)`, `delayed`.
    pub fn describe(&self) -> String {
        match self {
            Self::Distance { threshold } => format!("distance({threshold})"),
            Self::Delayed => "delayed".into(),
            Self::Goal { radius } => format!("goal({radius})"),
        }
    }

    /// Reads [`SparseRule::describe`]'s form back.
    pub fn parse(text: &str) -> Result<Self, RuleError> {
        let metres = |what: &'static str, rest: &str| -> Result<f64, RuleError> {
            let value = rest.strip_suffix(')').ok_or(RuleError::Unclosed)?;
            value.parse().map_err(|_| RuleError::NotANumber {
                what,
                value: value.to_string(),
            })
        };
        let rule = match text.split_once('(') {
            None if text == "delayed" => Self::Delayed,
            Some(("distance", rest)) => Self::Distance {
                threshold: metres("distance threshold", rest)?,
            },
            Some(("goal", rest)) => Self::Goal {
                radius: metres("goal radius", rest)?,
            },
            _ => return Err(RuleError::UnknownForm(text.to_string())),
        };
        rule.validate()?;
        Ok(rule)
    }
}

/// Wraps an env and replaces its reward by LOGO's sparse one.
pub struct SparseReward<E: Env> {
    inner: E,
    rule: SparseRule,
    spec: EnvSpec,
    x_init: f64,
    episode_dense_return: f64,
}

impl<E: Env> SparseReward<E> {
    /// `id` names the sparse task (the registry's: `SparseHopper-v4` for LOGO's rule).
    /// The goal kind pays only on an env whose steps report a goal distance (the
    /// registry builds it over Reacher and Pusher alone); on any other it pays 0.
    pub fn new(inner: E, rule: SparseRule, id: String) -> Self {
        let mut spec = inner.spec().clone();
        spec.id = id;
        Self {
            inner,
            rule,
            spec,
            x_init: 0.0,
            episode_dense_return: 0.0,
        }
    }

    pub fn rule(&self) -> SparseRule {
        self.rule
    }

    fn start_episode(&mut self) {
        self.x_init = self.inner.x_position();
        self.episode_dense_return = 0.0;
    }
}

impl<E: Env> Env for SparseReward<E> {
    fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    fn reset(&mut self, seed: Option<u64>, obs: &mut [f64]) {
        self.inner.reset(seed, obs);
        self.start_episode();
    }

    fn step(&mut self, action: &[f64], obs: &mut [f64]) -> Result<Step, EnvError> {
        let mut step = self.inner.step(action, obs)?;
        // Where the rule has a goal (a distance, a radius), being past it is success.
        let reached = match self.rule {
            SparseRule::Distance { threshold } => {
                Some(step.info.x_position - self.x_init > threshold)
            }
            SparseRule::Delayed => None,
            // The registry builds this rule only over a task with a goal distance.
            SparseRule::Goal { radius } => {
                Some(step.info.goal_distance.is_some_and(|d| d < radius))
            }
        };
        step.reward = match (self.rule, reached) {
            (SparseRule::Delayed, _) => {
                self.episode_dense_return += step.info.dense_reward;
                if step.done() {
                    self.episode_dense_return
                } else {
                    0.0
                }
            }
            (_, Some(true)) => 1.0,
            (_, _) => 0.0,
        };
        step.info.success = reached.or(step.info.success);
        Ok(step)
    }

    fn reset_point(&self) -> Result<ResetPoint, EnvError> {
        self.inner.reset_point()
    }

    fn restore_reset_point(&mut self, point: &ResetPoint, obs: &mut [f64]) -> Result<(), EnvError> {
        self.inner.restore_reset_point(point, obs)?;
        self.start_episode();
        Ok(())
    }

    fn set_state(&mut self, qpos: &[f64], qvel: &[f64], obs: &mut [f64]) -> Result<(), EnvError> {
        self.inner.set_state(qpos, qvel, obs)?;
        // A state set at the start of an episode is that episode's start.
        self.start_episode();
        Ok(())
    }

    fn state(&self) -> (&[f64], &[f64]) {
        self.inner.state()
    }
}

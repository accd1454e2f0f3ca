//! The environment interface shared by every env, wrapper and the vectorised env.

use std::fmt;
use std::path::PathBuf;

/// What an environment is: its id, dimensions and episode limit.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvSpec {
    /// Registry id, e.g. `Hopper-v4` or `SparseHopper-v4`.
    pub id: String,
    pub obs_dim: usize,
    pub act_dim: usize,
    /// Actuator control range; MuJoCo clamps actions to it, the env does not.
    pub action_low: Vec<f64>,
    pub action_high: Vec<f64>,
    /// Steps after which an episode is truncated (Gymnasium's `TimeLimit`).
    pub max_episode_steps: usize,
    /// MuJoCo steps per env step.
    pub frame_skip: usize,
    /// Seconds of simulated time per env step (timestep x frame skip).
    pub dt: f64,
}

/// Clamps each action component to its range (`clip_actions`, `logo eval --clip-actions`):
/// what Stable-Baselines3 and CleanRL send their envs.
pub fn clip_to_range(action: &mut [f64], low: &[f64], high: &[f64]) {
    for ((a, &lo), &hi) in action.iter_mut().zip(low).zip(high) {
        *a = a.clamp(lo, hi);
    }
}

/// Per-step facts beside the reward, so evaluation can report both reward streams.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepInfo {
    /// The dense (Gymnasium) reward of this step, whatever reward the env pays.
    pub dense_reward: f64,
    /// `qpos[0]` after the step: the forward position for the locomotion tasks.
    pub x_position: f64,
    /// Distance to the target in the plane, for the tasks with one (Reacher: fingertip to
    /// target; Pusher: object to goal): what the goal kind pays on.
    pub goal_distance: Option<f64>,
    /// Whether the task's goal is reached after this step, where the task defines one:
    /// a sparse kind's rule (past the distance threshold, within the goal radius), or a
    /// Python env's `info["is_success"]` / `info["success"]`. None: the task says nothing.
    pub success: Option<bool>,
}

/// The result of one step. The observation goes into the caller's buffer.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Step {
    pub reward: f64,
    /// The MDP ended (fell over, pendulum dropped): do not bootstrap.
    pub terminated: bool,
    /// The time limit cut the episode: bootstrap from the final observation.
    pub truncated: bool,
    pub info: StepInfo,
}

impl Step {
    pub fn done(&self) -> bool {
        self.terminated || self.truncated
    }
}

#[derive(Debug, thiserror::Error)]
pub enum EnvError {
    #[error("action has {got} values, {env} expects {expected}")]
    ActionLength {
        env: String,
        expected: usize,
        got: usize,
    },
    #[error("action[{index}] = {value} is not finite ({env})")]
    NonFiniteAction {
        env: String,
        index: usize,
        value: f64,
    },
    #[error("{what} has {got} values, {env} expects {expected}")]
    StateLength {
        env: String,
        what: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("{env}: step called {why}; call reset first")]
    NeedsReset { env: String, why: &'static str },
    #[error("unknown environment id {0:?}; known ids: {1}")]
    UnknownId(String, String),
    #[error("MJCF model {} not found: run ./scripts/setup.sh", .0.display())]
    ModelMissing(PathBuf),
    #[error("MuJoCo could not load {}: {reason}", path.display())]
    ModelLoad { path: PathBuf, reason: String },
    #[error("{0}: not at the start of an episode (a reset point is taken right after a reset)")]
    NotAtReset(String),
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// A saved random stream's position that is not a number.
    #[error("rng word_pos {0:?} is not an integer")]
    RngPosition(String),
    /// An external env's own code failed (a Python env raised).
    #[error("{env}: {message}")]
    External { env: String, message: String },
}

/// A reinforcement-learning environment with `f64` observations and actions.
///
/// Observations are written into caller-owned buffers of length `spec().obs_dim`, so the
/// vectorised env and the rollout code step without allocating.
///
/// What the trainer needs of an env is `spec`, `reset` and `step`: that is all an env
/// without a joint state of logo-rl's (a Python env) implements. The rest has defaults
/// for such an env, and the MuJoCo envs ([`crate::MujocoEnv`], [`crate::SparseReward`])
/// override every one: replaying recorded states and exact resumes need them.
pub trait Env: Send {
    fn spec(&self) -> &EnvSpec;

    /// Starts an episode. `Some(seed)` reseeds the reset-noise generator (as Gymnasium's
    /// `reset(seed=...)`); `None` continues its stream.
    fn reset(&mut self, seed: Option<u64>, obs: &mut [f64]);

    /// Applies `action` (length `act_dim`, finite) and advances one env step.
    fn step(&mut self, action: &[f64], obs: &mut [f64]) -> Result<Step, EnvError>;

    /// Overwrites the joint state of the current episode (Gymnasium's `set_state`), then
    /// writes the resulting observation. Used to replay recorded initial states; an error
    /// for an env without a joint state.
    fn set_state(&mut self, qpos: &[f64], qvel: &[f64], obs: &mut [f64]) -> Result<(), EnvError> {
        let _ = (qpos, qvel, obs);
        Err(EnvError::InvalidOption(format!(
            "{} has no joint state to set (recorded initial states need a MuJoCo env of logo-rl's)",
            self.spec().id
        )))
    }

    /// The joint state now: `(qpos, qvel)` (Gymnasium's `state_vector`, split); empty for
    /// an env without one.
    fn state(&self) -> (&[f64], &[f64]) {
        (&[], &[])
    }

    /// `qpos[0]` now: the forward position of the locomotion tasks (0 without a state).
    fn x_position(&self) -> f64 {
        self.state().0.first().copied().unwrap_or(0.0)
    }

    /// Where this env stands right after a reset, with its reset-noise generator's position:
    /// what a resumed training run needs to continue bit-identically. An error in the
    /// middle of an episode (mid-episode MuJoCo state also holds solver warm-starts). An
    /// env whose state cannot be taken gives [`ResetPoint::unrestorable`].
    fn reset_point(&self) -> Result<ResetPoint, EnvError> {
        Ok(ResetPoint::unrestorable())
    }

    /// Puts the env at `point`, exactly as if a reset had just produced it, and writes the
    /// observation; an env whose state cannot be taken starts a new episode instead.
    fn restore_reset_point(&mut self, point: &ResetPoint, obs: &mut [f64]) -> Result<(), EnvError> {
        let _ = point;
        self.reset(None, obs);
        Ok(())
    }
}

/// See [`Env::reset_point`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ResetPoint {
    pub qpos: Vec<f64>,
    pub qvel: Vec<f64>,
    pub rng: RngState,
}

impl ResetPoint {
    /// The point of an env whose state cannot be taken (an external env): no joint state,
    /// a generator at its start. Restoring it resets that env afresh, so a resumed run
    /// continues its learner exactly and its env from a new episode.
    pub fn unrestorable() -> Self {
        use rand::SeedableRng;
        Self {
            qpos: Vec::new(),
            qvel: Vec::new(),
            rng: RngState::of(&rand_chacha::ChaCha8Rng::seed_from_u64(0)),
        }
    }
}

/// The exact position of a ChaCha8 stream.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RngState {
    pub seed: [u8; 32],
    pub stream: u64,
    /// Decimal: JSON numbers cannot hold a u128.
    pub word_pos: String,
}

impl RngState {
    pub fn of(rng: &rand_chacha::ChaCha8Rng) -> Self {
        Self {
            seed: rng.get_seed(),
            stream: rng.get_stream(),
            word_pos: rng.get_word_pos().to_string(),
        }
    }

    pub fn to_rng(&self) -> Result<rand_chacha::ChaCha8Rng, EnvError> {
        use rand::SeedableRng;
        let word_pos: u128 = self
            .word_pos
            .parse()
            .map_err(|_| EnvError::RngPosition(self.word_pos.clone()))?;
        let mut rng = rand_chacha::ChaCha8Rng::from_seed(self.seed);
        rng.set_stream(self.stream);
        rng.set_word_pos(word_pos);
        Ok(rng)
    }
}

impl Env for Box<dyn Env> {
    fn spec(&self) -> &EnvSpec {
        (**self).spec()
    }
    fn reset(&mut self, seed: Option<u64>, obs: &mut [f64]) {
        (**self).reset(seed, obs)
    }
    fn step(&mut self, action: &[f64], obs: &mut [f64]) -> Result<Step, EnvError> {
        (**self).step(action, obs)
    }
    fn set_state(&mut self, qpos: &[f64], qvel: &[f64], obs: &mut [f64]) -> Result<(), EnvError> {
        (**self).set_state(qpos, qvel, obs)
    }
    fn state(&self) -> (&[f64], &[f64]) {
        (**self).state()
    }
    fn x_position(&self) -> f64 {
        (**self).x_position()
    }
    fn reset_point(&self) -> Result<ResetPoint, EnvError> {
        (**self).reset_point()
    }
    fn restore_reset_point(&mut self, point: &ResetPoint, obs: &mut [f64]) -> Result<(), EnvError> {
        (**self).restore_reset_point(point, obs)
    }
}

/// Gymnasium version of a task's formulas. `V4` is what LOGO used (gym -v2 semantics).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Version {
    V4,
    V5,
}

impl fmt::Display for Version {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Version::V4 => "v4",
            Version::V5 => "v5",
        })
    }
}

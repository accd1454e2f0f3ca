//! The MuJoCo stepping loop shared by every task, as Gymnasium's `MujocoEnv` does it:
//! write ctrl, `mj_step` frame-skip times, `mj_rnePostConstraint`, then the task's
//! reward, termination and observation; a `TimeLimit` on top reports truncation.

use std::path::PathBuf;
use std::sync::{Arc, Mutex, Once};

use mujoco_rs::prelude::{MjData, MjLogMessage, MjModel, MjtLogLevel, set_log_handler};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::env::{Env, EnvError, EnvSpec, ResetPoint, RngState, Step, StepInfo};

/// Simulation state of one env: an `MjData` over a model shared by all copies.
pub type Data = MjData<Arc<MjModel>>;

/// Where the MJCF files live: `$LOGO_MODELS_DIR`, else the repository's `models/`.
/// The distribution wheel (`scripts/wheel.sh`, `--cfg logo_wheel`) has no repository to
/// fall back on, and keeps no path of the machine that built it: `logo_rl` always sets
/// the variable (to the gymnasium wheel's assets).
pub fn models_dir() -> PathBuf {
    match std::env::var_os("LOGO_MODELS_DIR") {
        Some(dir) => PathBuf::from(dir),
        #[cfg(not(logo_wheel))]
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../models"),
        #[cfg(logo_wheel)]
        None => PathBuf::from("models"),
    }
}

/// How `reset` perturbs the model's initial pose (Gymnasium's `reset_noise_scale`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ResetNoise {
    /// qpos and qvel each += U(-scale, scale) (Hopper, Walker2d).
    Uniform { scale: f64 },
    /// qpos += U(-scale, scale), qvel += scale * N(0, 1) (HalfCheetah, InvertedDoublePendulum, Ant).
    UniformPosNormalVel { scale: f64 },
    /// The task draws its own initial state ([`Task::reset_state`]: Reacher's target,
    /// Pusher's object).
    Own,
}

impl ResetNoise {
    /// Draws `init` + noise into `qpos`, `qvel` in Gymnasium's order: all of qpos's noise,
    /// then qvel's. [`ResetNoise::Own`] leaves the initial state as it is.
    pub fn draw(
        self,
        rng: &mut ChaCha8Rng,
        init: (&[f64], &[f64]),
        qpos: &mut [f64],
        qvel: &mut [f64],
    ) {
        let (init_qpos, init_qvel) = init;
        qpos.copy_from_slice(init_qpos);
        qvel.copy_from_slice(init_qvel);
        match self {
            ResetNoise::Uniform { scale } => {
                uniform_noise(rng, qpos, scale);
                uniform_noise(rng, qvel, scale);
            }
            ResetNoise::UniformPosNormalVel { scale } => {
                uniform_noise(rng, qpos, scale);
                for v in qvel.iter_mut() {
                    let n: f64 = rng.sample(StandardNormal);
                    *v += scale * n;
                }
            }
            ResetNoise::Own => {}
        }
    }
}

/// Whether every entry of qpos and qvel is finite (Gymnasium's `np.isfinite(state).all()`).
pub(crate) fn state_is_finite(data: &Data) -> bool {
    data.qpos().iter().chain(data.qvel()).all(|s| s.is_finite())
}

/// Adds U(-scale, scale) to each value, in order.
pub fn uniform_noise(rng: &mut ChaCha8Rng, values: &mut [f64], scale: f64) {
    for v in values {
        *v += rng.random_range(-scale..scale);
    }
}

/// What a task reads from the state before a step's simulation.
#[derive(Debug, Clone, Copy, Default)]
pub struct BeforeStep {
    /// The position the forward reward differentiates: `qpos[0]` unless the task says
    /// otherwise (Ant: the torso body's x, Humanoid: the mass centre's).
    pub x: f64,
    /// The reward of a task that pays for the state before the step (Reacher-v4 computes
    /// it before simulating); else 0.
    pub reward: f64,
}

/// What makes one environment different from another: implement this for a new MJCF model.
/// (A method added here is forwarded by `impl Task for Box<dyn Task>` below too, or the
/// registry's boxed tasks fall back to its default.)
pub trait Task: Send + Sync + 'static {
    /// Registry id, e.g. `Hopper-v4`.
    fn id(&self) -> String;
    /// MJCF file name inside [`models_dir`].
    fn model_file(&self) -> &'static str;
    /// MuJoCo steps per env step.
    fn frame_skip(&self) -> usize;
    fn obs_dim(&self) -> usize;
    fn reset_noise(&self) -> ResetNoise;
    /// The initial state of an episode, drawn into `qpos`, `qvel` from the model's
    /// (`init`): by [`Task::reset_noise`] unless the task draws its own.
    fn reset_state(
        &self,
        rng: &mut ChaCha8Rng,
        init: (&[f64], &[f64]),
        qpos: &mut [f64],
        qvel: &mut [f64],
    ) {
        self.reset_noise().draw(rng, init, qpos, qvel);
    }
    /// Gymnasium's registered time limit.
    fn max_episode_steps(&self) -> usize {
        1000
    }
    /// Writes the observation of the current state.
    fn observe(&self, data: &Data, obs: &mut [f64]);
    /// What the reward needs from the state before the step (Gymnasium reads it before
    /// `do_simulation`, from the data the last step or reset left).
    fn before_step(&self, data: &Data, _action: &[f64]) -> BeforeStep {
        BeforeStep {
            x: data.qpos()[0],
            reward: 0.0,
        }
    }
    /// Reward and termination of the step that just ran. `before` is what
    /// [`Task::before_step`] read, `dt` the env step's duration, `action` the action as
    /// given (not clamped).
    fn reward(&self, data: &Data, before: BeforeStep, dt: f64, action: &[f64]) -> (f64, bool);
    /// Distance to the task's target in the plane, for the tasks with one (the goal kind).
    fn goal_distance(&self, _data: &Data) -> Option<f64> {
        None
    }
}

/// A boxed task is a task: the registry picks one per id at run time.
impl Task for Box<dyn Task> {
    fn id(&self) -> String {
        (**self).id()
    }
    fn model_file(&self) -> &'static str {
        (**self).model_file()
    }
    fn frame_skip(&self) -> usize {
        (**self).frame_skip()
    }
    fn obs_dim(&self) -> usize {
        (**self).obs_dim()
    }
    fn reset_noise(&self) -> ResetNoise {
        (**self).reset_noise()
    }
    fn reset_state(
        &self,
        rng: &mut ChaCha8Rng,
        init: (&[f64], &[f64]),
        qpos: &mut [f64],
        qvel: &mut [f64],
    ) {
        (**self).reset_state(rng, init, qpos, qvel);
    }
    fn max_episode_steps(&self) -> usize {
        (**self).max_episode_steps()
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        (**self).observe(data, obs);
    }
    fn before_step(&self, data: &Data, action: &[f64]) -> BeforeStep {
        (**self).before_step(data, action)
    }
    fn reward(&self, data: &Data, before: BeforeStep, dt: f64, action: &[f64]) -> (f64, bool) {
        (**self).reward(data, before, dt, action)
    }
    fn goal_distance(&self, data: &Data) -> Option<f64> {
        (**self).goal_distance(data)
    }
}

/// A MuJoCo environment: one [`Task`] over one `MjData`.
pub struct MujocoEnv<T: Task> {
    task: T,
    spec: EnvSpec,
    data: Data,
    init_qpos: Vec<f64>,
    init_qvel: Vec<f64>,
    rng: ChaCha8Rng,
    elapsed_steps: usize,
    /// False before the first reset and after a terminal step.
    running: bool,
    scratch_qpos: Vec<f64>,
    scratch_qvel: Vec<f64>,
}

/// MuJoCo's default handler prints warnings and appends them to `MUJOCO_LOG.TXT` in the
/// working directory. Route warnings and errors to stderr instead, once per distinct
/// message; drop debug/info messages and the deprecation notice Gymnasium's `half_cheetah.xml` triggers (`settotalmass`), which
/// MuJoCo 3.17 still honours and which says nothing about the run.
fn route_mujoco_messages() {
    static ONCE: Once = Once::new();
    fn handler(message: &MjLogMessage) {
        static SEEN: Mutex<Vec<String>> = Mutex::new(Vec::new());
        let text = message.subject().to_string();
        if (message.level() as u32) < (MjtLogLevel::mjLOG_WARNING as u32)
            || text.contains("settotalmass")
        {
            return;
        }
        let mut seen = SEEN.lock().unwrap_or_else(|e| e.into_inner());
        if !seen.contains(&text) {
            eprintln!("MuJoCo: {text}");
            seen.push(text);
        }
    }
    // SAFETY: every MuJoCo model of this crate is made by `load_model`, which calls this
    // first; `Once` holds any other caller until the handler is in place, so no thread
    // uses MuJoCo while it is installed.
    ONCE.call_once(|| unsafe { set_log_handler(handler) });
}

/// Loads `file` from [`models_dir`] with a clear error when it is missing.
pub fn load_model(file: &str) -> Result<Arc<MjModel>, EnvError> {
    route_mujoco_messages();
    let path = models_dir().join(file);
    if !path.is_file() {
        return Err(EnvError::ModelMissing(path));
    }
    MjModel::from_xml(&path)
        .map(Arc::new)
        .map_err(|e| EnvError::ModelLoad {
            path,
            reason: e.to_string(),
        })
}

impl<T: Task> MujocoEnv<T> {
    /// Builds an env over an already loaded model (shared by the copies of a [`crate::VecEnv`]).
    pub fn with_model(task: T, model: Arc<MjModel>, max_episode_steps: usize) -> Self {
        let data = MjData::new(model.clone());
        let ffi = model.ffi();
        let frame_skip = task.frame_skip();
        let (action_low, action_high) = model
            .actuator_ctrlrange()
            .iter()
            .map(|r| (r[0], r[1]))
            .unzip();
        let spec = EnvSpec {
            id: task.id(),
            obs_dim: task.obs_dim(),
            act_dim: ffi.nu as usize,
            action_low,
            action_high,
            max_episode_steps,
            frame_skip,
            dt: model.opt().timestep * frame_skip as f64,
        };
        // Gymnasium reads the initial pose from a fresh MjData: qpos0 and zero velocities.
        let init_qpos = data.qpos().to_vec();
        let init_qvel = data.qvel().to_vec();
        Self {
            task,
            spec,
            data,
            scratch_qpos: init_qpos.clone(),
            scratch_qvel: init_qvel.clone(),
            init_qpos,
            init_qvel,
            rng: ChaCha8Rng::seed_from_u64(0),
            elapsed_steps: 0,
            running: false,
        }
    }

    /// Loads the task's MJCF file and builds one env.
    pub fn new(task: T, max_episode_steps: usize) -> Result<Self, EnvError> {
        let model = load_model(task.model_file())?;
        Ok(Self::with_model(task, model, max_episode_steps))
    }

    pub fn task(&self) -> &T {
        &self.task
    }

    pub fn data(&self) -> &Data {
        &self.data
    }

    /// Gymnasium's `set_state`: copies the scratch qpos/qvel in, then `mj_forward`.
    fn write_scratch_state(&mut self) {
        self.data.qpos_mut().copy_from_slice(&self.scratch_qpos);
        self.data.qvel_mut().copy_from_slice(&self.scratch_qvel);
        self.data.forward();
    }
}

impl<T: Task> Env for MujocoEnv<T> {
    fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    fn reset(&mut self, seed: Option<u64>, obs: &mut [f64]) {
        if let Some(seed) = seed {
            self.rng = ChaCha8Rng::seed_from_u64(seed);
        }
        self.data.reset();
        self.task.reset_state(
            &mut self.rng,
            (&self.init_qpos, &self.init_qvel),
            &mut self.scratch_qpos,
            &mut self.scratch_qvel,
        );
        self.write_scratch_state();
        self.elapsed_steps = 0;
        self.running = true;
        self.task.observe(&self.data, obs);
    }

    fn step(&mut self, action: &[f64], obs: &mut [f64]) -> Result<Step, EnvError> {
        if !self.running {
            let why = if self.elapsed_steps == 0 {
                "before reset"
            } else {
                "after the episode ended"
            };
            return Err(EnvError::NeedsReset {
                env: self.spec.id.clone(),
                why,
            });
        }
        if action.len() != self.spec.act_dim {
            return Err(EnvError::ActionLength {
                env: self.spec.id.clone(),
                expected: self.spec.act_dim,
                got: action.len(),
            });
        }
        if let Some((index, &value)) = action.iter().enumerate().find(|(_, a)| !a.is_finite()) {
            return Err(EnvError::NonFiniteAction {
                env: self.spec.id.clone(),
                index,
                value,
            });
        }

        let before = self.task.before_step(&self.data, action);
        self.data.ctrl_mut().copy_from_slice(action);
        for _ in 0..self.task.frame_skip() {
            self.data.step();
        }
        self.data.rne_post_constraint();

        let (reward, terminated) = self.task.reward(&self.data, before, self.spec.dt, action);
        self.task.observe(&self.data, obs);
        self.elapsed_steps += 1;
        let truncated = self.elapsed_steps >= self.spec.max_episode_steps;
        self.running = !(terminated || truncated);
        Ok(Step {
            reward,
            terminated,
            truncated,
            info: StepInfo {
                dense_reward: reward,
                x_position: self.data.qpos()[0],
                goal_distance: self.task.goal_distance(&self.data),
                success: None,
            },
        })
    }

    fn set_state(&mut self, qpos: &[f64], qvel: &[f64], obs: &mut [f64]) -> Result<(), EnvError> {
        for (what, got, expected) in [
            ("qpos", qpos.len(), self.init_qpos.len()),
            ("qvel", qvel.len(), self.init_qvel.len()),
        ] {
            if got != expected {
                return Err(EnvError::StateLength {
                    env: self.spec.id.clone(),
                    what,
                    expected,
                    got,
                });
            }
        }
        self.scratch_qpos.copy_from_slice(qpos);
        self.scratch_qvel.copy_from_slice(qvel);
        self.write_scratch_state();
        self.task.observe(&self.data, obs);
        Ok(())
    }

    fn state(&self) -> (&[f64], &[f64]) {
        (self.data.qpos(), self.data.qvel())
    }

    fn reset_point(&self) -> Result<ResetPoint, EnvError> {
        if !self.running || self.elapsed_steps != 0 {
            return Err(EnvError::NotAtReset(self.spec.id.clone()));
        }
        Ok(ResetPoint {
            qpos: self.data.qpos().to_vec(),
            qvel: self.data.qvel().to_vec(),
            rng: RngState::of(&self.rng),
        })
    }

    fn restore_reset_point(&mut self, point: &ResetPoint, obs: &mut [f64]) -> Result<(), EnvError> {
        let rng = point
            .rng
            .to_rng()
            .map_err(|e| EnvError::InvalidOption(format!("{}: {e}", self.spec.id)))?;
        // As reset() does: cleared data (no warm-start), then the state, then forward.
        self.data.reset();
        self.set_state(&point.qpos, &point.qvel, obs)?;
        self.rng = rng;
        self.elapsed_steps = 0;
        self.running = true;
        Ok(())
    }
}

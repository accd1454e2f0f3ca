//! `logo train`'s TOML config. Unknown keys, wrong types and fields of another kind are
//! errors naming the file and the key; every value is checked in [`TrainConfig::validate`]
//! (on a fresh run and on `--resume`); paths are relative to the config file's folder.

use crate::error::Invalid;
pub use crate::error::{ConfigError, ConfigErrorKind};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_inline_default::serde_inline_default;

use logo_envs::{EnvConfig, EnvError, EnvSpec};
use logo_nn::DiscriminatorInit;

use crate::bc::{InitConfig, InitKind};
use crate::critic::CriticConfig;
use crate::dapg::DemonstrationRowsConfig;
use crate::delta_schedule::{DELTA_FLOOR, DeltaSchedule};
use crate::episode::SuccessRule;
use crate::methods::{Guided, METHODS, Start};
use crate::policy_update::PolicyUpdateConfig;
use crate::presets::{self, AlgorithmPreset};
use crate::sampler::RolloutMode;
use crate::validate::{
    MAX_ENVS, MAX_EVAL_EPISODES, MAX_SAMPLES_PER_ITER, check_positive, check_widths,
};

/// A run's settings: `env`, `iterations` and `samples_per_iter` are required, every other
/// key has its default beside its field (`docs/config.md` lists them all).
#[serde_inline_default]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainConfig {
    /// The trained task: an env id (`env = "SparseInvertedDoublePendulum-v4"`), or a
    /// dense id with the rule that makes it sparse (`[env]`, `id`, `sparse = { kind =
    /// "distance", threshold = 2.0 }`; see [`EnvConfig`]).
    pub env: EnvConfig,
    /// Evaluation env, in either form; default: `env` itself, reporting the dense return
    /// beside its own. [`TrainConfig::eval_env_id`] names the dense task for videos and
    /// `logo eval`.
    pub eval_env: Option<EnvConfig>,
    #[serde(default)]
    pub seed: u64,
    pub iterations: usize,
    /// Whole episodes until at least this many steps per iteration.
    pub samples_per_iter: usize,
    /// How batches are cut: "episodes" (whole episodes, the reference) or "steps" (a
    /// fixed number of steps per env copy; such runs cannot be resumed).
    #[serde(default)]
    pub rollout: RolloutMode,
    #[serde_inline_default(2)]
    pub num_envs: usize,
    #[serde_inline_default(2)]
    pub threads: usize,
    #[serde_inline_default(0.99)]
    pub gamma: f64,
    #[serde_inline_default(0.95)]
    pub gae_lambda: f64,
    /// KL bound δ of the improvement step.
    #[serde_inline_default(0.01)]
    pub max_kl: f64,
    #[serde_inline_default(vec![128, 128])]
    pub policy_hidden: Vec<usize>,
    /// Standardise observations by running statistics of every observation collected
    /// (`logo_nn::observation_norm`), kept with the policy in checkpoints and applied
    /// wherever it acts (`logo eval`, `logo_rl.load(...).predict`) and to the
    /// demonstrations the discriminator sees. Off by default, as in the reference.
    #[serde(default)]
    pub normalise_observations: bool,
    #[serde(default)]
    pub log_std_init: f64,
    /// The env reward's critic (`[critic]`).
    #[serde(default)]
    pub critic: CriticConfig,
    /// The reference's GAE across time-limit boundaries (see `gae.rs`).
    #[serde(default)]
    pub cross_episode_bootstrap: bool,
    /// Skip the improvement step on a batch without any env reward. Its advantages are
    /// then GAE over the env critic's residual values, scaled to unit variance by the
    /// per-batch normalisation: critic noise taken at the full KL bound. Off by default,
    /// as in the reference (docs/results.md, issue 13's CDQ follow-up).
    #[serde(default)]
    pub skip_improvement_without_reward: bool,
    #[serde_inline_default(1)]
    pub eval_every: usize,
    /// Each iteration's evaluation plays whole episodes until at least `eval_steps`
    /// steps and at least `eval_episodes` episodes (default 1: the steps alone, as the
    /// reference's 2,048) have been played; the best policy is chosen on it.
    #[serde_inline_default(2048)]
    pub eval_steps: usize,
    #[serde_inline_default(1)]
    pub eval_episodes: usize,
    /// When an evaluation episode counts as reaching the goal (see [`SuccessRule`]).
    #[serde(default)]
    pub success: SuccessRule,
    /// Where each iteration's evaluation episodes start: `"fixed"` (the default: the
    /// same initial states at every iteration, so that iterations compare on equal
    /// footing) or `"fresh"` (new ones each iteration, as the LOGO reference code
    /// evaluates, drawn from a stream of their own: training is the same either way).
    #[serde(default)]
    pub eval_initial_states: EvalInitialStates,
    /// Clip each sampled action, and each evaluation's mean action, to the env's action
    /// space before the env sees it (as Stable-Baselines3 and CleanRL do); the batch
    /// keeps the sampled action. MuJoCo
    /// clamps controls to their range anyway, so on a sparse task whose reward ignores
    /// the action this changes nothing in training (tests/golden.rs); on a dense task it
    /// changes what the control cost charges. Off by default, as in the reference code.
    #[serde(default)]
    pub clip_actions: bool,
    #[serde_inline_default(10)]
    pub checkpoint_every: usize,
    /// Start from this policy: a LOGO reference `.pt` (the reference's `--init-BC`) or a
    /// logo-rl checkpoint.
    pub init_policy: Option<PathBuf>,
    /// Where the policy starts (`[init]`): the seed's initialisation, or behaviour
    /// cloning on demonstrations (`kind = "bc"`: BC-TRPO, DAPG).
    #[serde(default, skip_serializing_if = "InitConfig::is_random")]
    pub init: InitConfig,
    /// The networks' float type of a new run where no `--dtype` flag chooses one:
    /// `"f64"` (the default on the CPU: the reference's precision) or `"f32"` (the fast
    /// preset's, configs/logo-fast/); a flag given over it is written here in the run's
    /// stored config. A resume goes by the checkpoint's engine history instead
    /// (`logo train --resume`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dtype: Option<Dtype>,
    /// The improvement step's kind and fields (`[improvement]`, default `kind = "trpo"`).
    #[serde(default)]
    pub improvement: PolicyUpdateConfig,
    /// LOGO's guidance; absent: the improvement step alone (TRPO, PPO, ...).
    pub guidance: Option<GuidanceConfig>,
    /// The improvement step's reward (`[reward]`): the env's, or mixed with the
    /// discriminator's −log D (GAIL, POfD).
    #[serde(default, skip_serializing_if = "RewardConfig::is_env_alone")]
    pub reward: RewardConfig,
    /// DAPG's demonstration rows in the improvement step (`[demonstration_rows]`,
    /// `dapg.rs`); absent: the step sees the policy's batch alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub demonstration_rows: Option<DemonstrationRowsConfig>,
    /// `[algorithm] name`: the preset this config was laid over (`presets.rs`); its
    /// keys are already in the tables above. Not written back: a run's stored config
    /// holds the expanded tables alone, which read back to the same config (laying the
    /// preset under them again would bring back keys the config had set to defaults).
    #[serde(rename = "algorithm", default, skip_serializing)]
    pub preset: Option<AlgorithmPreset>,
    /// The method this config is (`methods.rs`), as a run records it (its config.toml,
    /// its checkpoints' algorithm): `[algorithm] name`'s, else the config's own `method`,
    /// else the method whose makeup the config has ([`TrainConfig::identify`]). Absent only
    /// in runs older than it, which are identified by their keys.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<String>,
}

/// `[reward]`: what the improvement step ascends, per step
/// `env`·r + `discriminator`·(−log D(s, a)), with D `[guidance]`'s discriminator as the
/// last iteration left it. The default is the env reward alone; GAIL is `env = 0,
/// discriminator = 1`, POfD `env = 1, discriminator = λ₁` (both with `[guidance] step =
/// false`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RewardConfig {
    pub env: f64,
    pub discriminator: f64,
}

impl Default for RewardConfig {
    fn default() -> Self {
        Self {
            env: 1.0,
            discriminator: 0.0,
        }
    }
}

impl RewardConfig {
    /// The env reward alone, as every run before `[reward]` (left out of stored configs).
    pub fn is_env_alone(&self) -> bool {
        *self == Self::default()
    }

    /// The per-step reward of `env` and `discriminator` rewards.
    pub fn mix(&self, env: &[f64], discriminator: &[f64]) -> Vec<f64> {
        env.iter()
            .zip(discriminator)
            .map(|(r, c)| self.env * r + self.discriminator * c)
            .collect()
    }

    fn validate(&self) -> Result<(), Invalid> {
        for (key, v) in [
            ("reward.env", self.env),
            ("reward.discriminator", self.discriminator),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{key} must be a number ≥ 0, got {v}").into());
            }
        }
        if self.env == 0.0 && self.discriminator == 0.0 {
            return Err("reward: env and discriminator are both 0 (nothing to learn from)".into());
        }
        Ok(())
    }
}

/// What both refusals of `decay_on = "success"` without a success add for a task that has
/// no goal at all: on the suite's delayed Hopper, decaying on the return let the guidance
/// go long before the policy reached the demonstrations (docs/findings/suite.md).
pub(crate) const NO_GOAL_HINT: &str = "for a task with no goal, consider holding δ_k (the \
     guidance step's KL radius) at δ_0: guidance.decay_on = \"return\" with guidance.alpha = 1.0 \
     (docs/findings/suite.md#the-delayed-hopper-why-decaying-on-the-return-let-go)";

/// `[guidance] decay_on`: what δ_k's schedule reads.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DecaySignal {
    /// The batch's mean return (LOGO's).
    #[default]
    Return,
    /// The share of the batch's (sampled) episodes at the goal.
    Success,
    /// The share of the evaluation's episodes (the mean action, the policy a run reports)
    /// at the goal: δ_{k+1} is set from π_{k+1}'s evaluation, at the end of iteration k.
    Evaluation,
}

impl DecaySignal {
    /// Whether it reads episodes' success (and so needs a success rule).
    pub fn reads_success(self) -> bool {
        self != Self::Return
    }

    /// Its name in a config.
    pub fn name(self) -> &'static str {
        match self {
            Self::Return => "return",
            Self::Success => "success",
            Self::Evaluation => "evaluation",
        }
    }
}

/// The networks' float type: a config's `dtype` and the `--dtype` flag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Dtype {
    /// float64 (the reference implementation's precision)
    F64,
    F32,
}

/// `[guidance]`: with the guidance step, `delta0`, `alpha` and `warmup` are required
/// (`validate`); every other key has its default beside its field.
#[serde_inline_default]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GuidanceConfig {
    /// Demonstrations for the discriminator: a Minari dataset folder, or a LOGO `.npy`
    /// array of `[obs ‖ action]` rows.
    pub demos: Option<PathBuf>,
    /// A known behaviour policy (`.pt`): C = log(π_k / π_b) replaces the discriminator.
    pub behaviour_policy: Option<PathBuf>,
    /// LOGO's second policy step on r_C with KL ≈ δ_k (true, the default); false: no
    /// guidance step, the discriminator's reward reaches the policy through `[reward]`
    /// alone (GAIL, POfD), and `delta0`, `alpha`, `warmup`, `update` and `critic` are not
    /// set.
    #[serde_inline_default(true)]
    #[serde(skip_serializing_if = "is_true")]
    pub step: bool,
    /// δ_0, α and K_δ (iterations before δ_k may shrink): required with the step.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delta0: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warmup: Option<usize>,
    /// What δ_k's decay reads: the batch's mean return (`"return"`, LOGO's: on its
    /// sparse tasks the return rises only as the agent earns), the share of the batch's
    /// episodes that succeed by `success` (`"success"`: on a task with an action cost the
    /// return also rises as the actions shrink, with the goal out of reach), or the share
    /// of the evaluation's (`"evaluation"`: the mean action, which on sparse Ant lost the
    /// goal while the sampled episodes still reached it).
    #[serde(default)]
    pub decay_on: DecaySignal,
    /// With `decay_on = "success"` or `"evaluation"`: δ_k shrinks only where at least
    /// this share of the episodes read reached the goal (in (0, 1]), instead of where it
    /// beats the ten before; it waits for the agent. A task that reports no success never
    /// reaches it, so δ_k holds there. `"demonstrations"` in a file: the share of the
    /// demonstrations' episodes at the goal as their recording wrote it, read in as that
    /// number. Default: unset (LOGO's rule).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decay_from: Option<f64>,
    /// With `decay_from`: where the share falls short of it, δ_k grows back by 1/α, up to
    /// δ_0, so that the guidance returns when the agent loses the goal (true); false, the
    /// default: δ_k only ever shrinks.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub grow_back: bool,
    /// Observation dims the discriminator sees (censored setting); default: all.
    pub observe: Option<usize>,
    #[serde_inline_default(3e-4)]
    pub discriminator_lr: f64,
    /// Full-batch Adam steps of the discriminator per iteration (the reference's 1).
    #[serde_inline_default(1)]
    pub discriminator_steps: usize,
    #[serde_inline_default(vec![128, 128])]
    pub discriminator_hidden: Vec<usize>,
    /// The discriminator's output layer at the start: "reference" (×0.1, bias 0: the
    /// LOGO code's, the default) or "uniform" (PyTorch's default init).
    #[serde(default)]
    pub discriminator_init: DiscriminatorInit,
    /// The guidance step's kind (`[guidance.update]`); default: the improvement step's.
    pub update: Option<PolicyUpdateConfig>,
    /// The guidance reward's critic (`[guidance.critic]`); default: `[critic]`'s.
    pub critic: Option<CriticConfig>,
}

/// `eval_initial_states`: where evaluation episodes start.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EvalInitialStates {
    /// Reset seeds [`crate::episode::evaluation_seed`], the same at every iteration.
    #[default]
    Fixed,
    /// Reset seeds drawn at each iteration from [`crate::streams::evaluation`].
    Fresh,
}

fn is_true(b: &bool) -> bool {
    *b
}

impl ConfigError {
    fn new(path: &Path, kind: ConfigErrorKind, message: String) -> Self {
        Self {
            path: path.to_path_buf(),
            kind,
            message,
        }
    }

    /// A file that could not be read.
    fn reading(path: &Path, e: &std::io::Error) -> Self {
        let kind = match e.kind() {
            std::io::ErrorKind::NotFound => ConfigErrorKind::NotFound,
            _ => ConfigErrorKind::Unreadable,
        };
        Self::new(path, kind, e.to_string())
    }

    /// TOML's or serde's error on one line, of the kind its words say.
    fn toml(path: &Path, e: &toml::de::Error) -> Self {
        let message = e.to_string().trim_end().replace('\n', " ");
        // serde's own words, not the quoted line of the file (which could hold anything).
        let kind = match e.message().starts_with("invalid type") {
            true => ConfigErrorKind::Type,
            false => ConfigErrorKind::Value,
        };
        Self::new(path, kind, message)
    }

    /// What the checks refuse: a file a key names that is not there, or a value.
    fn refused(path: &Path, refused: Invalid) -> Self {
        let kind = match refused {
            Invalid::Missing(_) => ConfigErrorKind::NotFound,
            Invalid::Value(_) => ConfigErrorKind::Value,
        };
        Self::new(path, kind, refused.message().to_string())
    }
}

/// Lays `top` over `under`: tables merge key by key, any other value replaces.
fn lay_over(under: &mut toml::Table, top: toml::Table) {
    for (key, value) in top {
        match (under.get_mut(&key), value) {
            (Some(toml::Value::Table(below)), toml::Value::Table(above)) => lay_over(below, above),
            (_, value) => {
                under.insert(key, value);
            }
        }
    }
}

/// `[guidance] decay_from = "demonstrations"`: the level is the share of the
/// demonstrations' episodes that reached the goal, as their recording wrote it; it is put
/// in as that number, so the run's saved config names the level it ran with. Whether the
/// table had it (and so changed).
fn demonstrations_level(table: &mut toml::Table, base: &Path) -> Result<bool, String> {
    let Some(g) = table
        .get_mut("guidance")
        .and_then(toml::Value::as_table_mut)
    else {
        return Ok(false);
    };
    match g.get("decay_from") {
        Some(toml::Value::String(word)) if word == DEMONSTRATIONS_LEVEL => {}
        Some(toml::Value::String(word)) => {
            return Err(format!(
                "guidance.decay_from = {word:?}: expected a share of episodes in (0, 1], or \
                 \"{DEMONSTRATIONS_LEVEL}\" (the demonstrations' own success rate)"
            ));
        }
        _ => return Ok(false),
    }
    let said = format!("guidance.decay_from = \"{DEMONSTRATIONS_LEVEL}\"");
    let demos = g
        .get("demos")
        .and_then(toml::Value::as_str)
        .ok_or_else(|| {
            format!(
                "{said} needs guidance.demos: the dataset whose recorded success rate is the level"
            )
        })?;
    let rate = logo_data::minari::recorded_success_rate(&base.join(demos))
        .map_err(|e| format!("{said}: {e}; set decay_from to a share instead"))?;
    if !(rate > 0.0 && rate <= 1.0) {
        return Err(format!(
            "{said}: the demonstrations ({demos}) reached the goal in a share {rate} of their \
             episodes, and a level must be in (0, 1]; set decay_from to a share instead"
        ));
    }
    g.insert("decay_from".into(), toml::Value::Float(rate));
    Ok(true)
}

/// The word `decay_from` takes for the demonstrations' own success rate.
pub const DEMONSTRATIONS_LEVEL: &str = "demonstrations";

impl TrainConfig {
    /// Reads and checks a config; relative paths inside become relative to its folder.
    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        Self::load_with(path, toml::Table::new())
    }

    /// [`Self::load`] with `overrides` laid over the file: a value replaces the file's,
    /// a table is laid over the file's table key by key (`guidance = { delta0 = 0.1 }`
    /// changes δ_0 alone).
    pub fn load_with(path: &Path, overrides: toml::Table) -> Result<Self, ConfigError> {
        Self::load_edited(path, overrides, &[])
    }

    /// [`Self::load_with`], with the top-level keys `removed` taken out of the file first
    /// (`guidance`: the improvement step alone).
    pub fn load_edited(
        path: &Path,
        overrides: toml::Table,
        removed: &[&str],
    ) -> Result<Self, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError::reading(path, &e))?;
        let base = path.parent().unwrap_or(Path::new("."));
        if overrides.is_empty() && removed.is_empty() {
            return Self::parse(&text, path, base);
        }
        let mut table: toml::Table =
            toml::from_str(&text).map_err(|e| ConfigError::toml(path, &e))?;
        for key in removed {
            table.remove(*key);
        }
        lay_over(&mut table, overrides);
        Self::from_table(table, path, base)
    }

    /// A config file's keys as written, before any check of their meaning: the errors of
    /// a file that is not there or not TOML, as [`Self::load`] gives them.
    pub fn read_table(path: &Path) -> Result<toml::Table, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError::reading(path, &e))?;
        toml::from_str(&text).map_err(|e| ConfigError::toml(path, &e))
    }

    /// A config given as a table (the Python package's dict): `origin` names it in errors,
    /// relative paths inside are taken from `base`.
    pub fn from_table(table: toml::Table, origin: &Path, base: &Path) -> Result<Self, ConfigError> {
        // Through the text, so that errors read as they do for a file.
        let text = toml::to_string(&table)
            .map_err(|e| ConfigError::new(origin, ConfigErrorKind::Type, e.to_string()))?;
        Self::parse(&text, origin, base)
    }

    fn parse(text: &str, path: &Path, base: &Path) -> Result<Self, ConfigError> {
        let toml_error = |e: toml::de::Error| ConfigError::toml(path, &e);
        let refused = |e: String| ConfigError::refused(path, e.into());
        let mut table: toml::Table = toml::from_str(text).map_err(toml_error)?;
        let mut config: TrainConfig = match table.contains_key("algorithm") {
            // `[algorithm] name`: the preset's keys under the config's own.
            true => {
                let mut expanded =
                    presets::expand(table, lay_over).map_err(|e| ConfigError::refused(path, e))?;
                demonstrations_level(&mut expanded, base).map_err(refused)?;
                TrainConfig::deserialize(expanded).map_err(toml_error)?
            }
            false if demonstrations_level(&mut table, base).map_err(refused)? => {
                TrainConfig::deserialize(table).map_err(toml_error)?
            }
            // Read from the text, so that an error points at its line.
            false => toml::from_str(text).map_err(toml_error)?,
        };
        // Absolute (and without `..` where the file exists), so that the copy saved with a
        // run (config.toml, the checkpoint's metadata) still points at the same files when
        // the run is resumed.
        let resolve = |p: &mut PathBuf| {
            let joined = base.join(&*p);
            *p = std::fs::canonicalize(&joined)
                .or_else(|_| std::path::absolute(&joined))
                .unwrap_or(joined);
        };
        if let Some(p) = config.init_policy.as_mut() {
            resolve(p);
        }
        config.init.demos.as_mut().map(resolve);
        if let Some(rows) = config.demonstration_rows.as_mut() {
            rows.demos.as_mut().map(resolve);
        }
        if let Some(g) = config.guidance.as_mut() {
            g.demos.as_mut().map(resolve);
            g.behaviour_policy.as_mut().map(resolve);
        }
        config.method = Some(
            config
                .named_method()
                .map_err(|e| ConfigError::refused(path, e))?,
        );
        config
            .validate()
            .map_err(|e| ConfigError::refused(path, e))?;
        Ok(config)
    }

    /// The method's name a run of this config records: `[algorithm] name`'s, else the
    /// config's `method` (one of the table's), else the one its keys make.
    fn named_method(&self) -> Result<String, Invalid> {
        match (&self.preset, &self.method) {
            (Some(preset), Some(method)) if preset.name != *method => Err(format!(
                "method = {method:?} but algorithm.name = {:?}: give one of them",
                preset.name
            )
            .into()),
            (Some(preset), _) => Ok(preset.name.clone()),
            (None, Some(method)) => match crate::methods::method(method) {
                Some(m) if m.command.is_none() => Ok(method.clone()),
                _ => Err(format!(
                    "method = {method:?}: expected one of {}",
                    presets::names().join(", ")
                )
                .into()),
            },
            (None, None) => Ok(self.identify().to_string()),
        }
    }

    /// The file paths the config names, by key.
    fn paths_mut(&mut self) -> Vec<(&'static str, &mut PathBuf)> {
        let mut paths = Vec::new();
        if let Some(p) = self.init_policy.as_mut() {
            paths.push(("init_policy", p));
        }
        if let Some(p) = self.init.demos.as_mut() {
            paths.push(("init.demos", p));
        }
        if let Some(p) = self
            .demonstration_rows
            .as_mut()
            .and_then(|r| r.demos.as_mut())
        {
            paths.push(("demonstration_rows.demos", p));
        }
        if let Some(g) = self.guidance.as_mut() {
            if let Some(p) = g.demos.as_mut() {
                paths.push(("guidance.demos", p));
            }
            if let Some(p) = g.behaviour_policy.as_mut() {
                paths.push(("guidance.behaviour_policy", p));
            }
        }
        paths
    }

    /// A config stored in a checkpoint names its files by absolute path, which a copy
    /// of the project elsewhere (another clone, a cluster) does not have. Each such path
    /// that no longer exists is replaced by the longest tail of it, of at least two
    /// components, that exists under `root` (`/old/clone/data/logo/hopper` →
    /// `root/data/logo/hopper`); one that still exists, or has no such tail, is left as
    /// is (validation then names it). Returns a line per path replaced.
    pub fn relocate_missing_paths(&mut self, root: &Path) -> Vec<String> {
        let mut notes = Vec::new();
        for (key, path) in self.paths_mut() {
            if path.exists() {
                continue;
            }
            let parts: Vec<_> = path
                .components()
                .filter(|c| matches!(c, std::path::Component::Normal(_)))
                .collect();
            let found = (0..parts.len().saturating_sub(1))
                .map(|start| root.join(parts[start..].iter().collect::<PathBuf>()))
                .find(|candidate| candidate.exists());
            if let Some(found) = found {
                let found = std::fs::canonicalize(&found).unwrap_or(found);
                notes.push(format!(
                    "{key}: {} is not here; using {}",
                    path.display(),
                    found.display()
                ));
                *path = found;
            }
        }
        notes
    }

    /// Every value a file can get wrong; the message names the key.
    pub fn validate(&self) -> Result<(), Invalid> {
        self.check_sizes()?;
        self.check_values()?;
        self.check_combinations()
    }

    /// Counts: at least 1, and at most what a machine can hold.
    fn check_sizes(&self) -> Result<(), Invalid> {
        let positive = [
            ("iterations", self.iterations),
            ("samples_per_iter", self.samples_per_iter),
            ("num_envs", self.num_envs),
            ("threads", self.threads),
            ("eval_every", self.eval_every),
            ("eval_steps", self.eval_steps),
            ("eval_episodes", self.eval_episodes),
            ("checkpoint_every", self.checkpoint_every),
        ];
        if let Some((key, _)) = positive.iter().find(|(_, v)| *v == 0) {
            return Err(format!("{key} must be at least 1").into());
        }
        // Upper bounds: a batch, an evaluation and the env copies are held in memory, so a
        // size past these cannot run on any machine this is for (and a typo like
        // 2000000000 would otherwise sample for ever).
        let at_most = [
            (
                "samples_per_iter",
                self.samples_per_iter,
                MAX_SAMPLES_PER_ITER,
            ),
            ("eval_steps", self.eval_steps, MAX_SAMPLES_PER_ITER),
            ("eval_episodes", self.eval_episodes, MAX_EVAL_EPISODES),
            ("num_envs", self.num_envs, MAX_ENVS),
            ("threads", self.threads, MAX_ENVS),
        ];
        if let Some((key, value, max)) = at_most.iter().find(|(_, v, max)| v > max) {
            return Err(format!("{key} must be at most {max}, got {value}").into());
        }
        Ok(())
    }

    /// Each value on its own: envs, ranges, the tables' own checks, files.
    fn check_values(&self) -> Result<(), Invalid> {
        let unusable = |e: logo_envs::EnvKeyError| Invalid::Value(e.to_string());
        self.env.validate("env").map_err(unusable)?;
        if let Some(env) = &self.eval_env {
            env.validate("eval_env").map_err(unusable)?;
        }
        check_positive("max_kl", self.max_kl, false)?;
        if !(-20.0..=5.0).contains(&self.log_std_init) {
            return Err(format!(
                "log_std_init must be in [-20, 5] (σ from 2e-9 to 148), got {}",
                self.log_std_init
            )
            .into());
        }
        for (key, v) in [("gamma", self.gamma), ("gae_lambda", self.gae_lambda)] {
            if !(0.0..=1.0).contains(&v) {
                return Err(format!("{key} must be in [0, 1], got {v}").into());
            }
        }
        check_widths("policy_hidden", &self.policy_hidden)?;
        self.critic.validate("critic")?;
        self.improvement.validate("improvement")?;
        if let Some(p) = &self.init_policy
            && !p.is_file()
        {
            return Err(Invalid::Missing(format!(
                "init_policy: file {} not found",
                p.display()
            )));
        }
        if let Some(g) = &self.guidance {
            g.validate()?;
        }
        self.init.validate()?;
        self.reward.validate()?;
        if let Some(rows) = &self.demonstration_rows {
            rows.validate()?;
        }
        let demos = [
            ("init.demos", self.init.demos.as_ref()),
            (
                "demonstration_rows.demos",
                self.demonstration_rows
                    .as_ref()
                    .and_then(|r| r.demos.as_ref()),
            ),
        ];
        for (key, path) in demos {
            if let Some(p) = path
                && !p.exists()
            {
                return Err(Invalid::Missing(format!(
                    "{key}: {} not found",
                    p.display()
                )));
            }
        }
        Ok(())
    }

    /// Settings that cannot go together.
    fn check_combinations(&self) -> Result<(), Invalid> {
        if let Some(g) = &self.guidance
            && g.decay_on.reads_success()
            && g.decay_from.is_none()
            && self.success == SuccessRule::None
        {
            return Err(format!(
                "guidance.decay_on = \"{}\" needs a success rule: success = \"task\" \
                 or \"terminated\", not \"none\"; {NO_GOAL_HINT}",
                g.decay_on.name()
            )
            .into());
        }
        let discriminator = self.guidance.as_ref().is_some_and(|g| g.demos.is_some());
        if self.reward.discriminator > 0.0 && !discriminator {
            return Err("reward.discriminator needs a discriminator: set [guidance] demos".into());
        }
        if self.init.kind == InitKind::Bc {
            if self.init_policy.is_some() {
                return Err(
                    "init: kind = \"bc\" and init_policy both say where the policy \
                            starts; set one or the other"
                        .into(),
                );
            }
            if self.bc_demos().is_none() {
                return Err(
                    "init: kind = \"bc\" needs demonstrations: set init.demos (or \
                            guidance.demos)"
                        .into(),
                );
            }
        }
        if self.demonstration_rows.is_some() {
            if self.improvement.kind() != "npg" {
                return Err(format!(
                    "demonstration_rows: DAPG's demonstration rows go with [improvement] \
                     kind = \"npg\", not \"{}\"",
                    self.improvement.kind()
                )
                .into());
            }
            if self.demonstration_rows_demos().is_none() {
                return Err(
                    "demonstration_rows needs demonstrations: set demonstration_rows.demos \
                     (or init.demos, or guidance.demos)"
                        .into(),
                );
            }
        }
        // A policy file (a reference `.pt`) was trained on raw observations.
        let behaviour = self
            .guidance
            .as_ref()
            .and_then(|g| g.behaviour_policy.as_ref());
        if self.normalise_observations {
            for (key, set) in [
                ("init_policy", self.init_policy.is_some()),
                ("guidance.behaviour_policy", behaviour.is_some()),
            ] {
                if set {
                    return Err(format!(
                        "normalise_observations: {key} is a policy of raw observations; \
                         set one or the other"
                    )
                    .into());
                }
            }
        }
        Ok(())
    }

    /// The demonstrations `[init] kind = "bc"` clones: `init.demos`, else
    /// `guidance.demos`.
    pub fn bc_demos(&self) -> Option<&Path> {
        let guidance = self.guidance.as_ref().and_then(|g| g.demos.as_deref());
        self.init.demos.as_deref().or(guidance)
    }

    /// The demonstrations of `[demonstration_rows]` (DAPG) and the key that names them:
    /// its own `demos`, else those `[init]` clones.
    pub fn demonstration_rows_demos(&self) -> Option<(&'static str, &Path)> {
        let rows = self.demonstration_rows.as_ref()?;
        if let Some(p) = rows.demos.as_deref() {
            return Some(("demonstration_rows.demos", p));
        }
        let key = match self.init.demos {
            Some(_) => "init.demos",
            None => "guidance.demos",
        };
        self.bc_demos().map(|p| (key, p))
    }

    /// The env every evaluation runs on: `eval_env`, else the trained task itself.
    pub fn evaluated_env(&self) -> &EnvConfig {
        self.eval_env.as_ref().unwrap_or(&self.env)
    }

    /// An `eval_env` must take the trained policy: the same observation and action dims as
    /// `env`. Loads both models, so it is not part of [`Self::validate`].
    pub fn check_eval_env_dims(&self) -> Result<(), Invalid> {
        let Some(eval_env) = &self.eval_env else {
            return Ok(());
        };
        // A model file that is not there is a missing file; the rest are values.
        let spec = |env: &EnvConfig, key: &str| {
            env.factory()
                .map(|f| f.spec().clone())
                .map_err(|e| match e {
                    EnvError::ModelMissing(_) => Invalid::Missing(format!("{key}: {e}")),
                    e => Invalid::Value(format!("{key}: {e}")),
                })
        };
        let (trained, evaluated) = (spec(&self.env, "env")?, spec(eval_env, "eval_env")?);
        dims_mismatch(&trained, &evaluated).map_or(Ok(()), Err)
    }

    /// The registry id of the task a person watches (videos, `logo eval`): `eval_env`,
    /// else the trained task's dense form.
    pub fn eval_env_id(&self) -> String {
        match &self.eval_env {
            Some(env) => env.env_id().unwrap_or_else(|_| env.id.clone()),
            None => self.env.dense_id().to_string(),
        }
    }

    /// The guidance step's kind: `[guidance.update]`, else the improvement step's.
    pub fn guidance_update(&self) -> Option<&PolicyUpdateConfig> {
        let g = self.guidance.as_ref().filter(|g| g.step)?;
        Some(g.update.as_ref().unwrap_or(&self.improvement))
    }

    /// The guidance critic: `[guidance.critic]`, else `[critic]`.
    pub fn guidance_critic(&self) -> Option<&CriticConfig> {
        let g = self.guidance.as_ref().filter(|g| g.step)?;
        Some(g.critic.as_ref().unwrap_or(&self.critic))
    }

    /// The config with the choices that default to another table's written out: the
    /// guidance step's `update` and `critic` (`[improvement]`'s and `[critic]`'s) and the
    /// float type (`dtype`, as the engine flags resolved it). It trains as `self` does.
    pub fn resolved(mut self, dtype: Dtype) -> Self {
        self.dtype = Some(dtype);
        if let Some(g) = self.guidance.as_mut().filter(|g| g.step) {
            g.update.get_or_insert_with(|| self.improvement.clone());
            g.critic.get_or_insert_with(|| self.critic.clone());
        }
        self
    }

    /// The config as a TOML file: every field, defaults included, but for the few written
    /// only where they differ from their default (`[reward]`, `[init]`, `guidance.step`,
    /// `grow_back`) and absent options; an `[algorithm]` preset's keys are written out,
    /// its name is not (see `preset`).
    pub fn to_toml(&self) -> Result<String, toml::ser::Error> {
        toml::to_string(self)
    }

    /// What the run trains, as `metrics.csv` and the logs name it: "TRPO", "LOGO",
    /// "LOGO (guidance ppo-clip, twin-min critics)", ...
    pub fn algorithm(&self) -> String {
        let improvement = self.improvement.kind();
        let step = self.guidance.as_ref().map(|g| g.step);
        let mut name = match (step, improvement) {
            // Behaviour cloning is part of DAPG: no "BC-" below.
            (None, _) if self.demonstration_rows.is_some() => "DAPG".to_string(),
            (None, "trpo") => "TRPO".to_string(),
            (None, kind) => kind.to_uppercase(),
            (Some(true), "trpo") => "LOGO".to_string(),
            (Some(true), kind) => format!("LOGO+{}", kind.to_uppercase()),
            // The discriminator's reward alone, or mixed into the env's.
            (Some(false), kind) => {
                let name = if self.reward.env == 0.0 {
                    "GAIL"
                } else {
                    "POfD"
                };
                match kind {
                    "trpo" => name.to_string(),
                    kind => format!("{name}+{}", kind.to_uppercase()),
                }
            }
        };
        let mut notes = Vec::new();
        match (self.init.kind, self.demonstration_rows.is_some()) {
            (InitKind::Bc, false) => name = format!("BC-{name}"),
            (InitKind::Random, true) => notes.push("no behaviour cloning".to_string()),
            _ => {}
        }
        if let Some(update) = self.guidance_update()
            && update.kind() != improvement
        {
            notes.push(format!("guidance {}", update.kind()));
        }
        let guidance_twin = self.guidance_critic().is_some_and(|c| c.num_nets() == 2);
        match (self.critic.num_nets() == 2, guidance_twin) {
            (true, true) => notes.push("twin-min critics".into()),
            (true, false) if self.guidance.is_some() => {
                notes.push("twin-min env critic".into());
            }
            (true, false) => notes.push("twin-min critic".into()),
            (false, true) => notes.push("twin-min guidance critic".into()),
            (false, false) => {}
        }
        if !notes.is_empty() {
            name += &format!(" ({})", notes.join(", "));
        }
        name
    }
}

impl GuidanceConfig {
    /// δ_k's schedule at the start: δ_0, α and K_δ; without the guidance step, one that
    /// stays at its floor (the step never runs).
    pub fn schedule(&self) -> DeltaSchedule {
        match (self.step, self.delta0, self.alpha, self.warmup) {
            (true, Some(delta0), Some(alpha), Some(warmup)) => {
                match (self.decay_from, self.grow_back) {
                    (Some(level), true) => DeltaSchedule::following(delta0, alpha, warmup, level),
                    (Some(level), false) => DeltaSchedule::waiting(delta0, alpha, warmup, level),
                    (None, _) => DeltaSchedule::new(delta0, alpha, warmup),
                }
            }
            _ => DeltaSchedule::new(DELTA_FLOOR, 1.0, 0),
        }
    }

    /// The step's keys are set exactly with the step.
    fn check_step(&self) -> Result<(), Invalid> {
        let step_keys = [
            ("delta0", self.delta0.is_some()),
            ("alpha", self.alpha.is_some()),
            ("warmup", self.warmup.is_some()),
            ("decay_from", self.decay_from.is_some()),
            ("grow_back", self.grow_back),
            ("update", self.update.is_some()),
            ("critic", self.critic.is_some()),
        ];
        if !self.step {
            if let Some((key, _)) = step_keys.iter().find(|(_, set)| *set) {
                return Err(format!(
                    "guidance.{key} belongs to the guidance step, which guidance.step = false \
                     turns off; remove it"
                )
                .into());
            }
            if self.demos.is_none() {
                return Err(
                    "guidance.step = false needs demos: the discriminator's reward is all that \
                     is left of the guidance"
                        .into(),
                );
            }
            return Ok(());
        }
        if let Some((key, _)) = step_keys[..3].iter().find(|(_, set)| !*set) {
            return Err(format!(
                "guidance.{key} is required (the guidance step's δ_k schedule; \
                 docs/config.md), or set guidance.step = false"
            )
            .into());
        }
        check_positive("guidance.delta0", self.delta0.unwrap_or_default(), false)?;
        let alpha = self.alpha.unwrap_or_default();
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(format!("guidance.alpha must be in (0, 1], got {alpha}").into());
        }
        if self.grow_back && self.decay_from.is_none() {
            return Err(
                "guidance.grow_back needs guidance.decay_from: the level below which \
                 δ_k grows back"
                    .into(),
            );
        }
        if let Some(level) = self.decay_from {
            if !(level > 0.0 && level <= 1.0) {
                return Err(format!(
                    "guidance.decay_from must be a share of episodes, in (0, 1], \
                     got {level}"
                )
                .into());
            }
            if !self.decay_on.reads_success() {
                return Err(
                    "guidance.decay_from is a share of episodes at the goal: set \
                     guidance.decay_on = \"success\" or \"evaluation\" with it"
                        .into(),
                );
            }
        }
        Ok(())
    }

    fn validate(&self) -> Result<(), Invalid> {
        match (&self.demos, &self.behaviour_policy) {
            (None, None) => {
                return Err("guidance: set demos (a discriminator) or behaviour_policy".into());
            }
            (Some(_), Some(_)) => {
                return Err("guidance: set demos or behaviour_policy, not both".into());
            }
            _ => {}
        }
        for (key, p) in [
            ("guidance.demos", &self.demos),
            ("guidance.behaviour_policy", &self.behaviour_policy),
        ] {
            if let Some(p) = p
                && !p.exists()
            {
                return Err(Invalid::Missing(format!(
                    "{key}: {} not found",
                    p.display()
                )));
            }
        }
        self.check_step()?;
        check_positive("guidance.discriminator_lr", self.discriminator_lr, false)?;
        if self.discriminator_steps == 0 {
            return Err("guidance.discriminator_steps must be at least 1".into());
        }
        check_widths("guidance.discriminator_hidden", &self.discriminator_hidden)?;
        if self.observe == Some(0) {
            return Err("guidance.observe must be at least 1".into());
        }
        if let Some(update) = &self.update {
            update.validate("guidance.update")?;
        }
        if let Some(critic) = &self.critic {
            critic.validate("guidance.critic")?;
        }
        Ok(())
    }
}

/// Why an evaluation env cannot take a policy trained on `trained`, if it cannot: other
/// observation or action dims.
pub fn dims_mismatch(trained: &EnvSpec, evaluated: &EnvSpec) -> Option<Invalid> {
    let same = (evaluated.obs_dim, evaluated.act_dim) == (trained.obs_dim, trained.act_dim);
    (!same).then(|| {
        Invalid::Value(format!(
            "eval_env {} does not have the dims of env {}: {} observations and {} actions \
             against {} and {}",
            evaluated.id,
            trained.id,
            evaluated.obs_dim,
            evaluated.act_dim,
            trained.obs_dim,
            trained.act_dim
        ))
    })
}

/// Which method a config is (`methods.rs`), for a config that names none.
impl TrainConfig {
    /// The table's method whose makeup `config` has, for a config that names none (a
    /// shipped config written out in full, a run older than the name): among the methods
    /// with the same use of the guidance and the same reward sources, the one that matches
    /// most of the improvement step's kind, the start, and its own keys (every one of them
    /// in the config, with its value), the method with more keys first on a tie.
    pub fn identify(&self) -> &'static str {
        let (config, guided) = (self, self.guided());
        let sources = |(env, discriminator): (f64, f64)| (env != 0.0, discriminator != 0.0);
        let reward = (config.reward.env, config.reward.discriminator);
        let start = match config.init.kind {
            InitKind::Bc => Start::Clone,
            InitKind::Random => Start::Random,
        };
        let written = toml::Table::try_from(config).unwrap_or_default();
        METHODS
            .iter()
            .enumerate()
            .filter(|(_, m)| m.command.is_none() && m.guided == guided)
            .filter(|(_, m)| sources(m.reward) == sources(reward))
            .max_by_key(|&(at, m)| {
                let keys: toml::Table = toml::from_str(m.keys).expect("a method's keys are TOML");
                (
                    m.improvement == config.improvement.kind(),
                    m.start == start,
                    holds(&written, &keys),
                    keys_count(&keys),
                    // The table's order on a full tie: the earlier entry.
                    std::cmp::Reverse(at),
                )
            })
            .map_or("trpo", |(_, m)| m.name)
    }

    /// What `config` takes of LOGO's guidance.
    pub fn guided(&self) -> Guided {
        match &self.guidance {
            None => Guided::No,
            Some(g) if g.step => Guided::Step,
            Some(_) => Guided::Discriminator,
        }
    }
}

/// Whether `config` has every key of `keys`, with the same value.
fn holds(config: &toml::Table, keys: &toml::Table) -> bool {
    keys.iter()
        .all(|(key, value)| match (value, config.get(key)) {
            (toml::Value::Table(inner), Some(toml::Value::Table(theirs))) => holds(theirs, inner),
            (value, Some(theirs)) => value == theirs,
            (_, None) => false,
        })
}

fn keys_count(keys: &toml::Table) -> usize {
    keys.values()
        .map(|v| v.as_table().map_or(1, keys_count))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_stored_paths_are_found_again_under_a_new_root() {
        let root = std::env::temp_dir().join(format!("logo-relocate-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(root.join("data/logo/hopper")).unwrap();
        std::fs::write(root.join("policy.pt"), b"").unwrap();
        let toml = format!(
            "env = \"SparseHopper-v4\"\niterations = 1\nsamples_per_iter = 1000\n[guidance]\ndemos = {:?}\ndelta0 = 0.01\nalpha = 0.95\nwarmup = 50\n",
            root.join("data/logo/hopper")
        );
        let file = root.join("c.toml");
        std::fs::write(&file, toml).unwrap();
        let mut config = TrainConfig::load(&file).unwrap();
        // As if trained in another clone: the stored path is gone, its tail is here.
        let guidance = config.guidance.as_mut().unwrap();
        guidance.demos = Some(PathBuf::from("/gone/clone/data/logo/hopper"));
        let notes = config.relocate_missing_paths(&root);
        let demos = config.guidance.as_ref().unwrap().demos.clone().unwrap();
        assert_eq!(
            demos,
            std::fs::canonicalize(root.join("data/logo/hopper")).unwrap()
        );
        assert_eq!(notes.len(), 1);
        assert!(notes[0].starts_with("guidance.demos: /gone/clone/data/logo/hopper is not here"));
        // An existing path stays; a single-component tail is not enough; no tail at all
        // leaves the path for validation to name.
        assert!(config.relocate_missing_paths(&root).is_empty());
        config.init_policy = Some(PathBuf::from("/gone/policy.pt"));
        config.guidance.as_mut().unwrap().demos = Some(PathBuf::from("/gone/elsewhere/nothing"));
        assert!(config.relocate_missing_paths(&root).is_empty());
        assert_eq!(config.init_policy, Some(PathBuf::from("/gone/policy.pt")));
        std::fs::remove_dir_all(&root).unwrap();
    }
}

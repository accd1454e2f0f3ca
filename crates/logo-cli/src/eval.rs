//! `logo eval`: the mean-action (or sampled) policy of a checkpoint on the dense and the
//! sparse env.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use logo_envs::{Env, EnvConfig, EnvFactory, EnvOptions, clip_to_range};
use logo_nn::{
    ActingPolicy, Checkpoint, CheckpointMeta, Cpu, Engine, GaussianPolicy, ObservationStats,
    Policy, PolicyConfig,
};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::video::{Video, VideoArgs};
use logo_algo::EngineSpan;
use logo_algo::episode::{Episode, SuccessRule, run_episode_with};
use logo_engine::{EngineArgs, WithEngine};
use logo_stats::mean_std;

#[derive(Args)]
pub struct EvalArgs {
    /// A checkpoint written by `logo train`.
    #[arg(long)]
    checkpoint: PathBuf,
    #[arg(long, default_value_t = 10)]
    episodes: usize,
    /// Env to evaluate on (default: the checkpoint's training env, dense and sparse).
    #[arg(long)]
    env: Option<String>,
    /// Episode k starts from `reset(seed + k)`; with `--sample`, also seeds the actions.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Act with actions sampled from π(·|s) (how training collects its batches) instead
    /// of the mean action (how training evaluates).
    #[arg(long)]
    sample: bool,
    /// Also report where each episode first moved this many metres forward and its mean
    /// speed before and after that point: past a sparse reward's distance threshold (20 m
    /// for SparseHalfCheetah, 2 m for Hopper and Walker2d) the sparse reward pays the same
    /// whatever the speed, so this shows what the policy does where it is no longer paid
    /// for speed.
    #[arg(long, value_name = "METRES")]
    split_at: Option<f64>,
    /// Clip each action to the env's actuator range before the env sees it. MuJoCo
    /// clamps actions to that range anyway, so the motion is the same, but the dense
    /// locomotion rewards charge their control cost on the action as given: this
    /// separates what a policy does from what its out-of-range actions cost. Training and
    /// the per-iteration evaluation clip only where the run's config sets `clip_actions`
    /// (the reference code does not).
    #[arg(long)]
    clip_actions: bool,
    /// Print, as JSON, what a run's `eval.json` holds for one policy: --episodes
    /// episodes (at least 20, whatever --episodes says below that) of the checkpoint's
    /// trained task from the fresh initial
    /// states of its seed, the mean action as sent and clipped, each episode's return,
    /// dense return, length, distance and action RMS, and the success rate. The env is the
    /// one the run evaluated on (its config's `eval_env`, else the trained task).
    #[arg(
        long,
        conflicts_with_all = ["sample", "split_at", "clip_actions", "env", "video", "seed"]
    )]
    json: bool,
    /// The engine the policy is loaded onto (any engine or float type loads any
    /// checkpoint); episodes act with its host copy, as training does. Default: the one
    /// the checkpoint last trained on where that is a CPU one, else the kernels in
    /// float64.
    #[command(flatten)]
    engine: EngineArgs,
    /// `--video OUT.mp4` records the first env's episodes (the dense one by default).
    #[command(flatten)]
    video: VideoArgs,
}

/// The checkpoint's policy, converted onto the chosen engine and copied back for acting.
struct OnEngine<'a>(&'a StoredPolicy);

impl WithEngine for OnEngine<'_> {
    type Output = (ActingPolicy, String);
    fn run<E: Engine>(self, engine: E) -> Result<Self::Output> {
        Ok((self.0.acting(&engine), engine.describe()))
    }
}

/// The env a run evaluated on, as its checkpoint's config says (`eval_env`, else the
/// trained task, `env_id`); an `eval_env` that does not read is an error, not a silent
/// evaluation on another env.
fn evaluated_env(meta: &CheckpointMeta, path: &Path) -> Result<String> {
    let eval_env = &meta.extra["config"]["eval_env"];
    if eval_env.is_null() {
        return Ok(meta.env_id.clone());
    }
    let env: EnvConfig = serde_json::from_value(eval_env.clone())
        .with_context(|| format!("{}: metadata config eval_env", path.display()))?;
    env.env_id()
        .with_context(|| format!("{}: metadata config eval_env", path.display()))
}

/// When an episode of the run reached its goal, as its checkpoint's config says (older
/// checkpoints have no `success`: the task's own).
fn success_rule(meta: &CheckpointMeta, path: &Path) -> Result<SuccessRule> {
    let rule = &meta.extra["config"]["success"];
    if rule.is_null() {
        return Ok(SuccessRule::default());
    }
    serde_json::from_value(rule.clone())
        .with_context(|| format!("{}: metadata config success", path.display()))
}

/// A checkpoint's policy as it acts: the module, the observation statistics it sees
/// through (where its run standardised observations), and the checkpoint's metadata.
pub struct StoredPolicy {
    pub module: GaussianPolicy<Cpu>,
    pub observation_norm: Option<ObservationStats>,
    pub meta: CheckpointMeta,
}

impl StoredPolicy {
    /// Its host copy for acting, by way of `engine` (which converts the parameters to
    /// its float type, so that a float32 run acts as it trained).
    pub fn acting<E: Engine>(&self, engine: &E) -> ActingPolicy {
        Policy::from_module(engine, &self.module)
            .acting(engine)
            .with_observation_norm(self.observation_norm.clone())
    }
}

/// The policy stored in a checkpoint, with its observation statistics and the
/// checkpoint's metadata.
pub fn load_policy(path: &Path) -> Result<StoredPolicy> {
    let ckpt = Checkpoint::load(path)?;
    let meta = &ckpt.meta;
    let hidden = meta
        .networks
        .get("policy")
        .with_context(|| format!("{}: the metadata lists no policy network", path.display()))?;
    let config = PolicyConfig {
        obs_dim: meta.obs_dim,
        act_dim: meta.act_dim,
        hidden: hidden.clone(),
        log_std_init: 0.0,
    };
    let device = Default::default();
    let module = ckpt.apply("policy", config.init::<Cpu>(&device))?;
    let observation_norm = match ckpt.tensor("observation_norm.mean") {
        None => None,
        Some(_) => {
            let shape = ObservationStats::new(meta.obs_dim).module::<Cpu>(&device);
            let stats = ObservationStats::from_module(&ckpt.apply("observation_norm", shape)?);
            stats.check().with_context(|| path.display().to_string())?;
            Some(stats)
        }
    };
    Ok(StoredPolicy {
        module,
        observation_norm,
        meta: ckpt.meta,
    })
}

pub fn run(args: &EvalArgs) -> Result<()> {
    anyhow::ensure!(args.episodes > 0, "--episodes must be at least 1");
    if let Some(metres) = args.split_at {
        anyhow::ensure!(
            metres.is_finite() && metres > 0.0,
            "--split-at must be a positive number of metres, got {metres}"
        );
    }
    let policy = load_policy(&args.checkpoint)?;
    let meta = &policy.meta;
    let history =
        logo_algo::engine_history(meta).with_context(|| args.checkpoint.display().to_string())?;
    let last = history.last().map(|span| span.engine.as_str());
    let (engine_args, _) = args.engine.or_trained_on(last, EngineArgs::on_cpu);
    let (acting, engine) = engine_args.with(OnEngine(&policy))?;
    if args.json {
        return print_json(args, meta, &acting, engine);
    }
    println!("{}", header(args, meta, &history, &engine));
    // The dense task, and the sparse one trained on (LOGO's for a dense checkpoint).
    let dense_id = logo_envs::dense_id(&meta.env_id).to_string();
    let sparse_id = if meta.env_id == dense_id {
        format!("Sparse{dense_id}")
    } else {
        meta.env_id.clone()
    };
    let ids = match &args.env {
        Some(id) => vec![id.clone()],
        None => vec![dense_id, sparse_id],
    };
    for (i, id) in ids.iter().enumerate() {
        evaluate_on(args, meta, &acting, id, i == 0)?;
    }
    Ok(())
}

/// `--json`: what a run's eval.json holds for this policy.
fn print_json(
    args: &EvalArgs,
    meta: &CheckpointMeta,
    acting: &ActingPolicy,
    engine: String,
) -> Result<()> {
    // At least the 20 episodes of a run's eval.json (--episodes may ask for more).
    let episodes = args.episodes.max(crate::final_eval::EPISODES);
    let env = evaluated_env(meta, &args.checkpoint)?;
    let success = success_rule(meta, &args.checkpoint)?;
    let mut report = crate::final_eval::report(&env, acting, meta.seed, episodes, success)?;
    report["checkpoint"] = args.checkpoint.display().to_string().into();
    report["iteration"] = meta.iteration.into();
    report["env"] = env.into();
    report["engine"] = engine.into();
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}

/// The first line: the checkpoint, what trained it, and how it acts here.
fn header(args: &EvalArgs, meta: &CheckpointMeta, history: &[EngineSpan], engine: &str) -> String {
    let trained_on = history
        .iter()
        .map(|span| format!("{} from iteration {}", span.engine, span.from_iteration))
        .collect::<Vec<_>>()
        .join(", ");
    let acts = match (args.sample, args.clip_actions) {
        (true, false) => "sampled actions",
        (true, true) => "sampled actions clipped to the actuator range",
        (false, false) => "mean action",
        (false, true) => "mean action clipped to the actuator range",
    };
    format!(
        "{} ({} iteration {}, seed {}; trained on {}): {acts} on {engine}, {} episodes",
        args.checkpoint.display(),
        meta.algorithm,
        meta.iteration,
        meta.seed,
        if trained_on.is_empty() {
            "an unrecorded engine"
        } else {
            &trained_on
        },
        args.episodes
    )
}

/// `--episodes` episodes on env `id`, and their summary line (a video of the first env's
/// episodes where `--video` asks for one).
fn evaluate_on(
    args: &EvalArgs,
    meta: &CheckpointMeta,
    acting: &ActingPolicy,
    id: &str,
    first: bool,
) -> Result<()> {
    // Name where the id came from: the flag, or the checkpoint's metadata.
    let source = match &args.env {
        Some(_) => format!("--env {id}"),
        None => format!("{}: env_id {id}", args.checkpoint.display()),
    };
    let factory = EnvFactory::new(id, &EnvOptions::default()).with_context(|| source)?;
    let mut env = factory.build()?;
    let spec = env.spec().clone();
    anyhow::ensure!(
        (spec.obs_dim, spec.act_dim) == (meta.obs_dim, meta.act_dim),
        "{id} has obs/action dims ({}, {}), the checkpoint's policy ({}, {})",
        spec.obs_dim,
        spec.act_dim,
        meta.obs_dim,
        meta.act_dim
    );
    let mut video = match (&args.video.video, first) {
        (Some(path), true) => Some(Video::start(path, &factory, args.video.frames())?),
        _ => None,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(args.seed);
    let mut act = |obs: &[f64]| {
        let mut action = if args.sample {
            acting.sample(obs, &mut rng)
        } else {
            acting.mean(obs)
        };
        if args.clip_actions {
            clip_to_range(&mut action, &spec.action_low, &spec.action_high);
        }
        action
    };
    let mut episodes = Vec::new();
    let mut splits = Vec::new();
    for k in 0..args.episodes {
        let mut split = args.split_at.map(SplitTracker::new);
        let label = format!("episode {} | ", k + 1);
        let episode = run_episode_with(
            env.as_mut(),
            args.seed + k as u64,
            &mut act,
            |env, e: &Episode| {
                if let Some(split) = split.as_mut() {
                    split.observe(e);
                }
                match video.as_mut() {
                    Some(video) => video.episode_frame(env, &label, e),
                    None => Ok(()),
                }
            },
        )?;
        if let Some(split) = split {
            splits.push(split.finish(&episode, spec.dt));
        }
        episodes.push(episode);
    }
    if let (Some(video), Some(path)) = (video, &args.video.video) {
        let frames = video.finish()?;
        println!("video: {} ({frames} frames of {id})", path.display());
    }
    println!("{id:32} {}", summary(&episodes));
    if let Some(metres) = args.split_at {
        println!("{:32} {}", "", split_summary(metres, &splits));
    }
    Ok(())
}

/// Where an episode first moved `metres` forward (`--split-at`).
struct SplitTracker {
    metres: f64,
    reached: Option<(usize, f64)>,
}

/// An episode cut at its first crossing of `--split-at`: the step, and the mean forward
/// speed (m/s) up to it and after it (`None` where the episode ended there).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Split {
    step: usize,
    speed_before: f64,
    speed_after: Option<f64>,
}

impl SplitTracker {
    fn new(metres: f64) -> Self {
        Self {
            metres,
            reached: None,
        }
    }

    fn observe(&mut self, e: &Episode) {
        if self.reached.is_none() && e.moved >= self.metres {
            self.reached = Some((e.length, e.moved));
        }
    }

    /// The split of the finished episode `e`; `None` if it never crossed the mark.
    fn finish(self, e: &Episode, dt: f64) -> Option<Split> {
        let (step, moved) = self.reached?;
        let after = e.length - step;
        Some(Split {
            step,
            speed_before: moved / (step as f64 * dt),
            speed_after: (after > 0).then(|| (e.moved - moved) / (after as f64 * dt)),
        })
    }
}

/// One line for `--split-at`, over every episode's split (`None`: never got there): how
/// many got there, when, and how fast before and after (mean ± std over the episodes
/// that have each number).
fn split_summary(metres: f64, splits: &[Option<Split>]) -> String {
    let reached: Vec<&Split> = splits.iter().flatten().collect();
    let stat = |of: fn(&Split) -> Option<f64>| {
        let values: Vec<f64> = reached.iter().filter_map(|s| of(s)).collect();
        match values.is_empty() {
            true => "-".to_string(),
            false => {
                let (m, s) = mean_std(&values);
                format!("{m:.2} ± {s:.2}")
            }
        }
    };
    format!(
        "{metres} m reached in {} of {} episodes, at step {} | speed before {} m/s, \
         after {} m/s",
        reached.len(),
        splits.len(),
        stat(|s| Some(s.step as f64)),
        stat(|s| Some(s.speed_before)),
        stat(|s| s.speed_after),
    )
}

/// One line for an env's evaluation: mean ± std over episodes of the returns and of how
/// far `qpos[0]` moved, the mean length and the mean action RMS. The dense locomotion
/// rewards charge the control cost on the action as given, while MuJoCo clamps it to the
/// actuator range (±1 for these envs), so an RMS well above 1 explains a negative dense
/// return from a policy that does move forward.
fn summary(episodes: &[Episode]) -> String {
    let stat = |of: fn(&Episode) -> f64| mean_std(&episodes.iter().map(of).collect::<Vec<_>>());
    let (rm, rs) = stat(|e| e.return_);
    let (dm, ds) = stat(|e| e.dense_return);
    let (lm, _) = stat(|e| e.length as f64);
    let (xm, xs) = stat(|e| e.moved);
    let (am, _) = stat(|e| e.action_rms);
    format!(
        "return {rm:10.2} ± {rs:8.2} | dense return {dm:10.2} ± {ds:8.2} | length {lm:.0} \
         | x moved {xm:8.2} ± {xs:6.2} | action RMS {am:.2}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use logo_algo::episode::run_episode;

    /// A constant action of 2 on HalfCheetah (actuator range ±1): the RMS says 2, and the
    /// dense return is the distance over dt minus 0.1·‖a‖² per step on the unclamped
    /// action (6 × 4 × 0.1 = 2.4 per step), which is what makes it negative.
    #[test]
    fn an_episode_reports_distance_and_the_unclamped_action_size() {
        let mut env = EnvFactory::new("SparseHalfCheetah-v4", &EnvOptions::default())
            .unwrap()
            .build()
            .unwrap();
        let episode = run_episode(env.as_mut(), 0, |_| vec![2.0; 6]).unwrap();
        assert_eq!(episode.length, 1000);
        assert!((episode.action_rms - 2.0).abs() < 1e-12, "{episode:?}");
        let dt = 0.05;
        let expected = episode.moved / dt - 2.4 * episode.length as f64;
        assert!(
            (episode.dense_return - expected).abs() < 1e-6 * expected.abs(),
            "{episode:?}, expected dense {expected}"
        );
        assert!(episode.dense_return < 0.0, "{episode:?}");
    }

    /// `--clip-actions` on HalfCheetah (±1): a constant action of 2, clipped, plays the
    /// same episode as a constant 1; unclipped, MuJoCo clamps it to 1 too, so the cheetah
    /// moves exactly as far, but the dense return is charged 0.1 × 6 × (4 − 1) = 1.8 more
    /// per step.
    #[test]
    fn clipped_actions_move_the_same_and_cost_less() {
        let mut env = EnvFactory::new("HalfCheetah-v4", &EnvOptions::default())
            .unwrap()
            .build()
            .unwrap();
        let spec = env.spec().clone();
        let clipped = run_episode(env.as_mut(), 0, |_| {
            let mut action = vec![2.0; 6];
            clip_to_range(&mut action, &spec.action_low, &spec.action_high);
            action
        })
        .unwrap();
        let one = run_episode(env.as_mut(), 0, |_| vec![1.0; 6]).unwrap();
        let unclipped = run_episode(env.as_mut(), 0, |_| vec![2.0; 6]).unwrap();
        assert_eq!(clipped, one);
        assert_eq!(clipped.moved, unclipped.moved);
        let saved = clipped.dense_return - unclipped.dense_return;
        assert!(
            (saved - 1.8 * 1000.0).abs() < 1e-6,
            "{clipped:?} {unclipped:?}"
        );
        let mut mixed = vec![-3.0, -0.5, 0.5, 3.0];
        clip_to_range(&mut mixed, &[-1.0; 4], &[1.0, 1.0, 0.25, 2.0]);
        assert_eq!(mixed, vec![-1.0, -0.5, 0.25, 2.0]);
    }

    /// An episode moving 0.5 m a step for 4 steps, then 0.25 m a step for 4 more, cut at
    /// 2 m: reached at step 4, 5 m/s before and 2.5 m/s after (dt 0.1 s); one that stops
    /// short of the mark has no split.
    #[test]
    fn split_at_cuts_an_episode_at_its_first_crossing() {
        let steps = [0.5, 1.0, 1.5, 2.0, 2.25, 2.5, 2.75, 3.0];
        let episode = |moved: &[f64]| {
            let mut tracker = SplitTracker::new(2.0);
            let mut e = Episode::default();
            for &x in moved {
                e.length += 1;
                e.moved = x;
                tracker.observe(&e);
            }
            tracker.finish(&e, 0.1)
        };
        let split = episode(&steps).unwrap();
        assert_eq!(split.step, 4);
        assert!((split.speed_before - 5.0).abs() < 1e-12, "{split:?}");
        assert!(
            (split.speed_after.unwrap() - 2.5).abs() < 1e-12,
            "{split:?}"
        );
        let short = episode(&steps[..3]);
        assert_eq!(short, None);
        let at_the_end = episode(&steps[..4]).unwrap();
        assert_eq!((at_the_end.step, at_the_end.speed_after), (4, None));
        assert_eq!(
            split_summary(2.0, &[Some(split), short]),
            "2 m reached in 1 of 2 episodes, at step 4.00 ± 0.00 | speed before 5.00 ± 0.00 m/s, \
             after 2.50 ± 0.00 m/s"
        );
    }
}

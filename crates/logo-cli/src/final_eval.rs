//! The evaluation a run ends with (`eval.json`), and `logo eval --json`: a policy's mean
//! action over whole episodes of the trained task from fresh initial states, as sent and
//! clipped to the action space, with every episode's numbers.
//!
//! Fresh initial states: episode k of a run with seed s starts from
//! `reset(final_evaluation_seed(s, k))`, a stream of its own, apart from the fixed states
//! every training iteration evaluates on ([`logo_algo::episode::evaluation_seed`]), so the
//! end-of-run numbers are not those the best policy was picked on.

use std::io::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use logo_algo::episode::{Episode, SuccessRule, run_episode};
use logo_envs::{EnvFactory, EnvOptions, clip_to_range};
use logo_nn::ActingPolicy;
use logo_stats::mean;
use serde_json::{Value, json};

/// The episodes every run's final evaluation plays.
pub const EPISODES: usize = 20;

/// Reset seed of final-evaluation episode `episode` of a run with `seed`.
pub fn final_evaluation_seed(seed: u64, episode: usize) -> u64 {
    3_000_000 + seed * 1000 + episode as u64
}

/// How actions reach the env.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Acting {
    /// The mean action as the policy gives it (MuJoCo clamps it to the actuator range).
    Mean,
    /// The mean action clipped to the action space first (what the control cost sees).
    MeanClipped,
}

/// `episodes` episodes of `env_id` from the fresh initial states of `seed`.
pub fn play(
    env_id: &str,
    policy: &ActingPolicy,
    acting: Acting,
    seed: u64,
    episodes: usize,
) -> Result<Vec<Episode>> {
    let mut env = EnvFactory::new(env_id, &EnvOptions::default())?.build()?;
    let (low, high) = (
        env.spec().action_low.clone(),
        env.spec().action_high.clone(),
    );
    (0..episodes)
        .map(|k| {
            let episode = run_episode(env.as_mut(), final_evaluation_seed(seed, k), |obs| {
                let mut action = policy.mean(obs);
                if acting == Acting::MeanClipped {
                    clip_to_range(&mut action, &low, &high);
                }
                action
            })?;
            Ok(episode)
        })
        .collect()
}

/// Means over the episodes, and how many reached the goal by the run's success rule:
/// `"reached": [k, n]`, or null where the rule and the task define no success (a return
/// is not a success: a failed run on a task with an action cost still has one).
pub fn summary(episodes: &[Episode], success: SuccessRule) -> Value {
    let of = |f: fn(&Episode) -> f64| mean(&episodes.iter().map(f).collect::<Vec<_>>());
    let reached = success.count(episodes.iter().map(|e| (e.reached, e.terminated)));
    json!({
        "return": of(|e| e.return_),
        "dense_return": of(|e| e.dense_return),
        "length": of(|e| e.length as f64),
        "moved": of(|e| e.moved),
        "action_rms": of(|e| e.action_rms),
        "reached": reached.map(|(k, n)| [k, n]),
        "success_rate": reached.map(|(k, n)| k as f64 / n as f64),
    })
}

/// "reached the goal in k of n episodes", or nothing where no success is defined.
pub fn reached_line(summary: &Value) -> Option<String> {
    let pair = summary["reached"].as_array()?;
    let (k, n) = (pair.first()?.as_u64()?, pair.get(1)?.as_u64()?);
    Some(format!("reached the goal in {k} of {n} episodes"))
}

fn episode_json(e: &Episode) -> Value {
    json!({
        "return": e.return_,
        "dense_return": e.dense_return,
        "length": e.length,
        "terminated": e.terminated,
        "moved": e.moved,
        "action_rms": e.action_rms,
        "reached": e.reached,
    })
}

/// One policy's report: as sent and clipped, each a summary and its episodes.
pub fn report(
    env_id: &str,
    policy: &ActingPolicy,
    seed: u64,
    episodes: usize,
    success: SuccessRule,
) -> Result<Value> {
    let mut out = serde_json::Map::new();
    for (name, acting) in [
        ("mean_action", Acting::Mean),
        ("clipped", Acting::MeanClipped),
    ] {
        let played = play(env_id, policy, acting, seed, episodes)?;
        out.insert(
            name.into(),
            json!({
                "summary": summary(&played, success),
                "episodes": played.iter().map(episode_json).collect::<Vec<_>>(),
            }),
        );
    }
    Ok(Value::Object(out))
}

/// Writes the evaluation file `path` (a run's `eval.json`) atomically: `policies` maps
/// "final"/"best" to (checkpoint file, iteration, report).
pub fn write(
    path: &Path,
    env_id: &str,
    seed: u64,
    episodes: usize,
    policies: &[(&str, &str, u64, Value)],
) -> Result<()> {
    let mut by_name = serde_json::Map::new();
    for (name, file, iteration, report) in policies {
        let mut entry = json!({ "checkpoint": file, "iteration": iteration });
        entry
            .as_object_mut()
            .expect("an object")
            .extend(report.as_object().cloned().unwrap_or_default());
        by_name.insert(name.to_string(), entry);
    }
    let doc = json!({
        "env": env_id,
        "seed": seed,
        "episodes": episodes,
        "initial_states": format!(
            "fresh: episode k resets with seed {} + k",
            final_evaluation_seed(seed, 0)
        ),
        "policies": by_name,
    });
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(format!(".tmp.{}", std::process::id()));
    let tmp = std::path::PathBuf::from(tmp);
    // Written, synced, then renamed (as checkpoints are): a crash leaves the old file or
    // the whole new one.
    let text = serde_json::to_string_pretty(&doc)? + "\n";
    std::fs::File::create(&tmp)
        .and_then(|mut file| {
            file.write_all(text.as_bytes())?;
            file.sync_all()
        })
        .with_context(|| format!("{}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("{}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn success_is_the_rules_and_means_are_per_episode() {
        let e = |r: f64, len: usize, reached: Option<bool>, terminated: bool| Episode {
            return_: r,
            dense_return: 2.0 * r,
            length: len,
            reached,
            terminated,
            ..Episode::default()
        };
        let episodes = [
            e(0.0, 10, Some(false), true),
            e(3.0, 20, Some(true), false),
            e(1.0, 30, Some(true), false),
            e(-5.0, 40, Some(false), false),
        ];
        let s = summary(&episodes, SuccessRule::Task);
        assert_eq!(s["reached"], json!([2, 4]));
        assert_eq!(s["success_rate"], 0.5);
        assert_eq!(s["return"], -0.25);
        assert_eq!(s["length"], 25.0);
        assert_eq!(
            reached_line(&s).as_deref(),
            Some("reached the goal in 2 of 4 episodes")
        );
        let s = summary(&episodes, SuccessRule::Terminated);
        assert_eq!(s["reached"], json!([1, 4]));
        // A task without a goal, or a rule of none, reports no success: a non-zero return
        // is not one.
        let goalless: Vec<Episode> = episodes
            .iter()
            .map(|x| Episode {
                reached: None,
                ..x.clone()
            })
            .collect();
        for (episodes, rule) in [
            (&goalless[..], SuccessRule::Task),
            (&episodes[..], SuccessRule::None),
        ] {
            let s = summary(episodes, rule);
            assert!(s["reached"].is_null() && s["success_rate"].is_null(), "{s}");
            assert_eq!(reached_line(&s), None);
        }
    }

    #[test]
    fn fresh_states_are_not_the_training_evaluations() {
        for k in 0..100 {
            assert_ne!(
                final_evaluation_seed(0, k),
                logo_algo::episode::evaluation_seed(0, k)
            );
        }
    }
}

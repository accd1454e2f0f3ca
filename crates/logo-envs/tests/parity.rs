//! Replays the Gymnasium 1.4.0 trajectories recorded by `tests/parity/generate.py` and
//! checks every env id, dense and sparse: observations and rewards within 1e-9, the
//! termination and truncation flags on the same step. LOGO's four tasks are checked as
//! their `Sparse<id>`, the other seven with the delayed kind; every task with a
//! distance threshold its trajectory crosses, and Reacher and Pusher with the goal kind.

use std::path::{Path, PathBuf};

use logo_envs::{EnvFactory, EnvOptions, SparseRule};
use serde_json::Value;

const TOLERANCE: f64 = 1e-9;

fn fixtures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/parity/fixtures")
}

struct Trajectory<'a> {
    meta: &'a Value,
    data: &'a [f64],
}

impl Trajectory<'_> {
    fn array(&self, name: &str) -> (&[f64], usize) {
        let spec = &self.meta["arrays"][name];
        let offset = spec["offset"].as_u64().unwrap() as usize;
        let shape: Vec<usize> = spec["shape"]
            .as_array()
            .unwrap()
            .iter()
            .map(|d| d.as_u64().unwrap() as usize)
            .collect();
        let len: usize = shape.iter().product();
        let width = if shape.len() == 2 { shape[1] } else { 1 };
        (&self.data[offset..offset + len], width)
    }
    fn floats(&self, name: &str) -> Vec<f64> {
        self.meta[name]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOLERANCE
}

/// Replays one trajectory on `id` and returns the largest deviation seen, or the first mismatch.
fn replay(
    id: &str,
    options: &EnvOptions,
    traj: &Trajectory,
    reward_column: &str,
) -> Result<f64, String> {
    let factory = EnvFactory::new(id, options).map_err(|e| e.to_string())?;
    let mut env = factory.build().unwrap();
    let spec = env.spec().clone();
    let (obs_ref, obs_dim) = traj.array("obs");
    let (actions, act_dim) = traj.array("actions");
    assert_eq!(
        (obs_dim, act_dim),
        (spec.obs_dim, spec.act_dim),
        "{id}: fixture dims"
    );
    let rewards = traj.array(reward_column).0;
    let xs = traj.array("x_position").0;
    let terminated = traj.array("terminated").0;
    let truncated = traj.array("truncated").0;
    let steps = traj.meta["steps"].as_u64().unwrap() as usize;
    let name = traj.meta["name"].as_str().unwrap();

    let mut obs = vec![0.0; obs_dim];
    env.reset(Some(0), &mut obs);
    env.set_state(&traj.floats("qpos0"), &traj.floats("qvel0"), &mut obs)
        .map_err(|e| e.to_string())?;
    let mut worst = 0.0f64;
    let mut check = |what: &str, t: usize, got: f64, want: f64| -> Result<(), String> {
        worst = worst.max((got - want).abs());
        if close(got, want) {
            Ok(())
        } else {
            Err(format!(
                "{id} [{name}] step {t}: {what} = {got:.17e}, Gymnasium {want:.17e}"
            ))
        }
    };
    for (i, (&g, &w)) in obs.iter().zip(&obs_ref[..obs_dim]).enumerate() {
        check(&format!("initial obs[{i}]"), 0, g, w)?;
    }
    for t in 0..steps {
        let step = env
            .step(&actions[t * act_dim..][..act_dim], &mut obs)
            .map_err(|e| e.to_string())?;
        for (i, (&g, &w)) in obs
            .iter()
            .zip(&obs_ref[(t + 1) * obs_dim..][..obs_dim])
            .enumerate()
        {
            check(&format!("obs[{i}]"), t + 1, g, w)?;
        }
        check("reward", t + 1, step.reward, rewards[t])?;
        check("x_position", t + 1, step.info.x_position, xs[t])?;
        if step.terminated != (terminated[t] == 1.0) || step.truncated != (truncated[t] == 1.0) {
            return Err(format!(
                "{id} [{name}] step {}: terminated/truncated = {}/{}, Gymnasium {}/{}",
                t + 1,
                step.terminated,
                step.truncated,
                terminated[t],
                truncated[t]
            ));
        }
    }
    Ok(worst)
}

/// The Gymnasium fixture of `base_id`: its manifest, and the float64 values its
/// trajectories index.
fn fixture(dir: &Path, base_id: &str) -> (Value, Vec<f64>) {
    let manifest_path = dir.join(format!("{base_id}.json"));
    let manifest: Value = serde_json::from_str(
        &std::fs::read_to_string(&manifest_path)
            .unwrap_or_else(|e| panic!("{}: {e}", manifest_path.display())),
    )
    .unwrap();
    let bytes = std::fs::read(dir.join(format!("{base_id}.f64"))).unwrap();
    let data = bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    (manifest, data)
}

#[test]
fn every_env_id_matches_gymnasium() {
    let dir = fixtures_dir();
    let mut checked = 0;
    let mut failures = Vec::new();
    for base_id in logo_envs::BASE_ENV_IDS {
        let (manifest, data) = fixture(&dir, base_id);
        for meta in manifest["trajectories"].as_array().unwrap() {
            let traj = Trajectory { meta, data: &data };
            // The distance kind with the fixture's lower threshold, on the dense id.
            let low = EnvOptions {
                sparse: meta["low_threshold"]
                    .as_f64()
                    .map(|threshold| SparseRule::Distance { threshold }),
                ..EnvOptions::default()
            };
            let logo = manifest["logo_sparse"].as_bool().unwrap_or(true);
            let sparse_id = if logo {
                format!("Sparse{base_id}")
            } else {
                format!("{base_id}+delayed")
            };
            let mut runs = vec![
                (base_id.to_string(), EnvOptions::default(), "reward"),
                (sparse_id, EnvOptions::default(), "sparse_reward"),
                (base_id.to_string(), low, "sparse_reward_low"),
            ];
            // The goal kind, where the task has a target, at a radius the trajectory
            // crosses.
            if let Some(radius) = meta["goal_radius"].as_f64() {
                let goal = EnvOptions {
                    sparse: Some(SparseRule::Goal { radius }),
                    ..EnvOptions::default()
                };
                runs.push((base_id.to_string(), goal, "sparse_reward_goal"));
            }
            for (id, options, column) in runs {
                match replay(&id, &options, &traj, column) {
                    Ok(worst) => {
                        println!(
                            "{id:28} {:10} {column:17} max |diff| {worst:.1e}",
                            meta["name"].as_str().unwrap()
                        );
                        checked += 1;
                    }
                    Err(e) => failures.push(e),
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} mismatches with Gymnasium:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        checked >= logo_envs::BASE_ENV_IDS.len() * 3 * 3,
        "only {checked} trajectories were checked"
    );
}

/// The fixtures themselves must cover what the issue asks for, or the test above proves little.
#[test]
fn fixtures_cover_termination_truncation_and_both_sparse_branches() {
    let dir = fixtures_dir();
    let (mut early_termination, mut truncation, mut sparse_paid) = (false, false, false);
    let mut goal_paid = (false, false);
    for base_id in logo_envs::BASE_ENV_IDS {
        let (manifest, data) = fixture(&dir, base_id);
        for meta in manifest["trajectories"].as_array().unwrap() {
            let traj = Trajectory { meta, data: &data };
            let steps = meta["steps"].as_u64().unwrap();
            early_termination |= steps < 1000 && traj.array("terminated").0.contains(&1.0);
            truncation |= steps == 1000 && traj.array("truncated").0[999] == 1.0;
            sparse_paid |= traj.array("sparse_reward_low").0.contains(&1.0);
            if !meta["goal_radius"].is_null() {
                let paid = traj.array("sparse_reward_goal").0;
                goal_paid.0 |= paid.contains(&1.0);
                goal_paid.1 |= paid.contains(&0.0);
            }
        }
    }
    assert!(early_termination && truncation && sparse_paid);
    assert!(goal_paid.0 && goal_paid.1, "the goal kind's two branches");
}

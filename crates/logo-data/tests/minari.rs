//! Minari datasets: our writer and reader, both directions with Python's minari 0.5.4,
//! the LOGO demonstrations' import, and corrupted files (errors, never panics).

mod common;

use std::path::{Path, PathBuf};

use common::{python, repo, scratch, script};

use logo_data::import::{import_logo_npy, reset_pose, split_at_resets};
use logo_data::{DataError, Dataset, Episode, read_minari, write_minari};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;

fn sample_dataset(seed: u64) -> Dataset {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (obs_dim, act_dim) = (4, 2);
    let episodes = [7usize, 1, 12]
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let mut r =
                |n: usize| -> Vec<f64> { (0..n).map(|_| rng.random_range(-3.0..3.0)).collect() };
            Episode {
                observations: r((t + 1) * obs_dim),
                actions: r(t * act_dim),
                rewards: r(t),
                terminations: (0..t).map(|k| k + 1 == t && i != 1).collect(),
                truncations: (0..t).map(|k| k + 1 == t && i == 1).collect(),
            }
        })
        .collect();
    Dataset {
        obs_dim,
        act_dim,
        episodes,
        metadata: Default::default(),
    }
}

fn episodes_json(dataset: &Dataset) -> Value {
    let rows = |v: &[f64], w: usize| -> Value {
        v.chunks(w).map(|r| r.to_vec()).collect::<Vec<_>>().into()
    };
    dataset
        .episodes
        .iter()
        .map(|e| {
            serde_json::json!({
                "observations": rows(&e.observations, dataset.obs_dim),
                "actions": rows(&e.actions, dataset.act_dim),
                "rewards": e.rewards,
                "terminations": e.terminations,
                "truncations": e.truncations,
            })
        })
        .collect::<Vec<_>>()
        .into()
}

#[test]
fn write_then_read_gives_the_same_episodes() {
    let dir = scratch("roundtrip");
    let mut dataset = sample_dataset(1);
    dataset.metadata.insert("logo_note".into(), "kept".into());
    write_minari(&dataset, &dir).unwrap();
    let back = read_minari(&dir).unwrap();
    assert_eq!(back.episodes, dataset.episodes);
    assert_eq!((back.obs_dim, back.act_dim), (4, 2));
    assert_eq!(back.metadata["logo_note"], "kept");
    assert_eq!(back.metadata["total_steps"], 20);
    assert_eq!(back.metadata["total_episodes"], 3);
}

#[test]
fn a_dataset_written_by_python_minari_loads_here() {
    let Some(python) = python() else { return };
    let root = scratch("from-python");
    let dir = PathBuf::from(script(&python, &["write", root.to_str().unwrap()]).trim());
    let dataset = read_minari(&dir).unwrap();
    let expected: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("expected.json")).unwrap()).unwrap();
    assert_eq!(episodes_json(&dataset), expected);
    assert_eq!(dataset.metadata["dataset_id"], "test/roundtrip-v0");
}

#[test]
fn a_dataset_written_here_loads_in_python_minari() {
    let Some(python) = python() else { return };
    let dir = scratch("to-python");
    let dataset = sample_dataset(2);
    write_minari(&dataset, &dir).unwrap();
    std::fs::write(
        dir.join("expected.json"),
        episodes_json(&dataset).to_string(),
    )
    .unwrap();
    script(&python, &["read", dir.to_str().unwrap()]);
}

/// The episode lengths listed in the LOGO demonstrations' README.
const LOGO_LENGTHS: [(&str, &str, &[usize]); 4] = [
    ("hopper", "Hopper-v4", &[1000, 1000, 546, 323, 1000]),
    ("walker2d", "Walker2d-v4", &[1000, 1000, 1000, 1000, 584]),
    ("halfcheetah", "HalfCheetah-v4", &[1000; 5]),
    (
        "inverted_double_pendulum",
        "InvertedDoublePendulum-v4",
        &[29, 43, 31, 46, 34],
    ),
];

#[test]
fn the_shipped_logo_demonstrations_have_the_listed_episodes() {
    for (name, env, lengths) in LOGO_LENGTHS {
        let dataset = read_minari(&repo().join("data/logo").join(name)).unwrap();
        let got: Vec<usize> = dataset.episodes.iter().map(Episode::steps).collect();
        assert_eq!(got, lengths, "{name}");
        assert_eq!(dataset.env_id(), Some(env));
        // 1000-step episodes hit the time limit; shorter ones terminated.
        for ep in &dataset.episodes {
            assert_eq!(
                ep.truncations.last() == Some(&true),
                ep.steps() == 1000,
                "{name}"
            );
        }
    }
}

#[test]
fn importing_the_reference_npy_reproduces_the_shipped_datasets() {
    let reference = repo().join("../shared/reference/logo-demos");
    if !reference.is_dir() {
        eprintln!("skipped: {} is not there", reference.display());
        return;
    }
    for (name, env, _) in LOGO_LENGTHS {
        let npy = reference.join(format!("{name}.npy"));
        let shipped = read_minari(&repo().join("data/logo").join(name)).unwrap();
        let imported = import_logo_npy(&npy, env, shipped.obs_dim, shipped.act_dim, 1000).unwrap();
        assert_eq!(imported.episodes, shipped.episodes, "{name}");
    }
}

#[test]
fn splitting_ignores_a_balancing_state_near_the_reset_pose() {
    // Two IDP-like episodes: each starts at the pose and drifts slowly (staying inside the
    // reset box for a while); the second starts after a fall far from the pose.
    let pose = reset_pose("InvertedDoublePendulum-v4").unwrap();
    let mut obs = Vec::new();
    for start in [0.0, 0.0] {
        for k in 0..20 {
            let x = start + 0.01 * k as f64;
            let fallen = if k == 19 { 0.6 } else { 0.0 };
            obs.extend([
                x + fallen,
                0.01,
                0.0,
                1.0,
                1.0,
                0.1,
                0.0,
                0.0,
                5.0,
                5.0,
                5.0,
            ]);
        }
    }
    assert_eq!(split_at_resets(&obs, 11, &pose), vec![0, 20]);
}

#[test]
fn bad_values_are_errors_naming_file_episode_and_field() {
    let dir = scratch("nan");
    let mut dataset = sample_dataset(3);
    write_minari(&dataset, &dir).unwrap();
    dataset.episodes[2].actions[3] = f64::NAN;
    let err = write_minari(&dataset, &dir).unwrap_err().to_string();
    assert!(
        err.contains("episode 2") && err.contains("actions"),
        "{err}"
    );
    let mut short = sample_dataset(3);
    short.episodes[1].observations.truncate(4); // one observation for one step
    let err = short.validate(Path::new("x")).unwrap_err().to_string();
    assert!(
        err.contains("episode 1") && err.contains("observations"),
        "{err}"
    );
}

#[test]
fn end_flags_mid_episode_or_doubled_are_errors() {
    let mut mid = sample_dataset(3);
    let i = mid.episodes.iter().position(|e| e.steps() >= 2).unwrap();
    mid.episodes[i].terminations[0] = true;
    let err = mid.validate(Path::new("x")).unwrap_err().to_string();
    assert!(
        err.contains(&format!("episode {i}"))
            && err.contains("terminations")
            && err.contains("step 0"),
        "{err}"
    );
    let mut both = sample_dataset(3);
    let last = both.episodes[0].steps() - 1;
    both.episodes[0].terminations[last] = true;
    both.episodes[0].truncations[last] = true;
    let err = both.validate(Path::new("x")).unwrap_err().to_string();
    assert!(
        err.contains("episode 0") && err.contains("both set"),
        "{err}"
    );
}

#[test]
fn demonstrations_recorded_in_another_env_are_refused() {
    // Walker2d's demonstrations have HalfCheetah's dims (17, 6): only the recorded env
    // id tells them apart.
    let dir = repo().join("data/logo/walker2d");
    let err = logo_data::Demonstrations::load(&dir, "SparseHalfCheetah-v4", 17, 6)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("recorded in Walker2d-v4") && err.contains("SparseHalfCheetah-v4"),
        "{err}"
    );
    // Another version or the sparse variant of the same env is the same family.
    logo_data::Demonstrations::load(&dir, "Walker2d-v5", 17, 6).unwrap();
}

#[test]
fn corrupted_and_truncated_files_are_errors_not_panics() {
    let dir = scratch("fuzz");
    write_minari(&sample_dataset(4), &dir).unwrap();
    let h5 = dir.join("data/main_data.hdf5");
    let good = std::fs::read(&h5).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut errors = 0;
    for trial in 0..300 {
        let mut bytes = good.clone();
        if trial % 3 == 0 {
            bytes.truncate(rng.random_range(0..good.len()));
        } else {
            for _ in 0..rng.random_range(1..8) {
                let i = rng.random_range(0..bytes.len());
                bytes[i] = rng.random();
            }
        }
        std::fs::write(&h5, &bytes).unwrap();
        match read_minari(&dir) {
            Err(DataError::Hdf5 { path, .. }) | Err(DataError::Field { path, .. }) => {
                assert!(path.ends_with("main_data.hdf5"), "{}", path.display());
                errors += 1;
            }
            Err(other) => panic!("unexpected error kind: {other}"),
            Ok(dataset) => dataset.validate(&h5).unwrap(), // a flip in unused bytes
        }
    }
    assert!(
        errors > 100,
        "only {errors} of 300 corruptions were detected"
    );
    // A broken metadata.json names itself.
    std::fs::write(&h5, &good).unwrap();
    std::fs::write(dir.join("data/metadata.json"), "{ not json").unwrap();
    let err = read_minari(&dir).unwrap_err().to_string();
    assert!(err.contains("metadata.json"), "{err}");
}

#[test]
fn a_d4rl_file_written_by_h5py_imports_with_its_episodes() {
    let Some(python) = python() else { return };
    let dir = scratch("d4rl");
    let file = dir.join("d4rl.hdf5");
    script(&python, &["d4rl", file.to_str().unwrap()]);
    let dataset = logo_data::import::import_d4rl(&file).unwrap();
    assert_eq!((dataset.obs_dim, dataset.act_dim), (3, 2));
    let lengths: Vec<usize> = dataset.episodes.iter().map(Episode::steps).collect();
    assert_eq!(lengths, vec![4, 5, 3]);
    let ends: Vec<(bool, bool)> = dataset
        .episodes
        .iter()
        .map(|e| {
            (
                *e.terminations.last().unwrap(),
                *e.truncations.last().unwrap(),
            )
        })
        .collect();
    assert_eq!(ends, vec![(true, false), (false, true), (false, true)]);
    // Rewards 0..12 in order; each final observation is next_observations' row
    // (observations + 1).
    assert_eq!(dataset.episodes[1].rewards, vec![4.0, 5.0, 6.0, 7.0, 8.0]);
    let ep = &dataset.episodes[0];
    for j in 0..3 {
        let last_obs = ep.observations[3 * 3 + j];
        assert!((ep.observations[4 * 3 + j] - (last_obs + 1.0)).abs() < 1e-6);
    }
    // And it converts: write as Minari, read back.
    let minari_dir = dir.join("converted");
    write_minari(&dataset, &minari_dir).unwrap();
    assert_eq!(read_minari(&minari_dir).unwrap().episodes, dataset.episodes);
}

#[test]
fn d4rl_next_observations_of_another_shape_are_refused() {
    let Some(python) = python() else { return };
    let dir = scratch("d4rl-next");
    // One column short would import wrong final observations; two rows short panicked.
    for (broken, expected) in [("narrow", "2 columns"), ("short", "30 values")] {
        let file = dir.join(format!("{broken}.hdf5"));
        script(&python, &["d4rl", file.to_str().unwrap(), broken]);
        let err = logo_data::import::import_d4rl(&file)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("next_observations") && err.contains(expected) && err.contains(broken),
            "{err}"
        );
    }
}

#[test]
fn demonstrations_of_the_wrong_dims_are_refused_with_the_file_named() {
    let dir = repo().join("data/logo/hopper");
    let err = logo_data::Demonstrations::load(&dir, "SparseHopper-v4", 17, 6)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("data/logo/hopper") && err.contains("(11, 3)") && err.contains("(17, 6)"),
        "{err}"
    );
    let ok = logo_data::Demonstrations::load(&dir, "SparseHopper-v4", 11, 3).unwrap();
    assert_eq!(ok.len(), 3869);
}

#[test]
fn an_empty_or_non_finite_logo_npy_is_an_error_not_a_panic() {
    let dir = scratch("bad-npy");
    let empty = dir.join("empty.npy");
    logo_data::write_npy(&empty, &[0, 14], &[]).unwrap();
    let err = import_logo_npy(&empty, "Hopper-v4", 11, 3, 1000)
        .unwrap_err()
        .to_string();
    assert!(err.contains("empty.npy"), "{err}");
    let nan = dir.join("nan.npy");
    let mut values = vec![0.0; 2 * 14];
    values[14 + 12] = f64::NAN;
    logo_data::write_npy(&nan, &[2, 14], &values).unwrap();
    let err = import_logo_npy(&nan, "Hopper-v4", 11, 3, 1000)
        .unwrap_err()
        .to_string();
    assert!(err.contains("row 1") && err.contains("action"), "{err}");
}

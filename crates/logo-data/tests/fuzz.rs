//! Generated corruptions of valid files, for every data loader: truncations, bit flips and
//! 8-byte fields overwritten with 0, 1, the type's maximum, NaN, ±inf. Each must end in
//! an error or in a dataset that passes its own validation; never a panic. CI runs
//! `PROPTEST_CASES` cases per loader (64 unless set); docs/reliability.md has the longer
//! run.

mod common;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use common::corrupt::{apply, config, mutation, no_panic};
use common::{python, repo, scratch, script};
use logo_data::import::import_d4rl;
use logo_data::{Dataset, read_minari, read_npy, write_npy};
use proptest::prelude::*;

/// A D4RL file written by h5py (gzip-compressed observations, next_observations), once.
fn d4rl_file() -> Option<&'static PathBuf> {
    static FILE: OnceLock<Option<PathBuf>> = OnceLock::new();
    FILE.get_or_init(|| {
        let python = python()?;
        let file = scratch("d4rl-source").join("d4rl.hdf5");
        script(&python, &["d4rl", file.to_str().unwrap()]);
        Some(file)
    })
    .as_ref()
}

/// A dataset a loader accepted must satisfy what loaders promise.
fn accepted(dataset: &Dataset, path: &Path) -> Result<(), TestCaseError> {
    dataset
        .validate(path)
        .map_err(|e| TestCaseError::fail(format!("accepted an invalid dataset: {e}")))?;
    for e in &dataset.episodes {
        prop_assert!(
            e.observations
                .iter()
                .chain(&e.actions)
                .chain(&e.rewards)
                .all(|v| v.is_finite()),
            "accepted a non-finite value"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    /// The header length a preamble declares, whatever it is, must be checked against the
    /// file before anything is allocated for it (a 4 GiB length once aborted the process).
    #[test]
    fn npy_header_lengths(version in 1u8..=3, length in any::<u32>(), tail in 0usize..300) {
        let mut bytes = b"\x93NUMPY".to_vec();
        bytes.extend([version, 0]);
        match version {
            1 => bytes.extend((length as u16).to_le_bytes()),
            _ => bytes.extend(length.to_le_bytes()),
        }
        bytes.extend(std::iter::repeat_n(b' ', tail));
        let dir = scratch("npy-header");
        let path = dir.join("header.npy");
        std::fs::write(&path, &bytes).unwrap();
        prop_assert!(no_panic("read_npy", || read_npy(&path))?.is_err());
    }

    #[test]
    fn npy_files(mutations in prop::collection::vec(mutation(), 1..4)) {
        let dir = scratch("npy");
        let good = dir.join("good.npy");
        let data: Vec<f64> = (0..60).map(|k| k as f64 * 0.25).collect();
        write_npy(&good, &[12, 5], &data).unwrap();
        let bad = dir.join("bad.npy");
        std::fs::write(&bad, apply(&std::fs::read(&good).unwrap(), &mutations)).unwrap();
        if let Ok(array) = no_panic("read_npy", || read_npy(&bad))? {
            let count = array.shape.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
            prop_assert_eq!(count, Some(array.data.len()));
        }
        // The demonstrations loader on top of it (LOGO's .npy form: [obs ‖ action] rows).
        let loaded = no_panic("Demonstrations::from_npy", || {
            logo_data::Demonstrations::from_npy(&bad, 3, 2)
        })?;
        if let Ok(demos) = loaded {
            prop_assert!(!demos.is_empty());
        }
    }

    #[test]
    fn minari_datasets(mutations in prop::collection::vec(mutation(), 1..4)) {
        let source = repo().join("data/logo/inverted_double_pendulum/data");
        let dir = scratch("minari");
        std::fs::create_dir_all(dir.join("data")).unwrap();
        let h5 = std::fs::read(source.join("main_data.hdf5")).unwrap();
        std::fs::write(dir.join("data/main_data.hdf5"), apply(&h5, &mutations)).unwrap();
        std::fs::copy(source.join("metadata.json"), dir.join("data/metadata.json")).unwrap();
        if let Ok(dataset) = no_panic("read_minari", || read_minari(&dir))? {
            accepted(&dataset, &dir)?;
        }
    }

    #[test]
    fn minari_metadata(mutations in prop::collection::vec(mutation(), 1..4)) {
        let source = repo().join("data/logo/inverted_double_pendulum/data");
        let dir = scratch("minari-meta");
        std::fs::create_dir_all(dir.join("data")).unwrap();
        std::fs::copy(source.join("main_data.hdf5"), dir.join("data/main_data.hdf5")).unwrap();
        let meta = std::fs::read(source.join("metadata.json")).unwrap();
        std::fs::write(dir.join("data/metadata.json"), apply(&meta, &mutations)).unwrap();
        if let Ok(dataset) = no_panic("read_minari", || read_minari(&dir))? {
            accepted(&dataset, &dir)?;
        }
    }

    #[test]
    fn d4rl_files(mutations in prop::collection::vec(mutation(), 1..4)) {
        let Some(source) = d4rl_file() else { return Ok(()) };
        let bad = scratch("d4rl").join("bad.hdf5");
        std::fs::write(&bad, apply(&std::fs::read(source).unwrap(), &mutations)).unwrap();
        if let Ok(dataset) = no_panic("import_d4rl", || import_d4rl(&bad))? {
            accepted(&dataset, &bad)?;
        }
    }
}

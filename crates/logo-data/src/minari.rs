//! Minari's HDF5 layout (minari 0.5.4): a dataset folder holding `data/main_data.hdf5`
//! (one `episode_{i}` group per episode: `observations` [T+1, obs], `actions` [T, act],
//! `rewards` [T], `terminations` [T], `truncations` [T]; attributes `id`, `total_steps`)
//! and `data/metadata.json`. Read and written with `hdf5-pure` (pure Rust: no system
//! HDF5 library to install).

use std::path::{Path, PathBuf};

use hdf5_pure::{AttrValue, Datatype, File, FileBuilder};
use hdf5_pure::{DatatypeByteOrder, EnumTypeBuilder, FixedPointLayout};
use serde_json::{Map, Value};

use crate::DataError;
use crate::dataset::{Dataset, Episode};

pub const MINARI_VERSION: &str = "0.5.4";

fn hdf5_path(dir: &Path) -> PathBuf {
    dir.join("data").join("main_data.hdf5")
}

fn metadata_path(dir: &Path) -> PathBuf {
    dir.join("data").join("metadata.json")
}

/// The share of a recorded dataset's episodes that reached the goal, as its recorder wrote
/// it (`metadata.json`'s `logo_recording.success_rate`: `logo data record`,
/// `logo_rl.record`). An error says what is missing: no Minari dataset at `dir`, or one
/// whose recording did not say (made elsewhere, or on a task without a goal).
pub fn recorded_success_rate(dir: &Path) -> Result<f64, String> {
    if !dir.exists() {
        return Err(format!("{}: no such file or folder", dir.display()));
    }
    if !is_minari_dir(dir) {
        return Err(format!(
            "{}: not a Minari dataset folder (a .npy records no success rate)",
            dir.display()
        ));
    }
    let meta = read_metadata(dir).map_err(|e| e.to_string())?;
    meta.get("logo_recording")
        .and_then(|r| r.get("success_rate"))
        .and_then(Value::as_f64)
        .ok_or_else(|| {
            format!(
                "{}: logo_recording.success_rate is not recorded (the dataset was made without a \
                 success rule, or not by logo data record / logo_rl.record)",
                metadata_path(dir).display()
            )
        })
}

/// A Minari dataset folder's `metadata.json`, which must be a JSON object.
fn read_metadata(dir: &Path) -> Result<Map<String, Value>, DataError> {
    let meta_path = metadata_path(dir);
    let text = std::fs::read_to_string(&meta_path).map_err(|source| DataError::Io {
        path: meta_path.clone(),
        source,
    })?;
    match serde_json::from_str(&text) {
        Ok(Value::Object(map)) => Ok(map),
        Ok(_) => Err(DataError::field(
            &meta_path,
            None,
            "(top level)",
            "expected a JSON object",
        )),
        Err(e) => Err(DataError::field(&meta_path, None, "(JSON)", &e.to_string())),
    }
}

/// Whether `path` looks like a Minari dataset folder.
pub fn is_minari_dir(path: &Path) -> bool {
    hdf5_path(path).is_file()
}

/// h5py's boolean: an enum {FALSE = 0, TRUE = 1} over a signed 8-bit integer.
fn bool_datatype() -> Datatype {
    let base = Datatype::FixedPoint {
        size: 1,
        byte_order: DatatypeByteOrder::LittleEndian,
        layout: FixedPointLayout {
            signed: true,
            bit_offset: 0,
            bit_precision: 8,
        },
    };
    EnumTypeBuilder::with_base(base)
        .value("FALSE", 0)
        .value("TRUE", 1)
        .build()
        .expect("0 and 1 fit an 8-bit base")
}

/// A gymnasium `Box` space serialised as minari does (a JSON string; unbounded limits
/// are Python's `Infinity` tokens).
pub fn box_space(low: &[f64], high: &[f64]) -> String {
    typed_box_space(low, high, "float64")
}

/// [`box_space`] of the given NumPy dtype (`"float32"`: as an env declares its space; the
/// dataset's arrays stay float64).
pub fn typed_box_space(low: &[f64], high: &[f64], dtype: &str) -> String {
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| match *x {
                x if x == f64::INFINITY => "Infinity".to_string(),
                x if x == f64::NEG_INFINITY => "-Infinity".to_string(),
                x => format!("{x:?}"),
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "{{\"type\": \"Box\", \"dtype\": \"{dtype}\", \"shape\": [{}], \"low\": [{}], \"high\": [{}]}}",
        low.len(),
        list(low),
        list(high)
    )
}

/// Writes `dataset` as a Minari dataset folder at `dir` (created; files replaced
/// atomically). Missing Minari metadata keys get defaults (unbounded spaces, this
/// version), and the totals are always recomputed.
pub fn write_minari(dataset: &Dataset, dir: &Path) -> Result<(), DataError> {
    dataset.validate(dir)?;
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| DataError::Io { path, source }
    };
    let data_dir = dir.join("data");
    std::fs::create_dir_all(&data_dir).map_err(io(&data_dir))?;

    let mut builder = FileBuilder::new();
    for (i, ep) in dataset.episodes.iter().enumerate() {
        let t = ep.steps() as u64;
        let group = builder.create_group(&format!("episode_{i}"));
        let mut group = group;
        group.set_attr("id", AttrValue::I64(i as i64));
        group.set_attr("total_steps", AttrValue::I64(t as i64));
        group
            .create_dataset("observations")
            .with_f64_data(&ep.observations)
            .with_shape(&[t + 1, dataset.obs_dim as u64]);
        group
            .create_dataset("actions")
            .with_f64_data(&ep.actions)
            .with_shape(&[t, dataset.act_dim as u64]);
        group.create_dataset("rewards").with_f64_data(&ep.rewards);
        for (name, flags) in [
            ("terminations", &ep.terminations),
            ("truncations", &ep.truncations),
        ] {
            let bytes: Vec<u8> = flags.iter().map(|f| u8::from(*f)).collect();
            group
                .create_dataset(name)
                .with_enum_u8_data(bool_datatype(), &bytes);
        }
        builder.add_group(group.finish());
    }
    let h5 = hdf5_path(dir);
    let bytes = builder.finish().map_err(|e| DataError::Hdf5 {
        path: h5.clone(),
        reason: e.to_string(),
    })?;

    let mut metadata = dataset.metadata.clone();
    let unbounded = |n: usize| box_space(&vec![f64::NEG_INFINITY; n], &vec![f64::INFINITY; n]);
    let defaults = [
        ("dataset_id", Value::from("logo/unnamed-v0")),
        ("minari_version", Value::from(MINARI_VERSION)),
        ("observation_space", Value::from(unbounded(dataset.obs_dim))),
        ("action_space", Value::from(unbounded(dataset.act_dim))),
    ];
    for (key, value) in defaults {
        metadata.entry(key).or_insert(value);
    }
    metadata.insert("data_format".into(), "hdf5".into());
    metadata.insert("jpeg_encoding".into(), false.into());
    metadata.insert("total_episodes".into(), dataset.episodes.len().into());
    metadata.insert("total_steps".into(), dataset.total_steps().into());
    metadata.insert("dataset_size".into(), Value::from(bytes.len() as f64 / 1e6));
    let json = serde_json::to_string_pretty(&Value::Object(metadata)).expect("JSON values");

    for (path, content) in [(h5, bytes), (metadata_path(dir), json.into_bytes())] {
        let tmp = path.with_extension("tmp");
        std::fs::write(&tmp, content).map_err(io(&tmp))?;
        std::fs::rename(&tmp, &path).map_err(io(&path))?;
    }
    Ok(())
}

/// A 1- or 2-D numeric HDF5 dataset as `f64` values, with its rows and columns. `bad`
/// makes the error for a field.
/// A float table (1 or 2 dims) of at most `max_values` values (see [`max_values`]).
pub(crate) fn read_table(
    dataset: Result<hdf5_pure::Dataset, hdf5_pure::Error>,
    field: &str,
    bad: &dyn Fn(&str, String) -> DataError,
    max_values: u64,
) -> Result<(Vec<f64>, usize, usize), DataError> {
    let ds = dataset.map_err(|e| bad(field, format!("missing or unreadable: {e}")))?;
    let shape = ds.shape().map_err(|e| bad(field, e.to_string()))?;
    let (rows, cols) = match shape.as_slice() {
        [rows] => (*rows, 1),
        [rows, cols] => (*rows, *cols),
        other => return Err(bad(field, format!("shape {other:?}, expected 1 or 2 dims"))),
    };
    // The shape comes from the file: refuse one that cannot be this file's data before
    // anything is allocated for it.
    let count = rows
        .checked_mul(cols)
        .filter(|&n| n <= max_values)
        .ok_or_else(|| {
            bad(
                field,
                format!("shape {shape:?} is larger than the file can hold"),
            )
        })?;
    let (rows, cols) = (rows as usize, cols as usize);
    let values = ds.read_f64().map_err(|e| bad(field, e.to_string()))?;
    if values.len() as u64 != count {
        return Err(bad(
            field,
            format!("{} values for shape {shape:?}", values.len()),
        ));
    }
    Ok((values, rows, cols))
}

/// The most values an HDF5 file of `bytes` bytes can hold: one byte per value,
/// compressed at most 1032:1 (deflate's limit).
pub(crate) fn max_values(bytes: usize) -> u64 {
    (bytes as u64).saturating_mul(1032)
}

/// A boolean (or 0/1 integer) HDF5 dataset.
pub(crate) fn read_flags(
    dataset: Result<hdf5_pure::Dataset, hdf5_pure::Error>,
    field: &str,
    bad: &dyn Fn(&str, String) -> DataError,
) -> Result<Vec<bool>, DataError> {
    let ds = dataset.map_err(|e| bad(field, format!("missing or unreadable: {e}")))?;
    let raw = ds.read_u8().map_err(|e| bad(field, e.to_string()))?;
    Ok(raw.into_iter().map(|b| b != 0).collect())
}

/// Reads a Minari dataset folder (as written by `minari` 0.5.4 or by [`write_minari`])
/// and validates it.
pub fn read_minari(dir: &Path) -> Result<Dataset, DataError> {
    let h5 = hdf5_path(dir);
    let metadata = read_metadata(dir)?;
    let hdf5_error = |e: hdf5_pure::Error| DataError::Hdf5 {
        path: h5.clone(),
        reason: e.to_string(),
    };
    let bytes = std::fs::read(&h5).map_err(|source| DataError::Io {
        path: h5.clone(),
        source,
    })?;
    let limit = max_values(bytes.len());
    let file = File::from_bytes(bytes).map_err(hdf5_error)?;
    let mut names: Vec<(usize, String)> = Vec::new();
    for name in file.root().groups().map_err(hdf5_error)? {
        let index = name
            .strip_prefix("episode_")
            .and_then(|i| i.parse::<usize>().ok())
            .ok_or_else(|| DataError::field(&h5, None, &name, "a group that is not episode_{i}"))?;
        names.push((index, name));
    }
    names.sort();
    let (mut obs_dim, mut act_dim) = (0, 0);
    let mut episodes = Vec::with_capacity(names.len());
    for (k, (index, name)) in names.iter().enumerate() {
        if *index != k {
            return Err(DataError::field(
                &h5,
                Some(k),
                "episode ids",
                &format!("found {name}, expected episode_{k} (ids must be 0..N)"),
            ));
        }
        let bad = |field: &str, reason: String| DataError::field(&h5, Some(k), field, &reason);
        let group = file
            .group(name)
            .map_err(|e| bad("(group)", e.to_string()))?;
        let matrix = |field: &str| read_table(group.dataset(field), field, &bad, limit);
        let flags = |field: &str| read_flags(group.dataset(field), field, &bad);
        let (observations, _, o) = matrix("observations")?;
        let (actions, _, a) = matrix("actions")?;
        let (rewards, _, _) = matrix("rewards")?;
        if k == 0 {
            (obs_dim, act_dim) = (o, a);
        } else if (o, a) != (obs_dim, act_dim) {
            return Err(bad(
                "observations/actions",
                format!("dims ({o}, {a}), episode 0 has ({obs_dim}, {act_dim})"),
            ));
        }
        episodes.push(Episode {
            observations,
            actions,
            rewards,
            terminations: flags("terminations")?,
            truncations: flags("truncations")?,
        });
    }
    Dataset::checked(obs_dim, act_dim, episodes, metadata, &h5)
}

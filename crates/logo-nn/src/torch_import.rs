//! Import of the LOGO reference's behaviour-cloning policies (PyTorch state dicts,
//! `../shared/reference/logo-demos/<env>_bc_policy.pt`), so training can start from BC as
//! the reference's `--init-BC` does.
//!
//! The reference's keys: `affine_layers.{i}.weight` (out, in) and `.bias` for the tanh
//! hidden layers, `action_mean.weight` / `.bias` for the output, `action_log_std` (1, act).
//! PyTorch stores Linear weights as (out, in); burn as (in, out): they are transposed.

use std::path::{Path, PathBuf};

use burn::module::Module;
use burn::tensor::backend::Backend;
use burn_store::pytorch::PytorchReader;

use crate::flat::vec_to_params;
use crate::policy::{GaussianPolicy, PolicyConfig};

#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error("{}: cannot read as a PyTorch file: {reason}", path.display())]
    Read { path: PathBuf, reason: String },
    #[error("{}: no tensor {key:?} (a LOGO reference policy has affine_layers.*, action_mean.*, action_log_std)", path.display())]
    Missing { path: PathBuf, key: String },
    #[error("{}: {key} has shape {found:?}, expected {expected}", path.display())]
    Shape {
        path: PathBuf,
        key: String,
        found: Vec<usize>,
        expected: String,
    },
    #[error("{}: {key} holds a non-finite value", path.display())]
    NonFinite { path: PathBuf, key: String },
}

/// A `(shape, values)` pair read from the state dict.
type Raw = (Vec<usize>, Vec<f64>);

fn tensor(reader: &PytorchReader, path: &Path, key: &str) -> Result<Raw, ImportError> {
    let missing = || ImportError::Missing {
        path: path.to_path_buf(),
        key: key.to_string(),
    };
    let snapshot = reader.get(key).ok_or_else(missing)?;
    let data = snapshot.to_data().map_err(|e| ImportError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    let shape = data.shape.to_vec();
    let values = data
        .convert::<f64>()
        .into_vec::<f64>()
        .map_err(|e| ImportError::Read {
            path: path.to_path_buf(),
            reason: format!("{key}: {e:?}"),
        })?;
    if values.iter().any(|v| !v.is_finite()) {
        return Err(ImportError::NonFinite {
            path: path.to_path_buf(),
            key: key.to_string(),
        });
    }
    Ok((shape, values))
}

/// Appends a PyTorch (out, in) weight transposed to (in, out), then its bias.
fn push_layer(flat: &mut Vec<f64>, (shape, w): &Raw, (_, b): &Raw) {
    let (out, inp) = (shape[0], shape[1]);
    flat.extend((0..inp).flat_map(|i| (0..out).map(move |o| w[o * inp + i])));
    flat.extend_from_slice(b);
}

/// The shape error for `key` of the file at `path`.
fn shape_error(path: &Path, key: &str, found: &[usize], expected: String) -> ImportError {
    ImportError::Shape {
        path: path.to_path_buf(),
        key: key.to_string(),
        found: found.to_vec(),
        expected,
    }
}

/// The hidden layers `affine_layers.{i}`, in order, each fed by the previous one.
fn hidden_layers(reader: &PytorchReader, path: &Path) -> Result<Vec<(Raw, Raw)>, ImportError> {
    let mut layers: Vec<(Raw, Raw)> = Vec::new();
    while reader
        .get(&format!("affine_layers.{}.weight", layers.len()))
        .is_some()
    {
        let i = layers.len();
        let (wk, bk) = (
            format!("affine_layers.{i}.weight"),
            format!("affine_layers.{i}.bias"),
        );
        let (w, b) = (tensor(reader, path, &wk)?, tensor(reader, path, &bk)?);
        if w.0.len() != 2 {
            return Err(shape_error(path, &wk, &w.0, "(out, in)".into()));
        }
        if let Some((prev, _)) = layers.last()
            && prev.0[0] != w.0[1]
        {
            let expected = format!("({}, {})", w.0[0], prev.0[0]);
            return Err(shape_error(path, &wk, &w.0, expected));
        }
        if b.0 != [w.0[0]] {
            return Err(shape_error(path, &bk, &b.0, format!("({},)", w.0[0])));
        }
        layers.push((w, b));
    }
    if layers.is_empty() {
        return Err(ImportError::Missing {
            path: path.to_path_buf(),
            key: "affine_layers.0.weight".into(),
        });
    }
    Ok(layers)
}

/// The output layer (`action_mean`) fed by `last_hidden` units, and `action_log_std`.
fn output_layer(
    reader: &PytorchReader,
    path: &Path,
    last_hidden: usize,
) -> Result<(Raw, Raw, Raw), ImportError> {
    let mean_w = tensor(reader, path, "action_mean.weight")?;
    let act_dim = mean_w.0[0];
    if mean_w.0 != [act_dim, last_hidden] {
        let expected = format!("(act, {last_hidden})");
        return Err(shape_error(path, "action_mean.weight", &mean_w.0, expected));
    }
    let mean_b = tensor(reader, path, "action_mean.bias")?;
    if mean_b.0 != [act_dim] {
        let expected = format!("({act_dim},)");
        return Err(shape_error(path, "action_mean.bias", &mean_b.0, expected));
    }
    let log_std = tensor(reader, path, "action_log_std")?;
    if log_std.1.len() != act_dim {
        let expected = format!("(1, {act_dim})");
        return Err(shape_error(path, "action_log_std", &log_std.0, expected));
    }
    Ok((mean_w, mean_b, log_std))
}

/// Reads a LOGO reference policy into a [`GaussianPolicy`] whose sizes come from the file.
pub fn load_reference_policy<B: Backend>(
    path: &Path,
    device: &B::Device,
) -> Result<GaussianPolicy<B>, ImportError> {
    let reader = PytorchReader::new(path).map_err(|e| ImportError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    let layers = hidden_layers(&reader, path)?;
    let obs_dim = layers[0].0.0[1];
    let hidden: Vec<usize> = layers.iter().map(|(w, _)| w.0[0]).collect();
    let last_hidden = *hidden.last().expect("at least one layer");
    let (mean_w, mean_b, log_std) = output_layer(&reader, path, last_hidden)?;
    let act_dim = mean_w.0[0];

    let mut flat = Vec::new();
    for (w, b) in &layers {
        push_layer(&mut flat, w, b);
    }
    push_layer(&mut flat, &mean_w, &mean_b);
    flat.extend_from_slice(&log_std.1);
    let config = PolicyConfig {
        obs_dim,
        act_dim,
        hidden,
        log_std_init: 0.0,
    };
    let policy = config.init::<B>(device);
    debug_assert_eq!(flat.len(), policy.num_params());
    Ok(vec_to_params(policy, &flat))
}

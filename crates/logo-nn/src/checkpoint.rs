//! Checkpoints: safetensors files (float64 tensors named by module path, e.g.
//! `policy.mean.layers.0.weight`) with the run's metadata as JSON in the header. Written
//! atomically; loading checks every name and shape; float64 values round-trip bit-exactly.
//! Any safetensors reader opens them (Python: `safetensors.safe_open(path, "np")`).

use std::collections::{BTreeMap, HashMap};
use std::io::Write;
use std::path::{Path, PathBuf};

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::tensor::backend::Backend;
use burn::tensor::{Tensor, TensorData};
use safetensors::tensor::{Dtype, TensorView};
use serde::{Deserialize, Serialize};

use crate::flat::to_f64;

/// The parts of a checkpoint that a policy alone keeps: tensor prefixes and networks.
const POLICY_PARTS: [&str; 2] = ["policy", "observation_norm"];
/// The metadata a policy alone keeps: what loading and evaluating it read.
const POLICY_EXTRA: [&str; 4] = ["config", "engine", "engines", "samples"];
/// The metadata key that marks a policy alone, and says which file it came from.
const POLICY_ALONE: &str = "exported";

/// Bumped when the layout of names or metadata changes incompatibly.
pub const FORMAT_VERSION: u32 = 1;
const META_KEY: &str = "logo_rl";

/// What a checkpoint says about the run that wrote it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckpointMeta {
    pub format_version: u32,
    pub env_id: String,
    pub obs_dim: usize,
    pub act_dim: usize,
    /// Hidden sizes of each network in the file, by prefix (`policy`, `critic`, ...).
    pub networks: BTreeMap<String, Vec<usize>>,
    pub algorithm: String,
    pub iteration: u64,
    pub seed: u64,
    /// Observation-normaliser state, or anything else the algorithm must restore.
    #[serde(default)]
    pub extra: serde_json::Value,
}

impl CheckpointMeta {
    pub fn new(env_id: &str, obs_dim: usize, act_dim: usize, algorithm: &str) -> Self {
        Self {
            format_version: FORMAT_VERSION,
            env_id: env_id.to_string(),
            obs_dim,
            act_dim,
            networks: BTreeMap::new(),
            algorithm: algorithm.to_string(),
            iteration: 0,
            seed: 0,
            extra: serde_json::Value::Null,
        }
    }
}

/// The metadata's sizes build networks before their tensors are read: each must be at
/// least 1, and every weight matrix they imply must fit in the `held` numbers the file
/// actually stores (so a corrupted size is refused before anything is allocated for it).
fn check_sizes(path: &Path, meta: &CheckpointMeta, held: usize) -> Result<(), CheckpointError> {
    let refused = |reason: String| CheckpointError::Meta {
        path: path.to_path_buf(),
        reason,
    };
    for (key, value) in [("obs_dim", meta.obs_dim), ("act_dim", meta.act_dim)] {
        if value == 0 || value > held {
            return Err(refused(format!(
                "{key} = {value}, expected 1..={held} (the numbers this file holds)"
            )));
        }
    }
    for (name, hidden) in &meta.networks {
        let dims: Vec<usize> = std::iter::once(meta.obs_dim)
            .chain(hidden.iter().copied())
            .chain(std::iter::once(1))
            .collect();
        let fits = dims.iter().all(|&d| d >= 1)
            && dims
                .windows(2)
                .all(|w| w[0].checked_mul(w[1]).is_some_and(|n| n <= held));
        if !fits {
            return Err(refused(format!(
                "networks.{name}: hidden sizes {hidden:?} do not fit the {held} numbers this file holds"
            )));
        }
    }
    Ok(())
}

#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: not a safetensors file ({reason})", path.display())]
    Format { path: PathBuf, reason: String },
    #[error("{}: not a logo-rl checkpoint: {reason}", path.display())]
    Meta { path: PathBuf, reason: String },
    #[error("{}: tensor {name} is missing", path.display())]
    Missing { path: PathBuf, name: String },
    #[error("{}: tensor {name} has shape {found:?}, the network expects {expected:?}", path.display())]
    Shape {
        path: PathBuf,
        name: String,
        expected: Vec<usize>,
        found: Vec<usize>,
    },
    #[error("{}: tensor {name} is {found}, expected F64", path.display())]
    Dtype {
        path: PathBuf,
        name: String,
        found: String,
    },
    #[error("{}: tensor {name} holds a non-finite value", path.display())]
    NonFinite { path: PathBuf, name: String },
    #[error("{}: tensors {names:?} belong to {}", path.display(), owner(prefix))]
    Unexpected {
        path: PathBuf,
        prefix: String,
        names: Vec<String>,
    },
}

/// Named float64 tensors plus metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    pub meta: CheckpointMeta,
    /// name -> (shape, row-major values)
    tensors: BTreeMap<String, (Vec<usize>, Vec<f64>)>,
    /// Where it was read from, for error messages.
    origin: PathBuf,
}

/// Where the tensors of an `Unexpected` error were looked for.
fn owner(prefix: &str) -> String {
    match prefix {
        "" => "none of the networks".into(),
        _ => format!("no part of the network under {prefix:?}"),
    }
}

/// The start of every name under `prefix`: none where it is empty.
fn root_path(prefix: &str) -> Vec<String> {
    if prefix.is_empty() {
        Vec::new()
    } else {
        vec![prefix.to_string()]
    }
}

/// Collects a module's float parameters under their dotted paths.
struct Named<'a> {
    path: Vec<String>,
    out: &'a mut BTreeMap<String, (Vec<usize>, Vec<f64>)>,
}

impl<B: Backend> ModuleVisitor<B> for Named<'_> {
    fn enter_module(&mut self, name: &str, _container_type: &str) {
        self.path.push(name.to_string());
    }
    fn exit_module(&mut self, _name: &str, _container_type: &str) {
        self.path.pop();
    }
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<B, D>>) {
        let t = param.val();
        self.out
            .insert(self.path.join("."), (t.dims().to_vec(), to_f64(t)));
    }
}

/// Replaces a module's float parameters by the checkpoint's, checking names and shapes.
struct Apply<'a> {
    path: Vec<String>,
    checkpoint: &'a Checkpoint,
    used: Vec<String>,
    error: Option<CheckpointError>,
}

impl<B: Backend> ModuleMapper<B> for Apply<'_> {
    fn enter_module(&mut self, name: &str, _container_type: &str) {
        self.path.push(name.to_string());
    }
    fn exit_module(&mut self, _name: &str, _container_type: &str) {
        self.path.pop();
    }
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<B, D>>) -> Param<Tensor<B, D>> {
        let name = self.path.join(".");
        let origin = self.checkpoint.origin.clone();
        param.map(|t| {
            let expected = t.dims().to_vec();
            let found = match self.checkpoint.tensors.get(&name) {
                None => Err(CheckpointError::Missing {
                    path: origin,
                    name: name.clone(),
                }),
                Some((shape, _)) if *shape != expected => Err(CheckpointError::Shape {
                    path: origin,
                    name: name.clone(),
                    expected: expected.clone(),
                    found: shape.clone(),
                }),
                Some((_, values)) => Ok(values),
            };
            match found {
                Ok(values) if self.error.is_none() => {
                    self.used.push(name.clone());
                    let new =
                        Tensor::from_data(TensorData::new(values.clone(), t.shape()), &t.device());
                    if t.is_require_grad() {
                        new.require_grad()
                    } else {
                        new
                    }
                }
                Ok(_) => t,
                Err(e) => {
                    self.error.get_or_insert(e);
                    t
                }
            }
        })
    }
}

impl Checkpoint {
    pub fn new(meta: CheckpointMeta) -> Self {
        Self {
            meta,
            tensors: BTreeMap::new(),
            origin: PathBuf::from("<memory>"),
        }
    }

    /// Adds every float parameter of `module` as `<prefix>.<path>` (as `<path>` where
    /// `prefix` is empty: a module of modules names each by its field).
    pub fn insert<B: Backend, M: Module<B>>(&mut self, prefix: &str, module: &M) {
        module.visit(&mut Named {
            path: root_path(prefix),
            out: &mut self.tensors,
        });
    }

    /// `module` with its parameters read from `<prefix>.<path>`; every parameter must be
    /// there with its shape, and nothing else may be under the prefix (nothing else in
    /// the file, where `prefix` is empty).
    pub fn apply<B: Backend, M: Module<B>>(
        &self,
        prefix: &str,
        module: M,
    ) -> Result<M, CheckpointError> {
        let mut apply = Apply {
            path: root_path(prefix),
            checkpoint: self,
            used: Vec::new(),
            error: None,
        };
        let module = module.map(&mut apply);
        if let Some(e) = apply.error {
            return Err(e);
        }
        // Every name in the file is under the empty prefix.
        let dotted = if prefix.is_empty() {
            String::new()
        } else {
            format!("{prefix}.")
        };
        let unexpected: Vec<String> = self
            .tensors
            .keys()
            .filter(|k| k.starts_with(&dotted) && !apply.used.contains(k))
            .cloned()
            .collect();
        if !unexpected.is_empty() {
            return Err(CheckpointError::Unexpected {
                path: self.origin.clone(),
                prefix: prefix.to_string(),
                names: unexpected,
            });
        }
        Ok(module)
    }

    /// Makes this checkpoint its policy alone, the form a run is kept in (`logo export`):
    /// the policy's and the observation statistics' tensors as they are, the metadata that
    /// loading and evaluating a policy read (env, sizes, config, engine history), none of
    /// the critics, discriminator or resume state, and a mark saying which file it came
    /// from (`from`; a policy made from a policy keeps its first mark).
    pub fn make_policy_alone(&mut self, from: &str) {
        let kept = |name: &str| {
            POLICY_PARTS.iter().any(|p| {
                name.strip_prefix(p)
                    .is_some_and(|rest| rest.starts_with('.'))
            })
        };
        self.tensors.retain(|name, _| kept(name));
        self.meta
            .networks
            .retain(|name, _| POLICY_PARTS.contains(&name.as_str()));
        let extra = std::mem::take(&mut self.meta.extra);
        let mut alone: serde_json::Map<String, serde_json::Value> = POLICY_EXTRA
            .iter()
            .filter_map(|&key| {
                let value = extra.get(key).filter(|v| !v.is_null())?;
                Some((key.to_string(), value.clone()))
            })
            .collect();
        let mark = extra
            .get(POLICY_ALONE)
            .cloned()
            .unwrap_or_else(|| serde_json::json!({ "from": from }));
        alone.insert(POLICY_ALONE.into(), mark);
        self.meta.extra = serde_json::Value::Object(alone);
    }

    /// Whether this is a policy alone ([`Self::make_policy_alone`]): it has no learner
    /// state to resume.
    pub fn is_policy_alone(&self) -> bool {
        !self.meta.extra[POLICY_ALONE].is_null()
    }

    pub fn tensor_names(&self) -> impl Iterator<Item = &str> {
        self.tensors.keys().map(String::as_str)
    }

    /// The shape and values of the tensor `name`.
    pub fn tensor(&self, name: &str) -> Option<(&[usize], &[f64])> {
        self.tensors
            .get(name)
            .map(|(shape, values)| (shape.as_slice(), values.as_slice()))
    }

    /// Writes to a temporary file beside `path`, syncs it, then renames it over `path`:
    /// a crash leaves the old checkpoint or the new one, never half of one.
    pub fn save(&self, path: &Path) -> Result<(), CheckpointError> {
        let io = |source| CheckpointError::Io {
            path: path.to_path_buf(),
            source,
        };
        let bytes: Vec<Vec<u8>> = self
            .tensors
            .values()
            .map(|(_, v)| v.iter().flat_map(|x| x.to_le_bytes()).collect())
            .collect();
        let views: Vec<(String, TensorView)> = self
            .tensors
            .iter()
            .zip(&bytes)
            .map(|((name, (shape, _)), data)| {
                (
                    name.clone(),
                    TensorView::new(Dtype::F64, shape.clone(), data)
                        .expect("shape and byte count agree"),
                )
            })
            .collect();
        let meta = serde_json::to_string(&self.meta).expect("metadata serialises");
        let header = HashMap::from([(META_KEY.to_string(), meta)]);
        let buffer =
            safetensors::serialize(views, Some(header)).map_err(|e| CheckpointError::Format {
                path: path.to_path_buf(),
                reason: e.to_string(),
            })?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        let tmp = path.with_extension(format!("tmp.{}", std::process::id()));
        let mut file = std::fs::File::create(&tmp).map_err(io)?;
        file.write_all(&buffer)
            .and_then(|_| file.sync_all())
            .map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    }

    pub fn load(path: &Path) -> Result<Self, CheckpointError> {
        let bytes = std::fs::read(path).map_err(|source| CheckpointError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let format = |reason: String| CheckpointError::Format {
            path: path.to_path_buf(),
            reason,
        };
        let (_, header) =
            safetensors::SafeTensors::read_metadata(&bytes).map_err(|e| format(e.to_string()))?;
        let meta_err = |reason: String| CheckpointError::Meta {
            path: path.to_path_buf(),
            reason,
        };
        let meta_json = header
            .metadata()
            .as_ref()
            .and_then(|m| m.get(META_KEY))
            .ok_or_else(|| meta_err(format!("no {META_KEY:?} entry in the header metadata")))?;
        let meta: CheckpointMeta =
            serde_json::from_str(meta_json).map_err(|e| meta_err(e.to_string()))?;
        if meta.format_version != FORMAT_VERSION {
            return Err(meta_err(format!(
                "format version {} (this build reads version {FORMAT_VERSION})",
                meta.format_version
            )));
        }
        let st =
            safetensors::SafeTensors::deserialize(&bytes).map_err(|e| format(e.to_string()))?;
        let mut tensors = BTreeMap::new();
        for (name, view) in st.tensors() {
            if view.dtype() != Dtype::F64 {
                return Err(CheckpointError::Dtype {
                    path: path.to_path_buf(),
                    name,
                    found: format!("{:?}", view.dtype()),
                });
            }
            let values: Vec<f64> = view
                .data()
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                .collect();
            if values.iter().any(|v| !v.is_finite()) {
                return Err(CheckpointError::NonFinite {
                    path: path.to_path_buf(),
                    name,
                });
            }
            tensors.insert(name, (view.shape().to_vec(), values));
        }
        let held: usize = tensors.values().map(|(_, v)| v.len()).sum();
        check_sizes(path, &meta, held)?;
        Ok(Self {
            meta,
            tensors,
            origin: path.to_path_buf(),
        })
    }
}

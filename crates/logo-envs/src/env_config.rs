//! An env as a config names it: `env = "SparseHopper-v4"` (any id of the registry), or a
//! table that makes a dense task's reward sparse by a rule of the config's choosing:
//!
//! ```toml
//! [env]
//! id = "Hopper-v4"
//! sparse = { kind = "distance", threshold = 2.0 }
//! ```
//!
//! A table whose rule is LOGO's for its task builds the same env as the `Sparse<id>`
//! name (same id, same numbers), so either form resumes the other's runs.

use std::fmt;

use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::registry::{EnvFactory, EnvOptions, canonical_id, dense_id, sparse_id};
use crate::{EnvError, SparseRule};

#[derive(Debug, Clone, PartialEq)]
pub struct EnvConfig {
    /// A registry id (`Hopper-v4`, `SparseHopper-v4`, `Hopper-v4+distance(5)`).
    pub id: String,
    /// The rule that makes `id`'s reward sparse; only with a dense id.
    pub sparse: Option<SparseRule>,
}

impl EnvConfig {
    /// A registry id alone, as `env = "<id>"` reads.
    pub fn named(id: &str) -> Self {
        Self {
            id: id.to_string(),
            sparse: None,
        }
    }

    /// Builds the factory (loads the model); errors name the id and what is wrong.
    pub fn factory(&self) -> Result<EnvFactory, EnvError> {
        let options = EnvOptions {
            sparse: self.sparse,
            ..EnvOptions::default()
        };
        EnvFactory::new(&self.id, &options)
    }

    /// The id the built env reports (its `spec().id`, a checkpoint's `env_id`).
    pub fn env_id(&self) -> Result<String, EnvError> {
        match self.sparse {
            Some(rule) => sparse_id(&self.id, rule),
            None => canonical_id(&self.id),
        }
    }

    /// The dense task (`Hopper-v4` for every sparse form of it).
    pub fn dense_id(&self) -> &str {
        dense_id(&self.id)
    }

    /// Whether the id and rule make an env, without loading its model; the message says
    /// what is wrong, for a config's `key`.
    pub fn validate(&self, key: &str) -> Result<(), EnvKeyError> {
        self.env_id().map(drop).map_err(|source| EnvKeyError {
            key: key.to_string(),
            source,
        })
    }
}

/// An env that a config's `key` names and that cannot be made.
#[derive(Debug, thiserror::Error)]
#[error("{key}: {source}")]
pub struct EnvKeyError {
    pub key: String,
    pub source: EnvError,
}

impl fmt::Display for EnvConfig {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.sparse {
            Some(rule) => write!(f, "{} (sparse: {})", self.id, rule.describe()),
            None => f.write_str(&self.id),
        }
    }
}

/// The table form's fields.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Table {
    id: String,
    sparse: Option<SparseRule>,
}

impl Serialize for EnvConfig {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        // Written back in the form it was read, so a run's config.toml reads as its own.
        match self.sparse {
            None => serializer.serialize_str(&self.id),
            Some(rule) => Table {
                id: self.id.clone(),
                sparse: Some(rule),
            }
            .serialize(serializer),
        }
    }
}

impl<'de> Deserialize<'de> for EnvConfig {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct StringOrTable;
        impl<'de> Visitor<'de> for StringOrTable {
            type Value = EnvConfig;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an env id, or a table with `id` and `sparse = { kind = ... }`")
            }
            fn visit_str<E: de::Error>(self, id: &str) -> Result<EnvConfig, E> {
                Ok(EnvConfig::named(id))
            }
            fn visit_map<M: MapAccess<'de>>(self, map: M) -> Result<EnvConfig, M::Error> {
                let table = Table::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(EnvConfig {
                    id: table.id,
                    sparse: table.sparse,
                })
            }
        }
        deserializer.deserialize_any(StringOrTable)
    }
}

//! `[algorithm] name = "…"` in a config: the keys that make an algorithm, laid under the
//! config's own (which win, key by key). The config then names the task, the budget and
//! the demonstrations, and the preset the rest: `name = "gail"` is `[guidance] step =
//! false` and `[reward] env = 0, discriminator = 1`. Each preset is the difference between
//! its `configs/<name>/` folder and `configs/trpo/` (or `configs/logo/` for LOGO's
//! variants); a test holds them to it. Each preset's keys are made from its entry in the
//! table of methods (`methods.rs`). A run stores the expanded tables and the method's
//! name (`method`), not `[algorithm]`.

use crate::error::Invalid;
use crate::methods::{Guided, METHODS, Start, method};
use serde::{Deserialize, Serialize};

/// Every preset's name: the table's methods that are configs of the trainer.
pub fn names() -> Vec<&'static str> {
    METHODS
        .iter()
        .filter(|m| m.command.is_none())
        .map(|m| m.name)
        .collect()
}

/// `[algorithm]`: the preset's name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AlgorithmPreset {
    pub name: String,
}

/// The preset's keys as TOML, made from its entry in the table: the entry's own keys,
/// then its improvement step's kind, its reward, its discriminator without the guidance
/// step and its start from the clone, where they differ from TRPO's; and what the method
/// takes of LOGO's guidance (and so needs of the config's `[guidance]`).
fn preset(name: &str) -> Option<(String, Guided)> {
    let method = method(name).filter(|m| m.command.is_none())?;
    // The entry's keys first: they may hold top-level keys (dtype), which must come
    // before any table.
    let mut keys = method.keys.to_string();
    if method.improvement != "trpo" {
        keys += &format!("[improvement]\nkind = {:?}\n", method.improvement);
    }
    if method.guided == Guided::Discriminator {
        keys += "[guidance]\nstep = false\n";
    }
    if method.reward != (1.0, 0.0) {
        let (env, discriminator) = method.reward;
        keys += &format!("[reward]\nenv = {env:?}\ndiscriminator = {discriminator:?}\n");
    }
    if method.start == Start::Clone {
        keys += "[init]\nkind = \"bc\"\n";
    }
    Some((keys, method.guided))
}

/// `table` with its `[algorithm]` preset's keys laid under it (the table's own win),
/// `lay_over` doing the laying. Without `[algorithm]`, `table` as it is.
pub fn expand(
    table: toml::Table,
    lay_over: fn(&mut toml::Table, toml::Table),
) -> Result<toml::Table, Invalid> {
    let Some(value) = table.get("algorithm") else {
        return Ok(table);
    };
    let chosen = AlgorithmPreset::deserialize(value.clone())
        .map_err(|e| format!("algorithm: {}", e.message()))?;
    let name = chosen.name.as_str();
    let (keys, guidance) = preset(name).ok_or_else(|| {
        format!(
            "algorithm.name = {name:?} is no preset; expected one of {}",
            names().join(", ")
        )
    })?;
    match (guidance, table.get("guidance")) {
        (Guided::No, Some(_)) => {
            return Err(format!(
                "algorithm.name = {name:?} has no discriminator or guidance step: remove \
                 [guidance] (demonstrations to clone go in [init] demos)"
            )
            .into());
        }
        (Guided::Discriminator | Guided::Step, None) => {
            return Err(format!(
                "algorithm.name = {name:?} needs [guidance] with its demos{}",
                if guidance == Guided::Step {
                    " and delta0, alpha, warmup"
                } else {
                    ""
                }
            )
            .into());
        }
        _ => {}
    }
    let mut expanded: toml::Table = toml::from_str(&keys).expect("a preset's keys are TOML");
    lay_over(&mut expanded, table);
    Ok(expanded)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_has_a_preset_and_its_keys_are_toml() {
        for name in names() {
            let (keys, _) = preset(name).unwrap_or_else(|| panic!("{name}"));
            toml::from_str::<toml::Table>(&keys).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert!(preset("sac").is_none());
    }
}

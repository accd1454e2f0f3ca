//! `[algorithm] name = "…"` in a config: the keys that make an algorithm, laid under the
//! config's own (which win, key by key). The config then names the task, the budget and
//! the demonstrations, and the preset the rest: `name = "gail"` is `[guidance] step =
//! false` and `[reward] env = 0, discriminator = 1`. Each preset is the difference between
//! its `configs/<name>/` folder and `configs/trpo/` (or `configs/logo/` for LOGO's
//! variants); a test holds them to it. A run stores the expanded tables, not the name.

use crate::error::Invalid;
use serde::{Deserialize, Serialize};

/// POfD's λ₁ in its preset, `configs/pofd/` and `logo compare` (docs/algorithms.md says why).
pub const POFD_LAMBDA: f64 = 0.1;

/// DAPG's (λ0, λ1) in its preset, `configs/dapg/` and `logo compare` (docs/algorithms.md).
pub const DAPG_LAMBDA: (f64, f64) = (0.1, 0.95);

/// Every preset's name.
pub const NAMES: [&str; 13] = [
    "trpo",
    "ppo",
    "bc-trpo",
    "gail",
    "pofd",
    "dapg",
    "logo",
    "logo-fast",
    "logo-ppo",
    "logo-cdq",
    "logo-ppo-cdq",
    "logo-clip-in-trpo",
    "logo-ppo-penalty",
];

/// `[algorithm]`: the preset's name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AlgorithmPreset {
    pub name: String,
}

/// The preset's keys as TOML, and whether the algorithm has LOGO's guidance step (and so
/// needs the config's `[guidance]`: its demonstrations, δ_0, α, K_δ).
fn preset(name: &str) -> Option<(String, Guidance)> {
    let improvement = |kind: &str| format!("[improvement]\nkind = \"{kind}\"\n");
    let twin = "[critic]\nkind = \"twin-min\"\n";
    let discriminator_alone = |env: f64, discriminator: f64| {
        format!(
            "[guidance]\nstep = false\n[reward]\nenv = {env:?}\ndiscriminator = {discriminator:?}\n"
        )
    };
    let preset = match name {
        "trpo" => (String::new(), Guidance::None),
        "ppo" => (improvement("ppo-clip"), Guidance::None),
        "bc-trpo" => ("[init]\nkind = \"bc\"\n".into(), Guidance::None),
        "gail" => (discriminator_alone(0.0, 1.0), Guidance::Discriminator),
        "pofd" => (
            discriminator_alone(1.0, POFD_LAMBDA),
            Guidance::Discriminator,
        ),
        "dapg" => (
            format!(
                "[init]\nkind = \"bc\"\n{}[demonstration_rows]\nlambda0 = {:?}\nlambda1 = {:?}\n",
                improvement("npg"),
                DAPG_LAMBDA.0,
                DAPG_LAMBDA.1
            ),
            Guidance::None,
        ),
        "logo" => (String::new(), Guidance::Step),
        "logo-fast" => (
            "dtype = \"f32\"\n[critic.fit]\nmethod = \"lbfgs\"\nsubsample = 0.25\n".into(),
            Guidance::Step,
        ),
        "logo-ppo" => (improvement("ppo-clip"), Guidance::Step),
        "logo-cdq" => (twin.into(), Guidance::Step),
        "logo-ppo-cdq" => (improvement("ppo-clip") + twin, Guidance::Step),
        "logo-clip-in-trpo" => (improvement("clip-in-trpo"), Guidance::Step),
        "logo-ppo-penalty" => (
            improvement("ppo-clip") + "[guidance.update]\nkind = \"ppo-penalty\"\n",
            Guidance::Step,
        ),
        _ => return None,
    };
    Some(preset)
}

/// What a preset needs of the config's `[guidance]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Guidance {
    /// None: the algorithm has no discriminator and no guidance step.
    None,
    /// Its demonstrations, for the discriminator (GAIL, POfD).
    Discriminator,
    /// LOGO's guidance, with its step.
    Step,
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
            NAMES.join(", ")
        )
    })?;
    match (guidance, table.get("guidance")) {
        (Guidance::None, Some(_)) => {
            return Err(format!(
                "algorithm.name = {name:?} has no discriminator or guidance step: remove \
                 [guidance] (demonstrations to clone go in [init] demos)"
            )
            .into());
        }
        (Guidance::Discriminator | Guidance::Step, None) => {
            return Err(format!(
                "algorithm.name = {name:?} needs [guidance] with its demos{}",
                if guidance == Guidance::Step {
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
        for name in NAMES {
            let (keys, _) = preset(name).unwrap_or_else(|| panic!("{name}"));
            toml::from_str::<toml::Table>(&keys).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert!(preset("sac").is_none());
    }
}

//! The methods of the table (`methods.rs`) as the trainer makes them: `logo algorithms`'
//! lines, the methods `logo compare` can make from one LOGO config ([`configure`]), and
//! the name of a config that does not say its own ([`identify`]: a config without
//! `[algorithm]` or `method`, a run older than the name).

use crate::bc::{InitConfig, InitKind};
use crate::config::{DecaySignal, GuidanceConfig, RewardConfig, TrainConfig};
use crate::dapg::DemonstrationRowsConfig;
use crate::error::Invalid;
pub use crate::methods::{Guided, METHODS, Method, POFD_LAMBDA, Start, method};
use crate::policy_update::{NpgConfig, PolicyUpdateConfig};
use serde::Deserialize;

/// `logo algorithms`: a line per algorithm, names aligned.
pub fn table() -> String {
    let width = METHODS.iter().map(|m| m.name.len()).max().unwrap_or(0);
    METHODS
        .iter()
        .map(|m| {
            let run = m
                .command
                .map_or(format!("configs/{}/", m.name), str::to_string);
            format!("{:width$}  {} [{}; {run}]\n", m.name, m.summary, m.paper)
        })
        .collect()
}

/// The methods `logo compare` (and [`configure`]) can make from one LOGO config: LOGO
/// first, then the table's order.
pub fn comparable() -> Vec<&'static str> {
    let others = METHODS.iter().filter(|m| m.comparable && m.name != "logo");
    std::iter::once("logo")
        .chain(others.map(|m| m.name))
        .collect()
}

/// `base`, a LOGO config (its task, budget, networks, TRPO settings and demonstrations),
/// made into algorithm `name` by the keys that make that algorithm and nothing else: the
/// same task and settings, so that the runs differ by their algorithm alone.
pub fn configure(base: &TrainConfig, name: &str) -> Result<TrainConfig, Invalid> {
    let guidance = base
        .guidance
        .as_ref()
        .filter(|g| g.step && g.demos.is_some())
        .ok_or_else(|| {
            "a comparison starts from a LOGO config: [guidance] with demos and its step \
             (delta0, alpha, warmup)"
                .to_string()
        })?;
    if base.init_policy.is_some() {
        return Err(
            "init_policy: a comparison starts each method from the seed's \
                    initialisation (bc-trpo from behaviour cloning); remove init_policy"
                .into(),
        );
    }
    let method = method(name).filter(|m| m.comparable).ok_or_else(|| {
        let known = comparable().join(", ");
        format!("unknown algorithm {name:?}: expected one of {known}")
    })?;
    let mut config = TrainConfig {
        init: InitConfig::default(),
        reward: RewardConfig {
            env: method.reward.0,
            discriminator: method.reward.1,
        },
        guidance: None,
        demonstration_rows: None,
        preset: None,
        method: Some(method.name.to_string()),
        ..base.clone()
    };
    match method.guided {
        Guided::Step => {
            config.guidance = Some(guidance.clone());
            config.init = base.init.clone();
        }
        // GAIL's and POfD's discriminator is LOGO's, without the guidance step.
        Guided::Discriminator => {
            config.guidance = Some(GuidanceConfig {
                step: false,
                delta0: None,
                alpha: None,
                warmup: None,
                update: None,
                critic: None,
                decay_on: DecaySignal::default(),
                decay_from: None,
                grow_back: false,
                ..guidance.clone()
            });
        }
        Guided::No => {}
    }
    if method.start == Start::Clone {
        // The guidance's demonstrations: named here where the method drops the guidance,
        // by default ([init] demos absent) where it keeps it.
        let demos = match method.guided {
            Guided::Step => base.init.demos.clone(),
            _ => guidance.demos.clone(),
        };
        config.init = InitConfig {
            kind: InitKind::Bc,
            demos,
            ..base.init.clone()
        };
    }
    match method.improvement {
        "trpo" => {}
        "npg" => config.improvement = PolicyUpdateConfig::Npg(npg_of(&base.improvement)),
        other => {
            return Err(
                format!("{name}: logo compare makes trpo or npg steps, not {other}").into(),
            );
        }
    }
    // The entry's own keys: DAPG's demonstration rows (from the guidance's demonstrations).
    let keys: toml::Table = toml::from_str(method.keys).expect("a method's keys are TOML");
    if let Some(rows) = keys.get("demonstration_rows") {
        config.demonstration_rows = Some(
            DemonstrationRowsConfig::deserialize(rows.clone())
                .map_err(|e| format!("{name}: demonstration_rows: {}", e.message()))?,
        );
    }
    config.validate()?;
    Ok(config)
}

/// The table's method whose makeup `config` has, for a config that names none (a
/// shipped config written out in full, a run older than the name): among the methods
/// with the same use of the guidance and the same reward sources, the one that matches
/// most of the improvement step's kind, the start, and its own keys (every one of them
/// in the config, with its value), the method with more keys first on a tie.
pub fn identify(config: &TrainConfig) -> &'static str {
    let guided = guided(config);
    let sources = |(env, discriminator): (f64, f64)| (env != 0.0, discriminator != 0.0);
    let reward = (config.reward.env, config.reward.discriminator);
    let start = match config.init.kind {
        InitKind::Bc => Start::Clone,
        InitKind::Random => Start::Random,
    };
    let written = toml::Table::try_from(config).unwrap_or_default();
    METHODS
        .iter()
        .filter(|m| m.command.is_none() && m.guided == guided)
        .filter(|m| sources(m.reward) == sources(reward))
        .max_by_key(|m| {
            let keys: toml::Table = toml::from_str(m.keys).expect("a method's keys are TOML");
            (
                m.improvement == config.improvement.kind(),
                m.start == start,
                holds(&written, &keys),
                keys_count(&keys),
                // The table's order on a full tie: the earlier entry.
                std::cmp::Reverse(METHODS.iter().position(|n| n.name == m.name)),
            )
        })
        .map_or("trpo", |m| m.name)
}

/// What `config` takes of LOGO's guidance.
pub fn guided(config: &TrainConfig) -> Guided {
    match &config.guidance {
        None => Guided::No,
        Some(g) if g.step => Guided::Step,
        Some(_) => Guided::Discriminator,
    }
}

/// Whether `config` has every key of `keys`, with the same value.
fn holds(config: &toml::Table, keys: &toml::Table) -> bool {
    keys.iter()
        .all(|(key, value)| match (value, config.get(key)) {
            (toml::Value::Table(inner), Some(toml::Value::Table(theirs))) => holds(theirs, inner),
            (value, Some(theirs)) => value == theirs,
            (_, None) => false,
        })
}

fn keys_count(keys: &toml::Table) -> usize {
    keys.values()
        .map(|v| v.as_table().map_or(1, keys_count))
        .sum()
}

/// The name checkpoints recorded before methods had names: "logo" with a guidance
/// step, "gail" or "pofd" with the discriminator's reward alone or mixed in, "dapg" with
/// demonstration rows, else "trpo". Read only to resume such a checkpoint.
pub fn name_before_the_table(config: &TrainConfig) -> &'static str {
    match &config.guidance {
        Some(g) if g.step => "logo",
        Some(_) if config.reward.env == 0.0 => "gail",
        Some(_) => "pofd",
        None if config.demonstration_rows.is_some() => "dapg",
        None => "trpo",
    }
}

/// DAPG's step with the natural-gradient settings of `step` where it has them.
fn npg_of(step: &PolicyUpdateConfig) -> NpgConfig {
    match step {
        PolicyUpdateConfig::Trpo(t) | PolicyUpdateConfig::ClipInTrpo(t) => NpgConfig::from(t),
        _ => NpgConfig::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each method of the trainer's configs has its folder with the four LOGO tasks (a
    /// renamed folder fails here), and the Figure 1 methods are in the table.
    #[test]
    fn every_listed_config_folder_has_the_four_tasks() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        for name in crate::presets::names() {
            for task in [
                "hopper",
                "walker2d",
                "halfcheetah",
                "inverted_double_pendulum",
            ] {
                let path = root.join(format!("configs/{name}/{task}.toml"));
                assert!(path.is_file(), "{name}: {} is missing", path.display());
            }
        }
        for name in ["trpo", "logo", "bc", "bc-trpo", "gail", "pofd", "dapg"] {
            assert!(method(name).is_some(), "{name} is not in the table");
        }
    }

    /// Every comparable method is one `configure` makes, and the names are unique.
    #[test]
    fn the_table_is_consistent() {
        let mut names: Vec<_> = METHODS.iter().map(|m| m.name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), METHODS.len(), "a name appears twice");
        for m in METHODS.iter().filter(|m| m.comparable) {
            assert!(
                m.command.is_none(),
                "{}: a comparable method is a config",
                m.name
            );
            assert!(
                matches!(m.improvement, "trpo" | "npg"),
                "{}: configure makes trpo or npg steps",
                m.name
            );
        }
        assert_eq!(comparable()[0], "logo");
    }
}

//! The methods of the table (`methods.rs`) as the trainer makes them: `logo algorithms`'
//! lines, the methods `logo compare` can make from one LOGO config ([`configure`]), and
//! the name checkpoints recorded before methods had names. (The method a config without
//! a name is: `TrainConfig::identify`.)

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
    take_guidance(&mut config, base, guidance, method);
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
    config.demonstration_rows = demonstration_rows(method)?;
    config.validate()?;
    Ok(config)
}

/// What `method` takes of the LOGO config's `guidance`: all of it (LOGO's variants, and
/// the config's `[init]` with it), its discriminator without the step (GAIL, POfD:
/// LOGO's discriminator, without the step's keys), or nothing.
fn take_guidance(
    config: &mut TrainConfig,
    base: &TrainConfig,
    guidance: &GuidanceConfig,
    method: &Method,
) {
    match method.guided {
        Guided::Step => {
            config.guidance = Some(guidance.clone());
            config.init = base.init.clone();
        }
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
}

/// The entry's own `[demonstration_rows]` (DAPG's λ0, λ1; the rows are the guidance's
/// demonstrations), or none.
fn demonstration_rows(method: &Method) -> Result<Option<DemonstrationRowsConfig>, Invalid> {
    let keys: toml::Table = toml::from_str(method.keys).expect("a method's keys are TOML");
    keys.get("demonstration_rows")
        .map(|rows| {
            DemonstrationRowsConfig::deserialize(rows.clone())
                .map_err(|e| format!("{}: demonstration_rows: {}", method.name, e.message()).into())
        })
        .transpose()
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

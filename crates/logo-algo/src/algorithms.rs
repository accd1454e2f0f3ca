//! The algorithms logo-rl trains, one line each: what `logo algorithms` prints. Each is a
//! configuration of the one trainer (a folder of `configs/` per task, and a preset a
//! config names by `[algorithm] name`), or `logo bc`; [`configure`] makes each baseline
//! from a LOGO config (`logo compare`).

use crate::bc::{InitConfig, InitKind};
use crate::config::{DecaySignal, GuidanceConfig, RewardConfig, TrainConfig};
use crate::dapg::DemonstrationRowsConfig;
use crate::error::Invalid;
use crate::policy_update::{NpgConfig, PolicyUpdateConfig};

/// One algorithm: its name, what it is in a line, where it comes from, and how to run it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Algorithm {
    pub name: &'static str,
    pub summary: &'static str,
    pub paper: &'static str,
    /// `configs/<folder>/<task>.toml`, or the command that runs it.
    pub run: &'static str,
}

/// Every algorithm, baselines first.
pub const ALGORITHMS: &[Algorithm] = &[
    Algorithm {
        name: "trpo",
        summary: "TRPO on the env reward alone",
        paper: "Schulman et al., 2015",
        run: "configs/trpo/",
    },
    Algorithm {
        name: "bc",
        summary: "behaviour cloning: the policy fitted to the demonstrations by maximum likelihood",
        paper: "(Pomerleau, 1991)",
        run: "logo bc",
    },
    Algorithm {
        name: "bc-trpo",
        summary: "behaviour cloning ([init] kind = \"bc\"), then TRPO on the env reward",
        paper: "(as in Rajeswaran et al., 2018)",
        run: "configs/bc-trpo/",
    },
    Algorithm {
        name: "gail",
        summary: "TRPO on the discriminator's −log D(s, a) alone; the env reward is unused",
        paper: "Ho & Ermon, 2016",
        run: "configs/gail/",
    },
    Algorithm {
        name: "pofd",
        summary: "TRPO on r + λ₁·(−log D(s, a)), the discriminator trained as LOGO's",
        paper: "Kang, Jie & Feng, 2018",
        run: "configs/pofd/",
    },
    Algorithm {
        name: "dapg",
        summary: "behaviour cloning, then natural gradient steps with the demonstrations as rows weighted λ0·λ1^k·max Â",
        paper: "Rajeswaran et al., 2018",
        run: "configs/dapg/",
    },
    Algorithm {
        name: "logo",
        summary: "TRPO step, then a guidance step toward the demonstrations (KL δ_k, decaying)",
        paper: "Rengarajan et al., ICLR 2022",
        run: "configs/logo/",
    },
    Algorithm {
        name: "logo-fast",
        summary: "LOGO in float32 with critic fits on a quarter of the rows (the fast preset)",
        paper: "logo-rl",
        run: "configs/logo-fast/",
    },
    Algorithm {
        name: "ppo",
        summary: "early-stopping PPO-Clip on the env reward alone (the seed paper's Algorithm 3)",
        paper: "Schulman et al., 2017",
        run: "configs/ppo/",
    },
    Algorithm {
        name: "logo-ppo",
        summary: "LOGO with both steps by early-stopping PPO-Clip",
        paper: "the seed paper",
        run: "configs/logo-ppo/",
    },
    Algorithm {
        name: "logo-cdq",
        summary: "LOGO with clipped double-Q critics (baseline min(V1, V2))",
        paper: "the seed paper",
        run: "configs/logo-cdq/",
    },
    Algorithm {
        name: "logo-ppo-cdq",
        summary: "LOGO with PPO-Clip steps and clipped double-Q critics (the seed paper's Algorithm 2)",
        paper: "the seed paper",
        run: "configs/logo-ppo-cdq/",
    },
    Algorithm {
        name: "logo-clip-in-trpo",
        summary: "LOGO with the clipped surrogate inside TRPO's natural-gradient step",
        paper: "the seed paper's code",
        run: "configs/logo-clip-in-trpo/",
    },
    Algorithm {
        name: "logo-ppo-penalty",
        summary: "LOGO: PPO-Clip improvement step, PPO-Penalty guidance step with δ_k its KL target (Algorithm 4)",
        paper: "the seed paper",
        run: "configs/logo-ppo-penalty/",
    },
];

/// `logo algorithms`: a line per algorithm, names aligned.
pub fn table() -> String {
    let width = ALGORITHMS.iter().map(|a| a.name.len()).max().unwrap_or(0);
    ALGORITHMS
        .iter()
        .map(|a| {
            format!(
                "{:width$}  {} [{}; {}]\n",
                a.name, a.summary, a.paper, a.run
            )
        })
        .collect()
}

/// The algorithms `logo compare` (and [`configure`]) can make from one LOGO config.
pub const COMPARABLE: [&str; 6] = ["logo", "trpo", "gail", "pofd", "bc-trpo", "dapg"];

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
    let mut config = TrainConfig {
        init: InitConfig::default(),
        reward: RewardConfig::default(),
        guidance: None,
        demonstration_rows: None,
        preset: None,
        ..base.clone()
    };
    // GAIL's and POfD's discriminator is LOGO's, without the guidance step.
    let discriminator_alone = || GuidanceConfig {
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
    };
    match name {
        "logo" => {
            config.guidance = Some(guidance.clone());
            config.init = base.init.clone();
        }
        "trpo" => {}
        "bc-trpo" | "dapg" => {
            config.init = InitConfig {
                kind: InitKind::Bc,
                demos: guidance.demos.clone(),
                ..base.init.clone()
            };
            if name == "dapg" {
                config.improvement = PolicyUpdateConfig::Npg(npg_of(&base.improvement));
                config.demonstration_rows = Some(DemonstrationRowsConfig {
                    demos: None,
                    lambda0: DAPG_LAMBDA.0,
                    lambda1: DAPG_LAMBDA.1,
                });
            }
        }
        "gail" | "pofd" => {
            config.guidance = Some(discriminator_alone());
            config.reward = match name {
                "gail" => RewardConfig {
                    env: 0.0,
                    discriminator: 1.0,
                },
                _ => RewardConfig {
                    env: 1.0,
                    discriminator: POFD_LAMBDA,
                },
            };
        }
        other => {
            let known = COMPARABLE.join(", ");
            return Err(format!("unknown algorithm {other:?}: expected one of {known}").into());
        }
    }
    config.validate()?;
    Ok(config)
}

/// DAPG's step with the natural-gradient settings of `step` where it has them.
fn npg_of(step: &PolicyUpdateConfig) -> NpgConfig {
    match step {
        PolicyUpdateConfig::Trpo(t) | PolicyUpdateConfig::ClipInTrpo(t) => NpgConfig::from(t),
        _ => NpgConfig::default(),
    }
}

pub use crate::presets::{DAPG_LAMBDA, POFD_LAMBDA};

#[cfg(test)]
mod tests {
    use super::*;

    /// Every algorithm with a config folder is a preset (`[algorithm] name`), and every
    /// preset is listed.
    #[test]
    fn the_listed_algorithms_are_the_presets() {
        let mut listed: Vec<&str> = ALGORITHMS
            .iter()
            .filter(|a| a.run.starts_with("configs/"))
            .map(|a| a.name)
            .collect();
        let mut presets = crate::presets::NAMES.to_vec();
        listed.sort();
        presets.sort();
        assert_eq!(listed, presets);
    }

    /// Each algorithm's configs exist for the four LOGO tasks (a renamed folder fails here).
    #[test]
    fn every_listed_config_folder_has_the_four_tasks() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        for a in ALGORITHMS.iter().filter(|a| a.run.starts_with("configs/")) {
            for task in [
                "hopper",
                "walker2d",
                "halfcheetah",
                "inverted_double_pendulum",
            ] {
                let path = root.join(a.run).join(format!("{task}.toml"));
                assert!(path.is_file(), "{}: {} is missing", a.name, path.display());
            }
        }
        let names: Vec<_> = ALGORITHMS.iter().map(|a| a.name).collect();
        for name in [
            "trpo",
            "logo",
            "bc",
            "bc-trpo",
            "gail",
            "pofd",
            "dapg",
            "logo-ppo-cdq",
        ] {
            assert!(names.contains(&name), "{name} is not listed");
        }
    }
}

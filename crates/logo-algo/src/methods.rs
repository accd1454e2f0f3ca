//! The table of methods: one entry per method logo-rl trains, and everything else (`logo
//! algorithms`, the `[algorithm] name` presets, `logo compare`'s list, the Python
//! package's lists and config folders, the name a run records) is read from it. Adding a
//! comparable method is one entry here plus its `configs/<name>/` folder
//! (docs/architecture.md walks through it).
//!
//! This file stands alone (no `use`): `crates/logo-py/build.rs` includes it to know which
//! config folders the package carries.

/// POfD's λ₁ (docs/algorithms.md says why).
pub const POFD_LAMBDA: f64 = 0.1;

/// What a method takes of LOGO's guidance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Guided {
    /// Neither the discriminator nor the guidance step.
    No,
    /// The discriminator, for the reward −log D, without the guidance step (GAIL, POfD).
    Discriminator,
    /// LOGO's guidance step toward the demonstrations (its discriminator, δ_0, α, K_δ).
    Step,
}

/// Where a method's policy starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// The seed's initialisation.
    Random,
    /// Behaviour cloning on the demonstrations (`[init] kind = "bc"`).
    Clone,
}

/// One method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Method {
    /// Its name: `[algorithm] name`, `configs/<name>/`, `logo compare --algorithms`, and
    /// what a run records (`config.toml`'s `method`, a checkpoint's algorithm).
    pub name: &'static str,
    /// What it is, in a line (`logo algorithms`).
    pub summary: &'static str,
    pub paper: &'static str,
    /// The command that runs it, for a method that is no config of the trainer (`logo
    /// bc`); None: its configs are `configs/<name>/`, and its name is a preset.
    pub command: Option<&'static str>,
    /// The improvement step's reward, per step `env`·r + `discriminator`·(−log D).
    pub reward: (f64, f64),
    /// The improvement step's kind (`[improvement] kind`).
    pub improvement: &'static str,
    pub guided: Guided,
    pub start: Start,
    /// The preset's keys beyond those the fields above make, as TOML: DAPG's
    /// demonstration rows, the fast preset's float type, a critic or guidance kind.
    pub keys: &'static str,
    /// Whether `logo compare` makes it from a LOGO config (the same task and settings).
    pub comparable: bool,
}

/// A method of the trainer: the env reward, TRPO, the seed's initialisation, no guidance,
/// comparable; each entry says how it differs.
const TRAINER: Method = Method {
    name: "",
    summary: "",
    paper: "",
    command: None,
    reward: (1.0, 0.0),
    improvement: "trpo",
    guided: Guided::No,
    start: Start::Random,
    keys: "",
    comparable: false,
};

/// Every method: the baselines first, in the LOGO paper's Figure 1 order.
pub const METHODS: &[Method] = &[
    Method {
        name: "trpo",
        summary: "TRPO on the env reward alone",
        paper: "Schulman et al., 2015",
        comparable: true,
        ..TRAINER
    },
    Method {
        name: "bc",
        summary: "behaviour cloning: the policy fitted to the demonstrations by maximum likelihood",
        paper: "(Pomerleau, 1991)",
        command: Some("logo bc"),
        start: Start::Clone,
        ..TRAINER
    },
    Method {
        name: "gail",
        summary: "TRPO on the discriminator's −log D(s, a) alone; the env reward is unused",
        paper: "Ho & Ermon, 2016",
        reward: (0.0, 1.0),
        guided: Guided::Discriminator,
        comparable: true,
        ..TRAINER
    },
    Method {
        name: "pofd",
        summary: "TRPO on r + λ₁·(−log D(s, a)), the discriminator trained as LOGO's",
        paper: "Kang, Jie & Feng, 2018",
        reward: (1.0, POFD_LAMBDA),
        guided: Guided::Discriminator,
        comparable: true,
        ..TRAINER
    },
    Method {
        name: "bc-trpo",
        summary: "behaviour cloning ([init] kind = \"bc\"), then TRPO on the env reward",
        paper: "(as in Rajeswaran et al., 2018)",
        start: Start::Clone,
        comparable: true,
        ..TRAINER
    },
    // (λ0, λ1) = (0.1, 0.95): docs/algorithms.md says why.
    Method {
        name: "dapg",
        summary: "behaviour cloning, then natural gradient steps with the demonstrations as rows weighted λ0·λ1^k·max Â",
        paper: "Rajeswaran et al., 2018",
        improvement: "npg",
        start: Start::Clone,
        keys: "[demonstration_rows]\nlambda0 = 0.1\nlambda1 = 0.95\n",
        comparable: true,
        ..TRAINER
    },
    Method {
        name: "logo",
        summary: "TRPO step, then a guidance step toward the demonstrations (KL δ_k, decaying)",
        paper: "Rengarajan et al., ICLR 2022",
        guided: Guided::Step,
        comparable: true,
        ..TRAINER
    },
    Method {
        name: "bc-logo",
        summary: "LOGO from the demonstrations' clone: behaviour cloning, then LOGO's two steps",
        paper: "logo-rl",
        guided: Guided::Step,
        start: Start::Clone,
        comparable: true,
        ..TRAINER
    },
    Method {
        name: "logo-fast",
        summary: "LOGO in float32 with critic fits on a quarter of the rows (the fast preset)",
        paper: "logo-rl",
        guided: Guided::Step,
        keys: "dtype = \"f32\"\n[critic.fit]\nmethod = \"lbfgs\"\nsubsample = 0.25\n",
        ..TRAINER
    },
    Method {
        name: "ppo",
        summary: "early-stopping PPO-Clip on the env reward alone (the seed paper's Algorithm 3)",
        paper: "Schulman et al., 2017",
        improvement: "ppo-clip",
        ..TRAINER
    },
    Method {
        name: "logo-ppo",
        summary: "LOGO with both steps by early-stopping PPO-Clip",
        paper: "the seed paper",
        improvement: "ppo-clip",
        guided: Guided::Step,
        ..TRAINER
    },
    Method {
        name: "logo-cdq",
        summary: "LOGO with clipped double-Q critics (baseline min(V1, V2))",
        paper: "the seed paper",
        guided: Guided::Step,
        keys: "[critic]\nkind = \"twin-min\"\n",
        ..TRAINER
    },
    Method {
        name: "logo-ppo-cdq",
        summary: "LOGO with PPO-Clip steps and clipped double-Q critics (the seed paper's Algorithm 2)",
        paper: "the seed paper",
        improvement: "ppo-clip",
        guided: Guided::Step,
        keys: "[critic]\nkind = \"twin-min\"\n",
        ..TRAINER
    },
    Method {
        name: "logo-clip-in-trpo",
        summary: "LOGO with the clipped surrogate inside TRPO's natural-gradient step",
        paper: "the seed paper's code",
        improvement: "clip-in-trpo",
        guided: Guided::Step,
        ..TRAINER
    },
    Method {
        name: "logo-ppo-penalty",
        summary: "LOGO: PPO-Clip improvement step, PPO-Penalty guidance step with δ_k its KL target (Algorithm 4)",
        paper: "the seed paper",
        improvement: "ppo-clip",
        guided: Guided::Step,
        keys: "[guidance.update]\nkind = \"ppo-penalty\"\n",
        ..TRAINER
    },
];

/// The method of this name.
pub fn method(name: &str) -> Option<&'static Method> {
    METHODS.iter().find(|m| m.name == name)
}

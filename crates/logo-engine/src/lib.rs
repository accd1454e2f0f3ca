//! The one place the engine is chosen: `--engine`, `--backend`, `--dtype` (or a config's
//! `dtype`) → a value of a type implementing `logo_nn::Engine`, handed to a generic
//! command ([`WithEngine`]).

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
pub use logo_algo::Dtype;
use logo_algo::TrainConfig;
use logo_nn::{BurnEngine, Engine, Kernels};

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EngineKind {
    /// The hand-tuned CPU kernels (the default).
    Kernels,
    /// burn tensor ops on `--backend`.
    Burn,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BackendKind {
    /// burn's ndarray backend, on the CPU.
    Ndarray,
    /// burn's wgpu backend (Vulkan, Metal, DX12; float32): build with `--features wgpu`.
    Wgpu,
    /// burn's CUDA backend: build with `--features cuda` (its build downloads LLVM).
    Cuda,
}

/// How networks run: the engine, its backend and float type.
#[derive(Args, Clone, Debug)]
pub struct EngineArgs {
    /// kernels (hand-tuned CPU, default) or burn (burn tensor ops on --backend).
    #[arg(long, value_enum)]
    pub engine: Option<EngineKind>,
    /// The burn engine's backend (implies --engine burn; default ndarray).
    #[arg(long, value_enum)]
    pub backend: Option<BackendKind>,
    /// The float type (default: a new run's config's `dtype`, else f64 on the CPU; f32
    /// on the GPU backends, which have no other).
    #[arg(long, value_enum)]
    pub dtype: Option<Dtype>,
}

impl EngineArgs {
    /// The flags that select this engine again (passed on to child `logo train`s).
    pub fn to_args(&self) -> Vec<String> {
        let name = |v: &dyn Fn() -> Option<clap::builder::PossibleValue>| {
            v().map(|p| p.get_name().to_string()).unwrap_or_default()
        };
        let mut args = Vec::new();
        if let Some(engine) = self.engine {
            args.extend(["--engine".to_string(), name(&|| engine.to_possible_value())]);
        }
        if let Some(backend) = self.backend {
            args.extend([
                "--backend".to_string(),
                name(&|| backend.to_possible_value()),
            ]);
        }
        // Left out when not given: a child's config may name its own `dtype`.
        if let Some(dtype) = self.dtype {
            args.extend(["--dtype".to_string(), name(&|| dtype.to_possible_value())]);
        }
        args
    }

    /// These flags for a new run of `config`: its `dtype` where no `--dtype` was given.
    pub fn for_config(&self, config: &TrainConfig) -> Self {
        Self {
            dtype: self.dtype.or(config.dtype),
            ..self.clone()
        }
    }

    /// No engine flag given at all.
    pub fn is_unset(&self) -> bool {
        self.engine.is_none() && self.backend.is_none() && self.dtype.is_none()
    }

    /// The flags that select the engine an `Engine::describe` names ("kernels f32",
    /// "burn ndarray f64", "burn wgpu f32"), or None for a name this build does not know.
    /// A build tag ("kernels f64 +avx512") is no flag: this build's kernels are taken, and
    /// the run's history records them from where it resumes.
    pub fn from_description(text: &str) -> Option<Self> {
        let words: Vec<&str> = text
            .split_whitespace()
            .filter(|word| !word.starts_with('+'))
            .collect();
        let (last, rest) = words.split_last()?;
        let dtype = match *last {
            "f64" => Dtype::F64,
            "f32" => Dtype::F32,
            _ => return None,
        };
        let (engine, backend) = match rest {
            ["kernels"] => (EngineKind::Kernels, None),
            ["burn", "ndarray"] => (EngineKind::Burn, Some(BackendKind::Ndarray)),
            ["burn", "wgpu"] => (EngineKind::Burn, Some(BackendKind::Wgpu)),
            ["burn", "cuda"] => (EngineKind::Burn, Some(BackendKind::Cuda)),
            _ => return None,
        };
        Some(Self {
            engine: Some(engine),
            backend,
            dtype: Some(dtype),
        })
    }

    /// These flags where any is given; else those of `trained_on` (the engine a run
    /// last trained on, as `Engine::describe` names it) where this build knows that
    /// name and `usable` accepts it. Also says whether `trained_on` was taken.
    pub fn or_trained_on(
        &self,
        trained_on: Option<&str>,
        usable: impl Fn(&Self) -> bool,
    ) -> (Self, bool) {
        match trained_on.and_then(Self::from_description) {
            Some(last) if self.is_unset() && usable(&last) => (last, true),
            _ => (self.clone(), false),
        }
    }

    /// Whether this engine runs on the CPU (the kernels, or burn on ndarray): one every
    /// build of `logo` has.
    pub fn on_cpu(&self) -> bool {
        matches!(self.backend, None | Some(BackendKind::Ndarray))
    }

    /// Whether the backend is a GPU one (float32 only).
    fn gpu(&self) -> bool {
        matches!(self.backend, Some(BackendKind::Wgpu | BackendKind::Cuda))
    }

    /// The float type: as given, else f32 on a GPU backend and f64 elsewhere.
    pub fn dtype(&self) -> Dtype {
        self.dtype
            .unwrap_or(if self.gpu() { Dtype::F32 } else { Dtype::F64 })
    }
}

/// A command generic over the engine, run once the engine is chosen.
pub trait WithEngine {
    type Output;
    fn run<E: Engine>(self, engine: E) -> Result<Self::Output>;
}

impl EngineArgs {
    /// Builds the chosen engine and runs `command` on it.
    pub fn with<W: WithEngine>(&self, command: W) -> Result<W::Output> {
        let engine = match (self.engine, self.backend) {
            (Some(EngineKind::Kernels), Some(backend)) => {
                bail!("--backend {backend:?} is for --engine burn, not kernels")
            }
            (Some(EngineKind::Kernels), None) | (None, None) => EngineKind::Kernels,
            _ => EngineKind::Burn,
        };
        if self.gpu() && self.dtype.is_none() {
            eprintln!(
                "note: the GPU backends compute in float32 (WGSL has no float64): --dtype f32"
            );
        }
        match (
            engine,
            self.backend.unwrap_or(BackendKind::Ndarray),
            self.dtype(),
        ) {
            (EngineKind::Kernels, _, Dtype::F64) => command.run(Kernels),
            (EngineKind::Kernels, _, Dtype::F32) => command.run(Kernels::<f32>::default()),
            (EngineKind::Burn, BackendKind::Ndarray, Dtype::F64) => {
                command.run(BurnEngine::<logo_nn::Cpu>::new(
                    Default::default(),
                    "ndarray f64",
                ))
            }
            (EngineKind::Burn, BackendKind::Ndarray, Dtype::F32) => {
                command.run(BurnEngine::<logo_nn::Cpu32>::new(
                    Default::default(),
                    "ndarray f32",
                ))
            }
            (EngineKind::Burn, BackendKind::Wgpu | BackendKind::Cuda, Dtype::F64) => {
                bail!(
                    "--dtype f64: the GPU backends compute in float32 only (WGSL has no float64); leave --dtype out or give f32 (a config's `dtype = \"f64\"` counts as --dtype f64)"
                )
            }
            #[cfg(feature = "wgpu")]
            (EngineKind::Burn, BackendKind::Wgpu, Dtype::F32) => {
                wgpu_adapter()?;
                command.run(BurnEngine::<logo_nn::burn::backend::Wgpu>::new(
                    Default::default(),
                    "wgpu f32",
                ))
            }
            #[cfg(not(feature = "wgpu"))]
            (EngineKind::Burn, BackendKind::Wgpu, Dtype::F32) => bail!(
                "this logo was built without burn's wgpu backend: build it with `cargo build --release -p logo-cli --features wgpu`"
            ),
            #[cfg(feature = "cuda")]
            (EngineKind::Burn, BackendKind::Cuda, Dtype::F32) => {
                command.run(BurnEngine::<logo_nn::burn::backend::Cuda>::new(
                    Default::default(),
                    "cuda f32",
                ))
            }
            #[cfg(not(feature = "cuda"))]
            (EngineKind::Burn, BackendKind::Cuda, Dtype::F32) => bail!(
                "this logo was built without burn's CUDA backend: build it with `cargo build --release -p logo-cli --features cuda` (its build downloads an LLVM toolchain)"
            ),
        }
    }
}

/// That wgpu finds a device to run on. Without one (no GPU, no Vulkan driver) burn's
/// runtime panics at its first operation; this asks first and says what to install.
#[cfg(feature = "wgpu")]
fn wgpu_adapter() -> Result<()> {
    use logo_nn::burn::backend::Wgpu;
    use logo_nn::burn::tensor::Tensor;
    let quiet = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let probe = std::panic::catch_unwind(|| {
        let device = Default::default();
        Tensor::<Wgpu, 1>::zeros([1], &device).into_data()
    });
    std::panic::set_hook(quiet);
    if probe.is_err() {
        bail!(
            "--backend wgpu: wgpu found no adapter (no GPU, or no Vulkan/Metal/DX12 driver for \
             it). Without a GPU, Mesa's lavapipe runs Vulkan on the CPU: `apt-get install \
             mesa-vulkan-drivers libvulkan1` on Debian or Ubuntu; with one, install its \
             vendor's Vulkan driver"
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_engine_name_maps_back_to_its_flags() {
        let flags = |text: &str| EngineArgs::from_description(text).map(|a| a.to_args());
        for (name, args) in [
            ("kernels f64", vec!["--engine", "kernels", "--dtype", "f64"]),
            ("kernels f32", vec!["--engine", "kernels", "--dtype", "f32"]),
            (
                "burn ndarray f32",
                vec!["--engine", "burn", "--backend", "ndarray", "--dtype", "f32"],
            ),
            (
                "burn wgpu f32",
                vec!["--engine", "burn", "--backend", "wgpu", "--dtype", "f32"],
            ),
        ] {
            assert_eq!(
                flags(name),
                Some(args.iter().map(|s| s.to_string()).collect())
            );
        }
        assert_eq!(
            flags("kernels f64 +avx512"),
            Some(
                ["--engine", "kernels", "--dtype", "f64"]
                    .map(String::from)
                    .to_vec()
            )
        );
        for unknown in ["", "kernels", "kernels f16", "burn f64", "tch cpu f64"] {
            assert_eq!(flags(unknown), None, "{unknown:?}");
        }
        let on_cpu = |text: &str| EngineArgs::from_description(text).unwrap().on_cpu();
        assert!(on_cpu("kernels f32") && on_cpu("burn ndarray f64") && !on_cpu("burn wgpu f32"));
        // The names the engines give themselves.
        assert!(EngineArgs::from_description(&Kernels::<f32>::default().describe()).is_some());
        assert!(EngineArgs::from_description(&Kernels::<f64>::default().describe()).is_some());
    }

    /// A sweep with no engine flag passes none on, so that each run's config may name
    /// its own `dtype` (and a resumed run keeps the engine it trained on).
    #[test]
    fn flags_not_given_are_not_passed_on() {
        let unset = EngineArgs {
            engine: None,
            backend: None,
            dtype: None,
        };
        assert!(unset.to_args().is_empty());
        let f32_only = EngineArgs {
            dtype: Some(Dtype::F32),
            ..unset
        };
        assert_eq!(f32_only.to_args(), ["--dtype", "f32"]);
    }
}

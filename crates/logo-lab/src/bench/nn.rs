//! `logo bench nn`: what the networks cost on each engine.
//!
//! - acting latency: the policy's mean action at batch 1 and at the rollout batch (one
//!   row per vectorised env), on the host copy every engine acts with;
//! - per engine, at the training batch (20,000 in the reference's Hopper iteration): the
//!   policy's Σ log π(a|s) and its gradient (forward trace, loss, Jᵀ·u), one Fisher-vector
//!   product (the activations and curvature cached once per policy step, as TRPO uses it,
//!   so the setup is reported apart), and one critic loss + gradient (a value net of the
//!   policy's sizes);
//! - the GEMM on one row block's three products.

use std::time::Instant;

use anyhow::Result;
use clap::Args;
use logo_nn::kernels::KernelFloat;
use logo_nn::loss::{gaussian_log_prob, mse, value_and_grad, value_and_grad2};
use logo_nn::{Cpu, Engine, FisherKind, FisherOperator, Policy, PolicyConfig, ValueNetConfig};
use serde::Serialize;

use logo_engine::{EngineArgs, WithEngine};
use logo_stats::median;

#[derive(Args)]
pub struct NnBenchArgs {
    #[arg(long)]
    json: bool,
    /// Training batch for the gradients and F·v.
    #[arg(long, default_value_t = 20_000)]
    batch: usize,
    /// Rollout batch (number of vectorised envs).
    #[arg(long, default_value_t = 16)]
    rollout_batch: usize,
    #[arg(long, default_value_t = 7)]
    repeats: usize,
    #[arg(long, default_value_t = 11)]
    obs_dim: usize,
    #[arg(long, default_value_t = 3)]
    act_dim: usize,
    /// Only this engine (default: kernels f64, burn ndarray f64, burn ndarray f32).
    #[command(flatten)]
    engine: EngineArgs,
    /// Bench only the engine given by --engine/--backend/--dtype.
    #[arg(long)]
    only: bool,
}

#[derive(Serialize)]
struct ActingBench {
    forward_batch1_us: f64,
    forward_rollout_batch_us: f64,
    rollout_batch: usize,
}

#[derive(Serialize)]
struct EngineBench {
    engine: String,
    hidden: Vec<usize>,
    batch: usize,
    /// Σ log π(a|s) and its parameter gradient.
    policy_gradient_ms: f64,
    fvp_setup_ms: f64,
    fvp_ms: f64,
    /// fvp_ms / policy_gradient_ms, median of per-repeat ratios.
    fvp_over_gradient: f64,
    /// MSE of a value net and its parameter gradient.
    critic_ms: f64,
}

/// The three products of one row block (`BLOCK_ROWS`) of a 128-wide hidden layer
/// (forward x·W, reverse dz·Wᵀ and xᵀ·dz) through `logo_nn::kernels::gemm`, one thread.
#[derive(Serialize)]
pub struct GemmBench {
    pub shape: &'static str,
    pub ms: f64,
    pub gflops: f64,
}

fn bench_gemm(args: &NnBenchArgs) -> Vec<GemmBench> {
    block_products::<f64>(args.repeats)
}

/// [`GemmBench`] of the three products of a 256-row block in float type `F`.
pub fn block_products<F: KernelFloat>(repeats: usize) -> Vec<GemmBench> {
    use logo_nn::kernels::gemm::{Finish, Start, gemm};
    let (rows, width) = (logo_nn::kernels::mlp::BLOCK_ROWS, 128);
    let x: Vec<F> = (0..rows * width)
        .map(|k| F::from_f64(((k as f64) * 0.37).sin()))
        .collect();
    let w: Vec<F> = (0..width * width)
        .map(|k| F::from_f64(((k as f64) * 0.11).cos()))
        .collect();
    // (name, (m, k, n), a, a strides, b, b strides)
    type Shape<'a, F> = (
        &'static str,
        (usize, usize, usize),
        &'a [F],
        (usize, usize),
        &'a [F],
        (usize, usize),
    );
    let shapes: [Shape<F>; 3] = [
        (
            "x·W   256x128x128",
            (rows, width, width),
            &x,
            (width, 1),
            &w,
            (width, 1),
        ),
        (
            "dz·Wᵀ 256x128x128",
            (rows, width, width),
            &x,
            (width, 1),
            &w,
            (1, width),
        ),
        (
            "xᵀ·dz 128x256x128",
            (width, rows, width),
            &x,
            (1, width),
            &x,
            (width, 1),
        ),
    ];
    let passes = 80; // products per timing, so one sample is milliseconds long
    shapes
        .iter()
        .map(|&(shape, dims, a, sa, b, sb)| {
            let mut c = vec![F::ZERO; dims.0 * dims.2];
            let mut timed = || {
                time(|| {
                    for _ in 0..passes {
                        gemm(dims, a, sa, b, sb, &mut c, Start::Zero, Finish::None);
                        std::hint::black_box(&c);
                    }
                })
                .1 / passes as f64
            };
            timed(); // warm-up
            let seconds = median(&(0..repeats).map(|_| timed()).collect::<Vec<_>>());
            GemmBench {
                shape,
                ms: seconds * 1e3,
                gflops: 2.0 * (dims.0 * dims.1 * dims.2) as f64 / seconds / 1e9,
            }
        })
        .collect()
}

fn time<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let out = f();
    (out, start.elapsed().as_secs_f64())
}

fn acting(args: &NnBenchArgs) -> ActingBench {
    let policy = PolicyConfig::new(args.obs_dim, args.act_dim)
        .init::<Cpu>(&Default::default())
        .acting();
    let rows = |n: usize| -> Vec<f64> {
        (0..n * args.obs_dim)
            .map(|k| ((k as f64) * 0.37).sin())
            .collect()
    };
    // Latency: many calls per sample, the median sample reported.
    let latency = |obs: &[f64]| -> f64 {
        let calls = 200;
        let samples: Vec<f64> = (0..args.repeats)
            .map(|_| {
                let (_, s) = time(|| {
                    for _ in 0..calls {
                        std::hint::black_box(policy.mean(obs));
                    }
                });
                s / calls as f64 * 1e6
            })
            .collect();
        median(&samples)
    };
    ActingBench {
        forward_batch1_us: latency(&rows(1)),
        forward_rollout_batch_us: latency(&rows(args.rollout_batch)),
        rollout_batch: args.rollout_batch,
    }
}

/// The median time of one critic's loss gradient over the batch `obs`, in ms.
fn critic_gradient_ms<E: Engine>(engine: &E, args: &NnBenchArgs, obs: &E::Rows) -> f64 {
    let critic = ValueNetConfig::new(args.obs_dim).init::<Cpu>(&Default::default());
    let net = engine.net(&critic.net.dims(), &logo_nn::flat::params_to_vec(&critic));
    let targets: Vec<f64> = (0..args.batch).map(|k| (k as f64 * 0.3).sin()).collect();
    let targets = engine.upload(&targets, [args.batch, 1]);
    let times: Vec<f64> = (0..args.repeats)
        .map(|_| {
            time(|| {
                let trace = engine.trace(&net, obs);
                let targets = burn::tensor::Tensor::from_inner(targets.clone());
                let (_, d_values) = value_and_grad(engine.output(&trace), |v| mse(v, targets));
                std::hint::black_box(engine.vjp(&net, &trace, d_values));
            })
            .1
        })
        .collect();
    median(&times) * 1e3
}

/// The training-batch benchmarks on one engine.
struct Bench<'a>(&'a NnBenchArgs);

impl WithEngine for Bench<'_> {
    type Output = EngineBench;

    fn run<E: Engine>(self, engine: E) -> Result<EngineBench> {
        let args = self.0;
        let config = PolicyConfig::new(args.obs_dim, args.act_dim);
        let policy = Policy::from_module(&engine, &config.init::<Cpu>(&Default::default()));
        let values = |n: usize, scale: f64| -> Vec<f64> {
            (0..n).map(|k| ((k as f64) * scale).sin()).collect()
        };
        let obs = engine.rows(&values(args.batch * args.obs_dim, 0.37), args.obs_dim);
        let actions = engine.upload(
            &values(args.batch * args.act_dim, 0.11),
            [args.batch, args.act_dim],
        );
        let policy_gradient = || {
            time(|| {
                let trace = engine.trace(&policy.mean, &obs);
                let (_, d_means, d_log_std) = value_and_grad2(
                    engine.output(&trace),
                    policy.log_std_tensor(&engine),
                    |means, log_std| {
                        gaussian_log_prob(
                            means,
                            log_std,
                            burn::tensor::Tensor::from_inner(actions.clone()),
                        )
                        .sum()
                    },
                );
                std::hint::black_box((engine.vjp(&policy.mean, &trace, d_means), d_log_std));
            })
            .1
        };
        let (trace, trace_s) = time(|| engine.trace(&policy.mean, &obs));
        let (fvp, curvature_s) = time(|| {
            FisherOperator::new(
                &engine,
                &policy,
                &trace,
                args.batch,
                0.01,
                FisherKind::Exact,
            )
        });
        let v = values(policy.num_params(), 0.05);
        policy_gradient(); // warm-up
        std::hint::black_box(fvp.apply(&v));
        let (mut pg, mut fv, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..args.repeats {
            let a = policy_gradient();
            let (_, b) = time(|| std::hint::black_box(fvp.apply(&v)));
            pg.push(a);
            fv.push(b);
            ratios.push(b / a);
        }
        let critic_ms = critic_gradient_ms(&engine, args, &obs);
        Ok(EngineBench {
            engine: engine.describe(),
            hidden: config.hidden.clone(),
            batch: args.batch,
            policy_gradient_ms: median(&pg) * 1e3,
            fvp_setup_ms: (trace_s + curvature_s) * 1e3,
            fvp_ms: median(&fv) * 1e3,
            fvp_over_gradient: median(&ratios),
            critic_ms,
        })
    }
}

pub fn run(args: &NnBenchArgs) -> Result<()> {
    anyhow::ensure!(
        args.batch > 0 && args.rollout_batch > 0 && args.repeats > 0,
        "batch sizes and --repeats must be at least 1"
    );
    let acting = acting(args);
    let engines: Vec<EngineArgs> = if args.only {
        vec![args.engine.clone()]
    } else {
        use logo_engine::{BackendKind, Dtype, EngineKind};
        let burn = |dtype| EngineArgs {
            engine: Some(EngineKind::Burn),
            backend: Some(BackendKind::Ndarray),
            dtype,
        };
        vec![
            EngineArgs {
                engine: Some(EngineKind::Kernels),
                backend: None,
                dtype: Some(Dtype::F64),
            },
            burn(Some(Dtype::F64)),
            burn(Some(Dtype::F32)),
        ]
    };
    let results = engines
        .iter()
        .map(|e| e.with(Bench(args)))
        .collect::<Result<Vec<_>>>()?;
    let gemms = bench_gemm(args);
    if args.json {
        let all = serde_json::json!({ "acting": acting, "engines": results, "gemm": gemms });
        println!("{}", serde_json::to_string_pretty(&all)?);
        return Ok(());
    }
    println!(
        "acting (host copy): mean action {:.1} µs at batch 1, {:.1} µs at batch {}",
        acting.forward_batch1_us, acting.forward_rollout_batch_us, acting.rollout_batch
    );
    println!(
        "{:20} {:>14} {:>12} {:>10} {:>10} {:>12}",
        "engine", "log π grad ms", "F·v setup", "F·v ms", "F·v/grad", "critic ms"
    );
    for r in &results {
        println!(
            "{:20} {:>14.1} {:>12.1} {:>10.1} {:>10.2} {:>12.1}",
            r.engine,
            r.policy_gradient_ms,
            r.fvp_setup_ms,
            r.fvp_ms,
            r.fvp_over_gradient,
            r.critic_ms
        );
    }
    println!(
        "(policy {:?} tanh, obs {} act {}; training batch {}; medians of {})",
        results[0].hidden, args.obs_dim, args.act_dim, args.batch, args.repeats
    );
    for g in &gemms {
        println!(
            "gemm {}: {:.3} ms ({:.1} GFLOP/s, one thread)",
            g.shape, g.ms, g.gflops
        );
    }
    Ok(())
}

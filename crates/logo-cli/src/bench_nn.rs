//! `logo bench nn`: what the policy costs at rollout and at a training batch.
//!
//! - forward latency of the mean action at batch 1 and at the rollout batch (one row per
//!   vectorised env), on the inner (no-autodiff) backend, as the rollout runs it;
//! - forward+backward of Σ log π(a|s) at the training batch (20,000 in the reference's
//!   Hopper iteration), on the autodiff backend;
//! - one Fisher-vector product at the same batch (activations cached once per policy
//!   step, as TRPO uses it, so the setup is reported apart), and its ratio to one
//!   forward+backward (target ≤ 2.5).

use std::time::Instant;

use anyhow::Result;
use burn::module::AutodiffModule;
use burn::tensor::backend::AutodiffBackend;
use clap::Args;
use logo_algo::critic::{HostValueObjective, value_loss_and_grad};
use logo_algo::lbfgs::Objective;
use logo_nn::burn;
use logo_nn::flat::from_f64;
use logo_nn::flat::params_to_vec;
use logo_nn::{
    Cpu, Cpu32Autodiff, CpuAutodiff, FisherVectorProduct, HostMlp, PolicyConfig, ValueNetConfig,
};
use serde::Serialize;

use crate::bench::median;

#[derive(Args)]
pub struct NnBenchArgs {
    #[arg(long)]
    json: bool,
    /// Training batch for forward+backward and F·v.
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
}

#[derive(Serialize)]
struct NnBench {
    dtype: &'static str,
    hidden: Vec<usize>,
    forward_batch1_us: f64,
    forward_rollout_batch_us: f64,
    rollout_batch: usize,
    batch: usize,
    forward_backward_ms: f64,
    fvp_setup_ms: f64,
    fvp_ms: f64,
    /// fvp_ms / forward_backward_ms, median of per-repeat ratios.
    fvp_over_forward_backward: f64,
}

/// One critic evaluation (MSE loss + gradient, a value net of the policy's sizes) at the
/// training batch: burn on the ndarray backend vs the host-buffer path the CPU fits use.
#[derive(Serialize)]
struct CriticBench {
    batch: usize,
    burn_ms: f64,
    host_1_thread_ms: f64,
    host_ms: f64,
    threads: usize,
    /// Multiply-adds × 2 of forward + reverse, over host_ms.
    host_gflops: f64,
}

/// The three products of one 1024-row block of a 128-wide hidden layer (forward x·W,
/// reverse dz·Wᵀ and xᵀ·dz), through `logo_nn::gemm` and through matrixmultiply,
/// alternated, one thread.
#[derive(Serialize)]
struct GemmBench {
    shape: &'static str,
    kernel_ms: f64,
    portable_ms: f64,
    /// portable / kernel, median of per-repeat ratios.
    speedup: f64,
    kernel_gflops: f64,
}

fn bench_gemm(args: &NnBenchArgs) -> Vec<GemmBench> {
    use logo_nn::gemm::{Finish, Start, gemm, gemm_portable};
    let (rows, width) = (1024, 128);
    let x: Vec<f64> = (0..rows * width)
        .map(|k| ((k as f64) * 0.37).sin())
        .collect();
    let w: Vec<f64> = (0..width * width)
        .map(|k| ((k as f64) * 0.11).cos())
        .collect();
    // (name, (m, k, n), a, a strides, b, b strides)
    type Shape<'a> = (
        &'static str,
        (usize, usize, usize),
        &'a [f64],
        (usize, usize),
        &'a [f64],
        (usize, usize),
    );
    let shapes: [Shape; 3] = [
        (
            "x·W   1024x128x128",
            (rows, width, width),
            &x,
            (width, 1),
            &w,
            (width, 1),
        ),
        (
            "dz·Wᵀ 1024x128x128",
            (rows, width, width),
            &x,
            (width, 1),
            &w,
            (1, width),
        ),
        (
            "xᵀ·dz 128x1024x128",
            (width, rows, width),
            &x,
            (1, width),
            &x,
            (width, 1),
        ),
    ];
    let passes = 20; // products per timing, so one sample is milliseconds long
    shapes
        .iter()
        .map(|&(shape, dims, a, sa, b, sb)| {
            let mut c = vec![0.0; dims.0 * dims.2];
            let mut timed = |portable: bool| {
                time(|| {
                    for _ in 0..passes {
                        if portable {
                            gemm_portable(dims, a, sa, b, sb, &mut c, Start::Zero, Finish::None);
                        } else {
                            gemm(dims, a, sa, b, sb, &mut c, Start::Zero, Finish::None);
                        }
                        std::hint::black_box(&c);
                    }
                })
                .1 / passes as f64
            };
            timed(false); // warm-up
            timed(true);
            let (mut kernel, mut portable, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
            for _ in 0..args.repeats {
                let (k, p) = (timed(false), timed(true));
                kernel.push(k);
                portable.push(p);
                ratios.push(p / k);
            }
            let kernel_s = median(kernel);
            GemmBench {
                shape,
                kernel_ms: kernel_s * 1e3,
                portable_ms: median(portable) * 1e3,
                speedup: median(ratios),
                kernel_gflops: 2.0 * (dims.0 * dims.1 * dims.2) as f64 / kernel_s / 1e9,
            }
        })
        .collect()
}

fn bench_critic(args: &NnBenchArgs) -> CriticBench {
    let device = Default::default();
    let hidden = PolicyConfig::new(args.obs_dim, args.act_dim).hidden;
    let net = ValueNetConfig {
        obs_dim: args.obs_dim,
        hidden: hidden.clone(),
    }
    .init::<Cpu>(&device);
    let obs: Vec<f64> = (0..args.batch * args.obs_dim)
        .map(|k| ((k as f64) * 0.37).sin())
        .collect();
    let target: Vec<f64> = (0..args.batch).map(|k| ((k as f64) * 0.3).cos()).collect();
    let theta = params_to_vec(&net);
    let dims = HostMlp::from_mlp(&net.net).dims;
    let host = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        let mut objective = HostValueObjective::new(dims.clone(), &obs, &target, 1e-3);
        let samples = (0..args.repeats)
            .map(|_| {
                time(|| {
                    pool.install(|| {
                        std::hint::black_box(objective.loss(&theta));
                        std::hint::black_box(objective.gradient());
                    })
                })
                .1
            })
            .collect();
        median(samples) * 1e3
    };
    let (obs_t, target_t) = (
        from_f64::<Cpu, 2>(&obs, [args.batch, args.obs_dim], &device),
        from_f64::<Cpu, 2>(&target, [args.batch, 1], &device),
    );
    let burn_ms = median(
        (0..args.repeats)
            .map(|_| {
                time(|| value_loss_and_grad(&net, obs_t.clone(), target_t.clone(), &theta, 1e-3)).1
            })
            .collect(),
    ) * 1e3;
    let threads = rayon::current_num_threads();
    let (host_1_thread_ms, host_ms) = (host(1), host(threads));
    let multiply_adds: usize = dims.windows(2).map(|w| w[0] * w[1]).sum::<usize>()
        + dims[1..dims.len() - 1]
            .iter()
            .zip(&dims[2..])
            .map(|(a, b)| a * b)
            .sum::<usize>()
        + dims.windows(2).map(|w| w[0] * w[1]).sum::<usize>();
    CriticBench {
        batch: args.batch,
        burn_ms,
        host_1_thread_ms,
        host_ms,
        threads,
        host_gflops: 2.0 * (multiply_adds * args.batch) as f64 / (host_ms * 1e-3) / 1e9,
    }
}

fn time<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let out = f();
    (out, start.elapsed().as_secs_f64())
}

fn bench<B: AutodiffBackend>(dtype: &'static str, args: &NnBenchArgs) -> NnBench {
    let device = Default::default();
    let config = PolicyConfig::new(args.obs_dim, args.act_dim);
    let policy = config.init::<B>(&device);
    let inner = policy.valid();
    let rows = |n: usize| -> Vec<f64> {
        (0..n * args.obs_dim)
            .map(|k| ((k as f64) * 0.37).sin())
            .collect()
    };
    let (obs1, obs_rollout, obs_batch) = (rows(1), rows(args.rollout_batch), rows(args.batch));
    let actions: Vec<f64> = (0..args.batch * args.act_dim)
        .map(|k| ((k as f64) * 0.11).cos())
        .collect();

    // Latency: many calls per sample, the median sample reported.
    let latency = |obs: &[f64], n: usize| -> f64 {
        let calls = 200;
        let samples: Vec<f64> = (0..args.repeats)
            .map(|_| {
                let (_, s) = time(|| {
                    for _ in 0..calls {
                        let out = inner.mean_action(from_f64(obs, [n, args.obs_dim], &device));
                        std::hint::black_box(out.into_data());
                    }
                });
                s / calls as f64 * 1e6
            })
            .collect();
        median(samples)
    };
    let forward_batch1_us = latency(&obs1, 1);
    let forward_rollout_batch_us = latency(&obs_rollout, args.rollout_batch);

    let obs_t = from_f64::<B, 2>(&obs_batch, [args.batch, args.obs_dim], &device);
    let act_t = from_f64::<B, 2>(&actions, [args.batch, args.act_dim], &device);
    let forward_backward = || {
        time(|| {
            let grads = policy
                .log_prob(obs_t.clone(), act_t.clone())
                .sum()
                .backward();
            std::hint::black_box(policy.log_std.val().grad(&grads));
        })
        .1
    };
    let (fvp, fvp_setup) = time(|| FisherVectorProduct::new(&inner, obs_t.clone().inner(), 0.01));
    let v: Vec<f64> = (0..fvp.dim()).map(|k| ((k as f64) * 0.05).sin()).collect();
    forward_backward(); // warm-up
    std::hint::black_box(fvp.apply(&v));
    let (mut fb, mut fv, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..args.repeats {
        let a = forward_backward();
        let (_, b) = time(|| std::hint::black_box(fvp.apply(&v)));
        fb.push(a);
        fv.push(b);
        ratios.push(b / a);
    }
    NnBench {
        dtype,
        hidden: config.hidden.clone(),
        forward_batch1_us,
        forward_rollout_batch_us,
        rollout_batch: args.rollout_batch,
        batch: args.batch,
        forward_backward_ms: median(fb) * 1e3,
        fvp_setup_ms: fvp_setup * 1e3,
        fvp_ms: median(fv) * 1e3,
        fvp_over_forward_backward: median(ratios),
    }
}

pub fn run(args: &NnBenchArgs) -> Result<()> {
    anyhow::ensure!(
        args.batch > 0 && args.rollout_batch > 0 && args.repeats > 0,
        "batch sizes and --repeats must be at least 1"
    );
    let results = vec![
        bench::<CpuAutodiff>("f64", args),
        bench::<Cpu32Autodiff>("f32", args),
    ];
    let critic = bench_critic(args);
    let gemms = bench_gemm(args);
    if args.json {
        let all = serde_json::json!({ "policy": results, "critic": critic, "gemm": gemms });
        println!("{}", serde_json::to_string_pretty(&all)?);
        return Ok(());
    }
    println!(
        "{:5} {:>12} {:>16} {:>14} {:>12} {:>10} {:>10}",
        "dtype", "fwd b=1 µs", "fwd rollout µs", "fwd+bwd ms", "F·v setup", "F·v ms", "F·v/f+b"
    );
    for r in &results {
        println!(
            "{:5} {:>12.1} {:>16.1} {:>14.1} {:>12.1} {:>10.1} {:>10.2}",
            r.dtype,
            r.forward_batch1_us,
            r.forward_rollout_batch_us,
            r.forward_backward_ms,
            r.fvp_setup_ms,
            r.fvp_ms,
            r.fvp_over_forward_backward
        );
    }
    println!(
        "(policy {}-{} tanh, obs {} act {}; rollout batch {}, training batch {}; medians of {})",
        results[0].hidden[0],
        results[0].hidden[1],
        args.obs_dim,
        args.act_dim,
        args.rollout_batch,
        args.batch,
        args.repeats
    );
    println!(
        "critic loss+gradient (f64, batch {}): burn {:.1} ms, host {:.1} ms on 1 thread, \
         {:.1} ms on {} ({:.1} GFLOP/s)",
        critic.batch,
        critic.burn_ms,
        critic.host_1_thread_ms,
        critic.host_ms,
        critic.threads,
        critic.host_gflops
    );
    for g in &gemms {
        println!(
            "gemm {}: kernel {:.3} ms ({:.1} GFLOP/s), matrixmultiply {:.3} ms, speedup {:.2}",
            g.shape, g.kernel_ms, g.kernel_gflops, g.portable_ms, g.speedup
        );
    }
    Ok(())
}

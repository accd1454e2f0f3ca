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
use logo_nn::burn;
use logo_nn::flat::from_f64;
use logo_nn::{Cpu32Autodiff, CpuAutodiff, FisherVectorProduct, PolicyConfig};
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
    if args.json {
        println!("{}", serde_json::to_string_pretty(&results)?);
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
    Ok(())
}

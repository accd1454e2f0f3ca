//! `logo bench envs`: env-step throughput against a raw `mj_step` loop on the same model.
//!
//! Both loops apply the same actions for the same number of env steps, and the raw loop
//! resets (`mj_resetData` + `mj_forward`) at the steps where the env's episodes ended, so
//! both simulate the same kinds of states. Runs alternate (raw, env, raw, env, ...) and the
//! reported ratio is the median of the per-repeat ratios.

use std::time::Instant;

use anyhow::Result;
use clap::Args;
use logo_envs::{Env, EnvFactory, EnvOptions, VecEnv};
use mujoco_rs::prelude::MjData;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use logo_stats::median;

#[derive(Args)]
pub struct EnvBenchArgs {
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Env steps per timed run.
    #[arg(long, default_value_t = 5_000)]
    steps: usize,
    /// Timed runs per variant; medians are reported.
    #[arg(long, default_value_t = 5)]
    repeats: usize,
    /// Worker threads for the vectorised run.
    #[arg(long, default_value_t = 2)]
    threads: usize,
    /// Env copies in the vectorised run.
    #[arg(long, default_value_t = 16)]
    vec_envs: usize,
    /// Env ids (default: the four LOGO tasks, v4).
    #[arg(long, value_delimiter = ',')]
    envs: Option<Vec<String>>,
}

#[derive(Serialize)]
struct EnvBench {
    id: String,
    frame_skip: usize,
    env_steps_per_s: f64,
    raw_env_steps_per_s: f64,
    /// Median over repeats of (env steps/s) / (raw loop env-equivalent steps/s).
    ratio: f64,
    vec_threads: usize,
    vec_envs: usize,
    vec_env_steps_per_s: f64,
    /// The same vectorised run on one thread.
    vec_one_thread_steps_per_s: f64,
    /// Median over repeats of (threads-thread rate) / (one-thread rate).
    vec_speedup: f64,
}

#[derive(Serialize)]
struct EnvBenchReport {
    steps: usize,
    repeats: usize,
    envs: Vec<EnvBench>,
}

pub fn run(args: &EnvBenchArgs) -> Result<()> {
    anyhow::ensure!(
        args.steps > 0 && args.repeats > 0,
        "--steps and --repeats must be at least 1"
    );
    let default_ids = [
        "Hopper-v4",
        "Walker2d-v4",
        "HalfCheetah-v4",
        "InvertedDoublePendulum-v4",
    ];
    let ids: Vec<String> = match &args.envs {
        Some(ids) => ids.clone(),
        None => default_ids.iter().map(|s| s.to_string()).collect(),
    };
    let envs = ids
        .iter()
        .map(|id| bench_env(args, id))
        .collect::<Result<Vec<_>>>()?;
    let report = EnvBenchReport {
        steps: args.steps,
        repeats: args.repeats,
        envs,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_table(&report);
    }
    Ok(())
}

/// One env's single-thread rates, and its vectorised rate against one thread's.
fn bench_env(args: &EnvBenchArgs, id: &str) -> Result<EnvBench> {
    let factory = EnvFactory::new(id, &EnvOptions::default())?;
    let spec = factory.spec().clone();
    let single = single_thread_rates(&factory, args.steps, args.repeats)?;
    let actions = single.actions;
    // Vectorised: every copy gets its own slice of the action stream. One-thread and
    // `threads`-thread runs alternate, so a slow spell of the machine hits both.
    let n = args.vec_envs;
    let per_batch = n * spec.act_dim;
    let batches = args.steps.div_ceil(n);
    let stream: Vec<f64> = actions
        .iter()
        .cycle()
        .take(batches * per_batch)
        .copied()
        .collect();
    let mut serial = VecEnv::new(&factory, n, 1, 0)?;
    let mut parallel = VecEnv::new(&factory, n, args.threads, 0)?;
    let timed = |venv: &mut VecEnv| -> Result<f64> {
        let start = Instant::now();
        for batch in stream.chunks(per_batch) {
            venv.step(batch)?;
        }
        Ok((batches * n) as f64 / start.elapsed().as_secs_f64())
    };
    timed(&mut parallel)?; // warm-up: start the worker threads
    let (mut vec_rates, mut one_thread_rates, mut speedups) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..args.repeats {
        let one = timed(&mut serial)?;
        let many = timed(&mut parallel)?;
        one_thread_rates.push(one);
        vec_rates.push(many);
        speedups.push(many / one);
    }
    Ok(EnvBench {
        id: id.to_string(),
        frame_skip: spec.frame_skip,
        env_steps_per_s: single.env_steps_per_s,
        raw_env_steps_per_s: single.raw_env_steps_per_s,
        ratio: single.ratio,
        vec_threads: args.threads,
        vec_envs: args.vec_envs,
        vec_env_steps_per_s: median(&vec_rates),
        vec_one_thread_steps_per_s: median(&one_thread_rates),
        vec_speedup: median(&speedups),
    })
}

fn print_table(report: &EnvBenchReport) {
    println!(
        "{:28} {:>12} {:>12} {:>7} {:>16} {:>8}",
        "env", "env steps/s", "raw steps/s", "ratio", "vec steps/s", "speedup"
    );
    for r in &report.envs {
        println!(
            "{:28} {:>12.0} {:>12.0} {:>7.3} {:>16} {:>8.2}",
            r.id,
            r.env_steps_per_s,
            r.raw_env_steps_per_s,
            r.ratio,
            format!(
                "{:.0} ({}x{})",
                r.vec_env_steps_per_s, r.vec_envs, r.vec_threads
            ),
            r.vec_speedup
        );
    }
    println!(
        "({} env steps per run, median of {} runs; raw = mj_step x frame_skip)",
        report.steps, report.repeats
    );
}

/// One thread's env steps/s through the env and through a bare `mj_step` loop on the same
/// model (medians of alternated repeats), and the uniform-random actions both took.
pub struct SingleThread {
    pub env_steps_per_s: f64,
    pub raw_env_steps_per_s: f64,
    /// Median of the per-repeat env/raw ratios.
    pub ratio: f64,
    pub actions: Vec<f64>,
}

/// [`SingleThread`] rates of `factory`'s env over `steps` env steps, `repeats` times.
pub fn single_thread_rates(
    factory: &EnvFactory,
    steps: usize,
    repeats: usize,
) -> Result<SingleThread> {
    let spec = factory.spec().clone();
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let actions: Vec<f64> = (0..steps)
        .flat_map(|_| {
            (0..spec.act_dim)
                .map(|j| rng.random_range(spec.action_low[j]..spec.action_high[j]))
                .collect::<Vec<_>>()
        })
        .collect();

    // Env loop: also records the initial state of every episode, for the raw loop to replay.
    let mut env = factory.build()?;
    let mut obs = vec![0.0; spec.obs_dim];
    let mut env_loop = |starts: &mut Vec<(usize, Vec<f64>, Vec<f64>)>| -> Result<f64> {
        starts.clear();
        env.reset(Some(0), &mut obs);
        let record = |t: usize, env: &dyn Env| (t, env.state().0.to_vec(), env.state().1.to_vec());
        starts.push(record(0, &*env));
        let start = Instant::now();
        for (t, a) in actions.chunks(spec.act_dim).enumerate() {
            if env.step(a, &mut obs)?.done() {
                env.reset(None, &mut obs);
                starts.push(record(t + 1, &*env));
            }
        }
        Ok(steps as f64 / start.elapsed().as_secs_f64())
    };
    // The same physics without the env: same initial states, same actions, same steps.
    let mut data = MjData::new(factory.model()?.clone());
    let mut raw_loop = |starts: &[(usize, Vec<f64>, Vec<f64>)]| -> f64 {
        let set = |data: &mut MjData<_>, (_, qpos, qvel): &(usize, Vec<f64>, Vec<f64>)| {
            data.reset();
            data.qpos_mut().copy_from_slice(qpos);
            data.qvel_mut().copy_from_slice(qvel);
            data.forward();
        };
        set(&mut data, &starts[0]);
        let mut next = starts.iter().skip(1).peekable();
        let start = Instant::now();
        for (t, a) in actions.chunks(spec.act_dim).enumerate() {
            data.ctrl_mut().copy_from_slice(a);
            for _ in 0..spec.frame_skip {
                data.step();
            }
            if let Some(s) = next.next_if(|s| s.0 == t + 1) {
                set(&mut data, s);
            }
        }
        steps as f64 / start.elapsed().as_secs_f64()
    };

    let mut starts = Vec::new();
    env_loop(&mut starts)?; // warm-up, and the episodes' initial states
    let (mut env_rates, mut raw_rates, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    let mut scratch = Vec::new();
    for _ in 0..repeats {
        let raw = raw_loop(&starts);
        let env_rate = env_loop(&mut scratch)?;
        raw_rates.push(raw);
        env_rates.push(env_rate);
        ratios.push(env_rate / raw);
    }

    Ok(SingleThread {
        env_steps_per_s: median(&env_rates),
        raw_env_steps_per_s: median(&raw_rates),
        ratio: median(&ratios),
        actions,
    })
}

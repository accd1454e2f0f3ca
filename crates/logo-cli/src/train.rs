//! `logo train`: run TRPO or LOGO from a TOML config, with a progress line per iteration,
//! `metrics.csv` and checkpoints in the output folder.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use logo_algo::episode::evaluation_seed;
use logo_algo::run_dir::{BEST, CHECKPOINT};
use logo_algo::{IterationMetrics, Schedule, TrainConfig, Trainer};
use logo_envs::{EnvFactory, EnvOptions};
use logo_nn::{Checkpoint, Engine};

use crate::final_eval;
use crate::video::{Frames, Video, VideoLook, record_episode};
use logo_engine::{EngineArgs, WithEngine};

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum StopMetric {
    Eval,
    Train,
}

#[derive(Args)]
pub struct TrainArgs {
    /// TOML config, e.g. configs/logo/inverted_double_pendulum.toml
    #[arg(long, required_unless_present = "resume")]
    config: Option<PathBuf>,
    /// Continue the run in this folder from its checkpoint (a killed run ends with the
    /// same final checkpoint as an uninterrupted one). Takes the run's own config;
    /// --iterations may extend it. It continues on the engine and float type the run
    /// last trained on; --engine, --backend or --dtype choose another (any engine can
    /// continue any run).
    #[arg(long, conflicts_with_all = ["config", "seed", "out", "threads"])]
    resume: Option<PathBuf>,
    /// Overrides the config's seed.
    #[arg(long)]
    seed: Option<u64>,
    /// Overrides the config's number of iterations.
    #[arg(long)]
    iterations: Option<usize>,
    /// Stop (and write the checkpoint) at the first evaluation whose dense return reaches
    /// this: the behaviour-policy pipeline, e.g. a dense TRPO run stopped at LOGO's
    /// behaviour level, then `logo data record`.
    #[arg(long)]
    stop_at_return: Option<f64>,
    /// Which return --stop-at-return watches: the deterministic evaluation's (dense), or
    /// the mean return of the iteration's sampled training episodes (the stochastic
    /// policy's, in the training env's reward): the one to use when the demonstrations
    /// will be recorded with sampled actions.
    #[arg(long, value_enum, default_value_t = StopMetric::Eval)]
    stop_metric: StopMetric,
    /// Output folder (default: runs/<config name>-seed<seed>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Overrides the config's worker threads.
    #[arg(long)]
    threads: Option<usize>,
    /// How each iteration's steps are laid over the threads; either gives the same
    /// metrics and checkpoints.
    #[arg(long, value_enum, default_value_t = Schedule::Pipelined)]
    schedule: Schedule,
    /// Every N iterations, a video of the mean-action policy (one episode of the dense
    /// evaluation env from the evaluation's first initial state, 480×480) into
    /// DIR/videos/iteration-<k>.mp4. It uses its own env and no random stream: the run's
    /// numbers are the same with it or without it.
    #[arg(long, value_name = "N")]
    video_every: Option<usize>,
    /// Write no TensorBoard event file (by default the run folder gets one, flushed each
    /// iteration: `tensorboard --logdir runs/`).
    #[arg(long)]
    no_tensorboard: bool,
    /// Print the config with every default filled in (and --seed, --iterations, --threads
    /// and --dtype laid over it), as the run would use it, and exit without training.
    #[arg(long, conflicts_with = "resume")]
    print_config: bool,
    #[command(flatten)]
    engine: EngineArgs,
}

/// How a run starts.
pub enum Start {
    /// A new run of this config into this folder.
    New(Box<TrainConfig>, PathBuf),
    /// The run in this folder, to this many iterations (None: its own config's).
    Resume(PathBuf, Option<usize>),
}

/// One `logo train`: where it starts and how it goes, whoever asked for it.
pub struct Job {
    pub start: Start,
    /// Stop at the first iteration whose metric reaches this return.
    pub stop: Option<(f64, StopMetric)>,
    pub schedule: Schedule,
    pub tensorboard: bool,
    pub video_every: Option<usize>,
}

/// Where a run's lines go, and whether it goes on: `logo train` prints them; the Python
/// package hands them to Python and stops at Ctrl-C.
pub trait Console {
    fn say(&mut self, line: &str);
    /// Asked after each iteration; an error stops the run once its checkpoint is written.
    fn go_on(&mut self) -> Result<()> {
        Ok(())
    }
}

/// `logo train`'s console: standard output, never interrupted (a signal ends the
/// process; `--resume` continues from the last periodic checkpoint).
pub struct Stdout;

impl Console for Stdout {
    fn say(&mut self, line: &str) {
        println!("{line}");
    }
}

/// `runs/<config name>-seed<seed>`: where a new run goes unless told otherwise.
pub fn run_dir_for_config(config_path: &Path, seed: u64) -> PathBuf {
    let name = config_path
        .file_stem()
        .map_or("run".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from(format!("runs/{name}-seed{seed}"))
}

pub fn run(args: &TrainArgs) -> Result<()> {
    if let Some(iterations) = args.iterations {
        anyhow::ensure!(iterations > 0, "--iterations must be at least 1");
    }
    anyhow::ensure!(
        args.video_every != Some(0),
        "--video-every must be at least 1"
    );
    if let Some(target) = args.stop_at_return {
        anyhow::ensure!(
            target.is_finite(),
            "--stop-at-return must be a finite number"
        );
    }
    let start = match &args.resume {
        Some(dir) => Start::Resume(dir.clone(), args.iterations),
        None => {
            let config_path = args.config.as_ref().expect("clap: --config or --resume");
            let mut config = TrainConfig::load(config_path)?;
            if let Some(seed) = args.seed {
                config.seed = seed;
            }
            if let Some(iterations) = args.iterations {
                config.iterations = iterations;
            }
            if let Some(threads) = args.threads {
                anyhow::ensure!(threads > 0, "--threads must be at least 1");
                config.threads = threads;
            }
            config
                .check_eval_env_dims()
                .with_context(|| config_path.display().to_string())?;
            if args.print_config {
                let dtype = args.engine.for_config(&config).dtype();
                print!("{}", config.resolved(dtype).to_toml()?);
                return Ok(());
            }
            let out =
                (args.out.clone()).unwrap_or_else(|| run_dir_for_config(config_path, config.seed));
            Start::New(Box::new(config), out)
        }
    };
    let job = Job {
        start,
        stop: args.stop_at_return.map(|r| (r, args.stop_metric)),
        schedule: args.schedule,
        tensorboard: !args.no_tensorboard,
        video_every: args.video_every,
    };
    run_job(job, &args.engine, &mut Stdout).map(|_| ())
}

/// Runs `job` on `engine` (a resumed run without engine flags continues on the engine it
/// last trained on) and returns the run's folder.
pub fn run_job(mut job: Job, engine: &EngineArgs, console: &mut dyn Console) -> Result<PathBuf> {
    let engine = match &mut job.start {
        Start::Resume(dir, _) => {
            let last = last_engine(dir);
            let (engine, taken) = engine.or_trained_on(last.as_deref(), |_| true);
            if taken {
                console.say(&format!(
                    "continuing on {}, the engine this run last trained on \
                     (--engine, --backend or --dtype choose another)",
                    last.unwrap_or_default()
                ));
            }
            engine
        }
        Start::New(config, _) => {
            let engine = engine.for_config(config);
            // The run's stored config names the type it trains in where it names one (a
            // --dtype flag wins over it), so a run made from it again trains the same way.
            // `for_config` gave the engine a dtype wherever the config names one.
            if config.dtype.is_some() {
                config.dtype = engine.dtype;
            }
            engine
        }
    };
    engine.with(Train { job, console })
}

/// The engine the run in `dir` last trained on, as its checkpoint's history names it;
/// None where that cannot be read (the resume itself then says what is wrong with the
/// checkpoint).
fn last_engine(dir: &Path) -> Option<String> {
    let checkpoint = Checkpoint::load(&dir.join(CHECKPOINT)).ok()?;
    Some(
        logo_algo::engine_history(&checkpoint.meta)
            .ok()?
            .pop()?
            .engine,
    )
}

/// `logo train` on the chosen engine.
struct Train<'c> {
    job: Job,
    console: &'c mut dyn Console,
}

impl WithEngine for Train<'_> {
    type Output = PathBuf;
    fn run<E: Engine>(self, engine: E) -> Result<PathBuf> {
        train(engine, self.job, self.console)
    }
}

fn train<E: Engine>(engine: E, job: Job, console: &mut dyn Console) -> Result<PathBuf> {
    let Job {
        start,
        stop,
        schedule,
        tensorboard,
        video_every,
    } = job;
    let (mut trainer, out) = open(engine, start, console)?;
    trainer.set_schedule(schedule);
    if tensorboard {
        trainer.write_tensorboard()?;
    }
    console.say(&start_line(&trainer, &out));
    if let Some(line) = cloning_line(&trainer) {
        console.say(&line);
    }
    let total = trainer.config.iterations;
    let mut last = None;
    // The speed is this invocation's: a resumed run's wall_s also holds earlier
    // invocations' time, perhaps under another load or on another machine.
    let started = std::time::Instant::now();
    let mut made = 0usize;
    while !trainer.done() {
        let m = trainer.step()?;
        made += 1;
        if video_every.is_some_and(|n| (m.iteration + 1).is_multiple_of(n)) {
            let line = record_iteration(&trainer, &out, m.iteration + 1)?;
            console.say(&line);
        }
        let per_iter = started.elapsed().as_secs_f64() / made as f64;
        console.say(&progress_line(&m, &trainer.config, per_iter));
        let reached = stop.is_some_and(|(target, metric)| match metric {
            StopMetric::Eval => m.eval_dense_return >= target,
            StopMetric::Train => m.train_sparse_return >= target,
        });
        let iteration = m.iteration + 1;
        last = Some(m);
        if let Err(stopped) = console.go_on() {
            let path = keep_checkpoint(&trainer, &out)?;
            console.say(&format!(
                "stopped after iteration {iteration}: checkpoint {} (--resume {} goes on)",
                path.display(),
                out.display()
            ));
            return Err(stopped);
        }
        if let (true, Some((target, metric))) = (reached, stop) {
            let path = keep_checkpoint(&trainer, &out)?;
            console.say(&format!(
                "reached --stop-at-return {target} ({metric:?} return): stopped, policy in {}",
                path.display()
            ));
            break;
        }
    }
    let Some(last) = last else {
        console.say(&format!(
            "nothing to do: the run in {} has done its {total} iterations (--iterations extends it)",
            out.display()
        ));
        // A run that ended before its evaluation was written (killed, or older than it).
        if !out.join("eval.json").is_file() {
            end_of_run_evaluation(&trainer, &out, console)?;
        }
        return Ok(out);
    };
    console.say(&format!(
        "done in {:.1} s: final eval dense return {:.1}; {} and {}",
        last.wall_s,
        last.eval_dense_return,
        out.join("metrics.csv").display(),
        out.join(CHECKPOINT).display()
    ));
    end_of_run_evaluation(&trainer, &out, console)?;
    Ok(out)
}

/// What `[init] kind = "bc"` did before the first iteration, if it ran.
fn cloning_line<E: Engine>(trainer: &Trainer<E>) -> Option<String> {
    let r = trainer.behaviour_cloning()?;
    Some(format!(
        "started from behaviour cloning on {} pairs: −log π(a|s) {:.3} → {:.3} in {} Adam steps",
        r.pairs, r.loss_before, r.loss_after, r.steps
    ))
}

/// Writes the run's checkpoint now (a run stopped early); returns its path.
fn keep_checkpoint<E: Engine>(trainer: &Trainer<E>, out: &Path) -> Result<PathBuf> {
    let path = out.join(CHECKPOINT);
    trainer.save_checkpoint(&path)?;
    Ok(path)
}

/// The trainer of a new run or of a resumed one, and its folder.
fn open<E: Engine>(
    engine: E,
    start: Start,
    console: &mut dyn Console,
) -> Result<(Trainer<E>, PathBuf)> {
    match start {
        Start::New(config, out) => {
            let trainer = Trainer::new(engine, *config, &out)?;
            Ok((trainer, out))
        }
        Start::Resume(dir, iterations) => {
            let trainer = Trainer::resume(engine, &dir, iterations)
                .with_context(|| format!("--resume {}", dir.display()))?;
            console.say(&format!(
                "resuming {} after iteration {}",
                dir.display(),
                trainer.iteration()
            ));
            // The evaluation of an earlier end: the new end writes its own.
            if !trainer.done() {
                let stale = dir.join("eval.json");
                if stale.is_file() {
                    std::fs::remove_file(&stale).with_context(|| format!("{}", stale.display()))?;
                }
            }
            Ok((trainer, dir))
        }
    }
}

/// What is trained, on what, and where to.
fn start_line<E: Engine>(trainer: &Trainer<E>, out: &Path) -> String {
    let config = &trainer.config;
    format!(
        "{} on {} (evaluated on {}), {} iterations x {} samples, seed {}, {} envs on {} threads, {} -> {}",
        config.algorithm(),
        config.env,
        config.evaluated_env(),
        config.iterations,
        config.samples_per_iter,
        config.seed,
        config.num_envs,
        config.threads,
        trainer.engine().describe(),
        out.display()
    )
}

/// One iteration's progress line, with the speed so far and the time left.
fn progress_line(m: &IterationMetrics, config: &TrainConfig, per_iter: f64) -> String {
    let total = config.iterations;
    // δ_k exists only where there is a guidance step.
    let delta = match config.guidance {
        Some(_) => format!(" | δk {:.3e}", m.delta_k),
        None => String::new(),
    };
    format!(
        "[{:>4}/{total}] samples {:>9} | sparse {:>9.2} | eval dense {:>9.2} | kl {:.4}{delta} | {:.2} s/it, ETA {:.0} s",
        m.iteration + 1,
        m.samples,
        m.train_sparse_return,
        m.eval_dense_return,
        m.kl,
        per_iter,
        per_iter * (total - m.iteration - 1) as f64
    )
}

/// `eval.json`: the final and the best policy (the latest to reach the highest evaluation
/// of the trained task's own return, kept by the trainer as best.safetensors) over fresh
/// initial states of the trained task, on the run's engine (see `final_eval`).
fn end_of_run_evaluation<E: Engine>(
    trainer: &Trainer<E>,
    out: &Path,
    console: &mut dyn Console,
) -> Result<()> {
    let config = &trainer.config;
    let engine = trainer.engine();
    let env_id = config.evaluated_env().env_id()?;
    let env = env_id.as_str();
    let (seed, episodes) = (config.seed, final_eval::EPISODES);
    let acting = trainer.acting();
    let mut policies = vec![(
        "final",
        CHECKPOINT,
        trainer.iteration() as u64,
        final_eval::report(env, &acting, seed, episodes, config.success)?,
    )];
    let best = out.join(BEST);
    if best.is_file() {
        let stored = crate::eval::load_policy(&best)?;
        let acting = stored.acting(engine);
        let report = final_eval::report(env, &acting, seed, episodes, config.success)?;
        policies.push(("best", BEST, stored.meta.iteration, report));
    }
    final_eval::write(&out.join("eval.json"), env, seed, episodes, &policies)?;
    for (name, _, iteration, report) in &policies {
        let s = &report["mean_action"]["summary"];
        let reached = final_eval::reached_line(s).map_or(String::new(), |line| format!(", {line}"));
        console.say(&format!(
            "{name} policy (iteration {iteration}) over {episodes} fresh episodes: return {:.1}, \
             dense return {:.1}{reached}",
            s["return"].as_f64().unwrap_or(f64::NAN),
            s["dense_return"].as_f64().unwrap_or(f64::NAN),
        ));
    }
    console.say(&format!("evaluation: {}", out.join("eval.json").display()));
    Ok(())
}

/// The video of `--video-every`: the mean action of the policy after `iteration`
/// iterations, one episode of the evaluation env from its first initial state.
fn record_iteration<E: Engine>(
    trainer: &Trainer<E>,
    out: &Path,
    iteration: usize,
) -> Result<String> {
    let config = &trainer.config;
    let factory = EnvFactory::new(&config.eval_env_id(), &EnvOptions::default())?;
    let dir = out.join("videos");
    std::fs::create_dir_all(&dir).with_context(|| format!("{}", dir.display()))?;
    let path = dir.join(format!("iteration-{iteration:05}.mp4"));
    let frames = Frames {
        width: 480,
        height: 480,
        fps: None,
        look: VideoLook::Fast,
    };
    let mut video = Video::start(&path, &factory, frames)?;
    let acting = trainer.acting();
    let mut env = factory.build()?;
    let label = format!("iteration {iteration} | ");
    let seed = evaluation_seed(config.seed, 0);
    let episode = record_episode(&mut video, env.as_mut(), seed, &label, |obs| {
        acting.mean(obs)
    })?;
    video.finish()?;
    Ok(format!(
        "video: {} (dense return {:.1}, {} steps)",
        path.display(),
        episode.dense_return,
        episode.length
    ))
}

//! `logo compare --config my_task.toml`: the user's question, "is LOGO the right method
//! for my sparse task and my demonstrations?", in one command. Each algorithm is made from
//! the one LOGO config (`logo_algo::algorithms::configure`: same task, settings and
//! demonstrations), the runs go through `logo sweep` (finished runs skipped, interrupted
//! ones resumed, local jobs or a Slurm array), and the folder gets `report.md` (IQM with
//! 95% intervals per method, P(LOGO > method), the final policies' own evaluation) and
//! `figure.png` (a curve per method with its 95% band), both of the dense evaluation or of
//! the metrics.csv column `--metric` names.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use clap::{Args, Command, FromArgMatches};
use logo_algo::algorithms::{comparable, configure};
use logo_algo::{IterationMetrics, TrainConfig};
use logo_engine::EngineArgs;
use logo_stats::Bootstrap;

use crate::plot::PlotArgs;
use crate::runs::{EVAL_RETURN, Metric, discover, parse_max_samples};
use crate::summary::{AtRule, compare_table, eval_json_table, intervals_table, table};
use crate::sweep::{self, SweepArgs};

#[derive(Args)]
pub struct CompareArgs {
    /// A LOGO config of the task (its env, budget, settings and `[guidance] demos`).
    #[arg(long)]
    config: PathBuf,
    /// The algorithms, comma-separated (default: every one `logo algorithms` marks
    /// comparable).
    #[arg(
        long,
        value_delimiter = ',',
        default_values_t = comparable().into_iter().map(String::from)
    )]
    algorithms: Vec<String>,
    /// Seeds: a range `0..5` (5 excluded), `0..=4`, a list `0,2,7`.
    #[arg(long, default_value = "0..5")]
    seeds: String,
    /// The budget in samples per run (e.g. 2M): iterations = ⌈samples / the config's
    /// samples_per_iter⌉. Default: the config's iterations.
    #[arg(long, value_parser = parse_max_samples)]
    samples: Option<f64>,
    /// Overrides the budget as a number of iterations.
    #[arg(long, conflicts_with = "samples")]
    iterations: Option<usize>,
    /// The comparison's folder (default: runs/compare-<config name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Runs at a time.
    #[arg(long, default_value_t = 1)]
    jobs: usize,
    /// Threads for all runs together (default: the machine's cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Read the budget as each run's mean of its N evaluations nearest it (as `logo
    /// summary --window`), instead of the one interpolated evaluation.
    #[arg(long)]
    window: Option<usize>,
    /// Also give the samples each method's seeds needed to reach this return.
    #[arg(long)]
    target: Option<f64>,
    /// Write a Slurm job array instead of running locally (`logo compare` again, once
    /// the array is done, writes the report).
    #[arg(long)]
    slurm: bool,
    /// Resamples of the bootstrap behind every interval.
    #[arg(long, default_value_t = 20_000)]
    reps: usize,
    /// The metrics.csv column the report and figure read: the mean action's dense
    /// evaluation by default (the LOGO paper's Figure 1), or e.g. train_sparse_return
    /// (the sampled episodes' sparse return: the sparse task itself) or eval_success.
    #[arg(long, default_value = EVAL_RETURN)]
    metric: String,
    #[command(flatten)]
    engine: EngineArgs,
}

/// Parses `args` as the subcommand `T` (`sweep`, `plot`) would be parsed on the command
/// line, so that compare runs them exactly as a user would.
fn as_subcommand<T: Args + FromArgMatches>(name: &'static str, args: &[String]) -> Result<T> {
    let matches = T::augment_args(Command::new(name))
        .try_get_matches_from(std::iter::once(name.to_string()).chain(args.iter().cloned()))
        .with_context(|| format!("logo {name} {}", args.join(" ")))?;
    Ok(T::from_arg_matches(&matches)?)
}

/// The flags' own errors, before anything is loaded or trained.
fn check_flags(args: &CompareArgs) -> Result<()> {
    ensure!(!args.algorithms.is_empty(), "--algorithms names none");
    for name in &args.algorithms {
        ensure!(
            comparable().contains(&name.as_str()),
            "--algorithms: unknown algorithm {name:?}: expected some of {}",
            comparable().join(", ")
        );
    }
    ensure!(args.reps >= 1, "--reps must be at least 1");
    ensure!(args.window != Some(0), "--window must be at least 1");
    let columns = IterationMetrics::numeric_columns();
    ensure!(
        columns.contains(&args.metric),
        "--metric {:?}: not a numeric column of metrics.csv; expected one of {}",
        args.metric,
        columns.join(", ")
    );
    Ok(())
}

pub fn run(args: &CompareArgs) -> Result<()> {
    check_flags(args)?;
    let mut base = TrainConfig::load(&args.config)?;
    if let Some(samples) = args.samples {
        ensure!(samples >= 1.0, "--samples must be at least 1");
        base.iterations = (samples / base.samples_per_iter as f64).ceil() as usize;
    }
    if let Some(iterations) = args.iterations {
        ensure!(iterations > 0, "--iterations must be at least 1");
        base.iterations = iterations;
    }
    let budget = (base.iterations * base.samples_per_iter) as f64;
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args
            .config
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy();
        PathBuf::from(format!("runs/compare-{stem}"))
    });
    let mut sweep_args = write_configs(args, &base, &out)?;
    sweep_args.extend([
        "--seeds".into(),
        args.seeds.clone(),
        "--out".into(),
        out.display().to_string(),
        "--jobs".into(),
        args.jobs.to_string(),
    ]);
    if let Some(threads) = args.threads {
        sweep_args.extend(["--threads".into(), threads.to_string()]);
    }
    if args.slurm {
        sweep_args.push("--slurm".into());
    }
    sweep_args.extend(args.engine.to_args());
    sweep::run(&as_subcommand::<SweepArgs>("sweep", &sweep_args)?)?;
    if args.slurm {
        println!(
            "compare: the runs are an array to submit; `logo compare` with the same flags, \
             once it is done, writes the report"
        );
        return Ok(());
    }
    // The runs asked for, and no others an earlier call may have left in the folder.
    let seeds = sweep::parse_seeds(&args.seeds)?;
    let run_dirs: Vec<PathBuf> = args
        .algorithms
        .iter()
        .flat_map(|a| {
            let method = out.join(a);
            seeds.iter().map(move |s| method.join(format!("seed{s}")))
        })
        .collect();
    let report = report(args, &run_dirs, budget)?;
    let path = out.join("report.md");
    std::fs::write(&path, &report).with_context(|| format!("{}", path.display()))?;
    let figure = out.join("figure.png");
    let mut plot_args: Vec<String> = run_dirs.iter().map(|d| d.display().to_string()).collect();
    plot_args.extend([
        "--out".into(),
        figure.display().to_string(),
        "--stat".into(),
        "iqm".into(),
        "--metric".into(),
        args.metric.clone(),
    ]);
    crate::plot::run(&as_subcommand::<PlotArgs>("plot", &plot_args)?)?;
    println!("compare: {} and {}", path.display(), figure.display());
    Ok(())
}

/// One config per algorithm in `out/configs/` (a sweep names its runs after the files);
/// their paths.
fn write_configs(args: &CompareArgs, base: &TrainConfig, out: &Path) -> Result<Vec<String>> {
    let configs_dir = out.join("configs");
    std::fs::create_dir_all(&configs_dir).with_context(|| format!("{}", configs_dir.display()))?;
    let mut configs = Vec::new();
    for name in &args.algorithms {
        let config = configure(base, name)
            .with_context(|| format!("{}: as {name}", args.config.display()))?;
        let path = configs_dir.join(format!("{name}.toml"));
        let text = format!(
            "# {name}, made by `logo compare` from {}\n{}",
            args.config.display(),
            config.to_toml()?
        );
        std::fs::write(&path, text).with_context(|| format!("{}", path.display()))?;
        configs.push(path.display().to_string());
    }
    Ok(configs)
}

/// `report.md`: the methods' returns at the budget, over seeds with intervals, and LOGO
/// against each other method.
fn report(args: &CompareArgs, run_dirs: &[PathBuf], budget: f64) -> Result<String> {
    let metric = Metric {
        column: args.metric.clone(),
        log10: false,
    };
    let runs = discover(run_dirs, &metric)?;
    let at = [budget];
    let rule = args.window.map_or(AtRule::Interpolate, AtRule::Window);
    let bootstrap = Bootstrap::with_reps(args.reps);
    let (metric_flag, values) = if args.metric == EVAL_RETURN {
        (
            String::new(),
            "the dense evaluation's returns (metrics.csv's `eval_dense_return`)".to_string(),
        )
    } else {
        (
            format!(" --metric {}", args.metric),
            format!(
                "metrics.csv's `{}`, but for the end-of-run table",
                args.metric
            ),
        )
    };
    let mut text = format!(
        "# {}: {}\n\nMade by `logo compare --config {} --algorithms {} --seeds {}{metric_flag}` \
         with a budget of {budget:.0} samples per run. Each method is the config made into \
         it by its own keys alone (the configs are in `configs/`; `docs/algorithms.md`). \
         The values are {values}.\n\n",
        args.config.display(),
        args.algorithms.join(", "),
        args.config.display(),
        args.algorithms.join(","),
        args.seeds,
    );
    text.push_str(&table(&runs, &at, rule, args.target)?);
    text.push('\n');
    text.push_str(&intervals_table(&runs, &at, rule, &bootstrap));
    if let Some(final_policies) = eval_json_table(&runs, &bootstrap)? {
        text.push('\n');
        text.push_str(&final_policies);
    }
    if args.algorithms.iter().any(|a| a == "logo") {
        for other in args.algorithms.iter().filter(|a| *a != "logo") {
            text.push('\n');
            text.push_str(&compare_table(&runs, "logo", other, &at, rule, &bootstrap)?);
        }
    }
    text.push_str("\n![the methods' curves: IQM over seeds with 95% bands](figure.png)\n");
    Ok(text)
}

//! `logo summary RUN_DIRS…`: the numbers behind a figure, one markdown row per
//! configuration (the groups of `logo plot`): the final, peak and late returns, mean ±
//! std over seeds, and optionally the return at fixed sample counts and the samples a
//! seed needed to reach a threshold. `--external` adds a row for an outside curve (a
//! published or reference run, one seed), so that a table at equal samples sets this
//! project's seeds beside it; `--window` reads every run as the reference curves are
//! quoted, as the mean of the evaluations nearest each sample count.

use std::collections::BTreeMap;

use anyhow::{Result, ensure};
use clap::Args;
use logo_stats::{Aggregate, Bootstrap, Estimate, mean_std, median};

use crate::runs::{
    EVAL_RETURN, Metric, Run, RunSelection, interpolate, parse_max_samples, up_to,
    with_external_runs,
};

#[derive(Args)]
pub struct SummaryArgs {
    #[command(flatten)]
    selection: RunSelection,
    /// Also report each configuration's return at this many samples (e.g. 2e6 or 2M;
    /// linear between evaluations; a run that stops earlier is left out of that column).
    /// Repeatable: one column each.
    #[arg(long, value_parser = parse_max_samples)]
    at: Vec<f64>,
    /// Read each `--at` column as each run's mean over its WINDOW evaluations nearest
    /// that sample count (the reference curves' README quotes 10), instead of the one
    /// interpolated evaluation. A run then counts if it stops at most one evaluation
    /// short of the sample count.
    #[arg(long)]
    window: Option<usize>,
    /// Also count the seeds whose evaluation reached this return, and the samples each
    /// first needed (median over those seeds).
    #[arg(long)]
    threshold: Option<f64>,
    /// Leave out the second table (mean and IQM over seeds with bootstrap intervals).
    #[arg(long)]
    no_intervals: bool,
    /// The metrics.csv column every per-iteration table reads (e.g. train_sparse_return:
    /// the sampled episodes' return on the trained task), instead of the dense
    /// evaluation's return. Named above the tables when it is not the default.
    #[arg(long, default_value = EVAL_RETURN)]
    metric: String,
    /// Resamples of the stratified bootstrap behind every interval.
    #[arg(long, default_value_t = 50_000)]
    reps: usize,
    /// Also compare configuration A with B at each budget: the probability that a seed of
    /// A improves on one of B, and the difference of their IQMs, with 95% intervals.
    /// Repeatable: one table per pair (e.g. every variant against LOGO).
    #[arg(long, num_args = 2, value_names = ["A", "B"], action = clap::ArgAction::Append)]
    compare: Vec<String>,
}

/// How a `--at` column reads a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AtRule {
    /// The evaluation curve at the sample count, linear between evaluations; runs
    /// that stop earlier are left out.
    Interpolate,
    /// The mean of this many evaluations nearest the sample count; runs that stop more
    /// than one evaluation short of it are left out.
    Window(usize),
}

/// What one run's evaluations say.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    pub final_return: f64,
    pub final_samples: f64,
    pub peak: f64,
    pub samples_at_peak: f64,
    /// Mean over the last 10% of evaluations (at least one).
    pub late_mean: f64,
    /// One per `--at` sample count: None where the run does not reach it.
    pub at: Vec<Option<f64>>,
    /// Samples at the first evaluation at or above the threshold.
    pub reached_at: Option<f64>,
}

pub fn summarise(run: &Run, at: &[f64], rule: AtRule, threshold: Option<f64>) -> RunSummary {
    let points = &run.points;
    let (final_samples, final_return) = points[points.len() - 1];
    let (samples_at_peak, peak) =
        points
            .iter()
            .copied()
            .fold((0.0, f64::NEG_INFINITY), |best, p| {
                if p.1 > best.1 { p } else { best }
            });
    let late = points.len().div_ceil(10);
    let late_mean = points[points.len() - late..]
        .iter()
        .map(|p| p.1)
        .sum::<f64>()
        / late as f64;
    RunSummary {
        final_return,
        final_samples,
        peak,
        samples_at_peak,
        late_mean,
        at: at.iter().map(|&x| value_at(points, x, rule)).collect(),
        reached_at: threshold.and_then(|t| points.iter().find(|p| p.1 >= t).map(|p| p.0)),
    }
}

/// The run's value at `x` samples under `rule`, or None where it stops too early.
fn value_at(points: &[(f64, f64)], x: f64, rule: AtRule) -> Option<f64> {
    let final_samples = points[points.len() - 1].0;
    match rule {
        AtRule::Interpolate => (x <= final_samples).then(|| interpolate(points, x)),
        AtRule::Window(n) => {
            // "One evaluation short": the median spacing between evaluations.
            let gaps: Vec<f64> = points.windows(2).map(|w| w[1].0 - w[0].0).collect();
            let spacing = if gaps.is_empty() { 0.0 } else { median(&gaps) };
            if x > final_samples + spacing {
                return None;
            }
            // Ties go to the later evaluation: a window of 10 at iteration k's samples
            // is iterations k-4..=k+5.
            let mut nearest = points.to_vec();
            nearest.sort_by(|a, b| {
                (a.0 - x)
                    .abs()
                    .total_cmp(&(b.0 - x).abs())
                    .then(b.0.total_cmp(&a.0))
            });
            let window = &nearest[..n.min(nearest.len())];
            Some(window.iter().map(|p| p.1).sum::<f64>() / window.len() as f64)
        }
    }
}

fn pm(values: &[f64]) -> String {
    let (m, s) = mean_std(values);
    format!("{m:.0} ± {s:.0}")
}

fn thousands(samples: f64) -> String {
    if samples >= 1e6 {
        format!("{:.2}M", samples / 1e6)
    } else {
        format!("{:.0}k", samples / 1e3)
    }
}

/// The markdown table for `runs`, one row per group in name order.
pub fn table(runs: &[Run], at: &[f64], rule: AtRule, threshold: Option<f64>) -> Result<String> {
    ensure!(
        at.iter().all(|x| x.is_finite() && *x > 0.0),
        "--at must be a positive sample count"
    );
    ensure!(
        rule != AtRule::Window(0),
        "--window must be at least one evaluation"
    );
    ensure!(
        threshold.is_none_or(f64::is_finite),
        "--threshold must be a number"
    );
    let mut groups: BTreeMap<&str, Vec<RunSummary>> = BTreeMap::new();
    for run in runs {
        groups
            .entry(&run.group)
            .or_default()
            .push(summarise(run, at, rule, threshold));
    }
    let mut header = vec![
        "configuration".to_string(),
        "seeds".into(),
        "samples (min–max)".into(),
        "final".into(),
        "peak".into(),
        "samples at peak (median)".into(),
        "mean of last 10%".into(),
    ];
    // The budget columns, named as the interval table names them (without "final").
    header.extend(budget_names(at, rule).into_iter().skip(1));
    if let Some(t) = threshold {
        header.push(format!("seeds ≥ {t} (median samples)"));
    }
    let mut out = format!(
        "| {} |\n|{}\n",
        header.join(" | "),
        " --- |".repeat(header.len())
    );
    for (group, s) in groups {
        let col = |f: fn(&RunSummary) -> f64| s.iter().map(f).collect::<Vec<_>>();
        let finals = col(|r| r.final_samples);
        let (lo, hi) = (
            finals.iter().copied().fold(f64::MAX, f64::min),
            finals.iter().copied().fold(f64::MIN, f64::max),
        );
        let mut row = vec![
            group.to_string(),
            s.len().to_string(),
            format!("{}–{}", thousands(lo), thousands(hi)),
            pm(&col(|r| r.final_return)),
            pm(&col(|r| r.peak)),
            thousands(median(&col(|r| r.samples_at_peak))),
            pm(&col(|r| r.late_mean)),
        ];
        for column in 0..at.len() {
            let values: Vec<f64> = s.iter().filter_map(|r| r.at[column]).collect();
            row.push(match values.len() {
                0 => "—".into(),
                1 if s.len() > 1 => format!("{} (1 seed)", pm(&values)),
                n if n < s.len() => format!("{} ({n} seeds)", pm(&values)),
                _ => pm(&values),
            });
        }
        if threshold.is_some() {
            let reached: Vec<f64> = s.iter().filter_map(|r| r.reached_at).collect();
            row.push(if reached.is_empty() {
                format!("0/{}", s.len())
            } else {
                let n = reached.len();
                format!("{n}/{} ({})", s.len(), thousands(median(&reached)))
            });
        }
        out.push_str(&format!("| {} |\n", row.join(" | ")));
    }
    Ok(out)
}

pub fn run(args: &SummaryArgs) -> Result<()> {
    let metric = Metric {
        column: args.metric.clone(),
        log10: false,
    };
    let selection = &args.selection;
    let mut runs = with_external_runs(selection.discover(&metric)?, &selection.externals)?;
    if let Some(max_samples) = selection.max_samples {
        up_to(&mut runs, max_samples)?;
    }
    let rule = args.window.map_or(AtRule::Interpolate, AtRule::Window);
    if args.metric != EVAL_RETURN {
        println!(
            "Every value below but eval.json's is metrics.csv's `{}`.\n",
            args.metric
        );
    }
    print!("{}", table(&runs, &args.at, rule, args.threshold)?);
    ensure!(args.reps >= 1, "--reps must be at least 1");
    let bootstrap = Bootstrap::with_reps(args.reps);
    if !args.no_intervals {
        print!("\n{}", intervals_table(&runs, &args.at, rule, &bootstrap));
    }
    if let Some(table) = eval_json_table(&runs, &bootstrap)? {
        print!("\n{table}");
    }
    for pair in args.compare.chunks_exact(2) {
        let (a, b) = (&pair[0], &pair[1]);
        print!(
            "\n{}",
            compare_table(&runs, a, b, &args.at, rule, &bootstrap)?
        );
    }
    Ok(())
}

/// Each group's values per budget column: "final", then one per `--at` (the seeds
/// that reach it).
fn budget_values(runs: &[Run], at: &[f64], rule: AtRule) -> BTreeMap<String, Vec<Vec<f64>>> {
    let mut groups: BTreeMap<String, Vec<Vec<f64>>> = BTreeMap::new();
    for run in runs {
        let s = summarise(run, at, rule, None);
        let columns = groups
            .entry(run.group.clone())
            .or_insert_with(|| vec![Vec::new(); at.len() + 1]);
        columns[0].push(s.final_return);
        for (column, value) in columns[1..].iter_mut().zip(&s.at) {
            column.extend(value);
        }
    }
    groups
}

fn budget_names(at: &[f64], rule: AtRule) -> Vec<String> {
    let mut names = vec!["final".to_string()];
    names.extend(at.iter().map(|&x| match rule {
        AtRule::Interpolate => format!("at {}", thousands(x)),
        AtRule::Window(n) => format!("at {}, mean of {n}", thousands(x)),
    }));
    names
}

fn interval(e: Estimate) -> String {
    format!("{:.0} [{:.0}, {:.0}]", e.point, e.lo, e.hi)
}

/// Mean and interquartile mean over each group's seeds at each budget, with
/// stratified-bootstrap 95% percentile intervals (logo-stats' conventions).
pub fn intervals_table(runs: &[Run], at: &[f64], rule: AtRule, bootstrap: &Bootstrap) -> String {
    let names = budget_names(at, rule);
    let mut out = format!(
        "Over seeds, with 95% stratified-bootstrap intervals ({} resamples):\n\n",
        bootstrap.reps
    );
    let mut header = vec!["configuration".to_string(), "seeds".to_string()];
    for name in &names {
        header.push(format!("{name}: mean [95% CI]"));
        header.push(format!("{name}: IQM [95% CI]"));
    }
    out.push_str(&format!(
        "| {} |\n|{}\n",
        header.join(" | "),
        " --- |".repeat(header.len())
    ));
    for (group, columns) in budget_values(runs, at, rule) {
        // Every run has a final value: its count is the group's seeds.
        let all = columns[0].len();
        let mut row = vec![group, all.to_string()];
        for values in &columns {
            match values.len() {
                0 => row.extend(["—".to_string(), "—".to_string()]),
                1 => row.extend([format!("{:.0}", values[0]), "—".to_string()]),
                n => {
                    let seeds = if n < all {
                        format!(" ({n} seeds)")
                    } else {
                        String::new()
                    };
                    for aggregate in [Aggregate::Mean, Aggregate::Iqm] {
                        row.push(interval(bootstrap.aggregate(values, aggregate)) + &seeds);
                    }
                }
            }
        }
        out.push_str(&format!("| {} |\n", row.join(" | ")));
    }
    out
}

/// The numbers of a run's `eval.json` that the summary reports, in column order.
const EVAL_JSON_COLUMNS: [(&str, &str, &str, &str); 5] = [
    ("final: return", "final", "mean_action", "return"),
    (
        "final: dense return",
        "final",
        "mean_action",
        "dense_return",
    ),
    ("final: dense, clipped", "final", "clipped", "dense_return"),
    ("best: return", "best", "mean_action", "return"),
    ("best: dense return", "best", "mean_action", "dense_return"),
];

/// The end-of-run evaluations (`eval.json`: 20 episodes from fresh initial states) of
/// the runs that have one, per configuration: mean over seeds with its 95% interval, and
/// the success rates; None where no run has one.
pub fn eval_json_table(runs: &[Run], bootstrap: &Bootstrap) -> Result<Option<String>> {
    let mut groups: BTreeMap<&str, Vec<serde_json::Value>> = BTreeMap::new();
    for run in runs {
        let Some(path) = run
            .dir
            .as_ref()
            .and_then(|d| crate::runs::kept_file(d, "eval.json"))
        else {
            continue;
        };
        let text = crate::runs::read_kept(&path)?;
        let doc: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| anyhow::anyhow!("{}: not an eval.json ({e})", path.display()))?;
        groups
            .entry(&run.group)
            .or_default()
            .push(doc["policies"].clone());
    }
    if groups.is_empty() {
        return Ok(None);
    }
    let mut header = vec!["configuration".to_string(), "runs".to_string()];
    header.extend(
        EVAL_JSON_COLUMNS
            .iter()
            .map(|c| format!("{} [95% CI]", c.0)),
    );
    header.extend(["final: success".to_string(), "best: success".to_string()]);
    let mut out = format!(
        "End-of-run evaluations (eval.json: 20 episodes from fresh initial states, mean over \
         seeds with 95% bootstrap intervals):\n\n| {} |\n|{}\n",
        header.join(" | "),
        " --- |".repeat(header.len())
    );
    for (group, docs) in groups {
        let values = |policy: &str, acting: &str, key: &str| -> Vec<f64> {
            docs.iter()
                .filter_map(|d| d[policy][acting]["summary"][key].as_f64())
                .collect()
        };
        let mut row = vec![group.to_string(), docs.len().to_string()];
        for (_, policy, acting, key) in EVAL_JSON_COLUMNS {
            let v = values(policy, acting, key);
            row.push(match v.len() {
                0 => "—".into(),
                1 => format!("{:.0}", v[0]),
                _ => interval(bootstrap.aggregate(&v, Aggregate::Mean)),
            });
        }
        for policy in ["final", "best"] {
            let v = values(policy, "mean_action", "success_rate");
            row.push(if v.is_empty() {
                "—".into()
            } else {
                format!("{:.0}%", 100.0 * logo_stats::mean(&v))
            });
        }
        out.push_str(&format!("| {} |\n", row.join(" | ")));
    }
    Ok(Some(out))
}

/// Configuration `a` against `b` at each budget: P(a > b) and IQM(a) − IQM(b), each with
/// its 95% interval over independent resamples of the two groups' seeds.
pub fn compare_table(
    runs: &[Run],
    a: &str,
    b: &str,
    at: &[f64],
    rule: AtRule,
    bootstrap: &Bootstrap,
) -> Result<String> {
    let groups = budget_values(runs, at, rule);
    let known = || groups.keys().cloned().collect::<Vec<_>>().join(", ");
    let of = |name: &str| {
        groups.get(name).ok_or_else(|| {
            anyhow::anyhow!(
                "--compare: no configuration {name:?} among the runs (they are: {})",
                known()
            )
        })
    };
    let (xa, xb) = (of(a)?, of(b)?);
    let mut out = format!(
        "{a} against {b}, with 95% bootstrap intervals ({} resamples):\n\n\
         | budget | seeds | P({a} > {b}) [95% CI] | IQM difference [95% CI] |\n\
         | --- | --- | --- | --- |\n",
        bootstrap.reps
    );
    for ((name, x), y) in budget_names(at, rule).iter().zip(xa).zip(xb) {
        if x.is_empty() || y.is_empty() {
            out.push_str(&format!(
                "| {name} | {} vs {} | — | — |\n",
                x.len(),
                y.len()
            ));
            continue;
        }
        let p = bootstrap.improvement(x, y);
        let d = bootstrap.estimate_two(std::slice::from_ref(x), std::slice::from_ref(y), |x, y| {
            Aggregate::Iqm.of(x) - Aggregate::Iqm.of(y)
        });
        out.push_str(&format!(
            "| {name} | {} vs {} | {:.2} [{:.2}, {:.2}] | {} |\n",
            x.len(),
            y.len(),
            p.point,
            p.lo,
            p.hi,
            interval(d)
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(group: &str, points: &[(f64, f64)]) -> Run {
        Run::unseeded(group, points.to_vec())
    }

    #[test]
    fn a_run_reports_its_peak_late_mean_and_threshold() {
        let points: Vec<(f64, f64)> = (1..=20)
            .map(|k| (k as f64 * 1000.0, if k == 8 { 500.0 } else { k as f64 }))
            .collect();
        let s = summarise(
            &run("a", &points),
            &[2500.0],
            AtRule::Interpolate,
            Some(15.0),
        );
        assert_eq!((s.peak, s.samples_at_peak), (500.0, 8000.0));
        assert_eq!((s.final_return, s.final_samples), (20.0, 20000.0));
        assert_eq!(s.late_mean, 19.5); // the last 2 of 20
        assert_eq!(s.at, [Some(2.5)]);
        assert_eq!(s.reached_at, Some(8000.0));
        // Past a run's end there is no value, and an unreached threshold is None.
        let s = summarise(
            &run("a", &points),
            &[30000.0],
            AtRule::Interpolate,
            Some(1000.0),
        );
        assert_eq!((s.at, s.reached_at), (vec![None], None));
    }

    #[test]
    fn the_table_aggregates_seeds_per_group() {
        let runs = [
            run("logo", &[(1e5, 10.0), (2e5, 30.0)]),
            run("logo", &[(1e5, 20.0), (2e5, 50.0)]),
            run("trpo", &[(1e5, 1.0), (1.5e5, 2.0)]),
        ];
        let t = table(&runs, &[1.5e5], AtRule::Interpolate, Some(25.0)).unwrap();
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines.len(), 4, "{t}");
        // final 40 ± 14 (30, 50), peak the same, at 150k: 20 and 35 → 28 ± 11.
        assert_eq!(
            lines[2],
            "| logo | 2 | 200k–200k | 40 ± 14 | 40 ± 14 | 200k | 40 ± 14 | 28 ± 11 | 2/2 (200k) |"
        );
        assert_eq!(
            lines[3],
            "| trpo | 1 | 150k–150k | 2 ± 0 | 2 ± 0 | 150k | 2 ± 0 | 2 ± 0 | 0/1 |"
        );
        assert!(table(&runs, &[-1.0], AtRule::Interpolate, None).is_err());
        assert!(table(&runs, &[1e5], AtRule::Window(0), None).is_err());
    }

    #[test]
    fn a_window_averages_the_nearest_evaluations_and_tolerates_one_missing() {
        // Evaluations every 1000 samples, value = k, from 1000 to 10000.
        let points: Vec<(f64, f64)> = (1..=10).map(|k| (k as f64 * 1000.0, k as f64)).collect();
        let r = run("a", &points);
        let at = [5000.0, 10500.0, 11000.0, 12000.0];
        let s = summarise(&r, &at, AtRule::Window(3), None);
        // Nearest 3 to 5000: 4000, 5000, 6000. At 10500 and 11000 the run is at most one
        // evaluation short (nearest: 8000-10000); at 12000 it is two short.
        assert_eq!(s.at, [Some(5.0), Some(9.0), Some(9.0), None]);
        // Equally near evaluations: the later one counts (5000 and 6000, not 4000).
        assert_eq!(
            summarise(&r, &[5000.0], AtRule::Window(2), None).at,
            [Some(5.5)]
        );
        // A window wider than the run takes the whole run.
        assert_eq!(
            summarise(&r, &[5000.0], AtRule::Window(50), None).at,
            [Some(5.5)]
        );
        // A seed that stops short is left out of that column, and the cell says so.
        let short = run("a", &points[..5]);
        let t = table(&[r.clone(), short], &[10000.0], AtRule::Window(3), None).unwrap();
        assert!(
            t.lines().nth(2).unwrap().ends_with("| 9 ± 0 (1 seed) |"),
            "{t}"
        );
        let t = table(&[r], &at[..2], AtRule::Window(3), None).unwrap();
        assert!(
            t.lines()
                .next()
                .unwrap()
                .ends_with("| at 5k, mean of 3 | at 10k, mean of 3 |"),
            "{t}"
        );
        assert!(
            t.lines().nth(2).unwrap().ends_with("| 5 ± 0 | 9 ± 0 |"),
            "{t}"
        );
    }

    fn five_and_three() -> Vec<Run> {
        let mut runs: Vec<Run> = [10.0, 20.0, 30.0, 40.0, 1000.0]
            .iter()
            .map(|&y| run("a", &[(1e5, y), (2e5, y)]))
            .collect();
        runs.extend(
            [1.0, 2.0, 3.0]
                .iter()
                .map(|&y| run("b", &[(1e5, y), (1.5e5, y)])),
        );
        runs
    }

    #[test]
    fn the_interval_table_gives_mean_and_iqm_with_their_intervals() {
        let runs = five_and_three();
        let bootstrap = Bootstrap::with_reps(2_000);
        let t = intervals_table(&runs, &[2e5], AtRule::Interpolate, &bootstrap);
        let rows: Vec<&str> = t
            .lines()
            .filter(|l| l.starts_with("| a") || l.starts_with("| b"))
            .collect();
        let values = [10.0, 20.0, 30.0, 40.0, 1000.0];
        let mean = bootstrap.aggregate(&values, Aggregate::Mean);
        let iqm = bootstrap.aggregate(&values, Aggregate::Iqm);
        // IQM of five drops one at each end: (20 + 30 + 40) / 3 = 30, far from the mean 220.
        assert_eq!(iqm.point, 30.0);
        assert_eq!(
            rows[0],
            format!(
                "| a | 5 | {} | {} | {} | {} |",
                interval(mean),
                interval(iqm),
                interval(mean),
                interval(iqm)
            )
        );
        // b stops before 200k: its budget cell is empty.
        assert!(
            rows[1].starts_with("| b | 3 | 2 [1, 3] | 2 [1, 3] | — | — |"),
            "{}",
            rows[1]
        );
    }

    #[test]
    fn compare_gives_the_probability_of_improvement_and_names_unknown_groups() {
        let runs = five_and_three();
        let bootstrap = Bootstrap::with_reps(2_000);
        let t = compare_table(&runs, "a", "b", &[], AtRule::Interpolate, &bootstrap).unwrap();
        // Every a is above every b: P = 1 in every resample.
        assert!(t.contains("| final | 5 vs 3 | 1.00 [1.00, 1.00] |"), "{t}");
        let t = compare_table(&runs, "b", "a", &[], AtRule::Interpolate, &bootstrap).unwrap();
        assert!(t.contains("| final | 3 vs 5 | 0.00 [0.00, 0.00] |"), "{t}");
        let e = compare_table(&runs, "a", "c", &[], AtRule::Interpolate, &bootstrap).unwrap_err();
        assert!(
            e.to_string().contains("no configuration \"c\"") && e.to_string().contains("a, b"),
            "{e}"
        );
    }

    #[test]
    fn eval_json_files_become_a_table_of_final_and_best() {
        let dir = std::env::temp_dir().join(format!("logo-summary-evals-{}", std::process::id()));
        let mut runs = Vec::new();
        for (seed, (ret, dense)) in [(1.0, 10.0), (3.0, 30.0)].into_iter().enumerate() {
            let run_dir = dir.join(format!("seed{seed}"));
            std::fs::create_dir_all(&run_dir).unwrap();
            let summary = |r: f64, d: f64| serde_json::json!({"summary": {"return": r, "dense_return": d, "success_rate": 0.5}});
            let doc = serde_json::json!({"policies": {
                "final": {"mean_action": summary(ret, dense), "clipped": summary(ret, dense + 1.0)},
                "best": {"mean_action": summary(ret + 1.0, dense), "clipped": summary(ret, dense)},
            }});
            std::fs::write(run_dir.join("eval.json"), doc.to_string()).unwrap();
            let mut run = run("logo", &[(1.0, 1.0)]);
            run.dir = Some(run_dir);
            runs.push(run);
        }
        runs.push(run("outside", &[(1.0, 1.0)]));
        let bootstrap = Bootstrap::with_reps(500);
        let table = eval_json_table(&runs, &bootstrap).unwrap().unwrap();
        let row = table.lines().find(|l| l.starts_with("| logo |")).unwrap();
        let final_return = interval(bootstrap.aggregate(&[1.0, 3.0], Aggregate::Mean));
        assert!(
            row.starts_with(&format!("| logo | 2 | {final_return} |")),
            "{row}"
        );
        assert!(row.ends_with("| 50% | 50% |"), "{row}");
        assert!(!table.contains("outside"), "{table}");
        std::fs::write(dir.join("seed0/eval.json"), "{").unwrap();
        let e = eval_json_table(&runs, &bootstrap).unwrap_err().to_string();
        assert!(
            e.contains("seed0/eval.json") && e.contains("not an eval.json"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

//! `logo summary RUN_DIRS…`: the numbers behind a figure, one markdown row per
//! configuration (the groups of `logo plot`): the final, peak and late returns, mean ±
//! std over seeds, and optionally the return at a fixed sample count and the samples a
//! seed needed to reach a threshold.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{Result, ensure};
use clap::Args;

use crate::plot::{Metric, Run, discover, interpolate, parse_max_samples, up_to};

#[derive(Args)]
pub struct SummaryArgs {
    /// Run folders, or folders holding runs (a sweep's output).
    #[arg(required = true)]
    runs: Vec<PathBuf>,
    /// Also report each configuration's return at this many samples (linear between
    /// evaluations; a run that stops earlier is left out of that column).
    #[arg(long)]
    at: Option<f64>,
    /// Also count the seeds whose evaluation reached this return, and the samples each
    /// first needed (median over those seeds).
    #[arg(long)]
    threshold: Option<f64>,
    /// Read each run only up to this many samples, as `logo plot --max-samples`.
    #[arg(long, value_parser = parse_max_samples)]
    max_samples: Option<f64>,
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
    pub at: Option<f64>,
    /// Samples at the first evaluation at or above the threshold.
    pub reached_at: Option<f64>,
}

pub fn summarise(run: &Run, at: Option<f64>, threshold: Option<f64>) -> RunSummary {
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
        at: at
            .filter(|&x| x <= final_samples)
            .map(|x| interpolate(points, x)),
        reached_at: threshold.and_then(|t| points.iter().find(|p| p.1 >= t).map(|p| p.0)),
    }
}

/// Mean ± sample standard deviation (0 for one value).
fn mean_std(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = if values.len() > 1 {
        values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
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

/// The markdown table for `runs`.
pub fn table(runs: &[Run], at: Option<f64>, threshold: Option<f64>) -> Result<String> {
    ensure!(
        at.is_none_or(|x| x.is_finite() && x > 0.0),
        "--at must be a positive sample count"
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
            .push(summarise(run, at, threshold));
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
    if let Some(x) = at {
        header.push(format!("at {}", thousands(x)));
    }
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
            thousands(median(&mut col(|r| r.samples_at_peak))),
            pm(&col(|r| r.late_mean)),
        ];
        if at.is_some() {
            let values: Vec<f64> = s.iter().filter_map(|r| r.at).collect();
            row.push(match values.len() {
                0 => "—".into(),
                n if n < s.len() => format!("{} ({n} seeds)", pm(&values)),
                _ => pm(&values),
            });
        }
        if threshold.is_some() {
            let mut reached: Vec<f64> = s.iter().filter_map(|r| r.reached_at).collect();
            row.push(if reached.is_empty() {
                format!("0/{}", s.len())
            } else {
                let n = reached.len();
                format!("{n}/{} ({})", s.len(), thousands(median(&mut reached)))
            });
        }
        out.push_str(&format!("| {} |\n", row.join(" | ")));
    }
    Ok(out)
}

pub fn run(args: &SummaryArgs) -> Result<()> {
    let mut runs = discover(&args.runs, &Metric::eval_return())?;
    if let Some(max_samples) = args.max_samples {
        up_to(&mut runs, max_samples)?;
    }
    print!("{}", table(&runs, args.at, args.threshold)?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(group: &str, points: &[(f64, f64)]) -> Run {
        Run {
            group: group.into(),
            env: None,
            points: points.to_vec(),
        }
    }

    #[test]
    fn a_run_reports_its_peak_late_mean_and_threshold() {
        let points: Vec<(f64, f64)> = (1..=20)
            .map(|k| (k as f64 * 1000.0, if k == 8 { 500.0 } else { k as f64 }))
            .collect();
        let s = summarise(&run("a", &points), Some(2500.0), Some(15.0));
        assert_eq!((s.peak, s.samples_at_peak), (500.0, 8000.0));
        assert_eq!((s.final_return, s.final_samples), (20.0, 20000.0));
        assert_eq!(s.late_mean, 19.5); // the last 2 of 20
        assert_eq!(s.at, Some(2.5));
        assert_eq!(s.reached_at, Some(8000.0));
        // Past a run's end there is no value, and an unreached threshold is None.
        let s = summarise(&run("a", &points), Some(30000.0), Some(1000.0));
        assert_eq!((s.at, s.reached_at), (None, None));
    }

    #[test]
    fn the_table_aggregates_seeds_per_group() {
        let runs = [
            run("logo", &[(1e5, 10.0), (2e5, 30.0)]),
            run("logo", &[(1e5, 20.0), (2e5, 50.0)]),
            run("trpo", &[(1e5, 1.0), (1.5e5, 2.0)]),
        ];
        let t = table(&runs, Some(1.5e5), Some(25.0)).unwrap();
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
        assert!(table(&runs, Some(-1.0), None).is_err());
    }
}

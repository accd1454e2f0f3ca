//! `logo plot RUN_DIRS… --out FIG.png|FIG.svg`: dense evaluation return against samples,
//! one line per configuration (the mean over its seeds, or with `--stat iqm` their
//! interquartile mean) in a shaded band: by default the line's 95% stratified-bootstrap
//! interval over seeds (logo-stats), with `--band std` mean ± std as the LOGO paper's
//! Figure 1 and the seed paper's Figures 2-3 draw them. The numbers drawn are written
//! beside the figure as CSV (`FIG.csv`). `--metric` draws any other numeric column of
//! `metrics.csv` the same way (mean log σ, step sizes, guidance KL, critic losses), and
//! `--log10` its base-10 logarithm, for quantities that span decades.
//!
//! Runs are found and grouped as `crate::runs` says (a sweep's folder plots as a whole).
//! Each run's curve is interpolated onto a common grid of sample counts over the range
//! every seed of its group covers, then averaged.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};
use clap::{Args, ValueEnum};
use logo_stats::{Aggregate, Bootstrap, mean_std};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::runs::{
    EVAL_RETURN, ExternalSpec, Metric, Run, RunSelection, interpolate, read_external, up_to,
    with_external_runs,
};

#[derive(Args)]
pub struct PlotArgs {
    #[command(flatten)]
    selection: RunSelection,
    /// The figure: .png or .svg. Its data go to the same path with .csv.
    #[arg(long)]
    out: PathBuf,
    /// Moving average over this many evaluations (centred) before averaging seeds.
    #[arg(long, default_value_t = 1)]
    smooth: usize,
    /// A horizontal reference line, NAME=VALUE (e.g. behaviour=1380); repeatable.
    #[arg(long = "hline", value_parser = parse_hline)]
    hlines: Vec<(String, f64)>,
    /// Add the LOGO paper's behaviour and expert levels for the runs' environment
    /// (docs/reference.md: Figure 1's dashed lines).
    #[arg(long)]
    paper_lines: bool,
    /// The title (default: the runs' training environment).
    #[arg(long)]
    title: Option<String>,
    /// Points on each curve's sample grid.
    #[arg(long, default_value_t = 200)]
    points: usize,
    /// The metrics.csv column to draw (e.g. mean_log_std, step_norm, guidance_kl,
    /// critic_loss); iterations where it is NaN are skipped.
    #[arg(long, default_value = EVAL_RETURN)]
    metric: String,
    /// Draw log10 of the metric (seeds are averaged in log space); values ≤ 0 are skipped.
    #[arg(long)]
    log10: bool,
    /// The line: the mean over a configuration's seeds, or their interquartile mean.
    #[arg(long, value_enum, default_value_t = Stat::Mean)]
    stat: Stat,
    /// The band: the line's 95% stratified-bootstrap interval over seeds, or (with the
    /// mean) mean ± std.
    #[arg(long, value_enum, default_value_t = BandKind::Ci)]
    band: BandKind,
    /// Resamples for each point's interval (--band ci).
    #[arg(long, default_value_t = 2_000)]
    reps: usize,
    /// Which corner the legend goes in: lower-right keeps it off curves that rise.
    #[arg(long, value_enum, default_value_t = Legend::UpperLeft)]
    legend: Legend,
}

/// The legend's corner.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Legend {
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
}

impl Legend {
    fn position(self) -> SeriesLabelPosition {
        match self {
            Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
            Legend::UpperRight => SeriesLabelPosition::UpperRight,
            Legend::LowerLeft => SeriesLabelPosition::LowerLeft,
            Legend::LowerRight => SeriesLabelPosition::LowerRight,
        }
    }
}

/// The line drawn for a configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Stat {
    Mean,
    Iqm,
}

/// The band shaded around it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BandKind {
    /// The line's 95% stratified-bootstrap interval over seeds.
    Ci,
    /// Mean ± sample standard deviation.
    Std,
}

/// How each grid point's seeds become a line and a band.
#[derive(Debug, Clone, Copy)]
pub struct Band {
    pub stat: Stat,
    pub kind: BandKind,
    pub bootstrap: Bootstrap,
}

impl Band {
    /// (line, low, high) of one grid point's values over seeds.
    fn of(&self, ys: &[f64]) -> (f64, f64, f64) {
        let aggregate = match self.stat {
            Stat::Mean => Aggregate::Mean,
            Stat::Iqm => Aggregate::Iqm,
        };
        match self.kind {
            BandKind::Std => {
                let (m, s) = mean_std(ys);
                (m, m - s, m + s)
            }
            BandKind::Ci => {
                let e = self.bootstrap.aggregate(ys, aggregate);
                (e.point, e.lo, e.hi)
            }
        }
    }
}

/// `--external` curves as single-seed [`Curve`]s at their own samples.
fn external_curves(
    specs: &[ExternalSpec],
    window: usize,
    max_samples: Option<f64>,
) -> Result<Vec<Curve>> {
    specs
        .iter()
        .map(|spec| {
            let mut points = read_external(spec)?;
            if let Some(max) = max_samples {
                points.retain(|p| p.0 <= max);
                ensure!(
                    !points.is_empty(),
                    "--external {}: no row at or below --max-samples {max}",
                    spec.path.display()
                );
            }
            let mean = smooth(&points.iter().map(|p| p.1).collect::<Vec<_>>(), window);
            Ok(Curve {
                group: spec.label.clone(),
                samples: points.iter().map(|p| p.0).collect(),
                std: vec![0.0; mean.len()],
                line: mean.clone(),
                lo: mean.clone(),
                hi: mean.clone(),
                mean,
                seeds: 1,
            })
        })
        .collect()
}

fn parse_hline(text: &str) -> Result<(String, f64), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| format!("{text:?}: expected NAME=VALUE"))?;
    let value: f64 = value
        .trim()
        .parse()
        .map_err(|_| format!("{text:?}: {value:?} is not a number"))?;
    if !value.is_finite() {
        return Err(format!("{text:?}: the value must be finite"));
    }
    Ok((name.trim().to_string(), value))
}

/// One configuration's curve on its grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    pub group: String,
    pub samples: Vec<f64>,
    pub mean: Vec<f64>,
    pub std: Vec<f64>,
    /// What is drawn: the line (mean or IQM) and its band.
    pub line: Vec<f64>,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub seeds: usize,
}

/// Centred moving average over `window` points (shrinking at the ends).
fn smooth(values: &[f64], window: usize) -> Vec<f64> {
    let half = window / 2;
    (0..values.len())
        .map(|i| {
            let (lo, hi) = (i.saturating_sub(half), (i + half + 1).min(values.len()));
            values[lo..hi].iter().sum::<f64>() / (hi - lo) as f64
        })
        .collect()
}

/// Each group's mean ± std (sample standard deviation; 0 for one seed), and its line and
/// band as `band` says, on `points` sample counts spread over the range all its runs
/// cover.
pub fn curves(runs: &[Run], window: usize, points: usize, band: &Band) -> Result<Vec<Curve>> {
    ensure!(points >= 2, "--points must be at least 2");
    ensure!(window >= 1, "--smooth must be at least 1");
    let mut groups: BTreeMap<&str, Vec<Vec<(f64, f64)>>> = BTreeMap::new();
    for run in runs {
        let ys = smooth(&run.points.iter().map(|p| p.1).collect::<Vec<_>>(), window);
        let curve = run.points.iter().map(|p| p.0).zip(ys).collect();
        groups.entry(&run.group).or_default().push(curve);
    }
    let mut out = Vec::new();
    for (group, members) in groups {
        let start = members.iter().map(|c| c[0].0).fold(f64::MIN, f64::max);
        let end = members
            .iter()
            .map(|c| c[c.len() - 1].0)
            .fold(f64::MAX, f64::min);
        if end < start {
            bail!("group {group}: its runs' sample ranges do not overlap");
        }
        let samples: Vec<f64> = (0..points)
            .map(|k| start + (end - start) * k as f64 / (points - 1) as f64)
            .collect();
        let mut curve = Curve {
            group: group.to_string(),
            samples: Vec::new(),
            mean: Vec::new(),
            std: Vec::new(),
            line: Vec::new(),
            lo: Vec::new(),
            hi: Vec::new(),
            seeds: members.len(),
        };
        for &x in &samples {
            let ys: Vec<f64> = members.iter().map(|c| interpolate(c, x)).collect();
            let (m, s) = mean_std(&ys);
            let (line, lo, hi) = band.of(&ys);
            curve.mean.push(m);
            curve.std.push(s);
            curve.line.push(line);
            curve.lo.push(lo);
            curve.hi.push(hi);
        }
        curve.samples = samples;
        out.push(curve);
    }
    Ok(out)
}

/// The runs to draw with their bands (the runs found, and each outside label of several
/// seeds: a folder, or CSVs given one label, drawn as a configuration is), cut at
/// `--max-samples`; and the outside curves of one CSV, drawn as lines.
fn runs_and_lines(
    selection: &RunSelection,
    metric: &Metric,
) -> Result<(Vec<Run>, Vec<ExternalSpec>)> {
    let externals = &selection.externals;
    let seeds_of = |label: &str| externals.iter().filter(|s| s.label == label).count();
    let (seeded, single): (Vec<ExternalSpec>, Vec<ExternalSpec>) = externals
        .iter()
        .cloned()
        .partition(|spec| spec.path.is_dir() || seeds_of(&spec.label) > 1);
    let mut runs = with_external_runs(selection.discover(metric)?, &seeded)?;
    if let Some(max_samples) = selection.max_samples {
        up_to(&mut runs, max_samples)?;
    }
    Ok((runs, single))
}

/// The LOGO paper's behaviour and expert levels (docs/reference.md, Figure 1) by env.
fn paper_lines(env: &str) -> Option<[(String, f64); 2]> {
    let name = logo_envs::dense_id(env);
    let (behaviour, expert) = match name.split('-').next()? {
        "Hopper" => (1380.0, 3400.0),
        "HalfCheetah" => (2650.0, 4500.0),
        "Walker2d" => (2450.0, 4150.0),
        "InvertedDoublePendulum" => (340.0, 9300.0),
        _ => return None,
    };
    Some([
        ("behaviour (LOGO paper)".into(), behaviour),
        ("expert (LOGO paper)".into(), expert),
    ])
}

pub fn run(args: &PlotArgs) -> Result<()> {
    let metric = Metric {
        column: args.metric.clone(),
        log10: args.log10,
    };
    let selection = &args.selection;
    let (runs, single) = runs_and_lines(selection, &metric)?;
    ensure!(
        !(args.stat == Stat::Iqm && args.band == BandKind::Std),
        "--stat iqm goes with --band ci: a std band is drawn around the mean"
    );
    ensure!(args.reps >= 1, "--reps must be at least 1");
    let band = Band {
        stat: args.stat,
        kind: args.band,
        bootstrap: Bootstrap::with_reps(args.reps),
    };
    let curves = curves(&runs, args.smooth, args.points, &band)?;
    let mut envs: Vec<&str> = runs.iter().filter_map(|r| r.env.as_deref()).collect();
    envs.sort_unstable();
    envs.dedup();
    let mut hlines = args.hlines.clone();
    if args.paper_lines {
        let env = envs
            .first()
            .context("--paper-lines: the runs name no env (config.toml)")?;
        hlines.extend(
            paper_lines(env)
                .with_context(|| format!("--paper-lines: no paper levels for {env}"))?,
        );
    }
    let title = args.title.clone().unwrap_or_else(|| envs.join(", "));
    let externals = external_curves(&single, args.smooth, selection.max_samples)?;
    let csv_path = args.out.with_extension("csv");
    write_csv(&csv_path, curves.iter().chain(&externals))?;
    let figure = Figure {
        curves: &curves,
        externals: &externals,
        hlines: &hlines,
        title: &title,
        y_label: &metric.label(),
        legend: args.legend,
    };
    match args.out.extension().and_then(|e| e.to_str()) {
        Some("png") => draw(
            BitMapBackend::new(&args.out, (960, 600)).into_drawing_area(),
            &figure,
        ),
        Some("svg") => draw(
            SVGBackend::new(&args.out, (960, 600)).into_drawing_area(),
            &figure,
        ),
        _ => bail!(
            "--out {}: the figure must end in .png or .svg",
            args.out.display()
        ),
    }
    .with_context(|| format!("drawing {}", args.out.display()))?;
    println!(
        "{}: {} curves from {} runs{}; data in {}",
        args.out.display(),
        curves.len(),
        runs.len(),
        match externals.len() {
            0 => String::new(),
            n => format!(" and {n} external"),
        },
        csv_path.display()
    );
    print_ends(&curves);
    Ok(())
}

/// Each curve's last point, as people copy it into tables.
fn print_ends(curves: &[Curve]) {
    let (lo, hi) = curves
        .iter()
        .flat_map(|c| &c.mean)
        .fold((f64::MAX, f64::MIN), |(lo, hi), &y| (lo.min(y), hi.max(y)));
    // One decimal more than the axis: these are the numbers people copy into tables.
    let value = |y: f64| format_value(y, (hi - lo) / 10.0);
    for c in curves {
        let last = c.mean.len() - 1;
        println!(
            "  {:30} {} seeds, at {:.0} samples: {} ± {}",
            c.group,
            c.seeds,
            c.samples[last],
            value(c.mean[last]),
            value(c.std[last])
        );
    }
}

/// What a figure shows: the runs' curves with their bands, outside curves, horizontal
/// lines, and its labels.
struct Figure<'a> {
    curves: &'a [Curve],
    externals: &'a [Curve],
    hlines: &'a [(String, f64)],
    title: &'a str,
    y_label: &'a str,
    legend: Legend,
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn write_csv<'a>(path: &Path, curves: impl IntoIterator<Item = &'a Curve>) -> Result<()> {
    let mut w = csv::Writer::from_path(path).with_context(|| format!("{}", path.display()))?;
    w.write_record([
        "config", "samples", "mean", "std", "seeds", "line", "band_lo", "band_hi",
    ])?;
    for c in curves {
        for k in 0..c.samples.len() {
            w.write_record([
                c.group.clone(),
                format!("{}", c.samples[k]),
                format!("{}", c.mean[k]),
                format!("{}", c.std[k]),
                c.seeds.to_string(),
                format!("{}", c.line[k]),
                format!("{}", c.lo[k]),
                format!("{}", c.hi[k]),
            ])?;
        }
    }
    w.flush().with_context(|| format!("{}", path.display()))?;
    Ok(())
}

/// Registers the embedded DejaVu Sans as the figure's font (no system font library).
pub fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .unwrap_or_else(|_| panic!("the embedded DejaVu Sans is a valid font"));
    });
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    figure: &Figure,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    register_font();
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow::anyhow!("{e:?}");
    root.fill(&WHITE).map_err(err)?;
    let Figure {
        curves, externals, ..
    } = figure;
    let x_max = curves
        .iter()
        .chain(*externals)
        .map(|c| *c.samples.last().expect("a curve has points"))
        .fold(1.0, f64::max);
    let ys = curves
        .iter()
        .chain(*externals)
        .flat_map(|c| c.lo.iter().chain(&c.hi).copied())
        .chain(figure.hlines.iter().map(|h| h.1));
    let (y_min, y_max) = ys.fold((f64::MAX, f64::MIN), |(lo, hi), y| (lo.min(y), hi.max(y)));
    let pad = if y_max > y_min {
        (y_max - y_min) * 0.05
    } else {
        y_max.abs().max(1.0) * 0.05
    };
    let mut chart = ChartBuilder::on(&root)
        .caption(figure.title, ("sans-serif", 26))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(0.0..x_max, (y_min - pad)..(y_max + pad))
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("samples")
        .y_desc(figure.y_label)
        .x_label_formatter(&|x| format_samples(*x))
        .y_label_formatter(&|y| format_value(*y, y_max - y_min))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(err)?;
    draw_lines(&mut chart, figure, x_max).map_err(err)?;
    chart
        .configure_series_labels()
        .position(figure.legend.position())
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// The runs' curves over their bands, the outside curves, the horizontal lines, each
/// with its legend entry.
fn draw_lines<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    figure: &Figure,
    x_max: f64,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    for (i, c) in figure.curves.iter().enumerate() {
        let color = line_color(i);
        let band: Vec<(f64, f64)> = c
            .samples
            .iter()
            .copied()
            .zip(c.hi.iter().copied())
            .chain(c.samples.iter().copied().zip(c.lo.iter().copied()).rev())
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(
            band,
            color.mix(0.18).filled(),
        )))?;
        chart
            .draw_series(LineSeries::new(
                c.samples.iter().copied().zip(c.line.iter().copied()),
                color.stroke_width(2),
            ))?
            .label(format!("{} (n = {})", c.group, c.seeds))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color.stroke_width(2)));
    }
    // Outside curves: one seed each, no band, thinner, in colours after the runs'.
    for (i, c) in figure.externals.iter().enumerate() {
        let color = line_color(figure.curves.len() + i);
        chart
            .draw_series(LineSeries::new(
                c.samples.iter().copied().zip(c.mean.iter().copied()),
                color.stroke_width(1),
            ))?
            .label(format!("{} (1 run)", c.group))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color.stroke_width(1)));
    }
    for (i, (name, value)) in figure.hlines.iter().enumerate() {
        let color = if i % 2 == 0 {
            BLACK.mix(0.6)
        } else {
            RGBAColor(120, 60, 0, 0.8)
        };
        chart
            .draw_series(DashedLineSeries::new(
                [(0.0, *value), (x_max, *value)],
                8,
                5,
                color.stroke_width(1),
            ))?
            .label(format!("{name} = {value}"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color.stroke_width(1)));
    }
    Ok(())
}

/// The i-th curve's colour: Tableau's ten, which stay apart on white and in print
/// (plotters' Palette99 puts yellow third).
fn line_color(i: usize) -> RGBAColor {
    const TABLEAU: [(u8, u8, u8); 10] = [
        (31, 119, 180),
        (255, 127, 14),
        (44, 160, 44),
        (214, 39, 40),
        (148, 103, 189),
        (140, 86, 75),
        (227, 119, 194),
        (127, 127, 127),
        (188, 189, 34),
        (23, 190, 207),
    ];
    let (r, g, b) = TABLEAU[i % TABLEAU.len()];
    RGBColor(r, g, b).to_rgba()
}

/// 1.5M, 200k, 900.
fn format_samples(x: f64) -> String {
    if x >= 1e6 {
        format!("{}M", trim(x / 1e6))
    } else if x >= 1e3 {
        format!("{}k", trim(x / 1e3))
    } else {
        format!("{x:.0}")
    }
}

/// A value with the decimals that tell ticks a tenth of `range` apart (returns: none).
fn format_value(y: f64, range: f64) -> String {
    let decimals = (1.0 - range.max(1e-12).log10().floor()).clamp(0.0, 8.0) as usize;
    let text = format!("{y:.decimals$}");
    // No "-0.00" on the axis.
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => text,
    }
}

fn trim(v: f64) -> String {
    let s = format!("{v:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runs::{each_seed_apart, parse_external};

    fn run(group: &str, points: &[(f64, f64)]) -> Run {
        Run::unseeded(group, points.to_vec())
    }

    fn std_band() -> Band {
        Band {
            stat: Stat::Mean,
            kind: BandKind::Std,
            bootstrap: Bootstrap::with_reps(100),
        }
    }

    #[test]
    fn the_default_band_is_the_bootstrap_interval_of_the_line() {
        // Five seeds, y = k·x for k = 1..=5 at x = 10: values 10, 20, 30, 40, 50.
        let runs: Vec<Run> = (1..=5)
            .map(|k| run("a", &[(0.0, 0.0), (10.0, 10.0 * k as f64)]))
            .collect();
        let bootstrap = Bootstrap::with_reps(2_000);
        for stat in [Stat::Mean, Stat::Iqm] {
            let band = Band {
                stat,
                kind: BandKind::Ci,
                bootstrap,
            };
            let c = &curves(&runs, 1, 2, &band).unwrap()[0];
            let aggregate = if stat == Stat::Mean {
                Aggregate::Mean
            } else {
                Aggregate::Iqm
            };
            let e = bootstrap.aggregate(&[10.0, 20.0, 30.0, 40.0, 50.0], aggregate);
            assert_eq!(
                (c.line[1], c.lo[1], c.hi[1]),
                (e.point, e.lo, e.hi),
                "{stat:?}"
            );
            assert!(c.lo[1] < 30.0 && 30.0 < c.hi[1]);
            // The table's mean ± std stays beside it.
            assert_eq!(c.mean[1], 30.0);
        }
    }

    #[test]
    fn curves_average_seeds_on_a_shared_grid() {
        let runs = [
            run("a", &[(0.0, 0.0), (10.0, 10.0), (20.0, 20.0)]),
            run("a", &[(2.0, 4.0), (12.0, 14.0), (18.0, 20.0)]),
            run("b", &[(0.0, 5.0), (30.0, 5.0)]),
        ];
        let c = curves(&runs, 1, 5, &std_band()).unwrap();
        assert_eq!(c.len(), 2);
        let a = &c[0];
        assert_eq!((a.group.as_str(), a.seeds), ("a", 2));
        // The range both seeds cover: 2..18.
        assert_eq!(a.samples, vec![2.0, 6.0, 10.0, 14.0, 18.0]);
        // Seed 0 is y = x; seed 1 is y = x + 2 on this range: mean x + 1, std √2.
        for (x, (m, s)) in a.samples.iter().zip(a.mean.iter().zip(&a.std)) {
            assert!((m - (x + 1.0)).abs() < 1e-12, "{x}: {m}");
            assert!((s - 2f64.sqrt()).abs() < 1e-12, "{x}: {s}");
        }
        assert_eq!(c[1].mean, vec![5.0; 5]);
        assert_eq!(c[1].std, vec![0.0; 5]);
    }

    #[test]
    fn each_seed_apart_gives_every_seeded_run_its_own_curve() {
        let mut runs = vec![
            run("logo", &[(1.0, 10.0)]),
            run("logo", &[(1.0, 30.0)]),
            run("reference", &[(1.0, 5.0)]),
        ];
        runs[0].seed = Some(0);
        runs[1].seed = Some(2);
        each_seed_apart(&mut runs);
        let curves = curves(&runs, 1, 2, &std_band()).unwrap();
        let lines: Vec<(&str, usize, f64)> = curves
            .iter()
            .map(|c| (c.group.as_str(), c.seeds, c.mean[0]))
            .collect();
        assert_eq!(
            lines,
            [
                ("logo seed 0", 1, 10.0),
                ("logo seed 2", 1, 30.0),
                ("reference", 1, 5.0)
            ]
        );
    }

    #[test]
    fn axis_values_get_the_decimals_their_range_needs() {
        assert_eq!(format_value(2500.0, 3000.0), "2500");
        assert_eq!(format_value(-0.4567, 0.5), "-0.46");
        assert_eq!(format_value(0.0123, 0.02), "0.012");
        assert_eq!(format_value(-0.0001, 0.5), "0.00");
    }

    #[test]
    fn smoothing_is_a_centred_moving_average() {
        assert_eq!(smooth(&[0.0, 3.0, 6.0, 9.0], 3), vec![1.5, 3.0, 6.0, 7.5]);
        assert_eq!(smooth(&[1.0, 2.0], 1), vec![1.0, 2.0]);
    }

    #[test]
    fn hlines_parse_and_samples_format() {
        assert_eq!(
            parse_hline("expert=3400").unwrap(),
            ("expert".into(), 3400.0)
        );
        assert!(parse_hline("3400").is_err());
        assert!(parse_hline("x=nan").is_err());
        assert_eq!(format_samples(1_500_000.0), "1.5M");
        assert_eq!(format_samples(200_000.0), "200k");
        assert_eq!(format_samples(900.0), "900");
    }

    #[test]
    fn an_external_curve_reads_its_columns_skips_empty_fields_and_names_bad_ones() {
        let dir = std::env::temp_dir().join(format!("logo-plot-external-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("reference.csv");
        std::fs::write(
            &path,
            "iteration,samples,rewards/eval_R_avg,KL\n1,20000,56.5,0.01\n2,40000,,0.01\n3,60000,71,0.01\n",
        )
        .unwrap();
        let spec =
            parse_external(&format!("{},samples,rewards/eval_R_avg", path.display())).unwrap();
        assert_eq!(spec.label, "reference", "the file's stem by default");
        assert_eq!(
            read_external(&spec).unwrap(),
            vec![(20000.0, 56.5), (60000.0, 71.0)]
        );
        let labelled = parse_external(&format!("{},samples,KL,delta", path.display())).unwrap();
        assert_eq!(labelled.label, "delta");
        let curves = external_curves(std::slice::from_ref(&spec), 1, Some(50000.0)).unwrap();
        assert_eq!(
            (curves[0].samples.clone(), curves[0].seeds),
            (vec![20000.0], 1)
        );

        let missing = ExternalSpec {
            value: "eval".into(),
            ..spec.clone()
        };
        let err = read_external(&missing).unwrap_err().to_string();
        assert!(
            err.contains("no column \"eval\"") && err.contains("rewards/eval_R_avg"),
            "{err}"
        );
        std::fs::write(&path, "samples,value\n1,2\n3,oops\n").unwrap();
        let bad = parse_external(&format!("{},samples,value", path.display())).unwrap();
        let err = format!("{:#}", read_external(&bad).unwrap_err());
        assert!(err.contains("row 2, column \"value\": \"oops\""), "{err}");
        assert!(parse_external("only.csv,samples").is_err());
        assert!(parse_external("a.csv,,value").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

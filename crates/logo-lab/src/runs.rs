//! The runs `logo plot` and `logo summary` read: every run folder under the paths given
//! (a folder holding `metrics.csv` is a run; any other folder is searched two levels
//! down, so a `logo sweep` folder reads as a whole), one column of each as (samples,
//! value) points, grouped into configurations by folder layout: runs in folders named
//! `seed<N>` by their parent folder (a sweep's `<out>/<name>/seed<N>`), `<name>-seed<N>`
//! by `<name>`, any other run on its own. Outside curves (`--external`: a published or
//! reference run, from any CSV) read as single-seed runs.

use std::collections::{BTreeMap, BTreeSet};
use std::io::Read;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};

/// Where an outside curve comes from (`--external`).
#[derive(Debug, Clone)]
pub struct ExternalSpec {
    pub path: PathBuf,
    pub samples: String,
    pub value: String,
    pub label: String,
}

pub(crate) fn parse_external(text: &str) -> std::result::Result<ExternalSpec, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [path, samples, value, rest @ ..] = parts.as_slice() else {
        return Err(format!(
            "{text:?}: expected CSV,SAMPLES_COLUMN,VALUE_COLUMN[,LABEL]"
        ));
    };
    if rest.len() > 1 || [path, samples, value].iter().any(|p| p.is_empty()) {
        return Err(format!(
            "{text:?}: expected CSV,SAMPLES_COLUMN,VALUE_COLUMN[,LABEL]"
        ));
    }
    let path = PathBuf::from(path);
    let label = match rest.first() {
        Some(label) if !label.is_empty() => label.to_string(),
        _ => path
            .file_stem()
            .map_or("external".into(), |s| s.to_string_lossy().into_owned()),
    };
    Ok(ExternalSpec {
        path,
        samples: samples.to_string(),
        value: value.to_string(),
        label,
    })
}

/// The CSV files of an outside curve: the file, or every `.csv` directly in the folder
/// (one seed each), in name order.
pub fn external_files(spec: &ExternalSpec) -> Result<Vec<PathBuf>> {
    if !spec.path.is_dir() {
        return Ok(vec![spec.path.clone()]);
    }
    let entries = std::fs::read_dir(&spec.path)
        .with_context(|| format!("--external {}", spec.path.display()))?;
    let mut files = Vec::new();
    for entry in entries {
        let path = entry
            .with_context(|| format!("--external {}", spec.path.display()))?
            .path();
        if path.extension().is_some_and(|e| e == "csv") {
            files.push(path);
        }
    }
    files.sort();
    ensure!(
        !files.is_empty(),
        "--external {}: a folder with no .csv file",
        spec.path.display()
    );
    Ok(files)
}

/// An outside curve: (samples, value) in the file's order, rows with an empty field
/// left out. A missing column, a field that is not a number, or no row at all is an
/// error naming the file (and the row).
pub fn read_external(spec: &ExternalSpec) -> Result<Vec<(f64, f64)>> {
    read_external_file(&spec.path, spec)
}

/// [`read_external`] of one file of `spec` (a folder's CSV).
fn read_external_file(path: &Path, spec: &ExternalSpec) -> Result<Vec<(f64, f64)>> {
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("--external {}", path.display()))?;
    let headers = reader
        .headers()
        .with_context(|| format!("--external {}", path.display()))?
        .clone();
    let column = |name: &str| {
        headers.iter().position(|h| h == name).with_context(|| {
            format!(
                "--external {}: no column {name:?} (the columns are {})",
                path.display(),
                headers.iter().collect::<Vec<_>>().join(", ")
            )
        })
    };
    let (xs, ys) = (column(&spec.samples)?, column(&spec.value)?);
    let mut points = Vec::new();
    for (row, record) in reader.records().enumerate() {
        let record = record.with_context(|| format!("--external {}", path.display()))?;
        let field = |at: usize| -> Result<Option<f64>> {
            let text = record.get(at).unwrap_or("").trim();
            if text.is_empty() {
                return Ok(None);
            }
            match text.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Some(v)),
                _ => bail!(
                    "--external {}: row {}, column {:?}: {text:?} is not a finite number",
                    path.display(),
                    row + 1,
                    &headers[at]
                ),
            }
        };
        if let (Some(x), Some(y)) = (field(xs)?, field(ys)?) {
            points.push((x, y));
        }
    }
    ensure!(
        !points.is_empty(),
        "--external {}: no row with both {:?} and {:?}",
        path.display(),
        spec.samples,
        spec.value
    );
    Ok(points)
}

/// `--external` curves as [`Run`]s of their labels: a run per CSV, its seed the N of a
/// `seed<N>` in the file's name where there is one.
pub fn external_runs(specs: &[ExternalSpec]) -> Result<Vec<Run>> {
    let mut runs = Vec::new();
    for spec in specs {
        for file in external_files(spec)? {
            let mut run = Run::unseeded(&spec.label, read_external_file(&file, spec)?);
            run.seed = file
                .file_stem()
                .and_then(|stem| stem.to_str())
                .and_then(|stem| stem.rsplit_once("seed"))
                .and_then(|(_, n)| n.split(|c: char| !c.is_ascii_digit()).next())
                .and_then(|n| n.parse().ok());
            runs.push(run);
        }
    }
    Ok(runs)
}

/// `runs` with the `--external` curves of `specs` added; a label that is also a
/// configuration among the runs is an error, not a silent merge.
pub fn with_external_runs(mut runs: Vec<Run>, specs: &[ExternalSpec]) -> Result<Vec<Run>> {
    let external = external_runs(specs)?;
    if let Some(clash) = external
        .iter()
        .find(|e| runs.iter().any(|r| r.group == e.group))
    {
        bail!(
            "--external label {:?} is also the name of a configuration among the runs; give the curve another label",
            clash.group
        );
    }
    runs.extend(external);
    Ok(runs)
}

/// A positive sample count: a number (`2000000`, `2e6`) or one with a `k` or `M` suffix
/// (`500k`, `2M`).
pub(crate) fn parse_max_samples(text: &str) -> std::result::Result<f64, String> {
    let trimmed = text.trim();
    let (digits, scale) = match trimmed.strip_suffix(['k', 'M']) {
        Some(digits) if trimmed.ends_with('k') => (digits, 1e3),
        Some(digits) => (digits, 1e6),
        None => (trimmed, 1.0),
    };
    match digits.parse::<f64>() {
        Ok(n) if n.is_finite() && n > 0.0 => Ok(n * scale),
        _ => Err(format!(
            "expected a positive number of samples (e.g. 2000000, 2e6, 2M, 500k), got {text:?}"
        )),
    }
}

/// Keeps each run's evaluations at or below `max_samples`; an error names a group whose
/// run has none there.
pub fn up_to(runs: &mut [Run], max_samples: f64) -> Result<()> {
    for run in runs {
        run.points.retain(|p| p.0 <= max_samples);
        ensure!(
            !run.points.is_empty(),
            "--max-samples {max_samples}: a run of {} has no evaluation at or below it",
            run.group
        );
    }
    Ok(())
}

/// The column `logo plot` and `logo summary` read by default.
pub const EVAL_RETURN: &str = "eval_dense_return";

/// Which column of metrics.csv to read, and whether as its log10.
#[derive(Debug, Clone)]
pub struct Metric {
    pub column: String,
    pub log10: bool,
}

impl Metric {
    pub fn eval_return() -> Self {
        Self {
            column: EVAL_RETURN.into(),
            log10: false,
        }
    }

    /// The axis label.
    pub(crate) fn label(&self) -> String {
        match (self.column.as_str(), self.log10) {
            (EVAL_RETURN, false) => "dense evaluation return".into(),
            (column, false) => column.into(),
            (column, true) => format!("log10 {column}"),
        }
    }

    /// The plotted value of one field, or None where it is not drawn.
    fn value(&self, v: f64) -> Option<f64> {
        let y = if self.log10 { v.log10() } else { v };
        y.is_finite().then_some(y)
    }
}

/// One run's evaluations.
#[derive(Debug, Clone)]
pub struct Run {
    pub group: String,
    /// N of a `seed<N>` or `<name>-seed<N>` folder.
    pub seed: Option<u64>,
    pub env: Option<String>,
    /// (samples, the metric), in order, iterations where the metric is defined only.
    pub points: Vec<(f64, f64)>,
    /// The run folder (None for an outside curve).
    pub dir: Option<PathBuf>,
}

impl Run {
    /// A run of no seed and no env: an outside curve (or a test's).
    pub fn unseeded(group: &str, points: Vec<(f64, f64)>) -> Self {
        Self {
            group: group.into(),
            seed: None,
            env: None,
            points,
            dir: None,
        }
    }
}

/// Which runs a figure or a table reads, and how it names them: the flags `logo plot`
/// and `logo summary` share.
#[derive(clap::Args, Debug, Clone)]
pub struct RunSelection {
    /// Run folders, or folders holding runs (a sweep's output).
    #[arg(required = true)]
    pub runs: Vec<PathBuf>,
    /// Read each run only up to this many samples, to compare runs of different lengths
    /// at an equal budget (e.g. 1e6 or 1000000).
    #[arg(long, value_parser = parse_max_samples)]
    pub max_samples: Option<f64>,
    /// Each seed apart, as its own configuration ("<configuration> seed N"), instead of
    /// a configuration's seeds pooled: for studies of one to three seeds.
    #[arg(long)]
    pub each_seed: bool,
    /// An outside curve (e.g. the reference code's: docs/results/reference-curves/):
    /// CSV,SAMPLES_COLUMN,VALUE_COLUMN[,LABEL]. A CSV is one seed: `logo plot` draws it
    /// as a line over the runs' bands. A folder of CSVs (`seed0.csv`, `seed1.csv`, ...)
    /// is a configuration of as many seeds, drawn with its band, and `logo summary`
    /// reads either as one more configuration (with --compare, IQMs and intervals).
    /// Empty fields are skipped; --max-samples (and plot's --smooth) apply too.
    /// Repeatable; CSVs of one label are seeds of one configuration.
    #[arg(long = "external", value_parser = parse_external)]
    pub externals: Vec<ExternalSpec>,
    /// A configuration's name in the figure or table, FOLDER=NAME (e.g. hopper=LOGO: a
    /// sweep names a configuration after its config file). Repeatable.
    #[arg(long = "label", value_parser = parse_label)]
    pub labels: Vec<(String, String)>,
}

impl RunSelection {
    /// The runs found under the folders, named as `--label` and `--each-seed` say. Each
    /// caller cuts them at `--max-samples` itself (summary after adding its externals).
    pub fn discover(&self, metric: &Metric) -> Result<Vec<Run>> {
        let mut runs = discover(&self.runs, metric)?;
        relabel(&mut runs, &self.labels)?;
        if self.each_seed {
            each_seed_apart(&mut runs);
        }
        Ok(runs)
    }
}

/// Every run under `paths` (see the module doc), reading `metric`.
pub fn discover(paths: &[PathBuf], metric: &Metric) -> Result<Vec<Run>> {
    let mut dirs = Vec::new();
    for path in paths {
        ensure!(path.is_dir(), "{}: not a folder", path.display());
        collect_runs(path, 3, &mut dirs)?;
    }
    ensure!(
        !dirs.is_empty(),
        "no run (a folder with metrics.csv) in {}",
        paths
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    dirs.iter().map(|d| read_run(d, metric)).collect()
}

/// A run folder's file `name`, or where the folder keeps it compressed, `name.gz` (a
/// run kept under docs/results/: docs/results/README.md); None where neither is there.
pub fn kept_file(dir: &Path, name: &str) -> Option<PathBuf> {
    let plain = dir.join(name);
    let compressed = dir.join(format!("{name}.gz"));
    [plain, compressed].into_iter().find(|p| p.is_file())
}

/// The contents of `path`, decompressed where it ends in `.gz`.
pub fn open_kept(path: &Path) -> Result<Box<dyn Read>> {
    let file = std::fs::File::open(path).with_context(|| format!("{}", path.display()))?;
    let reader = std::io::BufReader::new(file);
    Ok(match path.extension().is_some_and(|e| e == "gz") {
        true => Box::new(flate2::bufread::MultiGzDecoder::new(reader)),
        false => Box::new(reader),
    })
}

/// `open_kept` read whole as text.
pub fn read_kept(path: &Path) -> Result<String> {
    let mut text = String::new();
    open_kept(path)?
        .read_to_string(&mut text)
        .with_context(|| format!("{}", path.display()))?;
    Ok(text)
}

fn collect_runs(dir: &Path, depth: usize, out: &mut Vec<PathBuf>) -> Result<()> {
    if kept_file(dir, "metrics.csv").is_some() {
        out.push(dir.to_path_buf());
        return Ok(());
    }
    if depth == 0 {
        return Ok(());
    }
    let mut children: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("{}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    children.sort();
    for child in children {
        collect_runs(&child, depth - 1, out)?;
    }
    Ok(())
}

fn read_run(dir: &Path, metric: &Metric) -> Result<Run> {
    let path = kept_file(dir, "metrics.csv").unwrap_or_else(|| dir.join("metrics.csv"));
    let mut reader = csv::Reader::from_reader(open_kept(&path)?);
    let headers = reader
        .headers()
        .with_context(|| format!("{}", path.display()))?
        .clone();
    let column = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .with_context(|| format!("{}: no column {name:?}", path.display()))
    };
    let (samples_at, metric_at) = (column("samples")?, column(&metric.column)?);
    let mut points = Vec::new();
    for (line, record) in reader.records().enumerate() {
        let record = record.with_context(|| format!("{}", path.display()))?;
        let number = |at: usize| -> Result<f64> {
            let field = record.get(at).unwrap_or("");
            field.parse::<f64>().with_context(|| {
                format!(
                    "{}: row {}: {field:?} is not a number",
                    path.display(),
                    line + 1
                )
            })
        };
        if let Some(y) = metric.value(number(metric_at)?) {
            points.push((number(samples_at)?, y));
        }
    }
    ensure!(
        !points.is_empty(),
        "{}: no iteration with a finite {}",
        path.display(),
        metric.label()
    );
    let name = |p: &Path| {
        p.file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let folder = name(dir);
    let (group, seed) = group_of(&folder, dir.parent().map(name));
    let env = std::fs::read_to_string(dir.join("config.toml"))
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|t| {
            t.get("env")?
                .clone()
                .try_into::<logo_envs::EnvConfig>()
                .ok()
        })
        .and_then(|env| env.env_id().ok());
    Ok(Run {
        group,
        seed,
        env,
        points,
        dir: Some(dir.to_path_buf()),
    })
}

/// A run's group and seed: its parent's name for `seed<N>` (a sweep's layout), `<name>`
/// for `<name>-seed<N>`, else the folder's own name (and no seed).
fn group_of(folder: &str, parent: Option<String>) -> (String, Option<u64>) {
    let seed_of = |s: &str| s.strip_prefix("seed").and_then(|n| n.parse::<u64>().ok());
    if let (Some(seed), Some(parent)) = (seed_of(folder), parent) {
        return (parent, Some(seed));
    }
    match folder
        .rsplit_once('-')
        .and_then(|(name, seed)| Some((name, seed_of(seed)?)))
    {
        Some((name, seed)) => (name.to_string(), Some(seed)),
        None => (folder.to_string(), None),
    }
}

/// `--label FOLDER=NAME`: one configuration's name in a legend or table.
pub(crate) fn parse_label(text: &str) -> std::result::Result<(String, String), String> {
    match text.split_once('=') {
        Some((from, to)) if !from.trim().is_empty() && !to.trim().is_empty() => {
            Ok((from.trim().to_string(), to.trim().to_string()))
        }
        _ => Err(format!("{text:?}: expected FOLDER=NAME (e.g. hopper=LOGO)")),
    }
}

/// Renames configurations (`--label`). A sweep names a configuration after its config
/// file's stem (`hopper` for LOGO's), which says little in a figure. A name that is no
/// configuration's, one given two labels, or labels that leave two configurations with
/// one name (their seeds would be averaged together) are errors.
pub fn relabel(runs: &mut [Run], labels: &[(String, String)]) -> Result<()> {
    let groups: BTreeSet<&str> = runs.iter().map(|r| r.group.as_str()).collect();
    let mut renamed: BTreeMap<&str, &str> = BTreeMap::new();
    for (from, to) in labels {
        ensure!(
            groups.contains(from.as_str()),
            "--label {from}={to}: no configuration is named {from:?} (they are {})",
            groups.iter().copied().collect::<Vec<_>>().join(", ")
        );
        ensure!(
            renamed.insert(from, to).is_none(),
            "--label {from}={to}: {from:?} is given two labels"
        );
    }
    let name_of = |group: &str| renamed.get(group).copied().unwrap_or(group).to_string();
    let mut named: BTreeMap<String, &str> = BTreeMap::new();
    for group in &groups {
        if let Some(other) = named.insert(name_of(group), group) {
            bail!(
                "--label: {group:?} would be named {:?}, which {other:?} already is (their seeds would be averaged together)",
                name_of(group)
            );
        }
    }
    for run in runs {
        run.group = name_of(&run.group);
    }
    Ok(())
}

/// `--each-seed`: every run with a seed becomes a group of its own, "<group> seed N".
pub fn each_seed_apart(runs: &mut [Run]) {
    for run in runs {
        if let Some(seed) = run.seed {
            run.group = format!("{} seed {seed}", run.group);
        }
    }
}

/// The value of the piecewise-linear curve through `points` at `x` (inside its range).
pub(crate) fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    let i = points.partition_point(|p| p.0 < x);
    if i == 0 {
        return points[0].1;
    }
    if i == points.len() {
        return points[i - 1].1;
    }
    let ((x0, y0), (x1, y1)) = (points[i - 1], points[i]);
    if x1 == x0 {
        y1
    } else {
        y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(group: &str, points: &[(f64, f64)]) -> Run {
        Run::unseeded(group, points.to_vec())
    }

    #[test]
    fn max_samples_cuts_every_run_and_refuses_an_emptied_one() {
        let mut runs = [
            run("long", &[(0.0, 1.0), (10.0, 2.0), (20.0, 3.0)]),
            run("short", &[(0.0, 1.0), (9.0, 2.0)]),
        ];
        up_to(&mut runs, 10.0).unwrap();
        assert_eq!(runs[0].points, vec![(0.0, 1.0), (10.0, 2.0)]);
        assert_eq!(runs[1].points, vec![(0.0, 1.0), (9.0, 2.0)]);
        let mut late = [run("late", &[(5.0, 1.0)])];
        let e = up_to(&mut late, 4.0).unwrap_err().to_string();
        assert!(e.contains("late") && e.contains("--max-samples"), "{e}");
        assert_eq!(parse_max_samples("2e6"), Ok(2e6));
        assert_eq!(parse_max_samples("2M"), Ok(2e6));
        assert_eq!(parse_max_samples("2.5M"), Ok(2.5e6));
        assert_eq!(parse_max_samples("500k"), Ok(5e5));
        for bad in ["", "M", "-1M", "0", "2G", "nan", "twoM"] {
            assert!(parse_max_samples(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn labels_rename_a_configuration_and_refuse_unknown_or_clashing_names() {
        let mut runs = [
            run("hopper", &[(0.0, 1.0)]),
            run("hopper", &[(0.0, 2.0)]),
            run("hopper_ppo_cdq", &[(0.0, 3.0)]),
        ];
        let label = |t: &str| parse_label(t).unwrap();
        relabel(&mut runs, &[label("hopper=LOGO")]).unwrap();
        let groups: Vec<&str> = runs.iter().map(|r| r.group.as_str()).collect();
        assert_eq!(groups, ["LOGO", "LOGO", "hopper_ppo_cdq"]);
        let e = relabel(&mut runs, &[label("walker2d=LOGO")])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("walker2d") && e.contains("LOGO, hopper_ppo_cdq"),
            "{e}"
        );
        let e = relabel(&mut runs, &[label("hopper_ppo_cdq=LOGO")])
            .unwrap_err()
            .to_string();
        assert!(e.contains("already"), "{e}");
        assert_eq!(runs[2].group, "hopper_ppo_cdq", "an error renames nothing");
        // Two labels onto one new name would merge seeds too; one name, two labels is
        // ambiguous; a swap merges nothing.
        let e = relabel(&mut runs, &[label("LOGO=X"), label("hopper_ppo_cdq=X")])
            .unwrap_err()
            .to_string();
        assert!(e.contains("\"X\"") && e.contains("already"), "{e}");
        let e = relabel(&mut runs, &[label("LOGO=X"), label("LOGO=Y")])
            .unwrap_err()
            .to_string();
        assert!(e.contains("two labels"), "{e}");
        relabel(
            &mut runs,
            &[label("LOGO=hopper_ppo_cdq"), label("hopper_ppo_cdq=LOGO")],
        )
        .unwrap();
        let groups: Vec<&str> = runs.iter().map(|r| r.group.as_str()).collect();
        assert_eq!(groups, ["hopper_ppo_cdq", "hopper_ppo_cdq", "LOGO"]);
        assert_eq!(label(" a = b c "), ("a".into(), "b c".into()));
        for bad in ["", "hopper", "=LOGO", "hopper="] {
            assert!(parse_label(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn runs_group_by_sweep_and_script_layouts() {
        let group = |folder: &str, parent: &str| group_of(folder, Some(parent.into()));
        assert_eq!(
            group("seed3", "logo-hopper"),
            ("logo-hopper".into(), Some(3))
        );
        assert_eq!(group("logo-seed0", "idp"), ("logo".into(), Some(0)));
        assert_eq!(
            group("hopper-logo-s0", "runs"),
            ("hopper-logo-s0".into(), None)
        );
        assert_eq!(group("seedling", "x"), ("seedling".into(), None));
    }

    #[test]
    fn any_numeric_column_can_be_read_and_logged() {
        let dir = std::env::temp_dir().join(format!("logo-plot-metric-{}", std::process::id()));
        let run_dir = dir.join("arm").join("seed0");
        std::fs::create_dir_all(&run_dir).unwrap();
        std::fs::write(
            run_dir.join("metrics.csv"),
            "iteration,samples,eval_dense_return,guidance_kl,update_stop\n\
             0,100,5.0,NaN,accepted\n\
             1,200,NaN,0.01,accepted\n\
             2,300,7.0,0.0,accepted\n\
             3,400,8.0,1000.0,kl-limit\n",
        )
        .unwrap();
        let read = |column: &str, log10| {
            let metric = Metric {
                column: column.into(),
                log10,
            };
            discover(std::slice::from_ref(&dir), &metric)
        };
        let eval = read(EVAL_RETURN, false).unwrap();
        assert_eq!(eval[0].group, "arm");
        assert_eq!(
            eval[0].points,
            vec![(100.0, 5.0), (300.0, 7.0), (400.0, 8.0)]
        );
        // NaN and (in log space) zero are not drawn; the rest are log10'd exactly.
        let kl = read("guidance_kl", true).unwrap();
        assert_eq!(kl[0].points, vec![(200.0, -2.0), (400.0, 3.0)]);
        let linear = read("guidance_kl", false).unwrap();
        assert_eq!(linear[0].points.len(), 3);
        let text = read("update_stop", false).unwrap_err().to_string();
        assert!(
            text.contains("row 1") && text.contains("accepted"),
            "{text}"
        );
        let missing = format!("{:#}", read("critic_los", false).unwrap_err());
        assert!(missing.contains("no column \"critic_los\""), "{missing}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_kept_runs_compressed_metrics_read_as_the_plain_ones() {
        use std::io::Write;
        let dir = std::env::temp_dir().join(format!("logo-kept-gz-{}", std::process::id()));
        let text = "iteration,samples,eval_dense_return\n0,100,5.0\n1,200,6.5\n";
        let (plain, packed) = (dir.join("plain/seed0"), dir.join("packed/seed0"));
        for d in [&plain, &packed] {
            std::fs::create_dir_all(d).unwrap();
        }
        std::fs::write(plain.join("metrics.csv"), text).unwrap();
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        gz.write_all(text.as_bytes()).unwrap();
        std::fs::write(packed.join("metrics.csv.gz"), gz.finish().unwrap()).unwrap();
        let metric = Metric {
            column: EVAL_RETURN.into(),
            log10: false,
        };
        let runs = discover(std::slice::from_ref(&dir), &metric).unwrap();
        assert_eq!(runs.len(), 2, "both folders are runs");
        assert_eq!(runs[0].points, runs[1].points);
        assert_eq!(runs[0].points, vec![(100.0, 5.0), (200.0, 6.5)]);
        assert_eq!(
            kept_file(&packed, "metrics.csv"),
            Some(packed.join("metrics.csv.gz"))
        );
        assert_eq!(kept_file(&packed, "eval.json"), None);
        // A damaged archive is an error naming the file, not a panic or an empty run.
        std::fs::write(packed.join("metrics.csv.gz"), b"not gzip").unwrap();
        let err = format!(
            "{:#}",
            discover(std::slice::from_ref(&dir), &metric).unwrap_err()
        );
        assert!(err.contains("metrics.csv.gz"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

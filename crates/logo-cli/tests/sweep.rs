//! `logo sweep` (locally) and `logo plot` as a user runs them: two configs × two seeds,
//! re-run to skip and to resume, a failing run reported with its log while the others
//! finish, and the figure with its CSV checked against the runs' own metrics.

use logo_testkit::{Logo, Tiny, scratch};
use std::path::{Path, PathBuf};
use std::process::Output;

fn logo(args: &[&str]) -> Output {
    Logo::new(env!("CARGO_BIN_EXE_logo")).run(args)
}

fn tiny(dir: &Path, name: &str, extra: &str) -> PathBuf {
    Tiny::trpo()
        .with(extra)
        .write(&dir.join(format!("{name}.toml")))
}

fn rows(run: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(run.join("metrics.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect()
}

#[test]
fn a_sweep_skips_resumes_reports_failures_and_plots() {
    let dir = scratch("sweep");
    let a = tiny(&dir, "a", "");
    let b = tiny(&dir, "b", "max_kl = 0.05");
    let out = dir.join("out");
    let sweep = |configs: &[&Path], extra: &[&str]| {
        let mut args: Vec<String> = vec!["sweep".into()];
        args.extend(configs.iter().map(|c| c.display().to_string()));
        args.extend(["--seeds", "0..2", "--jobs", "2", "--out"].map(String::from));
        args.push(out.display().to_string());
        args.extend(extra.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        logo(&args)
    };
    let first = sweep(&[&a, &b], &[]);
    let stdout = String::from_utf8_lossy(&first.stdout);
    assert!(
        first.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&first.stderr)
    );
    assert!(
        stdout.contains("4 finished, 0 already done, 0 failed"),
        "{stdout}"
    );
    for name in ["a", "b"] {
        for seed in 0..2 {
            let run = out.join(name).join(format!("seed{seed}"));
            assert_eq!(rows(&run).len(), 2, "{}", run.display());
            let config = std::fs::read_to_string(run.join("config.toml")).unwrap();
            assert!(config.contains(&format!("seed = {seed}")), "{config}");
        }
    }
    // Again: nothing to do. Longer: each run resumes from its checkpoint.
    let again = sweep(&[&a, &b], &[]);
    assert!(String::from_utf8_lossy(&again.stdout).contains("0 finished, 4 already done"));
    let longer = sweep(&[&a], &["--iterations", "3"]);
    assert!(String::from_utf8_lossy(&longer.stdout).contains("2 finished"));
    let run = out.join("a").join("seed0");
    assert_eq!(rows(&run).len(), 3);
    let log = std::fs::read_to_string(run.join("train.log")).unwrap();
    assert!(log.contains("resuming"), "{log}");

    // A run that fails (its eval env does not fit) is reported with its log; the other
    // config's runs still run, and the sweep exits non-zero.
    let bad = tiny(&dir, "bad", "eval_env = \"Hopper-v4\"");
    let c = tiny(&dir, "c", "");
    let mixed = sweep(&[&bad, &c], &[]);
    let text = String::from_utf8_lossy(&mixed.stdout).into_owned()
        + &String::from_utf8_lossy(&mixed.stderr);
    assert!(!mixed.status.success(), "{text}");
    assert!(
        text.contains("2 finished, 0 already done, 2 failed"),
        "{text}"
    );
    assert!(
        text.contains(&out.join("bad/seed0/train.log").display().to_string()),
        "{text}"
    );
    assert_eq!(rows(&out.join("c").join("seed1")).len(), 2);

    // The figure and its data: with a 2-point grid, the CSV holds each config's mean and
    // std over its seeds (then the line drawn and its band) at the start and the end of
    // the range both seeds cover; an outside curve (a published reference) is drawn over
    // them and its points follow.
    let figure = dir.join("fig.png");
    let reference = dir.join("published.csv");
    std::fs::write(&reference, "step,score\n100,5\n200,\n300,7\n").unwrap();
    let external = format!("{},step,score,the paper", reference.display());
    let plot = logo(&[
        "plot",
        out.join("a").to_str().unwrap(),
        out.join("b").to_str().unwrap(),
        "--out",
        figure.to_str().unwrap(),
        "--points",
        "2",
        "--paper-lines",
        "--external",
        &external,
        "--label",
        "a=config A",
    ]);
    assert!(
        plot.status.success(),
        "{}",
        String::from_utf8_lossy(&plot.stderr)
    );
    let png = std::fs::read(&figure).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert!(png.len() > 10_000, "a drawn figure, not an empty one");
    let csv = std::fs::read_to_string(dir.join("fig.csv")).unwrap();
    let mut data: Vec<Vec<String>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    assert_eq!(data.len(), 6, "{csv}");
    let names: Vec<&str> = data.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(names[..4], ["b", "b", "config A", "config A"], "{csv}");
    let external_rows = data.split_off(4);
    assert_eq!(
        external_rows,
        [
            ["the paper", "100", "5", "0", "1", "5", "5", "5"],
            ["the paper", "300", "7", "0", "1", "7", "7", "7"]
        ]
        .map(|r| r.map(String::from).to_vec()),
        "{csv}"
    );
    // The same outside curve as a row of `logo summary`, read at 300 samples as the
    // mean of its 2 evaluations nearest (300 and 100); a label that is also a
    // configuration's name, or a sample count that is not one, is refused.
    let a_runs = out.join("a");
    let summary = |external: &str, at: &str| {
        logo(&[
            "summary",
            a_runs.to_str().unwrap(),
            "--external",
            external,
            "--at",
            at,
            "--window",
            "2",
        ])
    };
    let table = summary(&external, "300");
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(table.status.success(), "{text}");
    let row = text.lines().find(|l| l.starts_with("| the paper |"));
    assert!(
        row.is_some_and(|r| r.starts_with("| the paper | 1 |") && r.ends_with("| 6 ± 0 |")),
        "{text}"
    );
    let clash = summary(&format!("{},step,score,a", reference.display()), "300");
    let text = String::from_utf8_lossy(&clash.stderr);
    assert!(!clash.status.success() && text.contains("\"a\""), "{text}");
    let bad = summary(&external, "2G");
    let text = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success() && text.contains("2G"), "{text}");
    // A folder of outside CSVs is a configuration of that many seeds (the reference
    // code's five seeds): at 300 samples, window 1, the mean of 7 and 9, ± their std.
    let seeds = dir.join("reference-seeds");
    std::fs::create_dir_all(&seeds).unwrap();
    std::fs::write(seeds.join("seed0.csv"), "step,score\n100,5\n300,7\n").unwrap();
    std::fs::write(seeds.join("seed1.csv"), "step,score\n100,1\n300,9\n").unwrap();
    let folder = format!("{},step,score,reference", seeds.display());
    let grouped = logo(&[
        "summary",
        a_runs.to_str().unwrap(),
        "--external",
        &folder,
        "--at",
        "300",
        "--window",
        "1",
    ]);
    let text = String::from_utf8_lossy(&grouped.stdout);
    assert!(grouped.status.success(), "{text}");
    let row = text.lines().find(|l| l.starts_with("| reference |"));
    assert!(
        row.is_some_and(|r| r.starts_with("| reference | 2 |") && r.ends_with("| 8 ± 1 |")),
        "{text}"
    );
    // --each-seed: one row per seed of config b, each its own one-seed configuration,
    // under the name --label gives it; a --label naming no configuration is refused.
    let b_runs = out.join("b");
    let unknown = logo(&["summary", b_runs.to_str().unwrap(), "--label", "c=LOGO"]);
    let text = String::from_utf8_lossy(&unknown.stderr);
    assert!(
        !unknown.status.success() && text.contains("\"c\""),
        "{text}"
    );
    let apart = logo(&[
        "summary",
        b_runs.to_str().unwrap(),
        "--each-seed",
        "--label",
        "b=LOGO",
    ]);
    let text = String::from_utf8_lossy(&apart.stdout);
    // The first table (the interval table follows a blank line).
    let first_table = || text.lines().take_while(|l| !l.is_empty()).skip(2);
    let labels: Vec<&str> = first_table()
        .filter_map(|l| l.strip_prefix("| ")?.split(" |").next())
        .collect();
    assert!(apart.status.success(), "{text}");
    assert_eq!(labels, ["LOGO seed 0", "LOGO seed 1"], "{text}");
    assert!(first_table().all(|l| l.contains(" | 1 | ")), "{text}");
    // --metric: the tables read another metrics.csv column (each seed's last
    // train_dense_return here), named above them; an unknown column is refused by name.
    let by_metric = |column: &str| {
        logo(&[
            "summary",
            b_runs.to_str().unwrap(),
            "--each-seed",
            "--no-intervals",
            "--metric",
            column,
        ])
    };
    let dense = by_metric("train_dense_return");
    let text = String::from_utf8_lossy(&dense.stdout);
    assert!(dense.status.success(), "{text}");
    assert!(
        text.starts_with(
            "Every value below but eval.json's is metrics.csv's `train_dense_return`."
        ),
        "{text}"
    );
    let header = std::fs::read_to_string(b_runs.join("seed0/metrics.csv")).unwrap();
    let column = header
        .lines()
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == "train_dense_return")
        .unwrap();
    for seed in 0..2 {
        let last = rows(&b_runs.join(format!("seed{seed}"))).pop().unwrap();
        let value: f64 = last[column].parse().unwrap();
        let row = text
            .lines()
            .find(|l| l.starts_with(&format!("| b seed {seed} |")))
            .unwrap();
        let cells: Vec<&str> = row.split(" | ").collect();
        assert_eq!(cells[3], format!("{value:.0} ± 0"), "{text}");
    }
    let unknown = by_metric("no_such_column");
    let text = String::from_utf8_lossy(&unknown.stderr);
    assert!(
        !unknown.status.success() && text.contains("no_such_column"),
        "{text}"
    );
    // --compare is repeatable: one table per pair, in the order given.
    let pairs = logo(&[
        "summary",
        a_runs.to_str().unwrap(),
        b_runs.to_str().unwrap(),
        "--compare",
        "a",
        "b",
        "--compare",
        "b",
        "a",
    ]);
    let text = String::from_utf8_lossy(&pairs.stdout);
    let errors = String::from_utf8_lossy(&pairs.stderr);
    assert!(pairs.status.success(), "{errors}");
    let headers: Vec<&str> = text.lines().filter(|l| l.contains("| P(")).collect();
    assert_eq!(headers.len(), 2, "{text}");
    assert!(
        headers[0].contains("P(a > b)") && headers[1].contains("P(b > a)"),
        "{text}"
    );

    for (name, runs) in [("b", 2)] {
        let seeds: Vec<Vec<Vec<String>>> = (0..runs)
            .map(|s| rows(&out.join(name).join(format!("seed{s}"))))
            .collect();
        // Columns by name: metrics.csv gains columns over time.
        let header = std::fs::read_to_string(out.join(name).join("seed0/metrics.csv")).unwrap();
        let index = |column: &str| {
            header
                .lines()
                .next()
                .unwrap()
                .split(',')
                .position(|c| c == column)
                .unwrap()
        };
        let (samples, eval) = (index("samples"), index("eval_dense_return"));
        let col = |r: &Vec<String>, i: usize| r[i].parse::<f64>().unwrap();
        // Both runs' first evaluation is at their first iteration; the grid starts at
        // the later of the two first sample counts.
        let firsts: Vec<(f64, f64)> = seeds
            .iter()
            .map(|s| (col(&s[0], samples), col(&s[0], eval)))
            .collect();
        let lasts: Vec<(f64, f64)> = seeds
            .iter()
            .map(|s| (col(&s[1], samples), col(&s[1], eval)))
            .collect();
        let start = firsts[0].0.max(firsts[1].0);
        let end = lasts[0].0.min(lasts[1].0);
        let line = |samples: f64| {
            data.iter()
                .find(|r| r[0] == name && (r[1].parse::<f64>().unwrap() - samples).abs() < 1e-6)
                .unwrap_or_else(|| panic!("{name} at {samples}: {csv}"))
        };
        // Linear interpolation of each seed at the grid's ends, then mean and std.
        let at = |s: usize, x: f64| {
            let (x0, y0, x1, y1) = (firsts[s].0, firsts[s].1, lasts[s].0, lasts[s].1);
            y0 + (y1 - y0) * (x - x0) / (x1 - x0)
        };
        for x in [start, end] {
            let (y0, y1) = (at(0, x), at(1, x));
            let mean = (y0 + y1) / 2.0;
            let std = ((y0 - mean).powi(2) + (y1 - mean).powi(2)).sqrt();
            let r = line(x);
            assert!(
                (r[2].parse::<f64>().unwrap() - mean).abs() < 1e-9,
                "{name} mean at {x}: {r:?} vs {mean}"
            );
            assert!(
                (r[3].parse::<f64>().unwrap() - std).abs() < 1e-9,
                "{name} std at {x}: {r:?} vs {std}"
            );
            assert_eq!(r[4], "2");
        }
    }
}

//! `logo compare` at toy scale (2 methods × 2 seeds × 2 iterations): the runs, the
//! report's table against the runs' own metrics.csv, the figure, and a second call that
//! skips the finished runs.

use logo_testkit::{Logo, Tiny, one_line_error, scratch};

fn cli() -> Logo {
    Logo::new(env!("CARGO_BIN_EXE_logo"))
}

/// The last value of `column` in a run's metrics.csv.
fn final_value(run: &std::path::Path, column: &str) -> f64 {
    let text = std::fs::read_to_string(run.join("metrics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = header.iter().position(|h| *h == column).unwrap();
    let last = lines.last().unwrap();
    last.split(',').nth(column).unwrap().parse().unwrap()
}

/// Holds the report's "final" column to the mean of the seeds' last `column` values.
fn assert_final_column(report: &str, out: &std::path::Path, column: &str) {
    for method in ["logo", "trpo"] {
        let finals: Vec<f64> = (0..2)
            .map(|seed| final_value(&out.join(method).join(format!("seed{seed}")), column))
            .collect();
        let mean = (finals[0] + finals[1]) / 2.0;
        let row = report
            .lines()
            .find(|l| l.starts_with(&format!("| {method} | 2 |")))
            .unwrap_or_else(|| panic!("no row for {method}:\n{report}"));
        let final_cell = row.split(" | ").nth(3).unwrap();
        let shown: f64 = final_cell.split(" ± ").next().unwrap().parse().unwrap();
        assert!(
            (shown - mean).abs() <= 0.5,
            "{method} {column}: {final_cell} against {finals:?}"
        );
    }
}

#[test]
fn compare_runs_the_methods_and_reports_them() {
    let dir = scratch("compare");
    let config = Tiny::logo().lbfgs(3).write(&dir.join("task.toml"));
    let out = dir.join("cmp");
    let args = [
        "compare",
        "--config",
        config.to_str().unwrap(),
        "--algorithms",
        "logo,trpo",
        "--seeds",
        "0..2",
        "--iterations",
        "2",
        "--threads",
        "1",
        "--reps",
        "500",
        "--out",
        out.to_str().unwrap(),
    ];
    let printed = cli().succeed(&args);
    assert!(printed.contains("compare:"), "{printed}");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(out.join("figure.png").is_file());
    assert!(report.contains("| P(logo > trpo) [95% CI] |"), "{report}");
    // The first table's "final" column is the mean ± std of the seeds' last evaluations;
    // the final policies' own evaluations (eval.json) follow.
    assert_final_column(&report, &out, "eval_dense_return");
    assert!(
        report.contains("End-of-run evaluations (eval.json"),
        "{report}"
    );
    // The methods' configs differ by their keys alone.
    let trpo = std::fs::read_to_string(out.join("configs/trpo.toml")).unwrap();
    assert!(!trpo.contains("[guidance]"), "{trpo}");
    // Again: nothing to run, the same report.
    let again = cli().succeed(&args);
    assert!(again.contains("0 finished, 4 already done"), "{again}");
    let report_again = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert_eq!(report, report_again);
    // The same runs read by another column: the sparse task's own return.
    let sparse = [&args[..], &["--metric", "train_sparse_return"]].concat();
    cli().succeed(&sparse);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("--metric train_sparse_return`"), "{report}");
    assert_final_column(&report, &out, "train_sparse_return");
}

#[test]
fn compare_refuses_what_it_cannot_compare() {
    let dir = scratch("compare-bad");
    let trpo = Tiny::trpo().write(&dir.join("trpo.toml"));
    let e = one_line_error(&cli().run(&["compare", "--config", trpo.to_str().unwrap()]));
    assert!(e.contains("starts from a LOGO config"), "{e}");
    let logo = Tiny::logo().write(&dir.join("logo.toml"));
    let e = one_line_error(&cli().run(&[
        "compare",
        "--config",
        logo.to_str().unwrap(),
        "--algorithms",
        "logo,sac",
    ]));
    assert!(e.contains("unknown algorithm \"sac\""), "{e}");
    // A column metrics.csv does not have, or one of words: refused before any run.
    for bad in ["sparse_return", "update_stop"] {
        let out = dir.join(format!("cmp-{bad}"));
        let e = one_line_error(&cli().run(&[
            "compare",
            "--config",
            logo.to_str().unwrap(),
            "--metric",
            bad,
            "--out",
            out.to_str().unwrap(),
        ]));
        assert!(
            e.contains(&format!("--metric \"{bad}\"")) && e.contains("train_sparse_return"),
            "{e}"
        );
        assert!(!out.exists(), "{bad}: {} was made", out.display());
    }
}

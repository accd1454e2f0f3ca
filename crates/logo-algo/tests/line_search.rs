//! The Moré–Thuente line search and the L-BFGS "strong-wolfe" mode against SciPy
//! (`tests/python/line_search_oracle.py`: SciPy's port of MINPACK-2's dcsrch, and
//! `fmin_l_bfgs_b`, the LOGO reference's critic fit), and the strong Wolfe conditions on a
//! quadratic and on the Rosenbrock function.

use std::path::Path;
use std::process::Command;

use logo_algo::lbfgs::{Eager, LineSearch, minimize};
use logo_algo::more_thuente::{MoreThuente, Search};
use logo_testkit::python;
use serde_json::Value;

fn oracle() -> Option<Value> {
    let python = python()?;
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/line_search_oracle.py");
    let out = Command::new(python).arg(script).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(serde_json::from_slice(&out.stdout).unwrap())
}

// The test functions of Moré & Thuente (1994), as the oracle writes them: (φ, φ').
fn mt1(a: f64) -> (f64, f64) {
    let beta = 2.0;
    (-a / (a * a + beta), (a * a - beta) / (a * a + beta).powi(2))
}

fn mt2(a: f64) -> (f64, f64) {
    let b = a + 0.004;
    (
        b.powi(5) - 2.0 * b.powi(4),
        5.0 * b.powi(4) - 8.0 * b.powi(3),
    )
}

fn mt3(a: f64) -> (f64, f64) {
    let (beta, l) = (0.01, 39.0);
    let (p0, d0) = if a <= 1.0 - beta {
        (1.0 - a, -1.0)
    } else if a >= 1.0 + beta {
        (a - 1.0, 1.0)
    } else {
        (
            (a - 1.0).powi(2) / (2.0 * beta) + beta / 2.0,
            (a - 1.0) / beta,
        )
    };
    let c = 2.0 * (1.0 - beta) / (l * std::f64::consts::PI);
    let w = l * std::f64::consts::PI / 2.0;
    (p0 + c * (w * a).sin(), d0 + (1.0 - beta) * (w * a).cos())
}

fn rosenbrock(x: &[f64]) -> (f64, Vec<f64>) {
    let n = x.len();
    let mut f = 0.0;
    let mut g = vec![0.0; n];
    for i in 0..n - 1 {
        let t = x[i + 1] - x[i] * x[i];
        f += 100.0 * t * t + (1.0 - x[i]).powi(2);
        g[i] += -400.0 * x[i] * t - 2.0 * (1.0 - x[i]);
        g[i + 1] += 200.0 * t;
    }
    (f, g)
}

fn rosenbrock_line(a: f64) -> (f64, f64) {
    let x0 = [-1.2, 1.0];
    let (_, g0) = rosenbrock(&x0);
    let x: Vec<f64> = x0.iter().zip(&g0).map(|(x, g)| x - a * g).collect();
    let (f, g) = rosenbrock(&x);
    (f, -g.iter().zip(&g0).map(|(a, b)| a * b).sum::<f64>())
}

fn function(name: &str) -> fn(f64) -> (f64, f64) {
    match name {
        "mt1" => mt1,
        "mt2" => mt2,
        "mt3" => mt3,
        "rosenbrock_line" => rosenbrock_line,
        _ => panic!("unknown function {name}"),
    }
}

/// Every step the search evaluates, and how it ended.
fn run(phi: fn(f64) -> (f64, f64), first: f64, tolerances: (f64, f64, f64)) -> (Vec<f64>, Search) {
    let (f0, g0) = phi(0.0);
    let mut search = MoreThuente::new(f0, g0, first, tolerances, (0.0, 1e10)).unwrap();
    let mut steps = vec![first];
    for _ in 0..100 {
        let (f, g) = phi(*steps.last().unwrap());
        match search.next(f, g) {
            Search::Evaluate(next) => steps.push(next),
            end => return (steps, end),
        }
    }
    panic!("no end in 100 evaluations")
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn every_trial_step_is_scipys_dcsrch() {
    let Some(oracle) = oracle() else { return };
    let cases = oracle["dcsrch"].as_array().unwrap();
    assert!(cases.len() >= 40);
    for case in cases {
        let name = case["function"].as_str().unwrap();
        let first = case["first"].as_f64().unwrap();
        let tol = (
            case["ftol"].as_f64().unwrap(),
            case["gtol"].as_f64().unwrap(),
            case["xtol"].as_f64().unwrap(),
        );
        let want: Vec<f64> = case["steps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let (steps, end) = run(function(name), first, tol);
        let label = format!("{name} from {first} with {tol:?}");
        assert_eq!(
            steps.len(),
            want.len(),
            "{label}: {steps:?} vs SciPy's {want:?}"
        );
        for (a, b) in steps.iter().zip(&want) {
            assert!(
                close(*a, *b, 1e-12),
                "{label}: {steps:?} vs SciPy's {want:?}"
            );
        }
        // SciPy returns the step where it converged (none after a warning, where the
        // search's last step is its best).
        if let Some(result) = case["result"].as_f64() {
            assert!(close(*steps.last().unwrap(), result, 1e-12), "{label}");
        }
        let converged = case["task"].as_str().unwrap().starts_with("CONVERGENCE");
        assert_eq!(
            matches!(end, Search::Converged),
            converged,
            "{label}: {end:?}"
        );
    }
}

/// Where the search converges, the strong Wolfe conditions hold.
#[test]
fn the_converged_step_satisfies_the_strong_wolfe_conditions() {
    let quadratic = |a: f64| ((a - 3.0).powi(2) - 9.0, 2.0 * (a - 3.0));
    type Phi = fn(f64) -> (f64, f64);
    let cases: [(Phi, f64); 5] = [
        (quadratic, 1e-3),
        (quadratic, 100.0),
        (rosenbrock_line, 1e-3),
        (rosenbrock_line, 1.0),
        (mt1, 10.0),
    ];
    for (phi, first) in cases {
        for (ftol, gtol) in [(1e-3, 0.9), (1e-4, 0.1)] {
            let (steps, end) = run(phi, first, (ftol, gtol, 0.1));
            assert_eq!(end, Search::Converged, "from {first}");
            let a = *steps.last().unwrap();
            let (f0, g0) = phi(0.0);
            let (f, g) = phi(a);
            assert!(f <= f0 + ftol * a * g0, "sufficient decrease at {a}");
            assert!(g.abs() <= gtol * g0.abs(), "curvature at {a}: {g} vs {g0}");
        }
    }
    // Steps may exceed 1 (the backtracking search never does): near the quadratic's
    // minimum at 3 with a tight curvature condition.
    let (steps, _) = run(quadratic, 1e-3, (1e-3, 0.1, 0.1));
    assert!(*steps.last().unwrap() > 1.0, "{steps:?}");
}

/// L-BFGS in "strong-wolfe" mode follows `fmin_l_bfgs_b(maxiter=25)`'s iterates.
#[test]
fn strong_wolfe_lbfgs_follows_scipys_fmin_l_bfgs_b() {
    let Some(oracle) = oracle() else { return };
    let q = &oracle["quadratic"];
    let a: Vec<Vec<f64>> = q[0]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r.as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        })
        .collect();
    let b: Vec<f64> = q[1]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let quadratic = |x: &[f64]| {
        let ax: Vec<f64> = a
            .iter()
            .map(|r| r.iter().zip(x).map(|(a, x)| a * x).sum())
            .collect();
        let f = 0.5 * ax.iter().zip(x).map(|(a, x)| a * x).sum::<f64>()
            - b.iter().zip(x).map(|(b, x)| b * x).sum::<f64>();
        (
            f,
            ax.iter().zip(&b).map(|(a, b)| a - b).collect::<Vec<f64>>(),
        )
    };
    for problem in oracle["lbfgs"].as_array().unwrap() {
        let name = problem["problem"].as_str().unwrap();
        let x0: Vec<f64> = problem["x0"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let want: Vec<f64> = problem["x"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let result = if name.starts_with("rosenbrock") {
            minimize(&mut Eager::new(rosenbrock), x0, 25, LineSearch::StrongWolfe)
        } else {
            minimize(&mut Eager::new(quadratic), x0, 25, LineSearch::StrongWolfe)
        };
        assert_eq!(
            result.iterations as u64,
            problem["nit"].as_u64().unwrap(),
            "{name}: iterations"
        );
        for (got, want) in result.x.iter().zip(&want) {
            assert!(
                close(*got, *want, 1e-7),
                "{name}: {:?} vs SciPy's {want:?}",
                result.x
            );
        }
        assert!(
            close(result.loss, problem["f"].as_f64().unwrap(), 1e-7),
            "{name}: f"
        );
    }
}

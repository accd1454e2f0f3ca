//! One critic fit two ways, alternated: this project's L-BFGS (`lbfgs.rs`, Armijo
//! backtracking from the unit step) and argmin's (`LBFGS` with its Armijo backtracking
//! line search), the same memory (10), iterations (25), objective and starting point: an
//! 11-128-128-1 value net on a 20,000-row batch of a Hopper-sized problem, MSE + 1e-3‖θ‖²,
//! on the kernels engine. Prints, per variant, the median seconds of a fit, the forward
//! and reverse passes it made, and the loss it reached; then argmin run until it reaches
//! the hand-written fit's loss (issue 27's comparison; the figures are in
//! docs/benchmarks.md).
//!
//!     cargo run --release -p logo-algo --example critic_fit_argmin [-- ROUNDS]

use std::cell::RefCell;
use std::time::Instant;

use argmin::core::{CostFunction, Error, Executor, Gradient};
use argmin::solver::linesearch::BacktrackingLineSearch;
use argmin::solver::linesearch::condition::ArmijoCondition;
use argmin::solver::quasinewton::LBFGS;
use logo_algo::critic::ValueObjective;
use logo_algo::lbfgs::{self, LineSearch, Objective};
use logo_nn::flat::params_to_vec;
use logo_nn::{Cpu, Engine, Kernels, ValueNetConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const ROWS: usize = 20_000;
const OBS: usize = 11;
const ITERATIONS: u64 = 25;

/// The objective with counters, as argmin sees it: `cost` is a forward pass, `gradient`
/// reuses the latest forward pass at the same point (a reverse pass), else makes one.
struct Counted<'a> {
    objective: RefCell<ValueObjective<'a, Kernels>>,
    last: RefCell<Option<Vec<f64>>>,
    forwards: RefCell<usize>,
    reverses: RefCell<usize>,
}

impl CostFunction for Counted<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, theta: &Vec<f64>) -> Result<f64, Error> {
        *self.forwards.borrow_mut() += 1;
        *self.last.borrow_mut() = Some(theta.clone());
        Ok(self.objective.borrow_mut().loss(theta))
    }
}

impl Gradient for Counted<'_> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;
    fn gradient(&self, theta: &Vec<f64>) -> Result<Vec<f64>, Error> {
        if self.last.borrow().as_ref() != Some(theta) {
            self.cost(theta)?;
        }
        *self.reverses.borrow_mut() += 1;
        *self.last.borrow_mut() = None;
        Ok(self.objective.borrow_mut().gradient())
    }
}

/// This project's objective wrapper, counting the same way.
struct CountedOwn<'a, 'b> {
    objective: &'b mut ValueObjective<'a, Kernels>,
    forwards: usize,
    reverses: usize,
}

impl Objective for CountedOwn<'_, '_> {
    fn loss(&mut self, theta: &[f64]) -> f64 {
        self.forwards += 1;
        self.objective.loss(theta)
    }
    fn gradient(&mut self) -> Vec<f64> {
        self.reverses += 1;
        self.objective.gradient()
    }
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

fn main() -> Result<(), Error> {
    let rounds: usize = std::env::args()
        .nth(1)
        .map_or(5, |r| r.parse().expect("ROUNDS is a number"));
    let engine = Kernels;
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let obs: Vec<f64> = (0..ROWS * OBS)
        .map(|_| rng.random_range(-2.0..2.0))
        .collect();
    // Returns of a sparse task's size: a smooth function of the state, up to ≈ 60.
    let returns: Vec<f64> = obs
        .chunks_exact(OBS)
        .map(|o| 30.0 * (1.0 + (o[0] + 0.5 * o[1]).sin()) + 2.0 * o[2] * o[3])
        .collect();
    let device = Default::default();
    <Cpu as burn::tensor::backend::Backend>::seed(&device, 1);
    let module = ValueNetConfig {
        obs_dim: OBS,
        hidden: vec![128, 128],
    }
    .init::<Cpu>(&device);
    let theta0 = params_to_vec(&module);
    let dims = module.net.dims();
    let rows = engine.rows(&obs, OBS);
    let targets = engine.upload(&returns, [ROWS, 1]);

    // A counted objective from the same starting state, and argmin's solver as compared.
    let fresh = || Counted {
        objective: RefCell::new(ValueObjective::new(&engine, &dims, &rows, &targets, 1e-3)),
        last: RefCell::new(None),
        forwards: RefCell::new(0),
        reverses: RefCell::new(0),
    };
    let argmin_lbfgs = || -> Result<_, Error> {
        let search = BacktrackingLineSearch::new(ArmijoCondition::new(1e-4)?).rho(0.5)?;
        Ok(LBFGS::new(search, 10))
    };
    let (mut own, mut other, mut matched) = (Vec::new(), Vec::new(), Vec::new());
    for round in 0..rounds {
        let mut objective = ValueObjective::new(&engine, &dims, &rows, &targets, 1e-3);
        let mut counted = CountedOwn {
            objective: &mut objective,
            forwards: 0,
            reverses: 0,
        };
        let clock = Instant::now();
        let result = lbfgs::minimize(
            &mut counted,
            theta0.clone(),
            ITERATIONS as usize,
            LineSearch::Backtracking,
        );
        let seconds = clock.elapsed().as_secs_f64();
        own.push((seconds, counted.forwards, counted.reverses, result.loss));

        let counted = fresh();
        let solver = argmin_lbfgs()?;
        let clock = Instant::now();
        let result = Executor::new(counted, solver)
            .configure(|state| state.param(theta0.clone()).max_iters(ITERATIONS))
            .run()?;
        let seconds = clock.elapsed().as_secs_f64();
        let loss = result.state.best_cost;
        let counted = result.problem.problem.expect("the problem comes back");
        let (forwards, reverses) = (*counted.forwards.borrow(), *counted.reverses.borrow());
        other.push((seconds, forwards, reverses, loss));
        // argmin again, until it reaches the loss this project's fit reached (at most
        // 8× the iterations): the time of an equally good fit.
        let counted = fresh();
        let clock = Instant::now();
        let result = Executor::new(counted, argmin_lbfgs()?)
            .configure(|state| {
                state
                    .param(theta0.clone())
                    .max_iters(8 * ITERATIONS)
                    .target_cost(own[round].3)
            })
            .run()?;
        let equal_seconds = clock.elapsed().as_secs_f64();
        let iterations = result.state.iter;
        matched.push((equal_seconds, iterations, result.state.best_cost));
        eprintln!(
            "round {}: lbfgs.rs {:.3} s, argmin {:.3} s, argmin to the same loss {:.3} s ({iterations} iterations)",
            round + 1,
            own[round].0,
            seconds,
            equal_seconds
        );
    }
    for (name, runs) in [("lbfgs.rs (this project)", &own), ("argmin 0.10", &other)] {
        let (f, r, loss) = (runs[0].1, runs[0].2, runs[0].3);
        println!(
            "{name:26} median {:.3} s per fit; {f} forward and {r} reverse passes; final loss {loss:.4}",
            median(runs.iter().map(|r| r.0).collect())
        );
    }
    println!(
        "argmin / lbfgs.rs, median of per-round ratios: {:.2}",
        median(own.iter().zip(&other).map(|(a, b)| b.0 / a.0).collect())
    );
    println!(
        "argmin to lbfgs.rs's final loss: {} iterations, median {:.3} s, loss {:.4}; ratio {:.2}",
        matched[0].1,
        median(matched.iter().map(|m| m.0).collect()),
        matched[0].2,
        median(own.iter().zip(&matched).map(|(a, b)| b.0 / a.0).collect())
    );
    Ok(())
}

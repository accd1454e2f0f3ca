//! L-BFGS (memory 10) for the critics, with one of two line searches ([`LineSearch`]):
//! this port's backtracking Armijo search (the default), or the reference's: SciPy's
//! `fmin_l_bfgs_b(maxiter=25)`, whose line search is Moré–Thuente's (`more_thuente.rs`)
//! and whose iterates the `strong-wolfe` mode reproduces (tested against SciPy).

use logo_nn::flat::dot;
use serde::{Deserialize, Serialize};

use crate::more_thuente::{MoreThuente, Search};

/// A function to minimise. Split in two so that a line-search candidate that is rejected
/// costs only its loss: for the critics, a forward pass instead of forward + reverse.
pub trait Objective {
    /// The loss at `x`; keeps whatever [`Objective::gradient`] needs.
    fn loss(&mut self, x: &[f64]) -> f64;
    /// The gradient at the `x` of the latest [`Objective::loss`] call.
    fn gradient(&mut self) -> Vec<f64>;
}

/// An [`Objective`] from a closure that computes the loss and the gradient together.
pub struct Eager<F> {
    f: F,
    gradient: Vec<f64>,
}

impl<F: FnMut(&[f64]) -> (f64, Vec<f64>)> Eager<F> {
    pub fn new(f: F) -> Self {
        Self {
            f,
            gradient: Vec::new(),
        }
    }
}

impl<F: FnMut(&[f64]) -> (f64, Vec<f64>)> Objective for Eager<F> {
    fn loss(&mut self, x: &[f64]) -> f64 {
        let (loss, gradient) = (self.f)(x);
        self.gradient = gradient;
        loss
    }

    fn gradient(&mut self) -> Vec<f64> {
        std::mem::take(&mut self.gradient)
    }
}

pub struct LbfgsResult {
    pub x: Vec<f64>,
    pub loss: f64,
    pub iterations: usize,
    pub evaluations: usize,
}

/// How each iteration finds its step along the quasi-Newton direction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LineSearch {
    /// Armijo backtracking from the unit step by quadratic interpolation: a rejected
    /// point costs only its loss (this port's default).
    #[default]
    Backtracking,
    /// As SciPy's `fmin_l_bfgs_b` on an unbounded problem (the reference's critic fit):
    /// the Moré–Thuente strong-Wolfe search (ftol 1e-3, gtol 0.9, xtol 0.1; steps may
    /// exceed 1; at most 20 evaluations), a first step of 1/‖d‖, no update where
    /// sᵀy ≤ ε·(−gᵀs), and L-BFGS-B's stopping tests (factr 1e7, pgtol 1e-5).
    StrongWolfe,
}

const MEMORY: usize = 10;

/// The L-BFGS direction −H·g by the two-loop recursion over `history` (s, y, 1/yᵀs),
/// with H₀ = (sᵀy / yᵀy)·I from the latest pair, or `first` ·I without one.
fn direction(grad: &[f64], history: &[(Vec<f64>, Vec<f64>, f64)], first: f64) -> Vec<f64> {
    let mut q = grad.to_vec();
    let mut alphas = Vec::with_capacity(history.len());
    for (s, y, rho) in history.iter().rev() {
        let a = rho * dot(s, &q);
        q.iter_mut().zip(y).for_each(|(qi, yi)| *qi -= a * yi);
        alphas.push(a);
    }
    let gamma = history
        .last()
        .map_or(first, |(s, y, _)| dot(s, y) / dot(y, y));
    q.iter_mut().for_each(|qi| *qi *= gamma);
    for ((s, y, rho), a) in history.iter().zip(alphas.iter().rev()) {
        let b = rho * dot(y, &q);
        q.iter_mut().zip(s).for_each(|(qi, si)| *qi += (a - b) * si);
    }
    q.iter().map(|v| -v).collect()
}

/// x + step·d, a line search's trial point.
fn along(x: &[f64], d: &[f64], step: f64) -> Vec<f64> {
    x.iter().zip(d).map(|(xi, di)| xi + step * di).collect()
}

/// Minimises `f` from `x0` for at most `max_iter` iterations.
pub fn minimize(
    f: &mut impl Objective,
    x0: Vec<f64>,
    max_iter: usize,
    line_search: LineSearch,
) -> LbfgsResult {
    match line_search {
        LineSearch::Backtracking => minimize_backtracking(f, x0, max_iter),
        LineSearch::StrongWolfe => minimize_strong_wolfe(f, x0, max_iter),
    }
}

fn minimize_backtracking(f: &mut impl Objective, x0: Vec<f64>, max_iter: usize) -> LbfgsResult {
    let mut x = x0;
    let mut loss = f.loss(&x);
    let mut grad = f.gradient();
    let mut evaluations = 1;
    let mut history: Vec<(Vec<f64>, Vec<f64>, f64)> = Vec::new(); // (s, y, 1/yᵀs)
    let mut iterations = 0;
    while iterations < max_iter {
        // First step: unit length along −g.
        let first = 1.0 / dot(&grad, &grad).sqrt().max(1e-12);
        let direction = direction(&grad, &history, first);
        let slope = dot(&grad, &direction);
        if slope >= 0.0 || !slope.is_finite() {
            break; // not a descent direction: converged or numerically stuck
        }
        // Backtracking to the first step with Armijo's sufficient decrease; each retry
        // goes to the minimum of the quadratic through f(0), f'(0) and f(step), kept
        // within [0.1, 0.5]·step.
        let mut step = 1.0;
        let mut accepted = None;
        for _ in 0..20 {
            let candidate = along(&x, &direction, step);
            let l = f.loss(&candidate);
            evaluations += 1;
            if l.is_finite() && l <= loss + 1e-4 * step * slope {
                accepted = Some((candidate, l, f.gradient()));
                break;
            }
            let curvature = l - loss - slope * step;
            step = if l.is_finite() && curvature > 0.0 {
                (-slope * step * step / (2.0 * curvature)).clamp(0.1 * step, 0.5 * step)
            } else {
                0.1 * step
            };
        }
        let Some((x_new, loss_new, grad_new)) = accepted else {
            break;
        };
        let s: Vec<f64> = x_new.iter().zip(&x).map(|(a, b)| a - b).collect();
        let y: Vec<f64> = grad_new.iter().zip(&grad).map(|(a, b)| a - b).collect();
        let ys = dot(&y, &s);
        if ys > 1e-12 {
            if history.len() == MEMORY {
                history.remove(0);
            }
            history.push((s, y, 1.0 / ys));
        }
        iterations += 1;
        let improvement = loss - loss_new;
        (x, loss, grad) = (x_new, loss_new, grad_new);
        if improvement.abs() <= 1e-12 * loss.abs().max(1.0) {
            break;
        }
    }
    LbfgsResult {
        x,
        loss,
        iterations,
        evaluations,
    }
}

/// L-BFGS-B's stopping tolerances as `fmin_l_bfgs_b` sets them by default.
const FACTR: f64 = 1e7;
const PGTOL: f64 = 1e-5;

fn minimize_strong_wolfe(f: &mut impl Objective, x0: Vec<f64>, max_iter: usize) -> LbfgsResult {
    let mut x = x0;
    let mut loss = f.loss(&x);
    let mut grad = f.gradient();
    let mut evaluations = 1;
    let mut history: Vec<(Vec<f64>, Vec<f64>, f64)> = Vec::new();
    let mut iterations = 0;
    let max_abs = |g: &[f64]| g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if max_abs(&grad) <= PGTOL {
        return LbfgsResult {
            x,
            loss,
            iterations,
            evaluations,
        };
    }
    while iterations < max_iter {
        // The first iteration steps along −g with a first trial of 1/‖g‖; later ones
        // along −H·g with a first trial of 1.
        let direction = direction(&grad, &history, 1.0);
        let slope = dot(&grad, &direction);
        if slope >= 0.0 || !slope.is_finite() {
            break;
        }
        let first = if history.is_empty() && iterations == 0 {
            (1.0 / dot(&direction, &direction).sqrt()).min(1e10)
        } else {
            1.0
        };
        let Ok(mut search) = MoreThuente::new(loss, slope, first, (1e-3, 0.9, 0.1), (0.0, 1e10))
        else {
            break;
        };
        let mut step = first;
        let mut accepted = None;
        for _ in 0..20 {
            // Every trial point needs its gradient (the curvature condition).
            let candidate = along(&x, &direction, step);
            let l = f.loss(&candidate);
            let g = f.gradient();
            evaluations += 1;
            if !l.is_finite() {
                break;
            }
            match search.next(l, dot(&g, &direction)) {
                Search::Evaluate(next) => step = next,
                Search::Converged | Search::Warning(_) => {
                    accepted = Some((candidate, l, g));
                    break;
                }
            }
        }
        let Some((x_new, loss_new, grad_new)) = accepted else {
            break; // L-BFGS-B ends abnormally here; the point reached so far stands
        };
        let s: Vec<f64> = x_new.iter().zip(&x).map(|(a, b)| a - b).collect();
        let y: Vec<f64> = grad_new.iter().zip(&grad).map(|(a, b)| a - b).collect();
        let ys = dot(&y, &s);
        if ys > f64::EPSILON * -dot(&grad, &s) {
            if history.len() == MEMORY {
                history.remove(0);
            }
            history.push((s, y, 1.0 / ys));
        }
        iterations += 1;
        let relative = (loss - loss_new) / loss.abs().max(loss_new.abs()).max(1.0);
        (x, loss, grad) = (x_new, loss_new, grad_new);
        if relative <= FACTR * f64::EPSILON || max_abs(&grad) <= PGTOL {
            break;
        }
    }
    LbfgsResult {
        x,
        loss,
        iterations,
        evaluations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimises_the_rosenbrock_function() {
        let f = |x: &[f64]| {
            let (a, b) = (x[0], x[1]);
            let loss = (1.0 - a).powi(2) + 100.0 * (b - a * a).powi(2);
            (
                loss,
                vec![
                    -2.0 * (1.0 - a) - 400.0 * a * (b - a * a),
                    200.0 * (b - a * a),
                ],
            )
        };
        let r = minimize(
            &mut Eager::new(f),
            vec![-1.2, 1.0],
            200,
            LineSearch::Backtracking,
        );
        assert!(
            (r.x[0] - 1.0).abs() < 1e-5 && (r.x[1] - 1.0).abs() < 1e-5,
            "{:?} after {}",
            r.x,
            r.iterations
        );
    }

    #[test]
    fn solves_a_quadratic_within_its_dimension() {
        let f = |x: &[f64]| {
            let loss: f64 = x
                .iter()
                .enumerate()
                .map(|(i, v)| (i as f64 + 1.0) * (v - 2.0).powi(2))
                .sum();
            (
                loss,
                x.iter()
                    .enumerate()
                    .map(|(i, v)| 2.0 * (i as f64 + 1.0) * (v - 2.0))
                    .collect(),
            )
        };
        let r = minimize(
            &mut Eager::new(f),
            vec![0.0; 5],
            25,
            LineSearch::Backtracking,
        );
        assert!(r.loss < 1e-10, "{}", r.loss);
    }
}

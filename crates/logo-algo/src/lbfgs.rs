//! L-BFGS (memory 10) with a backtracking Armijo line search, for the critics. The
//! reference calls SciPy's `fmin_l_bfgs_b(maxiter=25)`, whose line search is the
//! Moré-Thuente one: the iterates differ, the objective and the budget are the same.

use logo_nn::flat::dot;

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

/// Minimises `f` from `x0` for at most `max_iter` iterations.
pub fn minimize(f: &mut impl Objective, x0: Vec<f64>, max_iter: usize) -> LbfgsResult {
    const MEMORY: usize = 10;
    let mut x = x0;
    let mut loss = f.loss(&x);
    let mut grad = f.gradient();
    let mut evaluations = 1;
    let mut history: Vec<(Vec<f64>, Vec<f64>, f64)> = Vec::new(); // (s, y, 1/yᵀs)
    let mut iterations = 0;
    while iterations < max_iter {
        // Two-loop recursion: d = −H g.
        let mut q = grad.clone();
        let mut alphas = Vec::with_capacity(history.len());
        for (s, y, rho) in history.iter().rev() {
            let a = rho * dot(s, &q);
            q.iter_mut().zip(y).for_each(|(qi, yi)| *qi -= a * yi);
            alphas.push(a);
        }
        let gamma = history.last().map_or_else(
            || 1.0 / dot(&grad, &grad).sqrt().max(1e-12), // first step: unit length
            |(s, y, _)| dot(s, y) / dot(y, y),
        );
        q.iter_mut().for_each(|qi| *qi *= gamma);
        for ((s, y, rho), a) in history.iter().zip(alphas.iter().rev()) {
            let b = rho * dot(y, &q);
            q.iter_mut().zip(s).for_each(|(qi, si)| *qi += (a - b) * si);
        }
        let direction: Vec<f64> = q.iter().map(|v| -v).collect();
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
            let candidate: Vec<f64> = x
                .iter()
                .zip(&direction)
                .map(|(xi, di)| xi + step * di)
                .collect();
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
        let r = minimize(&mut Eager::new(f), vec![-1.2, 1.0], 200);
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
        let r = minimize(&mut Eager::new(f), vec![0.0; 5], 25);
        assert!(r.loss < 1e-10, "{}", r.loss);
    }
}

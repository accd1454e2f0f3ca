//! The statistics every report of logo-rl uses, written once so that tables, figures,
//! evaluations and benches agree. Conventions:
//!
//! - **std** is the sample standard deviation (n − 1 in the denominator), 0 for one value;
//! - **median** averages the middle two of an even count;
//! - **quantiles** interpolate linearly between order statistics (numpy's default);
//! - the **interquartile mean** (IQM) drops ⌊n/4⌋ values from each end and averages the
//!   rest (`scipy.stats.trim_mean(x, 0.25)`, as rliable's `aggregate_iqm`); with fewer
//!   than 4 values it is the mean;
//! - the **probability of improvement** P(X > Y) counts ties as one half (the
//!   Mann–Whitney U statistic over all pairs, divided by their number), averaged over
//!   tasks;
//! - **confidence intervals** are percentile intervals of a stratified bootstrap: each
//!   task's runs (seeds) are resampled with replacement, the tasks kept, and the interval
//!   is the central `confidence` share of the statistic over the resamples. These are the
//!   conventions of Agarwal et al. (2021), "Deep RL at the edge of the statistical
//!   precipice", and of its `rliable` package, against which `tests/rliable.rs` checks
//!   them. The resamples come from a seeded ChaCha stream: the same data and seed give the
//!   same interval on every machine.
//!
//! Scores are given per task: `&[Vec<f64>]`, one vector of runs for each task (a task is
//! an environment, or a budget, whatever the runs are stratified by). Most reports have
//! one task; [`one_task`] wraps a slice.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The arithmetic mean; NaN for no values.
pub fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

/// The sample standard deviation (n − 1); 0 for one value, NaN for none.
pub fn std(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return if x.is_empty() { f64::NAN } else { 0.0 };
    }
    let m = mean(x);
    let ss: f64 = x.iter().map(|v| (v - m) * (v - m)).sum();
    (ss / (x.len() - 1) as f64).sqrt()
}

/// [`mean`] and [`std`] together.
pub fn mean_std(x: &[f64]) -> (f64, f64) {
    (mean(x), std(x))
}

/// A sorted copy (total order: NaN last; the statistics below return NaN for any NaN
/// rather than sort it away).
pub fn sorted(x: &[f64]) -> Vec<f64> {
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    v
}

/// The median: the middle value, or the mean of the middle two; NaN for none, or where
/// any value is NaN.
pub fn median(x: &[f64]) -> f64 {
    if has_nan(x) {
        return f64::NAN;
    }
    quantile_sorted(&sorted(x), 0.5)
}

fn has_nan(x: &[f64]) -> bool {
    x.iter().any(|v| v.is_nan())
}

/// The `q` quantile (0 ≤ q ≤ 1) of sorted values, linear between order statistics; NaN
/// for none, or where any value is NaN.
pub fn quantile_sorted(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() || has_nan(sorted) {
        return f64::NAN;
    }
    let h = (sorted.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(sorted.len() - 1);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

/// The interquartile mean: the mean after dropping ⌊n/4⌋ values from each end; NaN
/// where any value is NaN (not trimmed away as an outlier).
pub fn iqm(x: &[f64]) -> f64 {
    if has_nan(x) {
        return f64::NAN;
    }
    iqm_of_sorted(&sorted(x))
}

fn iqm_of_sorted(sorted: &[f64]) -> f64 {
    let cut = sorted.len() / 4;
    mean(&sorted[cut..sorted.len() - cut])
}

/// P(X > Y) + ½ P(X = Y) for one draw of each: the share of pairs (x, y) with x > y, ties
/// counted as one half (−0 and +0 tie); NaN where any value is NaN.
pub fn probability_of_improvement(x: &[f64], y: &[f64]) -> f64 {
    let mut wins = 0.0;
    for a in x {
        for b in y {
            wins += match a.partial_cmp(b) {
                Some(std::cmp::Ordering::Greater) => 1.0,
                Some(std::cmp::Ordering::Equal) => 0.5,
                Some(std::cmp::Ordering::Less) => 0.0,
                None => return f64::NAN,
            };
        }
    }
    wins / (x.len() * y.len()) as f64
}

/// Scores of one task.
pub fn one_task(x: &[f64]) -> Vec<Vec<f64>> {
    vec![x.to_vec()]
}

/// An aggregate over tasks × runs, as rliable defines them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Aggregate {
    /// The mean over tasks of each task's mean over runs.
    Mean,
    /// The interquartile mean of all scores together.
    Iqm,
}

impl Aggregate {
    pub fn of(self, tasks: &[Vec<f64>]) -> f64 {
        match self {
            Aggregate::Mean => mean(&tasks.iter().map(|t| mean(t)).collect::<Vec<_>>()),
            Aggregate::Iqm => iqm(&tasks.concat()),
        }
    }
}

/// The probability of improvement of X over Y, averaged over their tasks (X's task k
/// against Y's task k).
pub fn average_probability_of_improvement(x: &[Vec<f64>], y: &[Vec<f64>]) -> f64 {
    let per_task: Vec<f64> = x
        .iter()
        .zip(y)
        .map(|(a, b)| probability_of_improvement(a, b))
        .collect();
    mean(&per_task)
}

/// A point estimate with its confidence interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub point: f64,
    pub lo: f64,
    pub hi: f64,
}

impl Estimate {
    /// Whether `value` lies inside the interval (ends included).
    pub fn contains(&self, value: f64) -> bool {
        self.lo <= value && value <= self.hi
    }
}

/// Stratified-bootstrap percentile intervals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bootstrap {
    /// Resamples drawn.
    pub reps: usize,
    /// The interval's coverage, e.g. 0.95.
    pub confidence: f64,
    /// Seed of the resampling stream.
    pub seed: u64,
}

impl Default for Bootstrap {
    /// 50,000 resamples (rliable's default), 95%, seed 0.
    fn default() -> Self {
        Bootstrap {
            reps: 50_000,
            confidence: 0.95,
            seed: 0,
        }
    }
}

impl Bootstrap {
    pub fn with_reps(reps: usize) -> Self {
        Bootstrap {
            reps,
            ..Bootstrap::default()
        }
    }

    /// `statistic` of `tasks` and its interval over resamples of each task's runs.
    pub fn estimate(&self, tasks: &[Vec<f64>], statistic: impl Fn(&[Vec<f64>]) -> f64) -> Estimate {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let mut resample = tasks.to_vec();
        let values = (0..self.reps)
            .map(|_| {
                draw(&mut rng, tasks, &mut resample);
                statistic(&resample)
            })
            .collect();
        self.interval(statistic(tasks), values)
    }

    /// `statistic` of two sets of tasks and its interval over independent resamples of
    /// each (as rliable's probability of improvement: X's and Y's runs are not paired).
    pub fn estimate_two(
        &self,
        x: &[Vec<f64>],
        y: &[Vec<f64>],
        statistic: impl Fn(&[Vec<f64>], &[Vec<f64>]) -> f64,
    ) -> Estimate {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let (mut rx, mut ry) = (x.to_vec(), y.to_vec());
        let values = (0..self.reps)
            .map(|_| {
                draw(&mut rng, x, &mut rx);
                draw(&mut rng, y, &mut ry);
                statistic(&rx, &ry)
            })
            .collect();
        self.interval(statistic(x, y), values)
    }

    /// [`Aggregate`] of one task's values with its interval.
    pub fn aggregate(&self, values: &[f64], aggregate: Aggregate) -> Estimate {
        self.estimate(&one_task(values), |t| aggregate.of(t))
    }

    /// P(X > Y) over one task's values with its interval.
    pub fn improvement(&self, x: &[f64], y: &[f64]) -> Estimate {
        self.estimate_two(
            &one_task(x),
            &one_task(y),
            average_probability_of_improvement,
        )
    }

    fn interval(&self, point: f64, mut values: Vec<f64>) -> Estimate {
        values.sort_by(f64::total_cmp);
        let tail = (1.0 - self.confidence) / 2.0;
        Estimate {
            point,
            lo: quantile_sorted(&values, tail),
            hi: quantile_sorted(&values, 1.0 - tail),
        }
    }
}

/// One stratified resample: each task's runs drawn with replacement into `into`.
fn draw(rng: &mut ChaCha8Rng, tasks: &[Vec<f64>], into: &mut [Vec<f64>]) {
    for (task, out) in tasks.iter().zip(into.iter_mut()) {
        for slot in out.iter_mut() {
            *slot = task[rng.random_range(0..task.len())];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn std_is_the_sample_std_and_zero_for_one_value() {
        assert_eq!(std(&[3.0]), 0.0);
        assert!(std(&[]).is_nan());
        // A NaN is reported, not sorted to an end and trimmed away; signed zeros tie.
        let with_nan = [1.0, 2.0, f64::NAN, 3.0, 4.0, 5.0, 6.0, 7.0];
        assert!(iqm(&with_nan).is_nan() && median(&with_nan).is_nan());
        assert!(probability_of_improvement(&with_nan, &[1.0]).is_nan());
        assert_eq!(probability_of_improvement(&[-0.0], &[0.0]), 0.5);
        let interval = Bootstrap::with_reps(100).aggregate(&with_nan, Aggregate::Iqm);
        assert!(interval.point.is_nan() && interval.lo.is_nan() && interval.hi.is_nan());
        // Values 1..=4: mean 2.5, squares 5, over n − 1 = 3.
        assert!((std(&[1.0, 2.0, 3.0, 4.0]) - (5.0f64 / 3.0).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn median_and_quantiles_interpolate_as_numpy() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        let s = [1.0, 2.0, 4.0, 8.0];
        // numpy.percentile([1, 2, 4, 8], 25) = 1.75, 97.5 → 7.7
        assert!((quantile_sorted(&s, 0.25) - 1.75).abs() < 1e-15);
        assert!((quantile_sorted(&s, 0.975) - 7.7).abs() < 1e-12);
    }

    #[test]
    fn iqm_trims_a_quarter_from_each_end() {
        // n = 8: drop 2 at each end.
        assert_eq!(iqm(&[100.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, -100.0]), 3.5);
        // n = 5: drop 1 at each end; n = 3: the mean.
        assert_eq!(iqm(&[0.0, 1.0, 2.0, 3.0, 1000.0]), 2.0);
        assert_eq!(iqm(&[0.0, 3.0, 9.0]), 4.0);
    }

    #[test]
    fn improvement_counts_ties_as_half() {
        assert_eq!(probability_of_improvement(&[2.0], &[1.0]), 1.0);
        assert_eq!(probability_of_improvement(&[1.0, 2.0], &[1.0, 2.0]), 0.5);
        assert_eq!(probability_of_improvement(&[1.0], &[1.0, 3.0]), 0.25);
    }

    #[test]
    fn intervals_are_reproducible_and_hold_the_point() {
        let x = [1.0, 5.0, 2.0, 8.0, 3.0];
        let b = Bootstrap::with_reps(2_000);
        let e = b.aggregate(&x, Aggregate::Mean);
        assert_eq!(e, b.aggregate(&x, Aggregate::Mean));
        assert!(e.lo < e.point && e.point < e.hi, "{e:?}");
        // A constant sample has a zero-width interval.
        let c = b.aggregate(&[4.0; 5], Aggregate::Iqm);
        assert_eq!((c.lo, c.point, c.hi), (4.0, 4.0, 4.0));
    }
}

//! The Moré–Thuente line search (Moré & Thuente 1994, as MINPACK-2's `dcsrch` and
//! `dcstep` specify it): a step α along a descent direction that satisfies the strong
//! Wolfe conditions
//!
//! φ(α) ≤ φ(0) + ftol·α·φ'(0)   and   |φ'(α)| ≤ gtol·|φ'(0)|,
//!
//! found by safeguarded cubic and quadratic interpolation inside an interval that is
//! extrapolated until it brackets such a step. It is the line search of SciPy's
//! `fmin_l_bfgs_b` (L-BFGS-B calls it with ftol 1e-3, gtol 0.9, xtol 0.1), which the LOGO
//! reference fits its critics with. The tests hold every trial step to SciPy's port of
//! `dcsrch`.
//!
//! The search is a state machine: [`MoreThuente::new`] takes φ(0), φ'(0) and the first
//! trial step; each [`MoreThuente::next`] takes φ and φ' at the trial step and says where
//! to evaluate next, or that the search is over.

/// What the caller does next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Search {
    /// Evaluate φ and φ' at this step and call [`MoreThuente::next`].
    Evaluate(f64),
    /// The step last evaluated satisfies the strong Wolfe conditions.
    Converged,
    /// The search cannot make progress (rounding, the interval below `xtol`, or a step
    /// at `stpmin`/`stpmax`); the step last evaluated is the best it found.
    Warning(&'static str),
}

/// Extrapolation bounds of the trial interval before a step is bracketed.
const XTRAPL: f64 = 1.1;
const XTRAPU: f64 = 4.0;

#[derive(Debug, Clone)]
pub struct MoreThuente {
    gtol: f64,
    xtol: f64,
    stpmin: f64,
    stpmax: f64,
    brackt: bool,
    stage: u8,
    finit: f64,
    ginit: f64,
    gtest: f64,
    width: f64,
    width1: f64,
    stx: f64,
    fx: f64,
    gx: f64,
    sty: f64,
    fy: f64,
    gy: f64,
    stmin: f64,
    stmax: f64,
    stp: f64,
}

/// The endpoints of the interval and the trial step, as `dcstep` updates them.
struct Interval {
    stx: f64,
    fx: f64,
    dx: f64,
    sty: f64,
    fy: f64,
    dy: f64,
    stp: f64,
    brackt: bool,
}

/// A search that cannot start from what it was given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum SearchError {
    #[error("the first step is below stpmin")]
    BelowMin,
    #[error("the first step is above stpmax")]
    AboveMax,
    #[error("the direction is not a descent direction")]
    NotDescent,
    #[error("a tolerance or bound is negative, or stpmax < stpmin")]
    Bounds,
}

impl MoreThuente {
    /// A search from φ(0) = `f0`, φ'(0) = `g0` (< 0) with first trial step `stp`.
    pub fn new(
        f0: f64,
        g0: f64,
        stp: f64,
        (ftol, gtol, xtol): (f64, f64, f64),
        (stpmin, stpmax): (f64, f64),
    ) -> Result<Self, SearchError> {
        if stp < stpmin {
            return Err(SearchError::BelowMin);
        }
        if stp > stpmax {
            return Err(SearchError::AboveMax);
        }
        if g0 >= 0.0 {
            return Err(SearchError::NotDescent);
        }
        if ftol < 0.0 || gtol < 0.0 || xtol < 0.0 || stpmin < 0.0 || stpmax < stpmin {
            return Err(SearchError::Bounds);
        }
        let width = stpmax - stpmin;
        Ok(Self {
            gtol,
            xtol,
            stpmin,
            stpmax,
            brackt: false,
            stage: 1,
            finit: f0,
            ginit: g0,
            gtest: ftol * g0,
            width,
            width1: width / 0.5,
            stx: 0.0,
            fx: f0,
            gx: g0,
            sty: 0.0,
            fy: f0,
            gy: g0,
            stmin: 0.0,
            stmax: stp + XTRAPU * stp,
            stp,
        })
    }

    /// The step φ was last asked for.
    pub fn step(&self) -> f64 {
        self.stp
    }

    /// Takes φ(stp) = `f` and φ'(stp) = `g` at the current step.
    ///
    /// Long by design: a line-for-line port of MINPACK-2's `dcsrch` (as SciPy runs it),
    /// checked against SciPy's steps; kept in the original's order so the two can be
    /// read side by side.
    pub fn next(&mut self, f: f64, g: f64) -> Search {
        let stp = self.stp;
        let ftest = self.finit + stp * self.gtest;
        if self.stage == 1 && f <= ftest && g >= 0.0 {
            self.stage = 2;
        }
        if self.brackt && (stp <= self.stmin || stp >= self.stmax) {
            return Search::Warning("rounding errors prevent progress");
        }
        if self.brackt && self.stmax - self.stmin <= self.xtol * self.stmax {
            return Search::Warning("xtol test satisfied");
        }
        if stp == self.stpmax && f <= ftest && g <= self.gtest {
            return Search::Warning("stp = stpmax");
        }
        if stp == self.stpmin && (f > ftest || g >= self.gtest) {
            return Search::Warning("stp = stpmin");
        }
        if f <= ftest && g.abs() <= self.gtol * (-self.ginit) {
            return Search::Converged;
        }

        // In the first stage, while the sufficient-decrease condition does not hold with
        // an increase, work with the modified function ψ(α) = φ(α) − φ(0) − ftol·α·φ'(0).
        let modified = self.stage == 1 && f <= self.fx && f > ftest;
        let shift = |value: f64, at: f64| {
            if modified {
                value - at * self.gtest
            } else {
                value
            }
        };
        let slope = |value: f64| if modified { value - self.gtest } else { value };
        let mut interval = Interval {
            stx: self.stx,
            fx: shift(self.fx, self.stx),
            dx: slope(self.gx),
            sty: self.sty,
            fy: shift(self.fy, self.sty),
            dy: slope(self.gy),
            stp,
            brackt: self.brackt,
        };
        dcstep(
            &mut interval,
            shift(f, stp),
            slope(g),
            self.stmin,
            self.stmax,
        );
        let unshift = |value: f64, at: f64| {
            if modified {
                value + at * self.gtest
            } else {
                value
            }
        };
        let unslope = |value: f64| if modified { value + self.gtest } else { value };
        self.stx = interval.stx;
        self.fx = unshift(interval.fx, interval.stx);
        self.gx = unslope(interval.dx);
        self.sty = interval.sty;
        self.fy = unshift(interval.fy, interval.sty);
        self.gy = unslope(interval.dy);
        self.brackt = interval.brackt;
        let mut stp = interval.stp;

        // A bisection step when the interval did not shrink enough in two trials.
        if self.brackt {
            if (self.sty - self.stx).abs() >= 0.66 * self.width1 {
                stp = self.stx + 0.5 * (self.sty - self.stx);
            }
            self.width1 = self.width;
            self.width = (self.sty - self.stx).abs();
        }
        if self.brackt {
            self.stmin = self.stx.min(self.sty);
            self.stmax = self.stx.max(self.sty);
        } else {
            self.stmin = stp + XTRAPL * (stp - self.stx);
            self.stmax = stp + XTRAPU * (stp - self.stx);
        }
        stp = stp.max(self.stpmin).min(self.stpmax);
        // Unusual termination: fall back to the best step so far.
        if self.brackt
            && (stp <= self.stmin
                || stp >= self.stmax
                || self.stmax - self.stmin <= self.xtol * self.stmax)
        {
            stp = self.stx;
        }
        self.stp = stp;
        Search::Evaluate(stp)
    }
}

/// One safeguarded step of `dcstep`: from the interval's endpoints (stx the best step so
/// far, sty the other end) and φ, φ' at the trial step, the next trial step, and the
/// interval updated to keep bracketing.
///
/// Long by design: a line-for-line port of MINPACK-2's `dcstep`, its four cases in the
/// original's order, checked against SciPy's steps.
fn dcstep(iv: &mut Interval, fp: f64, dp: f64, stpmin: f64, stpmax: f64) {
    let Interval {
        stx,
        fx,
        dx,
        sty,
        fy,
        dy,
        stp,
        ..
    } = *iv;
    let sgnd = dp * (dx / dx.abs());
    // The minimiser of the cubic through (stx, fx, dx) and (stp, fp, dp); `sign` picks
    // the root that is a minimum.
    let cubic_gamma = |theta: f64, d1: f64, d2: f64, clamp: bool| {
        let s = theta.abs().max(d1.abs()).max(d2.abs());
        let radicand = (theta / s).powi(2) - (d1 / s) * (d2 / s);
        s * if clamp { radicand.max(0.0) } else { radicand }.sqrt()
    };
    let stpf = if fp > fx {
        // Case 1: a higher value. The minimum is bracketed; take the cubic step if it is
        // closer to stx than the quadratic one, else their mean.
        let theta = 3.0 * (fx - fp) / (stp - stx) + dx + dp;
        let mut gamma = cubic_gamma(theta, dx, dp, false);
        if stp < stx {
            gamma = -gamma;
        }
        let p = (gamma - dx) + theta;
        let q = ((gamma - dx) + gamma) + dp;
        let stpc = stx + (p / q) * (stp - stx);
        let stpq = stx + ((dx / ((fx - fp) / (stp - stx) + dx)) / 2.0) * (stp - stx);
        iv.brackt = true;
        if (stpc - stx).abs() < (stpq - stx).abs() {
            stpc
        } else {
            stpc + (stpq - stpc) / 2.0
        }
    } else if sgnd < 0.0 {
        // Case 2: a lower value and derivatives of opposite sign. Bracketed; take the
        // cubic step if it is farther from stp than the secant step, else the secant.
        let theta = 3.0 * (fx - fp) / (stp - stx) + dx + dp;
        let mut gamma = cubic_gamma(theta, dx, dp, false);
        if stp > stx {
            gamma = -gamma;
        }
        let p = (gamma - dp) + theta;
        let q = ((gamma - dp) + gamma) + dx;
        let stpc = stp + (p / q) * (stx - stp);
        let stpq = stp + (dp / (dp - dx)) * (stx - stp);
        iv.brackt = true;
        if (stpc - stp).abs() > (stpq - stp).abs() {
            stpc
        } else {
            stpq
        }
    } else if dp.abs() < dx.abs() {
        // Case 3: a lower value, derivatives of the same sign, the derivative's magnitude
        // decreasing. The cubic step only if it goes the right way and is finite.
        let theta = 3.0 * (fx - fp) / (stp - stx) + dx + dp;
        let mut gamma = cubic_gamma(theta, dx, dp, true);
        if stp > stx {
            gamma = -gamma;
        }
        let p = (gamma - dp) + theta;
        let q = (gamma + (dx - dp)) + gamma;
        let r = p / q;
        let stpc = if r < 0.0 && gamma != 0.0 {
            stp + r * (stx - stp)
        } else if stp > stx {
            stpmax
        } else {
            stpmin
        };
        let stpq = stp + (dp / (dp - dx)) * (stx - stp);
        if iv.brackt {
            // Take the step closer to stp, but not too far into the interval.
            let stpf = if (stpc - stp).abs() < (stpq - stp).abs() {
                stpc
            } else {
                stpq
            };
            if stp > stx {
                stpf.min(stp + 0.66 * (sty - stp))
            } else {
                stpf.max(stp + 0.66 * (sty - stp))
            }
        } else {
            // Extrapolate: the step farther from stp, within the bounds.
            let stpf = if (stpc - stp).abs() > (stpq - stp).abs() {
                stpc
            } else {
                stpq
            };
            stpf.min(stpmax).max(stpmin)
        }
    } else {
        // Case 4: a lower value, derivatives of the same sign, the derivative not
        // decreasing in magnitude. The cubic step between stp and sty if bracketed,
        // else a bound.
        if iv.brackt {
            let theta = 3.0 * (fp - fy) / (sty - stp) + dy + dp;
            let mut gamma = cubic_gamma(theta, dy, dp, false);
            if stp > sty {
                gamma = -gamma;
            }
            let p = (gamma - dp) + theta;
            let q = ((gamma - dp) + gamma) + dy;
            stp + (p / q) * (sty - stp)
        } else if stp > stx {
            stpmax
        } else {
            stpmin
        }
    };
    // Update the interval: stx is always the end with the lowest value.
    if fp > fx {
        iv.sty = stp;
        iv.fy = fp;
        iv.dy = dp;
    } else {
        if sgnd < 0.0 {
            iv.sty = stx;
            iv.fy = fx;
            iv.dy = dx;
        }
        iv.stx = stp;
        iv.fx = fp;
        iv.dx = dp;
    }
    iv.stp = stpf;
}

//! Dense output of one accepted step and the [`StepView`] handed to observers.
//!
//! Every method's continuous extension is written in Hairer's nested form
//! `y(t0 + θh) = r0 + θ(r1 + θ'(r2 + θ(r3 + θ'(r4 + θ(r5 + θ'(r6 + θ r7))))))`, `θ' = 1 − θ`, with
//! `r0 = y0`, `r1 = y1 − y0`, `r2 = h f0 − r1`, `r3 = r1 − h f1 − r2` (the cubic Hermite
//! interpolant) and `r(4+j) = h Σ_s d_js k_s` from the tableau's dense rows (DOPRI5: one row,
//! 4th order; DOP853: four rows, 7th order; RKF45 and RK4: none, cubic Hermite).

use super::tableau::Tableau;

/// Coefficients of the continuous extension of the last accepted step.
#[derive(Clone, Debug)]
pub struct DenseOutput {
    pub(crate) t0: f64,
    pub(crate) h: f64,
    pub(crate) n: usize,
    pub(crate) terms: usize,
    pub(crate) r: Vec<f64>,
}

impl DenseOutput {
    /// Buffers for dimension `n` and the given tableau.
    pub fn new(n: usize, tab: &Tableau) -> Self {
        let terms = 4 + tab.dense.len();
        DenseOutput {
            t0: 0.0,
            h: 0.0,
            n,
            terms,
            r: vec![0.0; terms * n],
        }
    }

    /// Build the coefficients from the step `(t0, y0) -> (t0 + h, y1)` and the stage slots `k`
    /// (`slots * n`, slot 0 = `f(t0, y0)`, end slot = `f(t0 + h, y1)`, extra stages filled).
    pub fn build(&mut self, tab: &Tableau, t0: f64, h: f64, y0: &[f64], y1: &[f64], k: &[f64]) {
        let n = self.n;
        self.t0 = t0;
        self.h = h;
        let end = tab.end_slot() * n;
        let (head, rest) = self.r.split_at_mut(4 * n);
        for i in 0..n {
            let dy = y1[i] - y0[i];
            let bspl = h * k[i] - dy;
            head[i] = y0[i];
            head[n + i] = dy;
            head[2 * n + i] = bspl;
            head[3 * n + i] = dy - h * k[end + i] - bspl;
        }
        for (row, out) in tab.dense.iter().zip(rest.chunks_exact_mut(n)) {
            out.fill(0.0);
            for (s, &d) in row.iter().enumerate() {
                if d != 0.0 {
                    let ks = &k[s * n..(s + 1) * n];
                    for (o, &kv) in out.iter_mut().zip(ks) {
                        *o += d * kv;
                    }
                }
            }
            for o in out.iter_mut() {
                *o *= h;
            }
        }
    }

    /// Evaluate the interpolant at `t` (extrapolates outside the step).
    pub fn eval(&self, t: f64, out: &mut [f64]) {
        let n = self.n;
        let th = if self.h != 0.0 {
            (t - self.t0) / self.h
        } else {
            0.0
        };
        let th1 = 1.0 - th;
        for (i, o) in out.iter_mut().enumerate().take(n) {
            let mut acc = self.r[(self.terms - 1) * n + i];
            for m in (0..self.terms - 1).rev() {
                let f = if m % 2 == 0 { th } else { th1 };
                acc = self.r[m * n + i] + f * acc;
            }
            *o = acc;
        }
    }
}

/// The multiples k·dt of a sampling grid inside a step: t_start < k·dt ≤ t_end, each bound
/// widened by a rounding margin of 1e-15 relative, ascending. What a fixed-rate sampler
/// interpolates, and what [`Integrator::set_sample_grid`] builds the dense output for: one
/// definition, so the two cannot disagree.
///
/// Both bounds use the same margin, so consecutive steps [a, b] and [b, c] partition the grid:
/// a point k·dt that lies within rounding of b (a stop at t0 + 100 µs against 4020 × 5 µs)
/// belongs to the first step only. (With the margin at the end alone, such a point was taken by
/// both steps: a sample written twice, and every later sample one grid step late.)
///
/// [`Integrator::set_sample_grid`]: super::Integrator::set_sample_grid
pub fn grid_points(dt: f64, t_start: f64, t_end: f64) -> impl Iterator<Item = f64> {
    // ts is past t beyond rounding.
    let past = |ts: f64, t: f64| ts > t + t.abs() * 1e-15;
    // From ⌊t_start/dt⌋: the point there may still lie past t_start (a rounded quotient).
    let k0 = (t_start / dt).floor() as i64;
    (k0..)
        .map(move |k| k as f64 * dt)
        .take_while(move |&ts| !past(ts, t_end))
        .filter(move |&ts| past(ts, t_start))
}

/// One accepted step as seen by an observer: interval and dense output.
pub struct StepView<'a> {
    pub(crate) dense: &'a DenseOutput,
    pub(crate) t_start: f64,
    pub(crate) t_end: f64,
    pub(crate) y_end: &'a [f64],
}

impl StepView<'_> {
    /// Start of the step.
    pub fn t_start(&self) -> f64 {
        self.t_start
    }

    /// End of the step (an event time if the step was cut at an event).
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// Dense output at `t` in `[t_start, t_end]` (exactly `y_end` at `t_end`); `out` has the
    /// system's dimension.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) {
        if t == self.t_end {
            out.copy_from_slice(self.y_end);
        } else {
            self.dense.eval(t, out);
        }
    }

    /// State at [`StepView::t_end`].
    pub fn y_end(&self) -> &[f64] {
        self.y_end
    }
}

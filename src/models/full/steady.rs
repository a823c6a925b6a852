//! The balls' steady rotation under the strip traction, with the rings and the ball centres
//! held: the orbital rate θ̇ and the inertial angular velocity ω of every ball at which the
//! traction leaves no orbital acceleration and ω only turns with the orbit (ω̇ = θ̇ e_x × ω,
//! constant in the frame that rotates with the ball; the traction supplies the gyroscopic
//! moment). This is the state the full model's balls settle to from the quasi-static start,
//! and the cage speed of the levels with kinematic balls.
//!
//! Two ways of tying the orbits ([`Orbit`]):
//! - free: each ball finds its own θ̇ (the cage-less full model: θ̈_j = 0 for every ball);
//! - caged: one θ̇ for all balls, at which the orbital torques of the traction cancel over the
//!   ball set (Σ_j m r_j² θ̈_j = 0: a cage without drag pushes the slow balls and holds the fast
//!   ones). A ball's share of that balance grows with its load, so the cage speed moves
//!   continuously as balls enter or leave the load zone.
//!
//! The problem splits into a scalar root per orbit and a 3-unknown spin problem per ball:
//! - Spin at a fixed θ̇: the ball's ω solves ω̇ − θ̇ e_x × ω = 0 by pseudo-transient
//!   continuation, steps (I/Δτ − J) δ = r with a finite-difference J. Δτ starts near Newton; a
//!   step is kept when it goes with the ball's own rotation (δ·r > 0; where the traction falls
//!   with slip, J has unstable directions a Newton step would run along) and its linearization
//!   predicts the residual it lands on; otherwise Δτ shrinks, so the iteration follows the
//!   ball's damped rotation across the non-monotone traction curve and past a fold, and ends as
//!   Newton. Solves at new orbital rates start from the last solved spins, in up to three
//!   halved continuation steps.
//! - A lightly loaded ball held far from its rolling speed can settle into a spin cycle
//!   instead (a relaxation cycle of tens of ms). In the caged balance it enters with its
//!   orbital acceleration averaged over its own motion ([`SteadyReport::unsettled`]); a free
//!   solve reports it.
//! - Orbit: g(θ̇) = θ̈ at the spin equilibrium falls with θ̇ (a ball slower than the races
//!   roll it is pushed forward, a faster one held back), and it has opposite signs at θ̇ = 0
//!   and at the shaft speed. The root is bracketed by stepping out from the starting guess (L1's
//!   outer-race control, load-weighted when caged, or a previous solution) and then found by
//!   the Illinois variant of regula falsi, which keeps the bracket. A sign that does not change
//!   before 0 or the shaft speed is reported, never replaced.
//!
//! The balls are independent while the rings are held, so each Jacobian column and each trial
//! is one right-hand side of the full model for all balls at once.

// The balls advance in lockstep through index-parallel per-ball arrays.
#![allow(clippy::needless_range_loop)]

use crate::models::balls::ball_contact::ContactOut;
use crate::models::balls::layout::*;
use crate::models::balls::BallCore;
use crate::models::Model;
use std::fmt;

/// A model whose balls' steady rotation can be solved: its balls have the full model's free
/// spin (three angular-velocity states each). The full model is one.
pub trait SteadyBalls: Model {
    /// The ball-level core (layout, inputs, ball constants).
    fn balls(&self) -> &BallCore;
    /// Each ball's orbital rate under L1's outer-race control [rad/s] (the starting guess).
    fn l1_orbit(&self) -> &[f64];
    /// Both contacts of ball j at state y (inner, outer), traction included.
    fn ball_contacts(&self, y: &[f64], j: usize) -> (ContactOut, ContactOut);
}

/// How the balls' orbital rates are tied (see the module notes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Orbit {
    /// Each ball its own orbital rate (no cage).
    Free,
    /// One orbital rate for all balls, the orbital torques balanced over the ball set.
    Caged,
}

/// Convergence of [`steady_rotation`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyReport {
    /// How the orbits were tied.
    pub orbit: Orbit,
    /// Balls in the solve (both contacts loaded).
    pub balls: usize,
    /// Orbit evaluations (one spin solve each).
    pub evaluations: usize,
    /// Right-hand sides evaluated.
    pub rhs_evals: usize,
    /// Largest spin residual at the end, |ω̇ − θ̇ e_x × ω| / (Ω |ω|) (Ω the shaft speed).
    pub spin_residual: f64,
    /// Orbit residual at the end over Ω²: caged |Σ m r² θ̈| / Σ m r², free the largest |θ̈_j|.
    pub orbit_residual: f64,
    /// Caged: the common orbital rate; free: the mean over the solved balls [rad/s].
    pub cage_speed: f64,
    /// Caged: balls whose spin has no steady state at the cage speed (a spin cycle), taken with
    /// their orbital acceleration averaged over their motion ([`SteadyReport::cycle_spread`]).
    pub unsettled: usize,
    /// Caged: the change of the cage speed that half the range of the unsettled balls'
    /// orbital accelerations over their cycles would make [rad/s] (0 when all settle): how
    /// much the averaging can matter.
    pub cycle_spread: f64,
}

/// Why [`steady_rotation`] has no answer.
#[derive(Debug, Clone, PartialEq)]
pub enum SteadyError {
    /// No ball touches both races (the traction cannot drive any ball).
    NoBallLoaded,
    /// The orbital acceleration keeps one sign up to a bound of the physical range [0, Ω].
    NoEquilibrium {
        /// The ball (free orbits) or None (caged).
        ball: Option<usize>,
        /// The bound reached \[rad/s\].
        at: f64,
        /// The orbital acceleration at that bound [rad/s²].
        accel: f64,
    },
    /// The search for the orbital rate did not close its bracket in the evaluations allowed.
    NotConverged {
        /// Right-hand-side evaluations spent.
        evaluations: usize,
    },
    /// A ball's spin did not settle at the given orbital rate.
    Spin {
        /// The ball (0-based).
        ball: usize,
        /// The orbital rate it was solved at \[rad/s\].
        orbit_rate: f64,
        /// The spin residual left, |ω̇ − θ̇ e_x × ω| / (Ω |ω|) (dimensionless).
        residual: f64,
    },
}

impl fmt::Display for SteadyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SteadyError::NoBallLoaded => write!(
                f,
                "no ball touches both races, so the traction sets no cage speed"
            ),
            SteadyError::NoEquilibrium { ball, at, accel } => {
                let who = match ball {
                    Some(j) => format!("ball {}'s orbital acceleration", j + 1),
                    None => "the orbital torque of the traction on the ball set".to_string(),
                };
                write!(
                    f,
                    "the traction has no steady rotation: {who} keeps its sign up to an orbital \
                     rate of {at:.4} rad/s ({accel:.4e} rad/s² there)"
                )
            }
            SteadyError::NotConverged { evaluations } => write!(
                f,
                "the orbital rate did not converge in {evaluations} evaluations"
            ),
            SteadyError::Spin {
                ball,
                orbit_rate,
                residual,
            } => write!(
                f,
                "ball {}'s spin does not settle at the orbital rate {orbit_rate:.4} rad/s \
                 (scaled residual {residual:.2e})",
                ball + 1
            ),
        }
    }
}

/// Relative tolerance of the orbital rates (× Ω).
const ORBIT_TOL: f64 = 1e-9;
/// Spin residual tolerance, |ω̇ − θ̇ e_x × ω| ≤ SPIN_TOL Ω |ω| (the strip traction's slip
/// signs make the residual piecewise smooth, which can stall Newton near 1e-8; against 1e-9
/// the cage speed agrees to 1e-9 of the shaft speed where every ball settles).
const SPIN_TOL: f64 = 1e-7;
/// Pseudo-transient iterations per spin solve.
const SPIN_ITER: usize = 100;
/// A spin that does not settle is followed over this many shaft revolutions in this many
/// steps ([`average_flow`]).
const FLOW_REVS: f64 = 10.0;
const FLOW_STEPS: usize = 300;
/// Spin solves per move to new orbital rates ([`move_to`]).
const MOVE_ATTEMPTS: usize = 8;
/// Orbit evaluations per solve (bracketing and regula falsi).
const ORBIT_ITER: usize = 80;

/// Scratch of the spin solves.
struct Work {
    d: Vec<f64>,
    r: Vec<[f64; 3]>,
    rt: Vec<[f64; 3]>,
    base: Vec<[f64; 3]>,
    /// Balls of the last spin solve that did not settle (averaged) and half the range of
    /// their orbital acceleration [rad/s²].
    unsettled: Vec<bool>,
    spread: Vec<f64>,
    jac: Vec<[[f64; 3]; 3]>,
    h: Vec<f64>,
    dtau: Vec<f64>,
    scale: Vec<f64>,
    rhs: usize,
}

fn spin_idx<M: SteadyBalls>(m: &M, j: usize) -> [usize; 3] {
    let b = m.balls().lay.ball(j);
    [b + BOM, b + BOM + 1, b + BOM + 2]
}

/// Spin residuals ω̇ − θ̇ e_x × ω of every ball and their orbital accelerations θ̈ (one RHS).
fn residuals<M: SteadyBalls>(m: &mut M, y: &[f64], w: &mut Work, out: Out) {
    m.rhs(0.0, y, &mut w.d);
    w.rhs += 1;
    let target = match out {
        Out::Base => &mut w.r,
        Out::Trial => &mut w.rt,
    };
    for (j, rj) in target.iter_mut().enumerate() {
        let b = m.balls().lay.ball(j);
        let th = y[b + BW];
        // θ̇ e_x × ω = θ̇ (0, −ω_z, ω_y).
        *rj = [
            w.d[b + BOM],
            w.d[b + BOM + 1] + th * y[b + BOM + 2],
            w.d[b + BOM + 2] - th * y[b + BOM + 1],
        ];
    }
}

#[derive(Clone, Copy)]
enum Out {
    Base,
    Trial,
}

fn norm3(v: &[f64; 3]) -> f64 {
    v.iter().fold(0.0_f64, |a, x| a.max(x.abs()))
}

/// The spin Jacobian ∂r/∂ω of every ball at `y` (residuals in `w.r`), one column for every
/// ball per right-hand side.
fn jacobian<M: SteadyBalls>(m: &mut M, y: &mut [f64], w: &mut Work) {
    let z = w.r.len();
    w.base.copy_from_slice(&w.r);
    for k in 0..3 {
        for j in 0..z {
            let i = spin_idx(m, j)[k];
            w.h[j] = 1e-7 * (y[i].abs() + y[m.balls().lay.ball(j) + BW].abs()).max(1.0);
            y[i] += w.h[j];
        }
        residuals(m, y, w, Out::Trial);
        for j in 0..z {
            y[spin_idx(m, j)[k]] -= w.h[j];
            for row in 0..3 {
                w.jac[j][row][k] = (w.rt[j][row] - w.base[j][row]) / w.h[j];
            }
        }
    }
}

/// Solves every active ball's spin at the orbital rates in `y` (pseudo-transient continuation,
/// all balls in lockstep). On return `w.r` holds the residuals at `y` and `orbit[j]` the balls'
/// θ̈. A ball whose spin does not settle is an error, or with `average` its orbital
/// acceleration is the mean over its own motion ([`average_flow`], `w.unsettled`).
///
/// A step is kept only if it lowers the ball's residual (2-norm); otherwise it is undone and
/// Δτ cut by 4, so a ball whose Newton step fails falls back on its own damped rotation. The
/// Jacobian is formed again only after a kept step.
fn solve_spins<M: SteadyBalls>(
    m: &mut M,
    y: &mut [f64],
    active: &[bool],
    w: &mut Work,
    orbit: &mut [f64],
    average: bool,
) -> Result<(), usize> {
    let z = active.len();
    residuals(m, y, w, Out::Base);
    let converged = |w: &Work, j: usize| norm3(&w.r[j]) <= SPIN_TOL * w.scale[j];
    let mut need_jac = true;
    let mut steps = vec![None; z];
    for _ in 0..SPIN_ITER {
        if (0..z).all(|j| !active[j] || converged(w, j)) {
            break;
        }
        if need_jac {
            jacobian(m, y, w);
            need_jac = false;
        }
        // One pseudo-time step per unconverged ball.
        for j in 0..z {
            steps[j] = None;
            if !active[j] || converged(w, j) {
                continue;
            }
            if w.dtau[j] == 0.0 {
                // The first solve starts near Newton (1000 × the fastest relaxation time);
                // later ones keep the pseudo-time step the last one ended with.
                let rate = (0..3)
                    .map(|r| w.jac[j][r].iter().map(|v| v.abs()).sum::<f64>())
                    .fold(0.0, f64::max);
                w.dtau[j] = if rate > 0.0 { 1e3 / rate } else { 1e-3 };
            }
            // The step must go with the ball's own rotation (δ·r > 0): where the traction
            // falls with slip, J has unstable directions and a Newton step would run away from
            // rolling, so Δτ is cut until the pseudo-time term dominates them.
            let mut step = None;
            for _ in 0..40 {
                let mut a = w.jac[j];
                for (r, row) in a.iter_mut().enumerate() {
                    for (c, v) in row.iter_mut().enumerate() {
                        *v = if r == c { 1.0 / w.dtau[j] } else { 0.0 } - *v;
                    }
                }
                match solve3(a, w.r[j]) {
                    Some(s) if (0..3).map(|k| s[k] * w.r[j][k]).sum::<f64>() > 0.0 => {
                        step = Some(s);
                        break;
                    }
                    _ => w.dtau[j] *= 0.25,
                }
            }
            if let Some(mut s) = step {
                // No step longer than a tenth of the spin scale.
                let cap = 0.1 * w.scale[j] / m.balls().inputs.shaft_speed;
                let len = norm3(&s);
                if len > cap {
                    s.iter_mut().for_each(|v| *v *= cap / len);
                }
                for (k, i) in spin_idx(m, j).into_iter().enumerate() {
                    y[i] += s[k];
                }
                steps[j] = Some(s);
            }
        }
        residuals(m, y, w, Out::Trial);
        for j in 0..z {
            let Some(s) = steps[j] else { continue };
            // The step follows the ball's rotation as far as the linearization holds: the
            // residual it predicts, r + J δ, must match the one found within half the larger
            // of the two residuals. The residual itself may grow (past the fold of a light
            // ball's spin, or along a falling traction curve on the way to rolling).
            let jac = &w.jac[j];
            let pred: [f64; 3] =
                std::array::from_fn(|r| w.r[j][r] + (0..3).map(|c| jac[r][c] * s[c]).sum::<f64>());
            let miss = norm3(&std::array::from_fn(|r| w.rt[j][r] - pred[r]));
            let reference = norm3(&w.r[j]).max(norm3(&pred));
            if miss.is_finite() && miss <= 0.5 * reference {
                let grow = (0.5 * reference / miss.max(1e-300)).sqrt().clamp(1.0, 10.0);
                w.dtau[j] = (w.dtau[j] * grow).min(1e6);
                w.r[j] = w.rt[j];
                need_jac = true;
            } else {
                for (k, i) in spin_idx(m, j).into_iter().enumerate() {
                    y[i] -= s[k];
                }
                w.dtau[j] *= 0.25;
            }
        }
    }
    // One clean evaluation at the final rates.
    residuals(m, y, w, Out::Base);
    for j in 0..z {
        orbit[j] = w.d[m.balls().lay.ball(j) + BW];
        w.unsettled[j] = false;
    }
    let open: Vec<usize> = (0..z).filter(|&j| active[j] && !converged(w, j)).collect();
    match open.first() {
        None => Ok(()),
        Some(&j) if !average => Err(j),
        Some(_) => {
            average_flow(m, y, w, orbit, &open);
            Ok(())
        }
    }
}

/// Balls whose spin has no steady state at their orbital rate (a lightly loaded ball held far
/// from its rolling speed can settle into a spin cycle instead): their orbital acceleration is
/// its mean over the second half of [`FLOW_REVS`] shaft revolutions of their own rotation,
/// followed by linearly implicit Euler steps. `w.spread[j]` gets half its range there.
fn average_flow<M: SteadyBalls>(
    m: &mut M,
    y: &mut [f64],
    w: &mut Work,
    orbit: &mut [f64],
    open: &[usize],
) {
    let dt = FLOW_REVS * std::f64::consts::TAU / m.balls().inputs.shaft_speed / FLOW_STEPS as f64;
    let mut sum = vec![0.0; orbit.len()];
    let mut range = vec![(f64::INFINITY, f64::NEG_INFINITY); orbit.len()];
    for step in 0..FLOW_STEPS {
        jacobian(m, y, w);
        for &j in open {
            let mut a = w.jac[j];
            for (r, row) in a.iter_mut().enumerate() {
                for (c, v) in row.iter_mut().enumerate() {
                    *v = if r == c { 1.0 / dt } else { 0.0 } - *v;
                }
            }
            if let Some(s) = solve3(a, w.r[j]) {
                for (k, i) in spin_idx(m, j).into_iter().enumerate() {
                    y[i] += s[k];
                }
            }
        }
        residuals(m, y, w, Out::Base);
        if step >= FLOW_STEPS / 2 {
            for &j in open {
                let g = w.d[m.balls().lay.ball(j) + BW];
                sum[j] += g;
                range[j] = (range[j].0.min(g), range[j].1.max(g));
            }
        }
    }
    let n = (FLOW_STEPS - FLOW_STEPS / 2) as f64;
    for &j in open {
        orbit[j] = sum[j] / n;
        w.unsettled[j] = true;
        w.spread[j] = 0.5 * (range[j].1 - range[j].0);
    }
}

/// Solves 3×3 `a x = b` by Gaussian elimination with partial pivoting (None if singular).
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for c in 0..3 {
        let p = (c..3).max_by(|&i, &k| a[i][c].abs().total_cmp(&a[k][c].abs()))?;
        if a[p][c].abs() < 1e-300 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        let pivot = a[c];
        for r in c + 1..3 {
            let f = a[r][c] / pivot[c];
            for (ark, pk) in a[r][c..].iter_mut().zip(&pivot[c..]) {
                *ark -= f * pk;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 3];
    for c in (0..3).rev() {
        let s: f64 = (c + 1..3).map(|k| a[c][k] * x[k]).sum();
        x[c] = (b[c] - s) / a[c][c];
    }
    Some(x)
}

/// A bracketing root finder for a decreasing g(x) on [lo, hi], driven from outside: give it
/// g at [`Root::x`], it moves `x` to the next point to evaluate.
#[derive(Debug, Clone, Copy)]
struct Root {
    x: f64,
    lo: f64,
    hi: f64,
    /// Last point with g > 0 (below the root) and with g < 0 (above).
    below: Option<(f64, f64)>,
    above: Option<(f64, f64)>,
    step: f64,
    tol: f64,
    /// Which side regula falsi replaced last (Illinois: halve the other side's g on a repeat).
    last: i8,
    state: RootState,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum RootState {
    Searching,
    Done,
    /// g kept its sign up to this bound; g there.
    Unbounded(f64, f64),
}

impl Root {
    fn new(x0: f64, lo: f64, hi: f64, step: f64, tol: f64) -> Self {
        Self {
            x: x0.clamp(lo, hi),
            lo,
            hi,
            below: None,
            above: None,
            step,
            tol,
            last: 0,
            state: RootState::Searching,
        }
    }

    fn update(&mut self, g: f64) {
        if self.state != RootState::Searching {
            return;
        }
        let x = self.x;
        if g == 0.0 {
            self.state = RootState::Done;
            return;
        }
        let side = if g > 0.0 { 1 } else { -1 };
        let bracketed = self.below.is_some() && self.above.is_some();
        // Illinois: the same end replaced twice in a row halves the other end's g.
        if bracketed && self.last == side {
            let other = if side > 0 {
                &mut self.above
            } else {
                &mut self.below
            };
            if let Some(o) = other.as_mut() {
                o.1 *= 0.5;
            }
        }
        if side > 0 {
            self.below = Some((x, g));
        } else {
            self.above = Some((x, g));
        }
        self.last = if bracketed { side } else { 0 };
        match (self.below, self.above) {
            (Some((xb, gb)), Some((xa, ga))) => {
                if (xa - xb).abs() <= self.tol {
                    // Inside the tolerance: the regula-falsi estimate between the ends.
                    self.x = xb - gb * (xa - xb) / (ga - gb);
                    self.state = RootState::Done;
                    return;
                }
                let mut xn = xb - gb * (xa - xb) / (ga - gb);
                let (l, h) = (xb.min(xa), xb.max(xa));
                if !(xn > l && xn < h) {
                    xn = 0.5 * (l + h);
                }
                self.x = xn;
            }
            (Some(_), None) => {
                if x >= self.hi {
                    self.state = RootState::Unbounded(x, g);
                    return;
                }
                self.x = (x + self.step).min(self.hi);
                self.step *= 2.0;
            }
            (None, Some(_)) => {
                if x <= self.lo {
                    self.state = RootState::Unbounded(x, g);
                    return;
                }
                self.x = (x - self.step).max(self.lo);
                self.step *= 2.0;
            }
            (None, None) => unreachable!("g is nonzero"),
        }
    }
}

/// The last state whose spins were solved: every ball's orbital rate and angular velocity.
struct Solved {
    rate: Vec<f64>,
    spin: Vec<[f64; 3]>,
}

impl Solved {
    fn save<M: SteadyBalls>(&mut self, m: &M, y: &[f64]) {
        for j in 0..self.rate.len() {
            self.rate[j] = y[m.balls().lay.ball(j) + BW];
            self.spin[j] = spin_idx(m, j).map(|i| y[i]);
        }
    }

    fn restore<M: SteadyBalls>(&self, m: &M, y: &mut [f64]) {
        for j in 0..self.rate.len() {
            y[m.balls().lay.ball(j) + BW] = self.rate[j];
            for (k, i) in spin_idx(m, j).into_iter().enumerate() {
                y[i] = self.spin[j][k];
            }
        }
    }
}

/// Moves the active balls' orbital rates from the last solved state to `target` and solves
/// their spins there; where a ball's spin does not settle after the whole move, the move is
/// made in continuation steps (halved until each settles, three times at most: a spin that
/// does not settle a few continuation steps on is a spin cycle, not a bad guess). With
/// `average`, a ball that still does not settle is taken at the target with its orbital
/// acceleration averaged over its own motion ([`average_flow`]); without, Err(ball).
#[allow(clippy::too_many_arguments)]
fn move_to<M: SteadyBalls>(
    m: &mut M,
    y: &mut [f64],
    active: &[bool],
    w: &mut Work,
    accel: &mut [f64],
    solved: &mut Solved,
    target: &[f64],
    average: bool,
) -> Result<(), usize> {
    // The fraction of the remaining move tried, and the attempts (a move that keeps settling
    // halfway and failing the rest ends after MOVE_ATTEMPTS).
    let mut f = 1.0;
    for attempt in 1.. {
        for j in (0..active.len()).filter(|&j| active[j]) {
            let from = solved.rate[j];
            y[m.balls().lay.ball(j) + BW] = from + f * (target[j] - from);
        }
        let exhausted = f <= 0.125 || attempt >= MOVE_ATTEMPTS;
        let last_try = average && exhausted;
        if last_try {
            for j in (0..active.len()).filter(|&j| active[j]) {
                y[m.balls().lay.ball(j) + BW] = target[j];
            }
        }
        match solve_spins(m, y, active, w, accel, last_try) {
            Ok(()) => {
                solved.save(m, y);
                if f == 1.0 || last_try {
                    return Ok(());
                }
                f = (2.0 * f).min(1.0);
            }
            Err(j) => {
                solved.restore(m, y);
                w.dtau.iter_mut().for_each(|d| *d = 0.0);
                if exhausted {
                    return Err(j);
                }
                f *= 0.5;
            }
        }
    }
    unreachable!("the attempts end the loop")
}

/// Solves the balls' steady rotation at state `y` (see the module notes) and writes the rates
/// into `y`. Needs `m` built with traction, at a positive shaft speed, with its modes set
/// (`update_mode`) at `y`. The balls' rates in `y` (the full model's start takes them from L1's
/// outer-race control) are where the spins are first solved; `guess` is the orbital rate the
/// search for the root starts from (a previous solution's, for continuation along a ramp; by
/// default each ball's own rate when free, their mean weighted by the inner contact load when
/// caged). Balls that do not touch both races keep their rates (caged: they take the common
/// one).
pub fn steady_rotation<M: SteadyBalls>(
    m: &mut M,
    y: &mut [f64],
    orbit: Orbit,
    guess: Option<f64>,
) -> Result<SteadyReport, SteadyError> {
    let z = m.balls().z;
    let omega = m.balls().inputs.shaft_speed;
    let lay = m.balls().lay;
    let q_inner: Vec<f64> = (0..z)
        .map(|j| {
            let (ci, co) = m.ball_contacts(y, j);
            if ci.q > 0.0 && co.q > 0.0 {
                ci.q
            } else {
                0.0
            }
        })
        .collect();
    let active: Vec<bool> = q_inner.iter().map(|&q| q > 0.0).collect();
    let n_active = active.iter().filter(|&&a| a).count();
    if n_active == 0 {
        return Err(SteadyError::NoBallLoaded);
    }
    let mut w = Work {
        d: vec![0.0; y.len()],
        r: vec![[0.0; 3]; z],
        rt: vec![[0.0; 3]; z],
        base: vec![[0.0; 3]; z],
        unsettled: vec![false; z],
        spread: vec![0.0; z],
        jac: vec![[[0.0; 3]; 3]; z],
        h: vec![0.0; z],
        dtau: vec![0.0; z],
        scale: (0..z)
            .map(|j| {
                let [a, b, c] = spin_idx(m, j);
                omega * (y[a] * y[a] + y[b] * y[b] + y[c] * y[c]).sqrt().max(omega)
            })
            .collect(),
        rhs: 0,
    };
    // Orbital inertia m r² of each ball (the caged balance's weights).
    let inertia: Vec<f64> = (0..z)
        .map(|j| {
            let r = m.balls().pitch_radius + y[lay.ball(j) + BR];
            m.balls().ball_mass * r * r
        })
        .collect();
    let spin_error = |w: &Work, y: &[f64], j: usize| SteadyError::Spin {
        ball: j,
        orbit_rate: y[lay.ball(j) + BW],
        residual: norm3(&w.r[j]) / w.scale[j],
    };
    let mut accel = vec![0.0; z];
    // The spins at the balls' own outer-race-control rates first (where L1's spins nearly
    // balance): the base of every move.
    for j in (0..z).filter(|&j| active[j]) {
        y[lay.ball(j) + BW] = m.l1_orbit()[j];
    }
    let mut solved = Solved {
        rate: vec![0.0; z],
        spin: vec![[0.0; 3]; z],
    };
    solve_spins(m, y, &active, &mut w, &mut accel, orbit == Orbit::Caged)
        .map_err(|j| spin_error(&w, y, j))?;
    solved.save(m, y);
    let new_root = |x0: f64| Root::new(x0, 0.0, omega, 2e-3 * omega.max(1e-300), ORBIT_TOL * omega);
    let mut roots: Vec<Root> = match orbit {
        Orbit::Free => (0..z)
            .map(|j| new_root(guess.unwrap_or(solved.rate[j])))
            .collect(),
        Orbit::Caged => {
            let x0 = guess.unwrap_or_else(|| {
                let (num, den) = (0..z).fold((0.0, 0.0), |(n, d), j| {
                    (n + q_inner[j] * solved.rate[j], d + q_inner[j])
                });
                num / den
            });
            vec![new_root(x0)]
        }
    };
    let caged_g = |accel: &[f64]| {
        let (num, den) = (0..z).filter(|&j| active[j]).fold((0.0, 0.0), |(n, d), j| {
            (n + inertia[j] * accel[j], d + inertia[j])
        });
        num / den
    };
    let targets = |roots: &[Root]| -> Vec<f64> {
        (0..z)
            .map(|j| match orbit {
                Orbit::Free => roots[j].x,
                Orbit::Caged => roots[0].x,
            })
            .collect()
    };
    let caged = orbit == Orbit::Caged;
    let mut evaluations = 0;
    // Each pass solves the spins at the roots' current rates; the pass after the last update
    // puts them at the roots' final estimates.
    let mut finished = false;
    loop {
        let target = targets(&roots);
        move_to(
            m,
            y,
            &active,
            &mut w,
            &mut accel,
            &mut solved,
            &target,
            caged,
        )
        .map_err(|j| spin_error(&w, y, j))?;
        if finished {
            break;
        }
        evaluations += 1;
        match orbit {
            Orbit::Free => {
                for j in (0..z).filter(|&j| active[j]) {
                    roots[j].update(accel[j]);
                }
            }
            Orbit::Caged => roots[0].update(caged_g(&accel)),
        }
        if let Some((k, (at, g))) = roots.iter().enumerate().find_map(|(k, r)| match r.state {
            RootState::Unbounded(at, g) => Some((k, (at, g))),
            _ => None,
        }) {
            return Err(SteadyError::NoEquilibrium {
                ball: (orbit == Orbit::Free).then_some(k),
                at,
                accel: g,
            });
        }
        finished = !roots
            .iter()
            .enumerate()
            .any(|(k, r)| r.state == RootState::Searching && (orbit == Orbit::Caged || active[k]));
        if !finished && evaluations >= ORBIT_ITER {
            return Err(SteadyError::NotConverged { evaluations });
        }
    }
    let spin_residual = (0..z)
        .filter(|&j| active[j])
        .map(|j| norm3(&w.r[j]) / w.scale[j])
        .fold(0.0, f64::max);
    let (orbit_residual, cage_speed) = match orbit {
        Orbit::Free => (
            (0..z)
                .filter(|&j| active[j])
                .map(|j| accel[j].abs())
                .fold(0.0, f64::max)
                / (omega * omega),
            (0..z)
                .filter(|&j| active[j])
                .map(|j| y[lay.ball(j) + BW])
                .sum::<f64>()
                / n_active as f64,
        ),
        Orbit::Caged => (caged_g(&accel).abs() / (omega * omega), roots[0].x),
    };
    let unsettled = w.unsettled.iter().filter(|&&u| u).count();
    // The caged balance's slope from the final bracket turns the spread of the unsettled balls'
    // torques into a spread of the cage speed.
    let cycle_spread = match (orbit, roots[0].below, roots[0].above) {
        (Orbit::Caged, Some((xb, gb)), Some((xa, ga))) if unsettled > 0 && xa != xb => {
            let slope = ((ga - gb) / (xa - xb)).abs();
            let share: f64 = (0..z)
                .filter(|&j| w.unsettled[j])
                .map(|j| inertia[j] * w.spread[j])
                .sum::<f64>()
                / (0..z)
                    .filter(|&j| active[j])
                    .map(|j| inertia[j])
                    .sum::<f64>();
            share / slope.max(1e-300)
        }
        _ => 0.0,
    };
    let spin_residual = if unsettled > 0 {
        (0..z)
            .filter(|&j| active[j] && !w.unsettled[j])
            .map(|j| norm3(&w.r[j]) / w.scale[j])
            .fold(0.0, f64::max)
    } else {
        spin_residual
    };
    Ok(SteadyReport {
        orbit,
        balls: n_active,
        evaluations,
        rhs_evals: w.rhs,
        spin_residual,
        orbit_residual,
        cage_speed,
        unsettled,
        cycle_spread,
    })
}

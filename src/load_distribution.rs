//! L1: Jones–Harris quasi-static load distribution with centrifugal force and gyroscopic
//! friction under outer-race control (docs/model.md#l1).
//!
//! # Model
//! Ball j sits at azimuth `θ_j = 2πj/z` (convention C1 (docs/model.md#c1): `e_r(θ) = (0, −sin θ, cos θ)`, so a
//! radial load `F_z = −F_r` centres the load zone at θ = π). In the ball's (x, r) plane its
//! centre `X = (X1, X2)` is measured from the outer groove centre. The inner groove centre is at
//! `A_j = A_0 + (δ_a, δ_y e_r,y(θ_j) + δ_z e_r,z(θ_j))`, where `A_0` is the unloaded offset
//! between the groove-centre circles of [`Bearing::groove_centre`]. Then
//! - `δ_o = |X| − (f_o−½)D`, `e_o = X/|X|`, `Q_o = K_o δ_o^{3/2}`;
//! - `δ_i = |A − X| − (f_i−½)D`, `e_i = (A − X)/|A − X|`, `Q_i = K_i δ_i^{3/2}`;
//! - ball equilibrium `Q_i e_i − Q_o e_o + F_c e_r + F_g t_o = 0`, with
//!   `F_c = m_b r_b ω_c²` (`r_b` the actual ball-centre radius), `F_g = 2 J ω_c ω_R sin(−β)/D`
//!   along `t_o = (−cos α_o, sin α_o)`, and ω_c, ω_R, β from the loaded outer-race-control
//!   formulas ([`crate::fault_frequencies::outer_race_control`]) at the ball's current α_i, α_o;
//! - ring equilibrium `(F_a, F_y, F_z) = Σ_j Q_i,j (e_i,x, e_i,r e_r(θ_j))`.
//!
//! # Solver
//! 1. A first guess from the closed-form pure-axial solution ([`pure_axial`]) plus a Stribeck
//!    estimate of the radial deflection.
//! 2. The zero-speed problem is the minimum of a convex potential
//!    `Σ (2/5) K_n (|A_j| − BD)_+^{5/2} − F·δ` (series constant K_n): damped Newton on it gives a
//!    robust start whatever the load direction.
//! 3. Full problem: per ball, a 2×2 Newton on X (analytic Hertz Jacobian; the weak dependence of
//!    ω_c, ω_R, β on the angles is lagged, converging to 1e-9 N); around it, Newton on the ring
//!    unknowns with a central finite-difference Jacobian and a backtracking line search, until
//!    the force residual is ≤ 1e-6 N and the last step ≤ 1e-10 m.
//!
//! Deep-groove bearings (α0 = 0) with F_a = 0: by symmetry δ_a = 0 solves the axial equation
//! exactly (every α and hence the gyroscopic friction is zero), so the axial DOF is fixed at 0
//! and only (δ_y, δ_z) are solved; the axial stiffness is still reported. An angular-contact
//! bearing (α0 > 0) cannot carry a load with F_a ≤ 0: the inner-ring balance
//! `F_a = Σ Q_i sin α_i` would need balls beyond the groove bottom, on the low-shoulder side.
//! That is reported as [`QuasiStaticError::BeyondGeometry`].
//!
//! Physical limits (beyond them Hertz theory and the groove geometry are meaningless): a contact
//! deflection above [`MAX_DEFLECTION_OVER_D`]·D, or a loaded contact angle of magnitude above
//! 85°.

use crate::fault_frequencies::{frequencies_from_cage, outer_race_control, FaultFrequencies};
use crate::geometry::{Bearing, Race};
use crate::operating::OperatingPoint;
use serde::Serialize;
use std::f64::consts::PI;
use std::fmt;

/// Largest contact deflection accepted, as a fraction of the ball diameter (1 % of D is about
/// 100× the ISO 76 permanent-deformation criterion of 1e-4 D).
pub const MAX_DEFLECTION_OVER_D: f64 = 0.01;
/// Largest loaded contact angle magnitude accepted \[deg\] ("reaching 90°").
const MAX_CONTACT_ANGLE_DEG: f64 = 85.0;
/// Finite-difference step of the stiffness matrix's fallback (docs/model.md#l1) \[m\].
const STIFFNESS_STEP: f64 = 1e-8;
/// Convergence tolerance on ring displacements \[m\].
const TOL_DISPLACEMENT: f64 = 1e-10;
/// Convergence tolerance on the ring force balance \[N\].
const TOL_FORCE: f64 = 1e-6;

/// A ball counts as loaded when its inner contact force exceeds the force tolerance
/// (rounding of the groove geometry can leave zero-load contacts at ~1e-17 N).
pub fn is_loaded(q_inner: f64) -> bool {
    q_inner > TOL_FORCE
}

const BALL_TOL_FORCE: f64 = 1e-9;
const MAX_BALL_ITER: usize = 60;
const MAX_RING_ITER: usize = 60;
const MAX_CONVEX_ITER: usize = 200;
const FD_JACOBIAN_STEP: f64 = 1e-9;

/// Equilibrium of one ball.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BallEquilibrium {
    /// Azimuth θ_j = 2πj/z \[rad\].
    pub theta: f64,
    /// Inner contact force Q_i \[N\].
    pub q_inner: f64,
    /// Outer contact force Q_o \[N\].
    pub q_outer: f64,
    /// Inner contact angle α_i \[rad\].
    pub alpha_inner: f64,
    /// Outer contact angle α_o \[rad\].
    pub alpha_outer: f64,
    /// Inner contact deflection δ_i \[m\] (negative: gap).
    pub delta_inner: f64,
    /// Outer contact deflection δ_o \[m\] (negative: gap).
    pub delta_outer: f64,
    /// Orbital (cage) speed ω_c of this ball [rad/s].
    pub cage_speed: f64,
    /// Spin speed in the cage frame ω_R [rad/s] (negative for Ω > 0).
    pub spin_speed: f64,
    /// Attitude angle β \[rad\]: spin axis `cos β e_x − sin β e_r`.
    pub beta: f64,
    /// Ball centre relative to the outer groove centre, (axial, radial) \[m\].
    pub x: [f64; 2],
    /// Centrifugal force F_c \[N\].
    pub centrifugal: f64,
    /// Gyroscopic friction force F_g at the outer contact \[N\] (along t_o).
    pub gyro_force: f64,
}

/// Quasi-static solution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuasiStatic {
    /// Shaft speed it was solved for [rad/s].
    pub speed: f64,
    /// Inner-ring axial displacement δ_a \[m\].
    pub delta_axial: f64,
    /// Inner-ring displacement along y \[m\].
    pub delta_y: f64,
    /// Inner-ring displacement along z \[m\].
    pub delta_z: f64,
    /// One entry per ball, j = 0..z−1.
    pub balls: Vec<BallEquilibrium>,
    /// Mean ω_c over the loaded balls, weighted by their inner contact loads [rad/s] (a ball
    /// entering the load zone counts as much as it carries, so the mean has no jump there).
    pub cage_speed: f64,
    /// Mean ω_R over the loaded balls, weighted as `cage_speed` [rad/s].
    pub spin_speed: f64,
    /// Stiffness ∂F_i/∂δ_j of the ball set acting on the inner ring, in (x, y, z) [N/m], balls
    /// re-equilibrated: analytic (implicit-function theorem over the ball equilibria), equal to
    /// the central difference with h = 1e-8 m to 1e-5 (unit test); that difference is the
    /// fallback where a ball's equilibrium is singular.
    pub stiffness: [[f64; 3]; 3],
    /// Ring Newton iterations (convex start + full problem).
    pub iterations: usize,
    /// Final ring force residual, max norm \[N\].
    pub residual: f64,
}

impl QuasiStatic {
    /// Radial displacement |(δ_y, δ_z)| \[m\].
    pub fn delta_radial(&self) -> f64 {
        self.delta_y.hypot(self.delta_z)
    }

    /// Balls whose inner contact carries load (see [`is_loaded`]).
    pub fn loaded_balls(&self) -> impl Iterator<Item = &BallEquilibrium> {
        self.balls.iter().filter(|b| is_loaded(b.q_inner))
    }

    /// Outer-race-control frequencies from the mean cage and spin speeds \[Hz\]. At zero speed
    /// every frequency is zero.
    pub fn frequencies(&self, b: &Bearing) -> FaultFrequencies {
        let fs = self.speed / (2.0 * PI);
        if self.speed == 0.0 {
            return frequencies_from_cage(b, 0.0, 0.0, 0.0);
        }
        frequencies_from_cage(
            b,
            fs,
            self.cage_speed / self.speed,
            self.spin_speed / self.speed,
        )
    }

    /// Sum of the inner contact forces acting on the ring, Σ Q_i (e_i,x, e_i,r e_r(θ_j)) \[N\].
    pub fn ring_force(&self) -> [f64; 3] {
        let mut f = [0.0; 3];
        for ball in &self.balls {
            let (s, c) = ball.alpha_inner.sin_cos();
            let (st, ct) = ball.theta.sin_cos();
            f[0] += ball.q_inner * s;
            f[1] += ball.q_inner * c * (-st);
            f[2] += ball.q_inner * c * ct;
        }
        f
    }
}

/// Why the quasi-static solve failed.
#[derive(Debug, Clone, PartialEq)]
pub enum QuasiStaticError {
    /// An input is NaN or infinite; names it.
    NonFinite {
        /// Which input.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// No ball is loaded between the rings, so the ring position is undetermined.
    NoBallLoaded(String),
    /// The load exceeds what the geometry can carry.
    BeyondGeometry(String),
    /// Newton did not converge.
    NotConverged {
        /// Which loop.
        stage: &'static str,
        /// Iterations spent.
        iterations: usize,
        /// Last residual (max norm) \[N\].
        residual: f64,
    },
}

impl fmt::Display for QuasiStaticError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            QuasiStaticError::NonFinite { name, value } => {
                write!(f, "input '{name}' is not a finite number ({value})")
            }
            QuasiStaticError::NoBallLoaded(why) => write!(f, "no ball is loaded: {why}"),
            QuasiStaticError::BeyondGeometry(why) => {
                write!(f, "load beyond what the bearing geometry can carry: {why}")
            }
            QuasiStaticError::NotConverged {
                stage,
                iterations,
                residual,
            } => write!(
                f,
                "{stage} Newton did not converge in {iterations} iterations (residual {residual:.3e} N)"
            ),
        }
    }
}

impl std::error::Error for QuasiStaticError {}

/// Closed-form pure-axial solution at zero speed: every ball carries the same load.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PureAxial {
    /// Loaded contact angle α (both contacts) \[rad\].
    pub alpha: f64,
    /// Ball load Q (both contacts) \[N\].
    pub q: f64,
    /// Total ball deflection δ_i + δ_o \[m\].
    pub delta_total: f64,
    /// Inner-ring axial displacement δ_a \[m\].
    pub delta_axial: f64,
}

/// Pure-axial load `fa` > 0 at zero speed, in closed form up to one monotone 1-D root:
/// with `L = |A_0|` the unloaded groove-centre distance and α0 its direction,
/// `cos α = L cos α0 / |A|`, `δ = |A| − BD`, `Q = K_n δ^{3/2}`, and `F_a = z Q sin α`, so
/// `F_a = z K_n (L cos α0 / cos α − BD)^{3/2} sin α`, solved for α by bisection;
/// then `δ_a = L cos α0 tan α − L sin α0`.
pub fn pure_axial(b: &Bearing, fa: f64) -> Result<PureAxial, QuasiStaticError> {
    if !fa.is_finite() {
        return Err(QuasiStaticError::NonFinite {
            name: "fa",
            value: fa,
        });
    }
    if fa <= 0.0 {
        return Err(QuasiStaticError::NoBallLoaded(format!(
            "a pure axial load must be > 0 (got Fa = {fa} N)"
        )));
    }
    let g = Geometry::new(b);
    let (a0x, a0r) = (g.a0[0], g.a0[1]);
    let kn = b.k_series();
    let z = b.z as f64;
    let bd = g.ri + g.ro;
    let force = |alpha: f64| -> f64 {
        let d = (a0r / alpha.cos() - bd).max(0.0);
        z * kn * d.powf(1.5) * alpha.sin()
    };
    // force(α) is 0 until the balls touch and increases monotonically after.
    let lo0 = 0.0;
    let hi0 = MAX_CONTACT_ANGLE_DEG.to_radians();
    if force(hi0) < fa {
        return Err(QuasiStaticError::BeyondGeometry(format!(
            "Fa = {fa} N would push the contact angle past {MAX_CONTACT_ANGLE_DEG}°"
        )));
    }
    let (mut lo, mut hi) = (lo0, hi0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if force(mid) < fa {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-16 {
            break;
        }
    }
    let alpha = 0.5 * (lo + hi);
    let delta_total = a0r / alpha.cos() - bd;
    let res = PureAxial {
        alpha,
        q: kn * delta_total.max(0.0).powf(1.5),
        delta_total,
        delta_axial: a0r * alpha.tan() - a0x,
    };
    // deflection of the stiffer-constant contact is the larger share
    let share = 1.0 / (1.0 + (b.k_outer / b.k_inner).powf(2.0 / 3.0));
    let dmax = delta_total * share.max(1.0 - share);
    if dmax > MAX_DEFLECTION_OVER_D * b.d {
        return Err(QuasiStaticError::BeyondGeometry(format!(
            "Fa = {fa} N needs a contact deflection of {:.1} µm, above the limit {:.1} µm \
             ({}% of D)",
            dmax * 1e6,
            MAX_DEFLECTION_OVER_D * b.d * 1e6,
            MAX_DEFLECTION_OVER_D * 100.0
        )));
    }
    Ok(res)
}

/// Geometry constants of the quasi-static problem.
struct Geometry<'a> {
    b: &'a Bearing,
    /// Unloaded inner-minus-outer groove-centre offset (axial, radial) [m].
    a0: [f64; 2],
    /// (f_i − ½) D and (f_o − ½) D [m].
    ri: f64,
    ro: f64,
    /// Outer groove-centre circle radius [m].
    r_go: f64,
    /// (−sin θ_j, cos θ_j) per ball.
    er: Vec<[f64; 2]>,
    theta: Vec<f64>,
}

impl<'a> Geometry<'a> {
    fn new(b: &'a Bearing) -> Self {
        let (xi, rgi) = b.groove_centre(Race::Inner);
        let (xo, rgo) = b.groove_centre(Race::Outer);
        let theta: Vec<f64> = (0..b.z).map(|j| 2.0 * PI * j as f64 / b.z as f64).collect();
        Self {
            b,
            a0: [xi - xo, rgi - rgo],
            ri: (b.f_inner - 0.5) * b.d,
            ro: (b.f_outer - 0.5) * b.d,
            r_go: rgo,
            er: theta.iter().map(|t| [-t.sin(), t.cos()]).collect(),
            theta,
        }
    }

    /// Inner groove centre relative to the outer one for ball j at ring displacement u.
    fn a(&self, j: usize, u: &[f64; 3]) -> [f64; 2] {
        [
            self.a0[0] + u[0],
            self.a0[1] + u[1] * self.er[j][0] + u[2] * self.er[j][1],
        ]
    }
}

/// Stiffness K(δ^{3/2} e) derivative for a contact whose centre offset is `v`:
/// `K[1.5 δ^½ e eᵀ + δ^{3/2}/|v| (I − e eᵀ)]`.
fn hertz_jacobian(k: f64, delta: f64, v: [f64; 2], nv: f64) -> [[f64; 2]; 2] {
    if delta <= 0.0 {
        return [[0.0; 2]; 2];
    }
    let e = [v[0] / nv, v[1] / nv];
    let a = 1.5 * k * delta.sqrt();
    let c = k * delta.powf(1.5) / nv;
    let mut m = [[0.0; 2]; 2];
    for i in 0..2 {
        for l in 0..2 {
            let id = if i == l { 1.0 } else { 0.0 };
            m[i][l] = a * e[i] * e[l] + c * (id - e[i] * e[l]);
        }
    }
    m
}

/// Evaluation of one ball at centre X.
#[derive(Clone, Copy)]
struct BallEval {
    residual: [f64; 2],
    jac: [[f64; 2]; 2],
    eq: BallEquilibrium,
    e_i: [f64; 2],
}

/// Centrifugal and gyroscopic forces on a ball at centre `x` with groove offset `a`, on (x, r):
/// `F_c e_r + F_g t_o`, with (F_c, F_g, ω_c, ω_R, β).
fn speed_forces(g: &Geometry, omega: f64, a: [f64; 2], x: [f64; 2]) -> ([f64; 2], [f64; 5]) {
    let b = g.b;
    let alpha_o = x[0].atan2(x[1]);
    let alpha_i = (a[0] - x[0]).atan2(a[1] - x[1]);
    let rc = outer_race_control(b, alpha_i, alpha_o);
    // Far from equilibrium (absurd angles) the race-control formulas can blow up (g + h → 0);
    // keep them bounded there: physically 0 ≤ ω_c/Ω ≤ 1.
    let cage_ratio = if rc.cage_ratio.is_finite() {
        rc.cage_ratio.clamp(0.0, 1.0)
    } else {
        0.5
    };
    let spin_ratio = if rc.spin_ratio.is_finite() {
        rc.spin_ratio.clamp(-b.dm / b.d, b.dm / b.d)
    } else {
        0.0
    };
    let wc = cage_ratio * omega;
    let wr = spin_ratio * omega;
    let fc = b.ball_mass * (g.r_go + x[1]) * wc * wc;
    let fg = 2.0 * b.ball_inertia * wc * wr * (-rc.beta).sin() / b.d;
    let (so, co) = alpha_o.sin_cos();
    ([-fg * co, fc + fg * so], [fc, fg, wc, wr, rc.beta])
}

/// Adds the central-difference derivative (h = 1e-9 m) of the speed forces with respect to the
/// ball centre `x` (`wrt_a` false) or the groove offset `a` (true) to `m`.
fn add_speed_force_slope(
    g: &Geometry,
    omega: f64,
    a: [f64; 2],
    x: [f64; 2],
    wrt_a: bool,
    m: &mut [[f64; 2]; 2],
) {
    let h = 1e-9;
    for l in 0..2 {
        let (mut ap, mut am, mut xp, mut xm) = (a, a, x, x);
        if wrt_a {
            ap[l] += h;
            am[l] -= h;
        } else {
            xp[l] += h;
            xm[l] -= h;
        }
        let (fp, _) = speed_forces(g, omega, ap, xp);
        let (fm, _) = speed_forces(g, omega, am, xm);
        for i in 0..2 {
            m[i][l] += (fp[i] - fm[i]) / (2.0 * h);
        }
    }
}

fn eval_ball(g: &Geometry, omega: f64, theta: f64, a: [f64; 2], x: [f64; 2]) -> BallEval {
    let b = g.b;
    let nx = x[0].hypot(x[1]);
    let e_o = [x[0] / nx, x[1] / nx];
    let d_o = nx - g.ro;
    let q_o = if d_o > 0.0 {
        b.k_outer * d_o.powf(1.5)
    } else {
        0.0
    };
    let y = [a[0] - x[0], a[1] - x[1]];
    let ny = y[0].hypot(y[1]);
    let e_i = [y[0] / ny, y[1] / ny];
    let d_i = ny - g.ri;
    let q_i = if d_i > 0.0 {
        b.k_inner * d_i.powf(1.5)
    } else {
        0.0
    };
    let (extra, [fc, fg, wc, wr, beta]) = speed_forces(g, omega, a, x);
    let residual = [
        q_i * e_i[0] - q_o * e_o[0] + extra[0],
        q_i * e_i[1] - q_o * e_o[1] + extra[1],
    ];
    let ji = hertz_jacobian(b.k_inner, d_i, y, ny);
    let jo = hertz_jacobian(b.k_outer, d_o, x, nx);
    let mut jac = [[0.0; 2]; 2];
    for i in 0..2 {
        for l in 0..2 {
            jac[i][l] = -ji[i][l] - jo[i][l];
        }
    }
    if omega != 0.0 {
        // the speed forces vary slowly with X: central differences
        add_speed_force_slope(g, omega, a, x, false, &mut jac);
    }
    BallEval {
        residual,
        jac,
        e_i,
        eq: BallEquilibrium {
            theta,
            q_inner: q_i,
            q_outer: q_o,
            alpha_inner: y[0].atan2(y[1]),
            alpha_outer: x[0].atan2(x[1]),
            delta_inner: d_i,
            delta_outer: d_o,
            cage_speed: wc,
            spin_speed: wr,
            beta,
            x,
            centrifugal: fc,
            gyro_force: fg,
        },
    }
}

fn norm2(v: [f64; 2]) -> f64 {
    v[0].hypot(v[1])
}

/// Zero-speed ball position for groove-centre offset A: collinear contacts sharing the total
/// deflection so that K_i δ_i^{3/2} = K_o δ_o^{3/2}. An unloaded ball sits mid-gap.
fn zero_speed_x(g: &Geometry, a: [f64; 2]) -> [f64; 2] {
    let na = norm2(a);
    let e = [a[0] / na, a[1] / na];
    let s = na - g.ri - g.ro;
    let d_o = if s > 0.0 {
        s / (1.0 + (g.b.k_outer / g.b.k_inner).powf(2.0 / 3.0))
    } else {
        0.5 * s
    };
    [e[0] * (g.ro + d_o), e[1] * (g.ro + d_o)]
}

/// Solves the equilibrium of ball j for groove offset `a`, starting at `x0`.
fn solve_ball(
    g: &Geometry,
    omega: f64,
    j: usize,
    a: [f64; 2],
    x0: Option<[f64; 2]>,
) -> Result<BallEval, QuasiStaticError> {
    let theta = g.theta[j];
    if norm2(a) < 1e-3 * (g.ri + g.ro) {
        return Err(QuasiStaticError::BeyondGeometry(format!(
            "the groove centres of ball {j} coincide: the rings are displaced past each other"
        )));
    }
    let xz = zero_speed_x(g, a);
    if omega == 0.0 {
        // Exact: no centrifugal or gyroscopic force, the contacts are collinear.
        return Ok(eval_ball(g, omega, theta, a, xz));
    }
    // A ball whose inner contact is open rests on the outer groove bottom (α_o = 0, where
    // β = 0 and the gyroscopic friction vanishes) under its centrifugal force alone.
    let xu = unloaded_ball(g, omega, a);
    if norm2([a[0] - xu[0], a[1] - xu[1]]) - g.ri <= 0.0 {
        let ev = eval_ball(g, omega, theta, a, xu);
        if norm2(ev.residual) <= TOL_FORCE {
            return Ok(ev);
        }
    }
    // Loaded ball: Newton from the warm start, else from the zero-speed solution.
    // The start has the outer contact pressed at least by the centrifugal force, so the
    // Jacobian is regular (an open outer contact leaves only the weak speed-force terms).
    let d_c = xu[1] - g.ro;
    let mut best: Option<BallEval> = None;
    let starts = [
        x0.filter(|x| x[0].is_finite() && x[1].is_finite() && norm2(*x) > 0.5 * g.ro),
        Some(xz),
        pinched_start(g, a, d_c),
    ];
    for start in starts.into_iter().flatten() {
        let n = norm2(start);
        let r = n.max(g.ro + d_c);
        let x = [start[0] / n * r, start[1] / n * r];
        let ev = newton_ball(g, omega, j, a, x);
        let rn = norm2(ev.residual);
        if rn <= BALL_TOL_FORCE {
            return Ok(ev);
        }
        if best.is_none_or(|b| rn < norm2(b.residual)) {
            best = Some(ev);
        }
    }
    match best {
        Some(ev) if norm2(ev.residual) <= TOL_FORCE => Ok(ev),
        Some(ev) => Err(QuasiStaticError::NotConverged {
            stage: "per-ball",
            iterations: MAX_BALL_ITER,
            residual: norm2(ev.residual),
        }),
        None => Err(QuasiStaticError::NotConverged {
            stage: "per-ball",
            iterations: 0,
            residual: f64::NAN,
        }),
    }
}

/// A start with both contacts engaged by about the centrifugal deflection: the intersection of
/// the circles |X| = r_o + d and |A − X| = r_i + d nearest the outer groove bottom. It serves
/// balls that the centrifugal force pushes into an inner contact open at zero speed.
fn pinched_start(g: &Geometry, a: [f64; 2], d: f64) -> Option<[f64; 2]> {
    let (r1, r2) = (g.ro + d, g.ri + d);
    let dist = norm2(a);
    if !(dist > (r1 - r2).abs() && dist < r1 + r2) {
        return None;
    }
    let e = [a[0] / dist, a[1] / dist];
    let n = [-e[1], e[0]];
    let along = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist);
    let h = (r1 * r1 - along * along).max(0.0).sqrt();
    let p1 = [along * e[0] + h * n[0], along * e[1] + h * n[1]];
    let p2 = [along * e[0] - h * n[0], along * e[1] - h * n[1]];
    let ang = |p: [f64; 2]| p[0].atan2(p[1]).abs();
    Some(if ang(p1) <= ang(p2) { p1 } else { p2 })
}

/// Centre of a ball held by its outer contact only: α_o = 0, `K_o δ_o^{3/2} = F_c`.
fn unloaded_ball(g: &Geometry, omega: f64, a: [f64; 2]) -> [f64; 2] {
    let mut x = [0.0, g.ro];
    for _ in 0..30 {
        let (f, _) = speed_forces(g, omega, a, x);
        let d = (f[1].max(0.0) / g.b.k_outer).powf(2.0 / 3.0);
        let xn = [0.0, g.ro + d];
        let done = (xn[1] - x[1]).abs() <= 1e-17;
        x = xn;
        if done {
            break;
        }
    }
    x
}

/// Damped Newton on one ball from `x`; returns the best evaluation reached.
fn newton_ball(g: &Geometry, omega: f64, j: usize, a: [f64; 2], mut x: [f64; 2]) -> BallEval {
    let theta = g.theta[j];
    let mut ev = eval_ball(g, omega, theta, a, x);
    let mut rn = norm2(ev.residual);
    for _ in 0..MAX_BALL_ITER {
        if rn <= BALL_TOL_FORCE {
            break;
        }
        // Two Newton directions: in polar coordinates (ρ, φ) about the outer groove centre,
        // which follows the curved valley of a ball held by its outer contact alone, and in
        // Cartesian X. Each with a backtracking line search on |R|.
        let rho = norm2(x);
        let phi = x[0].atan2(x[1]);
        let e_o = [x[0] / rho, x[1] / rho];
        let dphi = [e_o[1] * rho, -e_o[0] * rho]; // ∂X/∂φ
        let m = ev.jac;
        let mp = [
            [
                m[0][0] * e_o[0] + m[0][1] * e_o[1],
                m[0][0] * dphi[0] + m[0][1] * dphi[1],
            ],
            [
                m[1][0] * e_o[0] + m[1][1] * e_o[1],
                m[1][0] * dphi[0] + m[1][1] * dphi[1],
            ],
        ];
        let mut moved = false;
        for polar in [true, false] {
            let p = match solve2(if polar { mp } else { m }, ev.residual) {
                Some(p) => p,
                None => continue,
            };
            // cap the step: 10 % of the groove offset, 0.2 rad
            let cap = if polar {
                (0.1 * g.ro / p[0].abs().max(1e-300))
                    .min(0.2 / p[1].abs().max(1e-300))
                    .min(1.0)
            } else {
                (0.1 * g.ro / norm2(p).max(1e-300)).min(1.0)
            };
            let mut lambda = cap;
            for _ in 0..40 {
                let xt = if polar {
                    let (r, f) = (rho + lambda * p[0], phi + lambda * p[1]);
                    [r * f.sin(), r * f.cos()]
                } else {
                    [x[0] + lambda * p[0], x[1] + lambda * p[1]]
                };
                let et = eval_ball(g, omega, theta, a, xt);
                let rt = norm2(et.residual);
                if rt.is_finite() && rt < rn {
                    x = xt;
                    ev = et;
                    rn = rt;
                    moved = true;
                    break;
                }
                lambda *= 0.5;
            }
            if moved {
                break;
            }
        }
        if !moved {
            break;
        }
    }
    ev
}

/// Newton step of a 2×2 system: solves `m p = −r`; None when singular.
fn solve2(m: [[f64; 2]; 2], r: [f64; 2]) -> Option<[f64; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let scale = (m[0][0].abs() + m[0][1].abs()) * (m[1][0].abs() + m[1][1].abs());
    if det.is_nan() || det.abs() <= 1e-15 * scale {
        return None;
    }
    let p = [
        -(m[1][1] * r[0] - m[0][1] * r[1]) / det,
        -(-m[1][0] * r[0] + m[0][0] * r[1]) / det,
    ];
    (p[0].is_finite() && p[1].is_finite()).then_some(p)
}

/// All balls at ring displacement `u`; `xs` is the warm start and is updated.
struct RingEval {
    force: [f64; 3],
    balls: Vec<BallEval>,
}

fn eval_ring(
    g: &Geometry,
    omega: f64,
    u: &[f64; 3],
    xs: &[[f64; 2]],
) -> Result<RingEval, QuasiStaticError> {
    let mut force = [0.0; 3];
    let mut balls = Vec::with_capacity(g.theta.len());
    for j in 0..g.theta.len() {
        let a = g.a(j, u);
        let x0 = xs.get(j).copied();
        let ev = solve_ball(g, omega, j, a, x0)?;
        let q = ev.eq.q_inner;
        force[0] += q * ev.e_i[0];
        force[1] += q * ev.e_i[1] * g.er[j][0];
        force[2] += q * ev.e_i[1] * g.er[j][1];
        balls.push(ev);
    }
    Ok(RingEval { force, balls })
}

fn inf_norm3(v: &[f64; 3]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// Solves `m p = rhs` on the active DOFs (inactive: p = 0), Gaussian elimination with partial
/// pivoting and a tiny Levenberg regularisation when the matrix is (nearly) singular.
fn solve3(m: [[f64; 3]; 3], rhs: [f64; 3], active: [bool; 3]) -> Option<[f64; 3]> {
    let scale = (0..3)
        .filter(|&i| active[i])
        .fold(0.0_f64, |s, i| s.max(m[i][i].abs()));
    if scale <= 0.0 || !scale.is_finite() {
        return None;
    }
    let attempt = |mu: f64| -> Option<[f64; 3]> {
        let mut a = [[0.0; 4]; 3];
        for i in 0..3 {
            for l in 0..3 {
                a[i][l] = if active[i] && active[l] { m[i][l] } else { 0.0 };
            }
            if active[i] {
                a[i][i] += mu;
                a[i][3] = rhs[i];
            } else {
                a[i][i] = 1.0;
                a[i][3] = 0.0;
            }
        }
        for c in 0..3 {
            let piv = (c..3).max_by(|&p, &q| a[p][c].abs().total_cmp(&a[q][c].abs()))?;
            a.swap(c, piv);
            let pv = a[c][c];
            if pv.abs() <= 1e-13 * scale.max(1.0) || !pv.is_finite() {
                return None;
            }
            for r in 0..3 {
                if r != c {
                    let f = a[r][c] / pv;
                    let row_c = a[c];
                    for (v, w) in a[r].iter_mut().zip(row_c.iter()).skip(c) {
                        *v -= f * w;
                    }
                }
            }
        }
        let p = [a[0][3] / a[0][0], a[1][3] / a[1][1], a[2][3] / a[2][2]];
        p.iter().all(|v| v.is_finite()).then_some(p)
    };
    attempt(0.0).or_else(|| attempt(1e-9 * scale))
}

/// Zero-speed convex start: minimises Σ (2/5) K_n s_+^{5/2} − F·u.
fn convex_start(
    g: &Geometry,
    f_ext: [f64; 3],
    mut u: [f64; 3],
    active: [bool; 3],
    limit: f64,
) -> Result<([f64; 3], usize), QuasiStaticError> {
    let kn = g.b.k_series();
    let bd = g.ri + g.ro;
    let z = g.theta.len();
    // potential, gradient, Hessian
    let eval = |u: &[f64; 3]| -> (f64, [f64; 3], [[f64; 3]; 3], bool) {
        let mut phi = -(f_ext[0] * u[0] + f_ext[1] * u[1] + f_ext[2] * u[2]);
        let mut grad = [-f_ext[0], -f_ext[1], -f_ext[2]];
        let mut h = [[0.0; 3]; 3];
        let mut any = false;
        for j in 0..z {
            let a = g.a(j, u);
            let na = norm2(a);
            let s = na - bd;
            if s <= 0.0 {
                continue;
            }
            any = true;
            phi += 0.4 * kn * s.powf(2.5);
            let q = kn * s.powf(1.5);
            let e = [a[0] / na, a[1] / na];
            // P = ∂A/∂u: rows (1,0,0) and (0, er_y, er_z)
            let p = [[1.0, 0.0, 0.0], [0.0, g.er[j][0], g.er[j][1]]];
            let hj = hertz_jacobian(kn, s, a, na);
            for c in 0..3 {
                grad[c] += q * (e[0] * p[0][c] + e[1] * p[1][c]);
            }
            add_ring_congruence(g.er[j], hj, &mut h);
        }
        for c in 0..3 {
            if !active[c] {
                grad[c] = 0.0;
            }
        }
        (phi, grad, h, any)
    };
    let fnorm = inf_norm3(&f_ext).max(1.0);
    let mut it = 0;
    let (mut phi, mut grad, mut h, mut any) = eval(&u);
    while it < MAX_CONVEX_ITER {
        it += 1;
        if inf_norm3(&grad) <= 1e-9 * fnorm {
            break;
        }
        let p = if any {
            solve3(h, [-grad[0], -grad[1], -grad[2]], active)
        } else {
            None
        };
        let p = match p {
            Some(p) => p,
            None => {
                // nothing loaded yet: move towards the load
                let n = inf_norm3(&grad).max(1e-300);
                [
                    -grad[0] / n * 1e-6,
                    -grad[1] / n * 1e-6,
                    -grad[2] / n * 1e-6,
                ]
            }
        };
        let slope: f64 = (0..3).map(|c| grad[c] * p[c]).sum();
        let mut lambda = 1.0;
        let mut moved = false;
        for _ in 0..60 {
            let ut = [
                u[0] + lambda * p[0],
                u[1] + lambda * p[1],
                u[2] + lambda * p[2],
            ];
            let (pt, gt, ht, at) = eval(&ut);
            if pt.is_finite() && pt <= phi + 1e-4 * lambda * slope.min(0.0) {
                u = ut;
                phi = pt;
                grad = gt;
                h = ht;
                any = at;
                moved = true;
                break;
            }
            lambda *= 0.5;
        }
        if inf_norm3(&u) > limit {
            return Err(QuasiStaticError::BeyondGeometry(format!(
                "no equilibrium found before the ring displacement passed {:.1} µm",
                limit * 1e6
            )));
        }
        let step = lambda * inf_norm3(&p);
        if !moved || step < 1e-14 {
            break;
        }
    }
    Ok((u, it))
}

fn check_input(case: &OperatingPoint) -> Result<(), QuasiStaticError> {
    for (name, value) in [
        ("speed", case.shaft_speed),
        ("fa", case.fx),
        ("fy", case.fy),
        ("fz", case.fz),
    ] {
        if !value.is_finite() {
            return Err(QuasiStaticError::NonFinite { name, value });
        }
    }
    Ok(())
}

/// Solves the Jones–Harris quasi-static problem for a load case (see the module docs).
pub fn solve(b: &Bearing, case: &OperatingPoint) -> Result<QuasiStatic, QuasiStaticError> {
    solve_mounted(b, case, None)
}

/// Solves the quasi-static problem of an axially located inner ring: its axial displacement is
/// held at `delta_a` \[m\] (from the unloaded, centred position; positive along +x, the
/// direction an axial load Fa > 0 pushes it) and only the radial loads `case.fy`, `case.fz`
/// act (`case.fx` is not used). The axial force the balls then need from the ring's location
/// is the solution's [`QuasiStatic::ring_force`]`[0]`: this is how a single angular-contact
/// bearing carries a pure radial load when mounted.
pub fn solve_located(
    b: &Bearing,
    case: &OperatingPoint,
    delta_a: f64,
) -> Result<QuasiStatic, QuasiStaticError> {
    if !delta_a.is_finite() {
        return Err(QuasiStaticError::NonFinite {
            name: "axial displacement",
            value: delta_a,
        });
    }
    solve_mounted(b, case, Some(delta_a))
}

fn solve_mounted(
    b: &Bearing,
    case: &OperatingPoint,
    held: Option<f64>,
) -> Result<QuasiStatic, QuasiStaticError> {
    check_input(case)?;
    let g = Geometry::new(b);
    let omega = case.shaft_speed;
    let f_ext = [case.fx, case.fy, case.fz];
    let fr = case.fy.hypot(case.fz);
    let deep_groove = b.alpha0 == 0.0;
    if held.is_none() && b.alpha0 > 0.0 && case.fx <= 0.0 && (fr > 0.0 || case.fx < 0.0) {
        return Err(QuasiStaticError::BeyondGeometry(format!(
            "an angular-contact bearing (α0 = {:.2}°) needs an axial load Fa > 0 to carry a \
             load (Fa = {} N, Fr = {} N): its inner-ring balance Fa = Σ Q sin α would push the \
             balls past the groove bottom onto the low shoulder (an axially located ring \
             carries it: scene [mounting] axial = \"located\", FMU ring.axial = 1 or 2, \
             raceway static --axial-offset)",
            b.alpha0.to_degrees(),
            case.fx,
            fr
        )));
    }
    let active = [
        held.is_none() && !(deep_groove && case.fx == 0.0),
        true,
        true,
    ];
    let limit = 5.0 * MAX_DEFLECTION_OVER_D * b.d + (g.ri + g.ro);

    // First guess: closed-form pure axial, plus a Stribeck radial deflection.
    let mut u0 = [0.0; 3];
    if let Some(d) = held {
        u0[0] = d;
    } else if case.fx > 0.0 {
        u0[0] = pure_axial(b, case.fx)?.delta_axial;
    }
    if fr > 0.0 {
        let qmax = 5.0 * fr / (b.z as f64 * b.alpha0.cos().max(0.1));
        let d = (qmax / b.k_series()).powf(2.0 / 3.0) * 0.5;
        u0[1] = case.fy / fr * d;
        u0[2] = case.fz / fr * d;
    }
    let (mut u, it_convex) = convex_start(&g, f_ext, u0, active, limit)?;
    // The deflection limit, checked on the zero-speed solution first (a crushing load can
    // leave the per-ball problems at speed without a meaningful solution).
    let share = 1.0 / (1.0 + (b.k_outer / b.k_inner).powf(2.0 / 3.0));
    let share = share.max(1.0 - share);
    let s_max = (0..b.z)
        .map(|j| norm2(g.a(j, &u)) - g.ri - g.ro)
        .fold(0.0_f64, f64::max);
    let dlim = MAX_DEFLECTION_OVER_D * b.d;
    if s_max * share > dlim {
        return Err(QuasiStaticError::BeyondGeometry(format!(
            "the load needs a contact deflection of {:.1} µm (at zero speed), above the limit \
             {:.1} µm ({}% of D)",
            s_max * share * 1e6,
            dlim * 1e6,
            MAX_DEFLECTION_OVER_D * 100.0
        )));
    }

    // Full problem.
    let z = b.z;
    let mut xs: Vec<[f64; 2]> = (0..z).map(|j| zero_speed_x(&g, g.a(j, &u))).collect();
    let mut re = eval_ring(&g, omega, &u, &xs)?;
    let resid = |f: &[f64; 3]| -> [f64; 3] {
        let mut r = [f[0] - f_ext[0], f[1] - f_ext[1], f[2] - f_ext[2]];
        for c in 0..3 {
            if !active[c] {
                r[c] = 0.0;
            }
        }
        r
    };
    let mut r = resid(&re.force);
    let mut rn = inf_norm3(&r);
    let mut last_step = f64::INFINITY;
    let mut it = 0;
    let mut converged = false;
    // Step of the ring toward the load while no inner contact carries [m].
    let mut free = 1e-7;
    while it < MAX_RING_ITER {
        if rn <= TOL_FORCE && last_step <= TOL_DISPLACEMENT {
            converged = true;
            break;
        }
        it += 1;
        xs = re.balls.iter().map(|e| e.eq.x).collect();
        let any_loaded = re.balls.iter().any(|e| e.eq.q_inner > 0.0);
        if !any_loaded && rn > 0.0 {
            // No inner contact closed yet (a centrifugal gap): the residual cannot fall before
            // one closes, so the ring moves toward the load in doubling steps, each kept as it
            // is, until a contact carries (the Newton steps below then take over).
            let n = rn.max(1e-300);
            let ut = [
                u[0] - free * r[0] / n,
                u[1] - free * r[1] / n,
                u[2] - free * r[2] / n,
            ];
            match eval_ring(&g, omega, &ut, &xs) {
                Ok(et) => {
                    u = ut;
                    r = resid(&et.force);
                    rn = inf_norm3(&r);
                    re = et;
                    last_step = free;
                    free *= 2.0;
                }
                Err(_) => free *= 0.5,
            }
            if inf_norm3(&u) > limit {
                return Err(QuasiStaticError::BeyondGeometry(format!(
                    "no equilibrium found before the ring displacement passed {:.1} µm",
                    limit * 1e6
                )));
            }
            continue;
        }
        let p = if any_loaded {
            let jac = ring_jacobian(&g, omega, &u, &re.balls, &xs, FD_JACOBIAN_STEP, active)?;
            solve3(jac, [-r[0], -r[1], -r[2]], active)
        } else {
            None
        };
        let Some(p) = p else { break };
        let mut lambda = 1.0;
        let mut accepted = false;
        for _ in 0..40 {
            let ut = [
                u[0] + lambda * p[0],
                u[1] + lambda * p[1],
                u[2] + lambda * p[2],
            ];
            // a trial point where some ball has no solution is simply rejected
            let Ok(et) = eval_ring(&g, omega, &ut, &xs) else {
                lambda *= 0.5;
                continue;
            };
            let rt = resid(&et.force);
            let rtn = inf_norm3(&rt);
            if rtn < rn || (rtn <= TOL_FORCE && rn <= TOL_FORCE) {
                u = ut;
                re = et;
                r = rt;
                rn = rtn;
                accepted = true;
                break;
            }
            lambda *= 0.5;
        }
        last_step = lambda * inf_norm3(&p);
        if !accepted {
            if rn <= TOL_FORCE {
                converged = true;
            }
            break;
        }
        if inf_norm3(&u) > limit {
            return Err(QuasiStaticError::BeyondGeometry(format!(
                "no equilibrium found before the ring displacement passed {:.1} µm",
                limit * 1e6
            )));
        }
    }
    if !converged && rn <= TOL_FORCE && last_step <= TOL_DISPLACEMENT {
        converged = true;
    }
    let loaded: Vec<&BallEquilibrium> = re
        .balls
        .iter()
        .map(|e| &e.eq)
        .filter(|e| is_loaded(e.q_inner))
        .collect();
    if loaded.is_empty() {
        return Err(QuasiStaticError::NoBallLoaded(
            if inf_norm3(&f_ext) == 0.0 {
                "zero external load: the rings are free within the balls' play".into()
            } else {
                "no inner contact closes under this load".into()
            },
        ));
    }
    if !converged {
        return Err(QuasiStaticError::NotConverged {
            stage: "ring",
            iterations: it + it_convex,
            residual: rn,
        });
    }
    check_limits(b, &re)?;

    let (cage_speed, spin_speed) = load_weighted_rates(&loaded);
    xs = re.balls.iter().map(|e| e.eq.x).collect();
    let stiffness = ring_jacobian(&g, omega, &u, &re.balls, &xs, STIFFNESS_STEP, [true; 3])?;
    Ok(QuasiStatic {
        speed: omega,
        delta_axial: u[0],
        delta_y: u[1],
        delta_z: u[2],
        balls: re.balls.iter().map(|e| e.eq).collect(),
        cage_speed,
        spin_speed,
        stiffness,
        iterations: it + it_convex,
        residual: rn,
    })
}

/// Means of ω_c and ω_R over `loaded`, weighted by the inner contact loads ((0, 0) if none).
fn load_weighted_rates(loaded: &[&BallEquilibrium]) -> (f64, f64) {
    let (q, c, s) = loaded.iter().fold((0.0, 0.0, 0.0), |(q, c, s), e| {
        (
            q + e.q_inner,
            c + e.q_inner * e.cage_speed,
            s + e.q_inner * e.spin_speed,
        )
    });
    if q > 0.0 {
        (c / q, s / q)
    } else {
        (0.0, 0.0)
    }
}

fn check_limits(b: &Bearing, re: &RingEval) -> Result<(), QuasiStaticError> {
    let dlim = MAX_DEFLECTION_OVER_D * b.d;
    let alim = MAX_CONTACT_ANGLE_DEG.to_radians();
    for (j, e) in re.balls.iter().map(|e| &e.eq).enumerate() {
        let dmax = e.delta_inner.max(e.delta_outer);
        if dmax > dlim {
            return Err(QuasiStaticError::BeyondGeometry(format!(
                "ball {j} has a contact deflection of {:.1} µm, above the limit {:.1} µm \
                 ({}% of D)",
                dmax * 1e6,
                dlim * 1e6,
                MAX_DEFLECTION_OVER_D * 100.0
            )));
        }
        if is_loaded(e.q_inner) {
            for (name, a) in [("inner", e.alpha_inner), ("outer", e.alpha_outer)] {
                if a.abs() > alim {
                    return Err(QuasiStaticError::BeyondGeometry(format!(
                        "ball {j}: {name} contact angle {:.1}° beyond ±{MAX_CONTACT_ANGLE_DEG}°",
                        a.to_degrees()
                    )));
                }
                if b.alpha0 > 0.0 && a <= 0.0 {
                    return Err(QuasiStaticError::BeyondGeometry(format!(
                        "ball {j}: {name} contact angle {:.2}° crosses the groove bottom of an \
                         angular-contact bearing (more axial load Fa is needed)",
                        a.to_degrees()
                    )));
                }
            }
        }
    }
    Ok(())
}

/// Jacobian ∂F/∂u of the ring force at the converged ball equilibria `balls` (from
/// [`eval_ring`] at `u`), analytic by the implicit-function theorem: each ball's inner contact
/// force f(y), y = a − x, with the ball centre x following a through its equilibrium
/// R(x, a) = 0, so df/da = J_i (I + R_x⁻¹ R_a), J_i = ∂f/∂y the Hertz Jacobian and R_a = J_i plus
/// the speed forces' derivative in a (central differences, as in [`eval_ball`]). Mapped to the
/// ring's (axial, y, z) through a(u) and the radial direction e_r of the ball. This is what the
/// central difference of [`eval_ring`] approximates, at one ring evaluation instead of six.
/// None when a ball's R_x is singular or a ball did not converge (the caller then differences).
fn analytic_jacobian(
    g: &Geometry,
    omega: f64,
    u: &[f64; 3],
    balls: &[BallEval],
) -> Option<[[f64; 3]; 3]> {
    let b = g.b;
    let mut jac = [[0.0; 3]; 3];
    for (j, ev) in balls.iter().enumerate() {
        if norm2(ev.residual) > BALL_TOL_FORCE {
            return None;
        }
        let d_i = ev.eq.delta_inner;
        if d_i <= 0.0 {
            continue;
        }
        let a = g.a(j, u);
        let x = ev.eq.x;
        let y = [a[0] - x[0], a[1] - x[1]];
        let ji = hertz_jacobian(b.k_inner, d_i, y, norm2(y));
        // R_a = ∂R/∂a: the inner contact force q_i e_i(y) and the speed forces.
        let mut ra = ji;
        if omega != 0.0 {
            add_speed_force_slope(g, omega, a, x, true, &mut ra);
        }
        // dy/da = I + R_x⁻¹ R_a (solve2 returns −R_x⁻¹ r).
        let mut dyda = [[1.0, 0.0], [0.0, 1.0]];
        for l in 0..2 {
            let p = solve2(ev.jac, [ra[0][l], ra[1][l]])?;
            dyda[0][l] -= p[0];
            dyda[1][l] -= p[1];
        }
        let mut dfda = [[0.0; 2]; 2];
        for i in 0..2 {
            for l in 0..2 {
                dfda[i][l] = ji[i][0] * dyda[0][l] + ji[i][1] * dyda[1][l];
            }
        }
        // F = Pᵀ f and a = a0 + P u.
        add_ring_congruence(g.er[j], dfda, &mut jac);
    }
    jac.iter().flatten().all(|v| v.is_finite()).then_some(jac)
}

/// Adds Pᵀ m P to `out`, with P = ∂a/∂u = [[1, 0, 0], [0, e_r0, e_r1]] the map from the ring
/// displacement (axial, y, z) to a ball's groove-centre offset in its (axial, radial) plane.
fn add_ring_congruence(er: [f64; 2], m: [[f64; 2]; 2], out: &mut [[f64; 3]; 3]) {
    let p = [[1.0, 0.0, 0.0], [0.0, er[0], er[1]]];
    for c in 0..3 {
        for d in 0..3 {
            let mut acc = 0.0;
            for k in 0..2 {
                for l in 0..2 {
                    acc += p[k][c] * m[k][l] * p[l][d];
                }
            }
            out[c][d] += acc;
        }
    }
}

/// ∂F_ring/∂u at `u`, whose ring evaluation gave `balls` (warm start `xs`): analytic
/// ([`analytic_jacobian`]), else the central difference with step `h` over the `active` DOFs.
fn ring_jacobian(
    g: &Geometry,
    omega: f64,
    u: &[f64; 3],
    balls: &[BallEval],
    xs: &[[f64; 2]],
    h: f64,
    active: [bool; 3],
) -> Result<[[f64; 3]; 3], QuasiStaticError> {
    match analytic_jacobian(g, omega, u, balls) {
        Some(j) => Ok(j),
        None => fd_jacobian(g, omega, u, xs, h, active),
    }
}

/// Central-difference Jacobian ∂F_ring/∂u (columns of inactive DOFs are zero).
fn fd_jacobian(
    g: &Geometry,
    omega: f64,
    u: &[f64; 3],
    xs: &[[f64; 2]],
    h: f64,
    active: [bool; 3],
) -> Result<[[f64; 3]; 3], QuasiStaticError> {
    let mut jac = [[0.0; 3]; 3];
    for c in 0..3 {
        if !active[c] {
            continue;
        }
        let mut up = *u;
        let mut um = *u;
        up[c] += h;
        um[c] -= h;
        let fp = eval_ring(g, omega, &up, xs)?.force;
        let fm = eval_ring(g, omega, &um, xs)?.force;
        for r in 0..3 {
            jac[r][c] = (fp[r] - fm[r]) / (2.0 * h);
        }
    }
    Ok(jac)
}

/// Displacement-controlled quasi-static state (coupling mode "motion" at L0/L1): the inner ring
/// held at displacement `u` = (δ_a, δ_y, δ_z) relative to the outer ring \[m\], every ball in its
/// own equilibrium (contacts, centrifugal and gyroscopic forces) as in [`solve`]. The result's
/// [`QuasiStatic::ring_force`] is the load the ring needs to stay at `u` (the bearing pushes the
/// shaft with minus that), `stiffness` its Jacobian (analytic, see `analytic_jacobian`; the
/// central difference with h = [`STIFFNESS_STEP`] where a ball's equilibrium is singular).
/// `warm` holds the ball centres of a nearby solve (empty: zero-speed start); it is updated.
pub(crate) fn displacement_controlled(
    b: &Bearing,
    speed: f64,
    u: [f64; 3],
    warm: &mut Vec<[f64; 2]>,
) -> Result<QuasiStatic, QuasiStaticError> {
    check_input(&OperatingPoint {
        shaft_speed: speed,
        fx: u[0],
        fy: u[1],
        fz: u[2],
    })?;
    let g = Geometry::new(b);
    if warm.len() != b.z {
        *warm = (0..b.z).map(|j| zero_speed_x(&g, g.a(j, &u))).collect();
    }
    let re = eval_ring(&g, speed, &u, warm)?;
    *warm = re.balls.iter().map(|e| e.eq.x).collect();
    let stiffness = ring_jacobian(&g, speed, &u, &re.balls, warm, STIFFNESS_STEP, [true; 3])?;
    let loaded: Vec<&BallEquilibrium> = re
        .balls
        .iter()
        .map(|e| &e.eq)
        .filter(|e| is_loaded(e.q_inner))
        .collect();
    let (cage_speed, spin_speed) = load_weighted_rates(&loaded);
    Ok(QuasiStatic {
        speed,
        delta_axial: u[0],
        delta_y: u[1],
        delta_z: u[2],
        cage_speed,
        spin_speed,
        balls: re.balls.iter().map(|e| e.eq).collect(),
        stiffness,
        iterations: 0,
        residual: 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn analytic_ring_jacobian_equals_central_differences() {
        // The implicit-function Jacobian against the central difference of the re-solved ring
        // (the definition), at converged L1 states: pure axial, combined, speed 0 and 9900 rpm,
        // and a 9-ball deep-groove-like bearing under pure radial load.
        for (preset, fa, fr, rpm) in [
            ("niu2014-table1", 4000.0, 0.0, 0.0),
            ("niu2014-table1", 4000.0, 1000.0, 9900.0),
            ("niu2014-table1", 3000.0, 2500.0, 15000.0),
            ("cwru-6205-de", 0.0, 2000.0, 1797.0),
            ("cwru-6205-de", 300.0, 1500.0, 1797.0),
        ] {
            let b = Bearing::load(preset).unwrap();
            let case = OperatingPoint::from_rpm(rpm, fa, fr);
            let qs = solve(&b, &case).unwrap();
            let g = Geometry::new(&b);
            let u = [qs.delta_axial, qs.delta_y, qs.delta_z];
            let xs: Vec<[f64; 2]> = qs.balls.iter().map(|e| e.x).collect();
            let re = eval_ring(&g, case.shaft_speed, &u, &xs).unwrap();
            let an = analytic_jacobian(&g, case.shaft_speed, &u, &re.balls).expect("analytic");
            let fd = fd_jacobian(&g, case.shaft_speed, &u, &xs, STIFFNESS_STEP, [true; 3]).unwrap();
            let scale = fd.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
            for r in 0..3 {
                for c in 0..3 {
                    assert!(
                        (an[r][c] - fd[r][c]).abs() < 1e-5 * scale,
                        "{preset} Fa {fa} Fr {fr} {rpm} rpm: K[{r}][{c}] {} vs {} (scale {scale:e})",
                        an[r][c],
                        fd[r][c]
                    );
                }
            }
        }
    }
}

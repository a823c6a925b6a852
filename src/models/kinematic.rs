//! L0s: the kinematic signal generator (docs/model.md#l0 "L0s").
//!
//! States: the cage angle θ_c and the shaft angle φ (constant rates between input changes, so
//! every explicit Runge–Kutta method integrates them exactly and takes few steps). The cage speed
//! is the quasi-static level's (a cage-to-shaft ratio re-solved when the inputs move by more
//! than 2 %, times the current shaft speed).
//!
//! Fault events. The fault phase ψ counts ball passes over the spall: ψ = z(θ_start + θ_c − θ0)/2π
//! for an outer-race spall and ψ = z(θ0 + φ − θ_start − θ_c)/2π for an inner-race spall (both
//! increase), so the impulse train has the BPFO or BPFI of the L1 cage speed. Pass n enters the
//! spall at ψ = n + ε_n − h and leaves it at ψ = n + ε_n + h, where h = θ_e z/2π is the spall's
//! half-angle in ball spacings and ε_n the seeded slip jitter (σ = `lumped.slip_jitter` ball
//! spacings, i.e. 0.5–2 % for 0.005–0.02; deterministic in `lumped.seed` and n, clipped to ±0.45).
//! The entries and exits are registered at their exact times (ψ is linear in t between input
//! changes) when the outputs or an input change reach them, so they need no integrator stops.
//! The simulation has them registered before every output it takes ([`Model::catch_up`]), each
//! pass one unit of the step budget (`solver.max_steps`): an absurd cage speed or an enormous
//! communication step is an error naming the passes it would take, not an endless loop.
//!
//! Impulse shape and resonance (the documented choice). Each pass is a rectangular dip of the
//! contact force on the pedestal: the ball loses ΔQ = Q(θ)·[1 − (1 − g/δ)^1.5] of its load
//! (δ = (Q/K_n)^(2/3) its static approach, g the spall's largest drop) at the entry and regains it
//! at the exit. The load Q(θ) at the spall's current azimuth θ (measured from the load direction)
//! follows the load zone q(θ) = q_max[1 − (1 − cos θ)/(2ε)]^1.5 with q_max and ε from L1: constant
//! for an outer-race spall, modulated at the shaft rate for an inner-race spall. Each step of
//! force drives the linear 2-DOF system of the lumped level in z: the inner ring (with half the
//! balls) on L1's radial bearing stiffness K_zz against the pedestal (with the outer ring and
//! the other half of the balls) on k_p, c_p, with the contact damping c_br of the loaded balls.
//! Its two modes are the pedestal mode (fel, ≈ 0.6 kHz) and the ring-on-bearing mode (feh,
//! ≈ 5 kHz); the pedestal acceleration is the closed-form modal step response, so `pedestal.a.z`
//! is in m/s² like at the other levels. The responses of all past steps are kept per mode as one
//! complex amplitude (O(1) work per output); after an input change that re-solves L1, earlier
//! responses ring out with the new modes. The optional `[lumped] resonator` is not modelled at
//! this level. A healthy scene has no events.
//!
//! A spall on a ball (docs/model.md#ball-spall) turns with the kinematic spin of pure rolling on
//! the outer race, ψ = θ0 + (dm/D)(1 + γ0)·θ_c, and meets the outer race at ψ ≡ π/2 and the inner
//! at ψ ≡ −π/2: its fault phase counts those meetings, ψ_f = (ψ − π/2)/π (even passes at the outer
//! race, odd ones at the inner), at 2 × BSF, with the half-width (w_d/D)/π and the largest drop of
//! a raceway spall of its size on the race it meets. The load lost is the load zone's at the
//! spalled ball's azimuth (modulated at the cage rate), and the force step acts along that
//! azimuth.
//!
//! Static outputs (see [`super::quasi_static`]): everything except `pedestal.a.z`,
//! `pedestal.v.z`, `pedestal.z` (static deflection + modal response) and the contact force of the
//! ball inside the spall (reduced by ΔQ) is L1's static value.

use super::quasi_static::{static_outputs, L1Table};
use super::Model;
use crate::ball_spall::BallSpall;
use crate::defect::{Defect, SpallSummary};
use crate::geometry::{Bearing, Race};
use crate::models::{out, SimError};
use crate::operating::OperatingPoint;
use crate::scene::Scene;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

const CAGE: usize = 0;
const SHAFT: usize = 1;

/// One mode of the 2-DOF ring/pedestal system.
#[derive(Debug, Clone, Copy)]
struct Mode {
    /// Undamped circular frequency [rad/s].
    omega: f64,
    /// Decay rate ζω [1/s].
    sigma: f64,
    /// Damped circular frequency [rad/s].
    omega_d: f64,
    /// Pedestal-z response per newton of force pair (−F on the ring, +F on the pedestal):
    /// φ_p · φᵀ(−1, 1), with φ mass-normalised [1/kg].
    gain: f64,
}

/// The scene's one spall as the generator sees it.
#[derive(Debug, Clone, Copy)]
enum Fault {
    /// On a race: its place, extent and drop.
    Race(SpallSummary),
    /// On a ball (the module documentation).
    Ball(BallFault),
}

/// A spall on a ball as the generator sees it (the module documentation).
#[derive(Debug, Clone, Copy)]
struct BallFault {
    /// The ball's index from 0.
    ball: usize,
    /// Spin angle at the start, from midway between the contacts \[rad\].
    theta0: f64,
    /// Spin angle per cage angle, (dm/D)(1 + γ0).
    spin_per_orbit: f64,
    /// Half the spall's extent in spin angle \[rad\].
    half: f64,
    /// Largest drop at the (outer, inner) race \[m\].
    drop: [f64; 2],
}

/// The kinematic model.
#[derive(Clone)]
pub struct KinematicModel {
    bearing: Bearing,
    table: L1Table,
    inputs: OperatingPoint,
    /// The spall, if any.
    fault: Option<Fault>,
    theta_start: f64,
    /// Series Hertz constant of a ball [N/m^1.5].
    k_series: f64,
    jitter: f64,
    seed: u64,
    modes: [Mode; 2],
    /// Next pass whose entry / exit is still to come.
    next_entry: i64,
    next_exit: i64,
    /// Per mode, the superposed step responses as one complex amplitude: C = Σ_k g_k e^{λ(t_ref − t_k)}
    /// (re, im) at t_ref, and the static sum S = Σ_k g_k (g_k = modal gain × step force).
    acc: [(f64, f64, f64); 2],
    /// Time of the last force step [s].
    t_ref: f64,
    /// Load lost by the ball of the current pass (set at the entry, undone at the exit).
    dip: f64,
    /// Fault phases of the next entry and exit (cached: the slip jitter costs a log and a cos).
    entry_thr: f64,
    exit_thr: f64,
    /// The modal amplitudes at the last output time, for equally spaced outputs.
    memo: Memo,
    /// Most passes registered in one call from the outputs, a mode update or an input change
    /// (the scene's `solver.max_steps`; the simulation's own catch-up is budgeted per advance).
    max_passes: u64,
}

/// Outputs usually come at equally spaced times t_k: the superposed response then advances by
/// one complex multiplication per mode, C(t_k) = C(t_{k−1}) e^{λh} (1 + λδ) with δ the
/// difference between this spacing and the cached h (|δ| ≤ 1e-9 h, so the neglected (λδ)²/2 is
/// below 1e-18), instead of an exp and a sin_cos per mode. Any force step or state change
/// invalidates it, and it is rebuilt from the exact expression every 1024 reuses so that
/// rounding cannot accumulate beyond about 1e-13 relative.
#[derive(Debug, Clone, Copy, Default)]
struct Memo {
    valid: bool,
    /// Time of `c` [s].
    t: f64,
    /// Cached spacing h [s] and e^{λh} per mode (re, im).
    h: f64,
    f: [(f64, f64); 2],
    /// Per mode C(t) (re, im): the response without the exact-expression rotation.
    c: [(f64, f64); 2],
    reuses: u32,
}

impl KinematicModel {
    /// Builds the generator for a scene (L1 at the scene's inputs).
    pub fn new(
        scene: &Scene,
        bearing: &Bearing,
        inputs: &OperatingPoint,
    ) -> Result<Self, SimError> {
        let table = L1Table::solve(
            bearing,
            inputs,
            scene.lumped.cage_speed,
            super::held_axial(scene, bearing, inputs)?,
            None,
        )?;
        if scene.n_defects() > 1 {
            return Err(SimError::Input(format!(
                "the kinematic level (L0s) generates the impulse train of one spall; this scene \
                 has {} ([[defect]]): simulate it at the lumped, reduced or full level",
                scene.n_defects()
            )));
        }
        let q_ref = table.q_max.max(10.0);
        let mode = scene.spalls().next().and_then(|(_, m)| m);
        let fault = match &scene.defect {
            Some(spec) if spec.ring.race().is_none() => {
                let b = BallSpall::new(spec, bearing, q_ref, mode)?;
                Some(Fault::Ball(BallFault {
                    ball: b.ball(),
                    theta0: b.theta0(),
                    spin_per_orbit: b.spin_per_orbit(),
                    half: b.half_angle(),
                    drop: [b.at(Race::Outer).max_drop(), b.at(Race::Inner).max_drop()],
                }))
            }
            Some(spec) => Some(Fault::Race(Defect::summary_with_mode(
                spec, bearing, q_ref, mode,
            )?)),
            None => None,
        };
        let mut m = Self {
            bearing: bearing.clone(),
            modes: [Mode {
                omega: 0.0,
                sigma: 0.0,
                omega_d: 0.0,
                gain: 0.0,
            }; 2],
            table,
            inputs: *inputs,
            fault,
            theta_start: 0.0,
            k_series: bearing.k_series(),
            jitter: scene.lumped.slip_jitter.abs(),
            seed: scene.lumped.seed,
            next_entry: 0,
            next_exit: 0,
            acc: [(0.0, 0.0, 0.0); 2],
            t_ref: 0.0,
            dip: 0.0,
            entry_thr: 0.0,
            exit_thr: 0.0,
            memo: Memo::default(),
            max_passes: scene.solver.max_steps,
        };
        m.theta_start = m.choose_theta_start();
        m.modes = m.compute_modes();
        let psi0 = m.phase(&[0.0, 0.0]);
        let start = psi0.floor() as i64 - 2;
        m.next_entry = start;
        while m.entry_threshold(m.next_entry) <= psi0 {
            m.next_entry += 1;
        }
        // A pass already inside the spall at the start is skipped (its entry was not seen).
        m.next_exit = m.next_entry;
        m.refresh_thresholds();
        Ok(m)
    }

    /// Ball 0's start azimuth, as at the lumped level (no ball within θ_e + 0.02 rad of the spall).
    fn choose_theta_start(&self) -> f64 {
        let Some(Fault::Race(d)) = &self.fault else {
            return 0.0;
        };
        let clear = d.half_angle() + 0.02;
        let z = self.bearing.z;
        let spacing = TAU / z as f64;
        [0.0, 0.5 * spacing, 0.25 * spacing, 0.75 * spacing]
            .into_iter()
            .find(|&s| (0..z).all(|j| wrap(s + spacing * j as f64 - d.theta0()).abs() > clear))
            .unwrap_or(0.5 * spacing)
    }

    /// Modes of the ring (m1) on K_zz against the pedestal (m2) on k_p (z direction).
    fn compute_modes(&self) -> [Mode; 2] {
        let file = &self.bearing.file;
        let half_balls = 0.5 * self.bearing.z as f64 * self.bearing.ball_mass;
        let m1 = file.inner_ring.mass + half_balls;
        let m2 = file.pedestal.mass + half_balls;
        let kb = self.table.k_zz.abs().max(1.0);
        let kp = file.pedestal.k_z;
        // Contact damping of the loaded balls projected on z.
        let z = self.bearing.z;
        let cb: f64 = (0..z)
            .map(|j| {
                let th = TAU * j as f64 / z as f64;
                let (qi, _) = self.table.loads_at(th);
                if qi > 0.0 {
                    let c = self.table.alpha.cos() * th.cos();
                    file.contact.c_br * c * c
                } else {
                    0.0
                }
            })
            .sum();
        let cp = file.pedestal.c_z;
        let (k11, k12, k22) = (kb, -kb, kb + kp);
        let (c11, c12, c22) = (cb, -cb, cb + cp);
        // det(K − λM) = 0: m1 m2 λ² − (k11 m2 + k22 m1) λ + (k11 k22 − k12²) = 0.
        let a = m1 * m2;
        let b = -(k11 * m2 + k22 * m1);
        let c = k11 * k22 - k12 * k12;
        let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
        let mut modes = [Mode {
            omega: 0.0,
            sigma: 0.0,
            omega_d: 0.0,
            gain: 0.0,
        }; 2];
        for (i, lam) in [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)]
            .into_iter()
            .enumerate()
        {
            // Row 1: (k11 − λ m1) φ1 + k12 φ2 = 0.
            let (p1, p2) = (1.0, -(k11 - lam * m1) / k12);
            let norm = (m1 * p1 * p1 + m2 * p2 * p2).sqrt();
            let (p1, p2) = (p1 / norm, p2 / norm);
            let omega = lam.max(0.0).sqrt();
            let modal_c = c11 * p1 * p1 + 2.0 * c12 * p1 * p2 + c22 * p2 * p2;
            let zeta = if omega > 0.0 {
                (modal_c / (2.0 * omega)).clamp(0.0, 0.99)
            } else {
                0.0
            };
            modes[i] = Mode {
                omega,
                sigma: zeta * omega,
                omega_d: omega * (1.0 - zeta * zeta).sqrt(),
                gain: p2 * (p2 - p1),
            };
        }
        modes
    }

    /// Fault phase ψ [ball passes; for a spall on a ball, its meetings with a race] from the
    /// state.
    fn phase(&self, y: &[f64]) -> f64 {
        let z = self.bearing.z as f64;
        match &self.fault {
            None => 0.0,
            Some(Fault::Ball(b)) => (b.theta0 + b.spin_per_orbit * y[CAGE] - FRAC_PI_2) / PI,
            Some(Fault::Race(d)) => match d.ring() {
                Race::Outer => z * (self.theta_start + y[CAGE] - d.theta0()) / TAU,
                Race::Inner => z * (d.theta0() + y[SHAFT] - self.theta_start - y[CAGE]) / TAU,
            },
        }
    }

    /// dψ/dt [passes/s].
    fn phase_rate(&self) -> f64 {
        let z = self.bearing.z as f64;
        match &self.fault {
            None => 0.0,
            Some(Fault::Ball(b)) => b.spin_per_orbit * self.cage_speed() / PI,
            Some(Fault::Race(d)) => match d.ring() {
                Race::Outer => z * self.cage_speed() / TAU,
                Race::Inner => z * (self.inputs.shaft_speed - self.cage_speed()) / TAU,
            },
        }
    }

    /// Half-width of the spall in ball spacings (of a spall on a ball: in half spin turns).
    fn half_width(&self) -> f64 {
        match &self.fault {
            None => 0.0,
            Some(Fault::Ball(b)) => b.half / PI,
            Some(Fault::Race(d)) => d.half_angle() * self.bearing.z as f64 / TAU,
        }
    }

    /// Slip jitter of pass n [ball spacings].
    fn jitter_of(&self, n: i64) -> f64 {
        if self.jitter == 0.0 {
            return 0.0;
        }
        let mut s = self
            .seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add((n as u64).wrapping_mul(0x94D0_49BB_1331_11EB));
        let u1 = ((splitmix64(&mut s) >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
        let u2 = ((splitmix64(&mut s) >> 11) as f64) / (1u64 << 53) as f64;
        (self.jitter * (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()).clamp(-0.45, 0.45)
    }

    /// Re-computes the cached thresholds of `next_entry` and `next_exit`.
    fn refresh_thresholds(&mut self) {
        self.entry_thr = self.entry_threshold(self.next_entry);
        self.exit_thr = self.exit_threshold(self.next_exit);
    }

    fn entry_threshold(&self, n: i64) -> f64 {
        n as f64 + self.jitter_of(n) - self.half_width()
    }

    fn exit_threshold(&self, n: i64) -> f64 {
        n as f64 + self.jitter_of(n) + self.half_width()
    }

    /// Azimuth of the spall [rad].
    fn defect_azimuth(&self, d: &SpallSummary, y: &[f64]) -> f64 {
        match d.ring() {
            Race::Outer => d.theta0(),
            Race::Inner => d.theta0() + y[SHAFT],
        }
    }

    /// Azimuth of the load-zone centre: where e_r(θ) = (−sin θ, cos θ) points along (Fy, Fz).
    fn load_azimuth(&self) -> f64 {
        (-self.inputs.fy).atan2(self.inputs.fz)
    }

    /// Load-zone ball load q(θ) = q_max[1 − (1 − cos θ)/(2ε)]^1.5 at azimuth θ from the centre.
    pub fn load_zone(q_max: f64, epsilon: f64, theta: f64) -> f64 {
        if !epsilon.is_finite() {
            return q_max;
        }
        let base = 1.0 - (1.0 - theta.cos()) / (2.0 * epsilon);
        if base <= 0.0 {
            0.0
        } else {
            q_max * base * base.sqrt()
        }
    }

    /// Load lost by a ball over a spall of largest drop `max_drop` \[m\] at azimuth θ \[N\]
    /// (≥ 0).
    fn load_loss(&self, max_drop: f64, theta: f64) -> f64 {
        let q = Self::load_zone(
            self.table.q_max,
            self.table.epsilon,
            theta - self.load_azimuth(),
        );
        if q <= 0.0 || self.k_series <= 0.0 {
            return 0.0;
        }
        let delta = (q / self.k_series).powf(2.0 / 3.0);
        let rest = (1.0 - max_drop / delta).max(0.0);
        q * (1.0 - rest * rest.sqrt())
    }

    /// Registers every spall entry and exit the fault phase has passed by (t, y), each at its exact
    /// time t_k = t − (ψ − ψ_k)/ψ̇ (the rates are constant since the last input change), in order,
    /// at most `limit` passes (entries): returns how many it registered. Needing more (an absurd
    /// cage speed, an enormous step) is an error naming the numbers, with nothing registered: the
    /// passes stay pending, and the work per call is bounded by `limit`. With `register` false
    /// only that check is made (to within one pass), and nothing is registered.
    fn register_passes(
        &mut self,
        t: f64,
        y: &[f64],
        limit: u64,
        register: bool,
    ) -> Result<u64, String> {
        let Some(fault) = self.fault else {
            return Ok(0);
        };
        let rate = self.phase_rate();
        if rate <= 0.0 {
            return Ok(0);
        }
        let psi = self.phase(y);
        // Nothing due (the usual case at every output): no further work.
        let exit_first = self.next_exit < self.next_entry && self.exit_thr <= self.entry_thr;
        let next = if exit_first {
            self.exit_thr
        } else {
            self.entry_thr
        };
        if psi < next {
            return Ok(0);
        }
        // Consecutive thresholds lie 1 ± 0.9 apart (jitter within ±0.45), so about ψ − ψ_next + 1
        // passes are due: far more than allowed is refused before any work.
        let due = (psi - self.entry_thr).floor() + 1.0;
        let too_many = |due: f64, m: &Self| {
            // (Formatted only here: registering allocates nothing.)
            let spall = match fault {
                Fault::Race(d) if d.ring() == Race::Inner => "inner-race spall".to_string(),
                Fault::Race(_) => "outer-race spall".to_string(),
                Fault::Ball(b) => format!("spall on ball {} (passing a race)", b.ball + 1),
            };
            format!(
                "registering the spall passes up to t = {t} s would take {due:.3e} passes (the \
                 {spall} is passed {rate:.6e} times per second at the cage speed {:.6e} \
                 rad/s and shaft speed {:.6e} rad/s; next pass number {}), more than the {limit} \
                 allowed",
                m.table.cage_speed, m.inputs.shaft_speed, m.next_entry
            )
        };
        // (A NaN phase, from a non-finite cage speed, is refused too.)
        if due.is_nan() || due > limit as f64 + 1.0 {
            return Err(too_many(due, self));
        }
        if !register {
            return Ok(0);
        }
        // Within one of the limit: count exactly, and put everything back when over.
        let saved = (
            self.next_entry,
            self.next_exit,
            self.dip,
            self.acc,
            self.t_ref,
            self.entry_thr,
            self.exit_thr,
            self.memo,
        );
        let mut passes = 0u64;
        loop {
            let (entry, exit) = (self.entry_thr, self.exit_thr);
            let is_exit = self.next_exit < self.next_entry && exit <= entry;
            let thr = if is_exit { exit } else { entry };
            if thr > psi {
                break;
            }
            let back = (psi - thr) / rate;
            let tk = t - back;
            let theta = match fault {
                Fault::Race(d) if d.ring() == Race::Inner => {
                    d.theta0() + y[SHAFT] - self.inputs.shaft_speed * back
                }
                Fault::Race(d) => d.theta0(),
                // The spalled ball's azimuth then.
                Fault::Ball(b) => {
                    self.theta_start + y[CAGE] - self.cage_speed() * back
                        + TAU * b.ball as f64 / self.bearing.z as f64
                }
            };
            // cos α here, where a threshold is crossed, not per call (this runs at every sample).
            let e_rz = self.table.alpha.cos() * theta.cos();
            if is_exit {
                // The ball regains its load: the pedestal is pushed again.
                self.push_event(tk, self.dip * e_rz);
                self.next_exit += 1;
                self.exit_thr = self.exit_threshold(self.next_exit);
            } else {
                if passes == limit {
                    (
                        self.next_entry,
                        self.next_exit,
                        self.dip,
                        self.acc,
                        self.t_ref,
                        self.entry_thr,
                        self.exit_thr,
                        self.memo,
                    ) = saved;
                    return Err(too_many(due.max(limit as f64 + 1.0), self));
                }
                passes += 1;
                // The ball loses ΔQ: the force of the bearing on the pedestal drops by ΔQ e_r.
                let max_drop = match fault {
                    Fault::Race(d) => d.max_drop(),
                    // Even passes at the outer race, odd ones at the inner.
                    Fault::Ball(b) => b.drop[usize::from(self.next_entry.rem_euclid(2) == 1)],
                };
                self.dip = self.load_loss(max_drop, theta);
                self.push_event(tk, -self.dip * e_rz);
                self.next_entry += 1;
                self.entry_thr = self.entry_threshold(self.next_entry);
            }
        }
        Ok(passes)
    }

    /// Adds a step of force f [N] on the pedestal (−f on the ring) at time t.
    fn push_event(&mut self, t: f64, f: f64) {
        let dt = t - self.t_ref;
        for (m, acc) in self.modes.iter().zip(self.acc.iter_mut()) {
            let e = (-m.sigma * dt).exp();
            let (sn, cs) = (m.omega_d * dt).sin_cos();
            let (re, im) = (acc.0 * e, acc.1 * e);
            acc.0 = re * cs - im * sn + m.gain * f;
            acc.1 = re * sn + im * cs;
            acc.2 += m.gain * f;
        }
        self.t_ref = t;
        self.memo.valid = false;
    }

    /// Pedestal-z (displacement, velocity, acceleration) of the superposed modal step responses
    /// at t. With λ = −σ + iω_d and C(t) = C_ref e^{λ(t − t_ref)}: a = Re[C(1 + iσ/ω_d)],
    /// v = Re[−iC]/ω_d, x = (S − Re[C(1 − iσ/ω_d)])/ω².
    fn response(&mut self, t: f64) -> (f64, f64, f64) {
        let dt = t - self.t_ref;
        let memo = &mut self.memo;
        let step = t - memo.t;
        // Asked again at the memo's time: the same values, and the memo stays as it is (reading
        // the outputs twice does not change the later ones).
        let again = memo.valid && step == 0.0;
        let reuse = memo.valid && memo.reuses < 1024 && (step - memo.h).abs() <= 1e-9 * memo.h;
        let (mut x, mut v, mut a) = (0.0, 0.0, 0.0);
        for (k, (m, acc)) in self.modes.iter().zip(self.acc.iter()).enumerate() {
            let (re, im) = if again {
                memo.c[k]
            } else if reuse {
                // C(t) = C(t_prev) e^{λh} (1 + λδ), λ = −σ + iω_d.
                let d = step - memo.h;
                let (fr, fi) = memo.f[k];
                let (gr, gi) = (
                    fr * (1.0 - m.sigma * d) - fi * m.omega_d * d,
                    fi * (1.0 - m.sigma * d) + fr * m.omega_d * d,
                );
                let (cr, ci) = memo.c[k];
                (cr * gr - ci * gi, cr * gi + ci * gr)
            } else {
                let e = (-m.sigma * dt).exp();
                let (sn, cs) = (m.omega_d * dt).sin_cos();
                if memo.valid && step > 0.0 {
                    // Cache e^{λ·step} for the next output at the same spacing.
                    let e = (-m.sigma * step).exp();
                    let (sn, cs) = (m.omega_d * step).sin_cos();
                    memo.f[k] = (e * cs, e * sn);
                }
                (e * (acc.0 * cs - acc.1 * sn), e * (acc.0 * sn + acc.1 * cs))
            };
            memo.c[k] = (re, im);
            if m.omega_d <= 0.0 || (acc.0 == 0.0 && acc.1 == 0.0 && acc.2 == 0.0) {
                continue;
            }
            let r = m.sigma / m.omega_d;
            a += re - r * im;
            v += im / m.omega_d;
            x += (acc.2 - (re + r * im)) / (m.omega * m.omega);
        }
        if again {
            return (x, v, a);
        }
        if reuse {
            memo.reuses += 1;
        } else {
            if memo.valid && step > 0.0 {
                memo.h = step;
            } else {
                // First output after a change: the next one caches the spacing.
                memo.h = f64::NAN;
            }
            memo.reuses = 0;
        }
        memo.t = t;
        memo.valid = true;
        (x, v, a)
    }
}

fn splitmix64(s: &mut u64) -> u64 {
    *s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut x = *s;
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(TAU);
    if r > PI {
        r - TAU
    } else {
        r
    }
}

impl Model for KinematicModel {
    fn dim(&self) -> usize {
        2
    }

    fn nominal(&self, out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 1.0);
    }

    fn state_name(&self, i: usize) -> String {
        match i {
            CAGE => "cage angle θ_c".into(),
            SHAFT => "shaft angle φ".into(),
            _ => format!("state component {i}"),
        }
    }

    fn initial_state(&self, y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
    }

    fn set_inputs(&mut self, inputs: &OperatingPoint, t: f64, y: &[f64]) -> Result<(), SimError> {
        let table = if self.table.moved(inputs) {
            Some(L1Table::solve(
                &self.bearing,
                inputs,
                self.table.cage,
                self.table.held,
                Some(&self.table),
            )?)
        } else {
            None
        };
        // Steps reached under the old speed are registered with the old rates first (none, when
        // the simulation has caught up at t, as it does at the end of every advance).
        self.register_passes(t, y, self.max_passes, true)
            .map_err(|e| SimError::Input(format!("the inputs cannot change at t = {t} s: {e}")))?;
        self.inputs = *inputs;
        if let Some(table) = table {
            self.table = table;
            self.modes = self.compute_modes();
            self.memo.valid = false;
        }
        Ok(())
    }

    fn rhs(&mut self, _t: f64, _y: &[f64], dydt: &mut [f64]) {
        dydt[CAGE] = self.cage_speed();
        dydt[SHAFT] = self.inputs.shaft_speed;
    }

    /// No stops: the force steps are registered at their exact times when the outputs (or an
    /// input change) reach them, so the integrator can take steps as long as it likes.
    fn next_stop(&self, _t: f64, _y: &[f64], _t_max: f64) -> Option<f64> {
        None
    }

    /// Registers the passes reached by (t, y) if they are within the budget; otherwise they stay
    /// pending (registered by the next call that can, or refused by [`Model::catch_up`]).
    fn update_mode(&mut self, t: f64, y: &[f64]) {
        let _ = self.register_passes(t, y, self.max_passes, true);
    }

    /// The budget of spall passes is [`Model::catch_up`]'s, which the simulation calls before
    /// any output; if more passes were still due here, the pedestal's z outputs (which the passes
    /// drive) would be NaN rather than wrong.
    fn catch_up(&mut self, t: f64, y: &[f64], budget: u64) -> Result<u64, String> {
        self.register_passes(t, y, budget, true)
    }

    fn check_catch_up(&mut self, t: f64, y: &[f64], budget: u64) -> Result<(), String> {
        self.register_passes(t, y, budget, false).map(|_| ())
    }

    fn outputs(&mut self, t: f64, y: &[f64], o: &mut [f64]) {
        let caught_up = self.register_passes(t, y, self.max_passes, true).is_ok();
        static_outputs(
            &self.table,
            &self.bearing,
            &self.inputs,
            self.theta_start,
            y[CAGE],
            o,
        );
        let (x, v, a) = if caught_up {
            self.response(t)
        } else {
            (f64::NAN, f64::NAN, f64::NAN)
        };
        o[out::PEDESTAL_Z] += x;
        o[out::PEDESTAL_V_Z] = v;
        o[out::PEDESTAL_A_Z] = a;
        if !out::has_ball_block(o, self.bearing.z) {
            return;
        }
        if self.next_exit < self.next_entry {
            // The ball over the spall (or the spalled ball) carries ΔQ less.
            let z = self.bearing.z;
            let spacing = TAU / z as f64;
            let j = match &self.fault {
                Some(Fault::Race(d)) => {
                    let theta_d = self.defect_azimuth(d, y);
                    let rel = wrap(theta_d - self.theta_start - y[CAGE]);
                    Some(((rel / spacing).round() as i64).rem_euclid(z as i64) as usize)
                }
                Some(Fault::Ball(b)) => Some(b.ball),
                None => None,
            };
            if let Some(j) = j {
                o[out::CONTACT_START + j] = (o[out::CONTACT_START + j] - self.dip).max(0.0);
                o[out::CONTACT_START + z + j] = (o[out::CONTACT_START + z + j] - self.dip).max(0.0);
                out::set_separation_flags(o, z);
            }
        }
    }

    fn discrete_state(&self) -> Vec<f64> {
        let t = self.table.state();
        let mut s = vec![
            t[0],
            t[1],
            t[2],
            t[3],
            self.next_entry as f64,
            self.next_exit as f64,
            self.dip,
            self.t_ref,
        ];
        for acc in &self.acc {
            s.extend_from_slice(&[acc.0, acc.1, acc.2]);
        }
        s.push(t[4]);
        // The output memo, so that a restored run's outputs keep their bits (its spacing is NaN
        // until known: stored as 0, which no spacing is).
        let m = &self.memo;
        let h = if m.h.is_nan() { 0.0 } else { m.h };
        s.extend_from_slice(&[f64::from(u8::from(m.valid)), m.t, h, f64::from(m.reuses)]);
        for k in 0..2 {
            s.extend_from_slice(&[m.f[k].0, m.f[k].1, m.c[k].0, m.c[k].1]);
        }
        s
    }

    fn set_discrete_state(&mut self, s: &[f64]) -> Result<(), String> {
        // 14 or 15 values from snapshots taken before the cage speed and the memo were kept.
        if ![14, 15, 27].contains(&s.len()) || s.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "kinematic model state has 27 finite values, got {}",
                s.len()
            ));
        }
        // The table's inputs, then (since the cage speed is kept) its cage speed at the end.
        let table: Vec<f64> = s[..4].iter().chain(s.get(14)).copied().collect();
        self.table.restore(&self.bearing, &table)?;
        self.modes = self.compute_modes();
        self.next_entry = s[4] as i64;
        self.next_exit = s[5] as i64;
        self.dip = s[6];
        self.t_ref = s[7];
        for (k, acc) in self.acc.iter_mut().enumerate() {
            *acc = (s[8 + 3 * k], s[9 + 3 * k], s[10 + 3 * k]);
        }
        self.refresh_thresholds();
        self.memo.valid = false;
        if let Some(m) = s.get(15..27) {
            self.memo = Memo {
                valid: m[0] != 0.0,
                t: m[1],
                h: if m[2] == 0.0 { f64::NAN } else { m[2] },
                reuses: m[3] as u32,
                f: [(m[4], m[5]), (m[8], m[9])],
                c: [(m[6], m[7]), (m[10], m[11])],
            };
        }
        Ok(())
    }

    /// The registered passes, the modal amplitudes and the output memo (the L1 table changes
    /// only with the inputs, between advances).
    fn checkpoint(&self, b: &mut Vec<f64>) {
        b.clear();
        b.extend_from_slice(&[
            self.next_entry as f64,
            self.next_exit as f64,
            self.dip,
            self.t_ref,
            self.entry_thr,
            self.exit_thr,
        ]);
        for a in &self.acc {
            b.extend_from_slice(&[a.0, a.1, a.2]);
        }
        let m = &self.memo;
        b.extend_from_slice(&[f64::from(u8::from(m.valid)), m.t, m.h, f64::from(m.reuses)]);
        for k in 0..2 {
            b.extend_from_slice(&[m.f[k].0, m.f[k].1, m.c[k].0, m.c[k].1]);
        }
    }

    fn rollback(&mut self, b: &[f64], _t: f64, _y: &[f64]) -> Result<(), String> {
        if b.len() != 24 {
            return Err(format!(
                "kinematic checkpoint has 24 values, got {}",
                b.len()
            ));
        }
        self.next_entry = b[0] as i64;
        self.next_exit = b[1] as i64;
        self.dip = b[2];
        self.t_ref = b[3];
        self.entry_thr = b[4];
        self.exit_thr = b[5];
        for (k, a) in self.acc.iter_mut().enumerate() {
            *a = (b[6 + 3 * k], b[7 + 3 * k], b[8 + 3 * k]);
        }
        let m = &mut self.memo;
        m.valid = b[12] != 0.0;
        m.t = b[13];
        m.h = b[14];
        m.reuses = b[15] as u32;
        for k in 0..2 {
            let i = 16 + 4 * k;
            m.f[k] = (b[i], b[i + 1]);
            m.c[k] = (b[i + 2], b[i + 3]);
        }
        Ok(())
    }

    fn cage_speed(&self) -> f64 {
        self.table.cage_speed_at(self.inputs.shaft_speed)
    }

    fn contacts_follow_inputs(&self) -> bool {
        true
    }
}

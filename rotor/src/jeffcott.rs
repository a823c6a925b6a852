//! Jeffcott rotor with one bearing station: plain Rust physics, no FMI.
//!
//! Two lumped masses in the bearing's frame (x axial, y and z radial, shaft rotation about +x):
//! the **journal** (mass `m_j`, the inner-ring centre, displacement `x_j = (x, y, z)`) and the
//! **disk** (mass `m_d`, lateral displacement `(y_d, z_d)`) on a massless shaft of lateral
//! stiffness `k_s` and damping `c_s`. Axially the disk rides with the journal (`disk.axial = 1`,
//! the default; with 0 the axial inertia is the journal's alone, m_a = m_j). With `m_d = 0`
//! the rotor is rigid: one mass `m_j` carrying the unbalance.
//!
//! ```text
//!   m_a ẍ_j           = F_x + L_x − c_j ẋ_j,   m_a = m_j + m_d (disk.axial = 1) or m_j
//!   m_j ÿ_j           = F_y + L_y − c_j ẏ_j + k_s (y_d − y_j) + c_s (ẏ_d − ẏ_j)
//!   m_j z̈_j           = F_z + L_z − c_j ż_j + k_s (z_d − z_j) + c_s (ż_d − ż_j) − m_j g
//!   m_d ÿ_d           = −k_s (y_d − y_j) − c_s (ẏ_d − ẏ_j) + U_y
//!   m_d z̈_d           = −k_s (z_d − z_j) − c_s (ż_d − ż_j) − m_d g + U_z
//! ```
//!
//! `F` is the force of the bearing on the shaft (the coupling input), `L` a constant external
//! load, `g` gravity along −z, and `U` the unbalance force of `m_u e` at the shaft angle φ
//! (φ̇ = Ω): `U = m_u e (Ω² cos φ + Ω̇ sin φ, Ω² sin φ − Ω̇ cos φ)`.
//!
//! Shaft speed: `Ω(t) = Ω₀` ramping at `|α|` towards `Ω_f` from the start time (a run-up), in
//! closed form, so φ is exact.
//!
//! Bearing force inside a communication step `[t_k, t_k + H]` (what a co-simulation master
//! hands over): `F(t) = F_k + Ḟ_k (t − t_k) + K (x_j(t) − x_j(t_k)) + C (ẋ_j(t) − ẋ_j(t_k))`.
//! `Ḟ_k = 0, K = C = 0` is the constant-input (zero-order hold) coupling, `Ḟ_k ≠ 0` linear
//! extrapolation, and `K = ∂F/∂x`, `C = ∂F/∂v` of the bearing (its directional derivatives) the
//! interface-Jacobian coupling, where the rotor integrates the linearised bearing reaction
//! inside the step.
//!
//! # Coupling mode tlm
//!
//! Value exchange at the stiff bearing contact is unstable at any useful communication step;
//! in coupling mode tlm ([`Coupling::Tlm`], [`TlmRotor`]) the rotor is cut at the compliant
//! shaft instead. The journal's mass moves into the bearing model (the BallBearing's inner
//! ring), the rotor keeps the disk, and the shaft (`k_s`, `c_s`) becomes a transmission line of
//! delay `T` (the communication step) and characteristic impedance `Z_c = k_s T`
//! ([`crate::tlm`]), simulated entirely here:
//!
//! ```text
//!   m_d ÿ_d = F_line,y(t) + U_y
//!   m_d z̈_d = F_line,z(t) − m_d g + U_z
//!   F_line(t) = g_d(t) − (Z_c + c_s) v_d(t) + c_s v_j(t − T)      per axis, v_d = (ẏ_d, ż_d)
//!   g_d(t) = o_j(t − T),   o_j = 2 Z_c v_j − g_j,   g_j(t) = o_d(t − T),   o_d = 2 Z_c v_d − g_d
//! ```
//!
//! with `g_d` and `v_j(t − T)` linear inside a communication step between their samples. The
//! rotor receives the journal velocity `v_j(t_k)` at each communication point and sends `c0`,
//! `c1` and `Z_c + c_s`, with which the bearing applies
//! `F(t) = c0 + (c1 − c0)(t − t_k)/T − (Z_c + c_s) v_j(t)` to its journal over its next step.
//! The line's parasitic mass `k_s T²` is the scheme's error (second order in `T`), plus the
//! delayed damper's `c_s T` (first order, see [`crate::tlm`]); the line is passive, so the
//! coupling is stable at any delay.
//!
//! The journal is the bearing's in this mode; the rotor reports it as seen through the line:
//! its lateral displacement integrated from the received velocities by the trapezoidal rule
//! from `journal0`, its velocity the received one. Axially nothing moves (the axial direction
//! is the bearing's: its inner-ring mass and axial load); `journal.mass`, `journal.c` and the
//! constant load `L` do not act (they belong to the bearing side).

use crate::tlm::{LineHistory, LineStep, TlmLine, AXES};
use raceway_solver::{
    Checkpoint, Integrator, IntegratorState, Method, Options, SolverError, System,
};

/// How the rotor couples to the bearing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Coupling {
    /// The rotor owns the journal and takes the bearing force as input ([`Rotor`]).
    #[default]
    Force,
    /// Transmission-line coupling at the shaft: the journal is the bearing's, the rotor keeps
    /// the disk and simulates the shaft as a line ([`TlmRotor`]).
    Tlm,
}

impl Coupling {
    /// The mode of the FMU parameter `coupling` (0 force, 1 tlm).
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            0 => Some(Coupling::Force),
            1 => Some(Coupling::Tlm),
            _ => None,
        }
    }

    /// The FMU parameter value `coupling` of the mode.
    pub fn code(self) -> i32 {
        match self {
            Coupling::Force => 0,
            Coupling::Tlm => 1,
        }
    }

    /// The mode's name (`force`, `tlm`).
    pub fn name(self) -> &'static str {
        match self {
            Coupling::Force => "force",
            Coupling::Tlm => "tlm",
        }
    }
}

/// Parameters of the rotor (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct RotorParams {
    /// Journal (bearing-station) mass \[kg\] (> 0).
    pub journal_mass: f64,
    /// Disk mass \[kg\] (>= 0; 0: rigid rotor).
    pub disk_mass: f64,
    /// Shaft lateral stiffness journal–disk [N/m] (> 0 if `disk_mass > 0`).
    pub shaft_k: f64,
    /// Shaft lateral damping [N·s/m].
    pub shaft_c: f64,
    /// Damping of the journal to ground, all three directions [N·s/m] (a damper, seal, ...).
    pub journal_c: f64,
    /// Unbalance m_u·e [kg·m] on the disk (on the journal if rigid).
    pub unbalance: f64,
    /// Gravity [m/s²], acting along −z.
    pub gravity: f64,
    /// Constant external load on the journal \[N\].
    pub load: [f64; 3],
    /// Initial journal displacement \[m\]; the disk starts at its static sag below it.
    pub journal0: [f64; 3],
    /// Shaft speed at the start [rad/s] (>= 0).
    pub speed_initial: f64,
    /// Shaft speed at the end of the ramp [rad/s] (>= 0).
    pub speed_final: f64,
    /// Ramp rate magnitude [rad/s²] (0: constant speed `speed_initial`).
    pub speed_rate: f64,
    /// How the rotor couples to the bearing ([`Rotor`] runs the force mode, [`TlmRotor`] the
    /// tlm mode).
    pub coupling: Coupling,
    /// Delay of the TLM line \[s\] (> 0; coupling mode tlm only): the master's communication
    /// step.
    pub tlm_delay: f64,
    /// Whether the disk rides axially with the journal (coupling mode force): the axial inertia
    /// is then `journal_mass + disk_mass`, else `journal_mass` alone (as in coupling mode tlm,
    /// where the axial direction is the bearing's ring).
    pub disk_axial: bool,
}

impl Default for RotorParams {
    /// The default rotor: 2 kg journal, 8 kg disk on a 2 MN/m shaft (first critical speed
    /// ≈ 500 rad/s ≈ 4770 rpm on a rigid bearing), 2 % shaft damping, 100 g·mm unbalance,
    /// the default bearing scene's loads (Fa = 4000 N, Fr = 1000 N), at 9900 rpm.
    fn default() -> Self {
        RotorParams {
            journal_mass: 2.0,
            disk_mass: 8.0,
            shaft_k: 2.0e6,
            shaft_c: 160.0,
            journal_c: 0.0,
            unbalance: 1.0e-4,
            gravity: 9.81,
            load: [4000.0, 0.0, -1000.0],
            journal0: [0.0; 3],
            speed_initial: 9900.0 * std::f64::consts::PI / 30.0,
            speed_final: 9900.0 * std::f64::consts::PI / 30.0,
            speed_rate: 0.0,
            coupling: Coupling::Force,
            tlm_delay: 1e-4,
            disk_axial: true,
        }
    }
}

/// A parameter error, naming the parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamError(pub String);

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl RotorParams {
    /// Checks ranges; the error names the offending field.
    pub fn validate(&self) -> Result<(), ParamError> {
        let fields: [(&str, f64); 12] = [
            ("journal.mass", self.journal_mass),
            ("disk.mass", self.disk_mass),
            ("shaft.k", self.shaft_k),
            ("shaft.c", self.shaft_c),
            ("journal.c", self.journal_c),
            ("unbalance", self.unbalance),
            ("gravity", self.gravity),
            ("speed.initial", self.speed_initial),
            ("speed.final", self.speed_final),
            ("speed.rate", self.speed_rate),
            ("load.Fx", self.load[0]),
            ("journal.x0", self.journal0[0]),
        ];
        for (name, v) in fields {
            if !v.is_finite() {
                return Err(ParamError(format!("{name} = {v} is not finite")));
            }
        }
        for (name, v) in [
            ("load.Fy", self.load[1]),
            ("load.Fz", self.load[2]),
            ("journal.y0", self.journal0[1]),
            ("journal.z0", self.journal0[2]),
            ("tlm.delay", self.tlm_delay),
        ] {
            if !v.is_finite() {
                return Err(ParamError(format!("{name} = {v} is not finite")));
            }
        }
        if self.coupling == Coupling::Tlm {
            self.validate_tlm()?;
        }
        if self.journal_mass <= 0.0 {
            return Err(ParamError(format!(
                "journal.mass = {} kg must be > 0",
                self.journal_mass
            )));
        }
        for (name, v) in [
            ("disk.mass", self.disk_mass),
            ("shaft.c", self.shaft_c),
            ("journal.c", self.journal_c),
            ("unbalance", self.unbalance),
            ("speed.initial", self.speed_initial),
            ("speed.final", self.speed_final),
            ("speed.rate", self.speed_rate),
        ] {
            if v < 0.0 {
                return Err(ParamError(format!("{name} = {v} must be >= 0")));
            }
        }
        if self.disk_mass > 0.0 && self.shaft_k <= 0.0 {
            return Err(ParamError(format!(
                "shaft.k = {} N/m must be > 0 when disk.mass > 0",
                self.shaft_k
            )));
        }
        Ok(())
    }

    /// The requirements of coupling mode tlm (whatever [`RotorParams::coupling`] says): a disk
    /// (`disk.mass > 0`), a shaft to make the line of (`shaft.k > 0`) and a delay
    /// (`tlm.delay > 0`). The error names the parameter.
    pub fn validate_tlm(&self) -> Result<(), ParamError> {
        if !(self.disk_mass.is_finite() && self.disk_mass > 0.0) {
            return Err(ParamError(format!(
                "disk.mass = {} kg: coupling = 1 (tlm) needs disk.mass > 0 (the rotor keeps the \
                 disk; the journal's mass is the BallBearing's in this mode)",
                self.disk_mass
            )));
        }
        if !(self.shaft_k.is_finite() && self.shaft_k > 0.0) {
            return Err(ParamError(format!(
                "shaft.k = {} N/m: coupling = 1 (tlm) needs shaft.k > 0 (the shaft becomes the \
                 transmission line, Zc = shaft.k * tlm.delay)",
                self.shaft_k
            )));
        }
        if !(self.tlm_delay.is_finite() && self.tlm_delay > 0.0) {
            return Err(ParamError(format!(
                "tlm.delay = {} s must be > 0 (the master's communication step)",
                self.tlm_delay
            )));
        }
        Ok(())
    }

    /// Unbalance force \[N\] (y, z) at time `tau` after the start (see the module docs).
    pub fn unbalance_force(&self, tau: f64) -> [f64; 2] {
        let (w, wd, phi) = self.speed(tau);
        let (s, c) = phi.sin_cos();
        let u = self.unbalance;
        [u * (w * w * c + wd * s), u * (w * w * s - wd * c)]
    }

    /// Whether the rotor is a single rigid mass (no disk).
    pub fn rigid(&self) -> bool {
        self.disk_mass == 0.0
    }

    /// Static sag of the disk below the journal under gravity \[m\] (0 if rigid).
    pub fn disk_sag(&self) -> f64 {
        if self.rigid() {
            0.0
        } else {
            self.disk_mass * self.gravity / self.shaft_k
        }
    }

    /// Duration of the speed ramp \[s\] (0 without a ramp).
    pub fn ramp_time(&self) -> f64 {
        if self.speed_rate > 0.0 {
            (self.speed_final - self.speed_initial).abs() / self.speed_rate
        } else {
            0.0
        }
    }

    /// Shaft speed Ω, its rate Ω̇ and angle φ at time `tau` after the start.
    pub fn speed(&self, tau: f64) -> (f64, f64, f64) {
        let tau = tau.max(0.0);
        let tr = self.ramp_time();
        if tr == 0.0 {
            return (self.speed_initial, 0.0, self.speed_initial * tau);
        }
        let a = self.speed_rate * (self.speed_final - self.speed_initial).signum();
        if tau < tr {
            (
                self.speed_initial + a * tau,
                a,
                self.speed_initial * tau + 0.5 * a * tau * tau,
            )
        } else {
            let phi_r = self.speed_initial * tr + 0.5 * a * tr * tr;
            (self.speed_final, 0.0, phi_r + self.speed_final * (tau - tr))
        }
    }
}

/// The bearing force law over one communication step (see the module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InterfaceForce {
    /// Force of the bearing on the shaft at the step start \[N\].
    pub f: [f64; 3],
    /// Its rate over the step [N/s] (linear extrapolation; 0: held constant).
    pub df: [f64; 3],
    /// ∂F/∂x_j [N/m], row i = force component i.
    pub k: [[f64; 3]; 3],
    /// ∂F/∂ẋ_j [N·s/m].
    pub c: [[f64; 3]; 3],
}

/// State layout: journal x, y, z, ẋ, ẏ, ż; disk y, z, ẏ, ż.
pub const DIM: usize = 10;

/// The right-hand side (a [`System`]); knows the step's interface force and its start state.
#[derive(Debug, Clone)]
struct Rhs {
    p: RotorParams,
    t0: f64,
    iface: InterfaceForce,
    tk: f64,
    xk: [f64; 6],
}

impl Rhs {
    fn bearing_force(&self, t: f64, y: &[f64]) -> [f64; 3] {
        let mut f = [0.0; 3];
        for (i, fi) in f.iter_mut().enumerate() {
            let mut v = self.iface.f[i] + self.iface.df[i] * (t - self.tk);
            for j in 0..3 {
                v += self.iface.k[i][j] * (y[j] - self.xk[j])
                    + self.iface.c[i][j] * (y[3 + j] - self.xk[3 + j]);
            }
            *fi = v;
        }
        f
    }

    fn unbalance(&self, t: f64) -> [f64; 2] {
        self.p.unbalance_force(t - self.t0)
    }
}

impl System for Rhs {
    fn dim(&self) -> usize {
        DIM
    }

    fn rhs(&mut self, t: f64, y: &[f64], d: &mut [f64]) {
        let p = &self.p;
        let f = self.bearing_force(t, y);
        let u = self.unbalance(t);
        let (mj, md) = (p.journal_mass, p.disk_mass);
        // journal velocities
        d[0] = y[3];
        d[1] = y[4];
        d[2] = y[5];
        let ext = [
            f[0] + p.load[0] - p.journal_c * y[3],
            f[1] + p.load[1] - p.journal_c * y[4],
            f[2] + p.load[2] - p.journal_c * y[5] - mj * p.gravity,
        ];
        if p.rigid() {
            d[3] = ext[0] / mj;
            d[4] = (ext[1] + u[0]) / mj;
            d[5] = (ext[2] + u[1]) / mj;
            // the (absent) disk moves with the journal
            d[6] = y[4];
            d[7] = y[5];
            d[8] = d[4];
            d[9] = d[5];
        } else {
            let sy = p.shaft_k * (y[6] - y[1]) + p.shaft_c * (y[8] - y[4]);
            let sz = p.shaft_k * (y[7] - y[2]) + p.shaft_c * (y[9] - y[5]);
            d[3] = ext[0] / if p.disk_axial { mj + md } else { mj };
            d[4] = (ext[1] + sy) / mj;
            d[5] = (ext[2] + sz) / mj;
            d[6] = y[8];
            d[7] = y[9];
            d[8] = (-sy + u[0]) / md;
            d[9] = (-sz - md * p.gravity + u[1]) / md;
        }
    }
}

/// A running rotor: parameters, interface force of the current step, integrator.
#[derive(Debug, Clone)]
pub struct Rotor {
    rhs: Rhs,
    integ: Integrator,
}

/// Integrator failure inside [`Rotor::advance`].
#[derive(Debug, Clone, PartialEq)]
pub struct RotorError {
    /// Time of the last accepted state.
    pub t: f64,
    pub message: String,
}

impl std::fmt::Display for RotorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "rotor integration failed at t = {}: {}",
            self.t, self.message
        )
    }
}

/// What the rotor reports.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RotorOutputs {
    pub journal_x: [f64; 3],
    pub journal_v: [f64; 3],
    pub journal_a: [f64; 3],
    pub disk: [f64; 2],
    pub disk_v: [f64; 2],
    pub speed: f64,
    /// Shaft angle wrapped to [0, 2π).
    pub angle: f64,
    /// Unbalance force \[N\] (y, z).
    pub unbalance: [f64; 2],
    /// Bearing force acting now \[N\] (as integrated; 0 in coupling mode tlm, where the
    /// bearing force acts on the bearing's journal).
    pub bearing_force: [f64; 3],
    /// Coupling mode tlm: `c0`, the line's force on the journal at the start of the bearing's
    /// next step before the impedance term \[N\] (y, z); 0 in force mode.
    pub tlm_c0: [f64; 2],
    /// Coupling mode tlm: `c1`, the same at the end of that step \[N\] (y, z); 0 in force mode.
    pub tlm_c1: [f64; 2],
    /// Coupling mode tlm: the impedance `Z_c + c_s` the bearing applies to the journal
    /// velocity \[N·s/m\]; 0 in force mode.
    pub tlm_zc: f64,
}

impl Rotor {
    /// A rotor at `t0` in its initial state (journal at `journal0`, disk at its static sag,
    /// at rest), integrated by DOPRI5 with relative tolerance `rtol`.
    pub fn new(p: &RotorParams, t0: f64, rtol: f64) -> Result<Self, ParamError> {
        p.validate()?;
        if !(rtol > 0.0 && rtol < 0.1) {
            return Err(ParamError(format!("tolerance {rtol} must lie in (0, 0.1)")));
        }
        let mut y0 = [0.0; DIM];
        y0[..3].copy_from_slice(&p.journal0);
        y0[6] = p.journal0[1];
        y0[7] = p.journal0[2] - p.disk_sag();
        // displacements to 1e-12 m, velocities to 1e-9 m/s
        let atol = vec![
            1e-12, 1e-12, 1e-12, 1e-9, 1e-9, 1e-9, 1e-12, 1e-12, 1e-9, 1e-9,
        ];
        let opts = Options::new(Method::Dopri5, rtol, atol);
        let integ = Integrator::new(opts, t0, &y0).map_err(|e| ParamError(e.to_string()))?;
        let mut xk = [0.0; 6];
        xk.copy_from_slice(&y0[..6]);
        Ok(Rotor {
            rhs: Rhs {
                p: p.clone(),
                t0,
                iface: InterfaceForce::default(),
                tk: t0,
                xk,
            },
            integ,
        })
    }

    pub fn params(&self) -> &RotorParams {
        &self.rhs.p
    }

    pub fn t(&self) -> f64 {
        self.integ.t()
    }

    pub fn state(&self) -> &[f64] {
        self.integ.y()
    }

    /// Sets the bearing force law for the steps from now on (applies from the current time).
    pub fn set_interface(&mut self, iface: InterfaceForce) {
        self.rhs.iface = iface;
        self.rhs.tk = self.integ.t();
        self.rhs.xk.copy_from_slice(&self.integ.y()[..6]);
        self.integ.discontinuity();
    }

    pub fn interface(&self) -> &InterfaceForce {
        &self.rhs.iface
    }

    /// Integrates to `t_end` (>= the current time).
    pub fn advance(&mut self, t_end: f64) -> Result<(), RotorError> {
        // the interface law is anchored at the start of each call (a communication step)
        self.rhs.tk = self.integ.t();
        self.rhs.xk.copy_from_slice(&self.integ.y()[..6]);
        self.integ
            .advance(&mut self.rhs, t_end, None)
            .map_err(|e: SolverError| RotorError {
                t: self.integ.t(),
                message: e.to_string(),
            })
    }

    /// Integrator work counters (steps, rejected, rhs evaluations).
    pub fn stats(&self) -> (u64, u64, u64) {
        let s = self.integ.stats();
        (s.steps, s.rejected, s.rhs_evals)
    }

    /// Model Exchange: sets the time and the state (`DIM` finite values) of the next
    /// evaluations; the importer integrates. The interface force law keeps its anchor (the time
    /// and state at which it was last set).
    pub fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), String> {
        self.integ.try_set_state(t, y).map_err(|e| e.to_string())
    }

    /// Model Exchange: the derivatives of the state at the current time and state.
    pub fn derivatives(&mut self, d: &mut [f64]) {
        let t = self.integ.t();
        let mut y = [0.0; DIM];
        y.copy_from_slice(self.integ.y());
        self.rhs.rhs(t, &y, d);
    }

    /// Nominal magnitudes of the states (displacements 1e-5 m, velocities 1e-2 m/s, as the
    /// bearing's lumped level).
    pub fn nominals(out: &mut [f64]) {
        for (i, v) in out.iter_mut().enumerate() {
            *v = if matches!(i, 0..=2 | 6 | 7) {
                1e-5
            } else {
                1e-2
            };
        }
    }

    /// Model Exchange: the end of the speed ramp if it lies after the current time (the
    /// unbalance force's rate jumps there).
    pub fn next_time_event(&self) -> Option<f64> {
        let tr = self.rhs.p.ramp_time();
        let end = self.rhs.t0 + tr;
        (tr > 0.0 && end > self.integ.t()).then_some(end)
    }

    /// The outputs at the current time.
    pub fn outputs(&mut self) -> RotorOutputs {
        let t = self.integ.t();
        let mut y = [0.0; DIM];
        y.copy_from_slice(self.integ.y());
        let mut d = [0.0; DIM];
        self.rhs.rhs(t, &y, &mut d);
        let (w, _, phi) = self.rhs.p.speed(t - self.rhs.t0);
        RotorOutputs {
            journal_x: [y[0], y[1], y[2]],
            journal_v: [y[3], y[4], y[5]],
            journal_a: [d[3], d[4], d[5]],
            disk: [y[6], y[7]],
            disk_v: [y[8], y[9]],
            speed: w,
            angle: phi.rem_euclid(std::f64::consts::TAU),
            unbalance: self.rhs.unbalance(t),
            bearing_force: self.rhs.bearing_force(t, &y),
            tlm_c0: [0.0; 2],
            tlm_c1: [0.0; 2],
            tlm_zc: 0.0,
        }
    }

    /// Serializable solver and interface state (the parameters are not included).
    pub fn snapshot(&self) -> (IntegratorState, InterfaceForce, f64, [f64; 6]) {
        (
            self.integ.snapshot(),
            self.rhs.iface,
            self.rhs.tk,
            self.rhs.xk,
        )
    }

    /// Restores a [`Rotor::snapshot`] taken from a rotor with the same parameters.
    pub fn restore(
        &mut self,
        s: &IntegratorState,
        iface: InterfaceForce,
        tk: f64,
        xk: [f64; 6],
    ) -> Result<(), String> {
        self.integ.restore(s).map_err(|e| e.to_string())?;
        self.rhs.iface = iface;
        self.rhs.tk = tk;
        self.rhs.xk = xk;
        Ok(())
    }
}

/// Disk state layout in coupling mode tlm: y_d, z_d, ẏ_d, ż_d.
pub const TLM_DIM: usize = 4;

/// The disk-only right-hand side of coupling mode tlm (a [`System`]): the disk driven by the
/// line's force of the current communication step, gravity and the unbalance.
#[derive(Debug, Clone)]
struct DiskRhs {
    p: RotorParams,
    t0: f64,
    /// The line's part of the current communication step.
    step: LineStep,
    /// Start and length of the current communication step.
    tk: f64,
    h: f64,
}

impl System for DiskRhs {
    fn dim(&self) -> usize {
        TLM_DIM
    }

    fn rhs(&mut self, t: f64, y: &[f64], d: &mut [f64]) {
        let p = &self.p;
        let s = (t - self.tk) / self.h;
        let f = self.step.disk_force(s, [y[2], y[3]]);
        let u = p.unbalance_force(t - self.t0);
        let md = p.disk_mass;
        d[0] = y[2];
        d[1] = y[3];
        d[2] = (f[0] + u[0]) / md;
        // the line's static force is exactly md * g: at rest this is exactly 0
        d[3] = (f[1] - md * p.gravity + u[1]) / md;
    }
}

/// The journal as the rotor sees it through the line in coupling mode tlm: the last velocity
/// sample received and the displacement integrated from the samples (trapezoidal rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeenJournal {
    /// Time of the last sample \[s\].
    pub t: f64,
    /// Lateral displacement (y, z) at that time \[m\].
    pub x: [f64; AXES],
    /// The velocity sample (y, z) \[m/s\].
    pub v: [f64; AXES],
}

/// Everything a [`TlmRotor`] needs to continue bit-exactly (its parameters aside).
#[derive(Debug, Clone, PartialEq)]
pub struct TlmSnapshot {
    /// The disk's integrator.
    pub integrator: IntegratorState,
    /// The line's history.
    pub line: LineHistory,
    /// The journal as seen through the line.
    pub journal: SeenJournal,
}

/// A running rotor in coupling mode tlm: the disk, the line standing for the shaft, and the
/// journal as seen through it (see the module docs).
#[derive(Debug, Clone)]
pub struct TlmRotor {
    rhs: DiskRhs,
    integ: Integrator,
    line: TlmLine,
    seen: SeenJournal,
    /// The integrator at the start of the current step, to take a failed step back.
    checkpoint: Checkpoint,
}

impl TlmRotor {
    /// A rotor at `t0` in its initial state: the disk at rest in its static equilibrium (at
    /// `journal0` less its sag), the line carrying the disk's weight, the journal at `journal0`;
    /// the disk integrated by DOPRI5 with relative tolerance `rtol`. Checks the parameters
    /// including [`RotorParams::validate_tlm`].
    pub fn new(p: &RotorParams, t0: f64, rtol: f64) -> Result<Self, ParamError> {
        p.validate()?;
        p.validate_tlm()?;
        if !(rtol > 0.0 && rtol < 0.1) {
            return Err(ParamError(format!("tolerance {rtol} must lie in (0, 0.1)")));
        }
        let y0 = [p.journal0[1], p.journal0[2] - p.disk_sag(), 0.0, 0.0];
        // displacements to 1e-12 m, velocities to 1e-9 m/s
        let opts = Options::new(Method::Dopri5, rtol, vec![1e-12, 1e-12, 1e-9, 1e-9]);
        let integ = Integrator::new(opts, t0, &y0).map_err(|e| ParamError(e.to_string()))?;
        // the line carries the disk's weight (the same product as in the right-hand side)
        let line = TlmLine::at_rest(
            p.shaft_k,
            p.shaft_c,
            p.tlm_delay,
            [0.0, p.disk_mass * p.gravity],
        )
        .map_err(ParamError)?;
        Ok(TlmRotor {
            rhs: DiskRhs {
                p: p.clone(),
                t0,
                step: LineStep::default(),
                tk: t0,
                h: p.tlm_delay,
            },
            integ,
            line,
            seen: SeenJournal {
                t: t0,
                x: [p.journal0[1], p.journal0[2]],
                v: [0.0; AXES],
            },
            checkpoint: Checkpoint::with_capacity(TLM_DIM, 0),
        })
    }

    /// The parameters.
    pub fn params(&self) -> &RotorParams {
        &self.rhs.p
    }

    /// The current time \[s\].
    pub fn t(&self) -> f64 {
        self.integ.t()
    }

    /// The disk's state (see [`TLM_DIM`]).
    pub fn state(&self) -> &[f64] {
        self.integ.y()
    }

    /// The line.
    pub fn line(&self) -> &TlmLine {
        &self.line
    }

    /// The journal as seen through the line (at its last sample).
    pub fn seen_journal(&self) -> &SeenJournal {
        &self.seen
    }

    /// One communication step from now to `t_end` (`t_end − t` is the line's delay; the
    /// caller checks it), given the journal velocity `vj` (y, z) received for now. On failure
    /// nothing changes (the rotor stays at the step's start, the error's `t`). Does not
    /// allocate.
    pub fn step(&mut self, vj: [f64; AXES], t_end: f64) -> Result<(), RotorError> {
        let tk = self.integ.t();
        let h = t_end - tk;
        if !(h.is_finite() && h > 0.0) {
            return Err(RotorError {
                t: tk,
                message: format!("step to t = {t_end} does not go forward"),
            });
        }
        let step = self.line.begin_step(vj);
        self.rhs.step = step;
        self.rhs.tk = tk;
        self.rhs.h = h;
        self.integ.checkpoint(&mut self.checkpoint);
        // the line's force changes its slope at the communication point
        self.integ.discontinuity();
        if let Err(e) = self.integ.advance(&mut self.rhs, t_end, None) {
            self.integ.rollback(&self.checkpoint);
            return Err(RotorError {
                t: tk,
                message: e.to_string(),
            });
        }
        let y = self.integ.y();
        self.line.end_step(&step, [y[2], y[3]]);
        let s = &mut self.seen;
        let dt = tk - s.t;
        for ((x, v), vn) in s.x.iter_mut().zip(s.v).zip(vj) {
            *x += 0.5 * dt * (v + vn);
        }
        s.v = vj;
        s.t = tk;
        Ok(())
    }

    /// Integrator work counters (steps, rejected, rhs evaluations).
    pub fn stats(&self) -> (u64, u64, u64) {
        let s = self.integ.stats();
        (s.steps, s.rejected, s.rhs_evals)
    }

    /// The outputs at the current time, `vj` (y, z) being the journal velocity received for
    /// now (the input, set or not yet set for this point): the journal as seen through the
    /// line is the trapezoidal integral up to now with `vj` at the end, its acceleration the
    /// slope of the velocity samples since the last one used (0 at the start).
    pub fn outputs(&self, vj: [f64; AXES]) -> RotorOutputs {
        let p = &self.rhs.p;
        let t = self.integ.t();
        let y = self.integ.y();
        let s = &self.seen;
        let dt = t - s.t;
        let mut journal_x = p.journal0;
        let mut journal_v = [0.0; 3];
        let mut journal_a = [0.0; 3];
        for a in 0..AXES {
            journal_x[1 + a] = s.x[a] + 0.5 * dt * (s.v[a] + vj[a]);
            journal_v[1 + a] = vj[a];
            if dt > 0.0 {
                journal_a[1 + a] = (vj[a] - s.v[a]) / dt;
            }
        }
        let (w, _, phi) = p.speed(t - self.rhs.t0);
        RotorOutputs {
            journal_x,
            journal_v,
            journal_a,
            disk: [y[0], y[1]],
            disk_v: [y[2], y[3]],
            speed: w,
            angle: phi.rem_euclid(std::f64::consts::TAU),
            unbalance: p.unbalance_force(t - self.rhs.t0),
            bearing_force: [0.0; 3],
            tlm_c0: self.line.c0(),
            tlm_c1: self.line.c1(),
            tlm_zc: self.line.impedance(),
        }
    }

    /// The state to continue from (the parameters are not included).
    pub fn snapshot(&self) -> TlmSnapshot {
        TlmSnapshot {
            integrator: self.integ.snapshot(),
            line: self.line.history(),
            journal: self.seen,
        }
    }

    /// Restores a [`TlmRotor::snapshot`] taken from a rotor with the same parameters.
    pub fn restore(&mut self, s: &TlmSnapshot) -> Result<(), String> {
        self.integ
            .restore(&s.integrator)
            .map_err(|e| e.to_string())?;
        self.line.set_history(s.line);
        self.seen = s.journal;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rotor without gravity and external load on a linear bearing given through the
    /// interface Jacobian (F = −k x − c v exactly, since F_k = −k x_k − c v_k at every step).
    fn on_spring(p: &RotorParams, k: f64, c: f64, t_end: f64, h: f64) -> (Rotor, Vec<[f64; 3]>) {
        let mut r = Rotor::new(p, 0.0, 1e-10).unwrap();
        let mut hist = Vec::new();
        let n = (t_end / h).round() as usize;
        for i in 0..n {
            let y = r.state().to_vec();
            let mut iface = InterfaceForce::default();
            for a in 0..3 {
                iface.f[a] = -k * y[a] - c * y[3 + a];
                iface.k[a][a] = -k;
                iface.c[a][a] = -c;
            }
            r.set_interface(iface);
            r.advance((i + 1) as f64 * h).unwrap();
            let y = r.state();
            hist.push([r.t(), y[1], y[2]]);
        }
        (r, hist)
    }

    fn quiet(p: &mut RotorParams) {
        p.gravity = 0.0;
        p.load = [0.0; 3];
        p.unbalance = 0.0;
    }

    /// A constant axial force accelerates the journal at F/(m_j + m_d), or at F/m_j when the
    /// disk does not ride axially (`disk.axial = 0`): x = F t²/(2 m_a).
    #[test]
    fn axial_inertia_follows_disk_axial() {
        for (axial, m_a) in [(true, 10.0), (false, 2.0)] {
            let mut p = RotorParams {
                disk_axial: axial,
                ..RotorParams::default()
            };
            quiet(&mut p);
            p.speed_initial = 0.0;
            p.speed_final = 0.0;
            let mut r = Rotor::new(&p, 0.0, 1e-10).unwrap();
            r.set_interface(InterfaceForce {
                f: [100.0, 0.0, 0.0],
                ..InterfaceForce::default()
            });
            r.advance(1e-3).unwrap();
            let exact = 100.0 * 1e-6 / (2.0 * m_a);
            let x = r.state()[0];
            assert!(
                (x - exact).abs() < 1e-9 * exact,
                "disk.axial {axial}: {x} vs {exact}"
            );
        }
    }

    #[test]
    fn free_vibration_matches_the_damped_oscillator() {
        let mut p = RotorParams {
            disk_mass: 0.0,
            journal_mass: 2.0,
            journal0: [0.0, 1e-5, -2e-5],
            ..RotorParams::default()
        };
        quiet(&mut p);
        let (k, zeta) = (1.0e8, 0.02);
        let m: f64 = 2.0;
        let w = (k / m).sqrt();
        let c = 2.0 * zeta * m * w;
        let (r, hist) = on_spring(&p, k, c, 0.005, 1e-4);
        let wd = w * (1.0 - zeta * zeta).sqrt();
        for (x0, col) in [(1e-5, 1), (-2e-5, 2)] {
            for row in &hist {
                let t = row[0];
                let exact =
                    x0 * (-zeta * w * t).exp() * ((wd * t).cos() + zeta * w / wd * (wd * t).sin());
                assert!(
                    (row[col] - exact).abs() < 1e-6 * x0.abs(),
                    "t = {t}: {} vs closed form {exact}",
                    row[col]
                );
            }
        }
        // axial: no spring force was applied except the interface law along x (x0 = 0): stays 0
        assert_eq!(r.state()[0], 0.0);
    }

    /// Steady unbalance response of the two-mass rotor on a linear isotropic bearing
    /// (k_b, c_b), solved as a complex 2×2 system: the independent reference.
    fn two_mass_amplitudes(p: &RotorParams, kb: f64, cb: f64, w: f64) -> (f64, f64) {
        #[derive(Clone, Copy)]
        struct C(f64, f64);
        let mul = |a: C, b: C| C(a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let sub = |a: C, b: C| C(a.0 - b.0, a.1 - b.1);
        let div = |a: C, b: C| {
            let d = b.0 * b.0 + b.1 * b.1;
            C((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let ks = C(p.shaft_k, w * p.shaft_c);
        // [kb + ks − mj w² + i w (cb+cj), −ks; −ks, ks − md w²] [xj; xd] = [0; mu e w²]
        let a11 = C(
            kb + p.shaft_k - p.journal_mass * w * w,
            w * (cb + p.journal_c + p.shaft_c),
        );
        let a12 = C(-ks.0, -ks.1);
        let a22 = C(p.shaft_k - p.disk_mass * w * w, w * p.shaft_c);
        let f = C(p.unbalance * w * w, 0.0);
        let det = sub(mul(a11, a22), mul(a12, a12));
        let xj = div(mul(C(-a12.0, -a12.1), f), det);
        let xd = div(mul(a11, f), det);
        (xj.0.hypot(xj.1), xd.0.hypot(xd.1))
    }

    #[test]
    fn unbalance_response_matches_the_linear_two_mass_rotor() {
        let (kb, cb) = (5.0e7, 2000.0);
        for rpm in [3000.0, 4800.0, 7000.0] {
            let w = rpm * std::f64::consts::PI / 30.0;
            let mut p = RotorParams {
                speed_initial: w,
                speed_final: w,
                shaft_c: 800.0, // ζ ≈ 0.1 for a quick decay of the transient
                ..RotorParams::default()
            };
            p.gravity = 0.0;
            p.load = [0.0; 3];
            let (r, hist) = on_spring(&p, kb, cb, 0.25, 2e-4);
            let _ = r;
            // amplitude of the journal orbit over the last 0.05 s (circular orbit)
            let tail: Vec<_> = hist.iter().filter(|h| h[0] > 0.2).collect();
            let amp_j = tail
                .iter()
                .map(|h| h[1].hypot(h[2]))
                .fold(0.0_f64, f64::max);
            let (aj, _) = two_mass_amplitudes(&p, kb, cb, w);
            assert!(
                (amp_j / aj - 1.0).abs() < 2e-3,
                "{rpm} rpm: journal amplitude {amp_j:e} vs linear rotor {aj:e}"
            );
        }
    }

    #[test]
    fn disk_resonance_of_the_default_rotor_is_near_the_shaft_critical_speed() {
        // On a rigid bearing the disk's critical speed is sqrt(k_s/m_d); the two-mass reference
        // on a very stiff bearing must peak there (checks the reference's algebra, too).
        let p = RotorParams::default();
        let wc = (p.shaft_k / p.disk_mass).sqrt();
        let peak = (0..2000)
            .map(|i| 0.5 * wc + i as f64 * wc / 2000.0)
            .max_by(|a, b| {
                let fa = two_mass_amplitudes(&p, 1e12, 0.0, *a).1;
                let fb = two_mass_amplitudes(&p, 1e12, 0.0, *b).1;
                fa.total_cmp(&fb)
            })
            .unwrap();
        assert!((peak / wc - 1.0).abs() < 2e-3, "peak {peak} vs {wc}");
    }

    #[test]
    fn speed_ramp_angle_is_the_integral_of_the_speed() {
        let p = RotorParams {
            speed_initial: 100.0,
            speed_final: 600.0,
            speed_rate: 2000.0,
            ..RotorParams::default()
        };
        assert!((p.ramp_time() - 0.25).abs() < 1e-15);
        let n = 100_000;
        let t_end = 0.4;
        let mut phi = 0.0;
        for i in 0..n {
            let (a, b) = (
                i as f64 * t_end / n as f64,
                (i + 1) as f64 * t_end / n as f64,
            );
            phi += 0.5 * (p.speed(a).0 + p.speed(b).0) * (b - a);
        }
        let (w, wd, phi_c) = p.speed(t_end);
        assert_eq!(w, 600.0);
        assert_eq!(wd, 0.0);
        assert!((phi - phi_c).abs() < 1e-6, "{phi} vs {phi_c}");
        assert_eq!(p.speed(0.1).1, 2000.0);
        // a run-down ramps the other way
        let q = RotorParams {
            speed_initial: 600.0,
            speed_final: 100.0,
            speed_rate: 1000.0,
            ..RotorParams::default()
        };
        assert!((q.speed(0.1).0 - 500.0).abs() < 1e-12);
    }

    #[test]
    fn gravity_and_load_give_the_static_equilibrium_on_a_spring() {
        // rigid 2 kg rotor on k = 1e8 N/m: static deflection (L − m g ẑ)/k
        let mut p = RotorParams {
            disk_mass: 0.0,
            unbalance: 0.0,
            journal_c: 4000.0,
            ..RotorParams::default()
        };
        p.load = [400.0, 100.0, -200.0];
        let k = 1e8;
        let (r, _) = on_spring(&p, k, 0.0, 0.05, 1e-4);
        let y = r.state();
        let expect = [400.0 / k, 100.0 / k, (-200.0 - 2.0 * 9.81) / k];
        for a in 0..3 {
            assert!(
                (y[a] - expect[a]).abs() < 1e-6 * expect[a].abs(),
                "axis {a}: {} vs {}",
                y[a],
                expect[a]
            );
        }
    }

    #[test]
    fn linear_extrapolated_force_is_integrated_exactly() {
        // rigid rotor, F = F0 + dF t along y, no spring: y = F0 t²/2m + dF t³/6m
        let mut p = RotorParams {
            disk_mass: 0.0,
            ..RotorParams::default()
        };
        quiet(&mut p);
        let mut r = Rotor::new(&p, 0.0, 1e-10).unwrap();
        r.set_interface(InterfaceForce {
            f: [0.0, 10.0, 0.0],
            df: [0.0, 3000.0, 0.0],
            ..Default::default()
        });
        r.advance(0.01).unwrap();
        let t: f64 = 0.01;
        let exact = (10.0 * t * t / 2.0 + 3000.0 * t.powi(3) / 6.0) / 2.0;
        assert!((r.state()[1] - exact).abs() < 1e-9 * exact);
    }

    #[test]
    fn unbalance_force_is_the_reaction_of_the_eccentric_mass() {
        // U = −m_u · d²/dt² (e cos φ, e sin φ), by central differences of the closed-form
        // angle, during a run-up (Ω̇ ≠ 0) and after it
        let p = RotorParams {
            speed_initial: 200.0,
            speed_final: 900.0,
            speed_rate: 4000.0,
            unbalance: 3e-4,
            ..RotorParams::default()
        };
        let pos = |tau: f64| {
            let phi = p.speed(tau).2;
            [phi.cos(), phi.sin()]
        };
        let h = 1e-5;
        for tau in [0.01, 0.09, 0.3] {
            let (a, b, c) = (pos(tau - h), pos(tau), pos(tau + h));
            let u = p.unbalance_force(tau);
            for i in 0..2 {
                let acc = (a[i] - 2.0 * b[i] + c[i]) / (h * h);
                let expect = -p.unbalance * acc;
                assert!(
                    (u[i] - expect).abs() < 1e-5 * p.unbalance * 900.0 * 900.0,
                    "τ = {tau}, axis {i}: {} vs {expect}",
                    u[i]
                );
            }
        }
    }

    #[test]
    fn invalid_parameters_are_named() {
        let p = RotorParams {
            journal_mass: 0.0,
            ..RotorParams::default()
        };
        assert!(p.validate().unwrap_err().0.contains("journal.mass"));
        let p = RotorParams {
            shaft_k: 0.0,
            ..RotorParams::default()
        };
        assert!(p.validate().unwrap_err().0.contains("shaft.k"));
        let p = RotorParams {
            unbalance: f64::NAN,
            ..RotorParams::default()
        };
        assert!(p.validate().unwrap_err().0.contains("unbalance"));
        let mut p = RotorParams::default();
        p.load[2] = f64::INFINITY;
        assert!(p.validate().unwrap_err().0.contains("load.Fz"));
    }
}

#[cfg(test)]
mod tlm_tests {
    use super::*;

    /// The default rotor's disk and shaft in coupling mode tlm with delay `t`, without
    /// gravity, unbalance, loads or shaft damping.
    fn quiet_tlm(t: f64) -> RotorParams {
        RotorParams {
            coupling: Coupling::Tlm,
            tlm_delay: t,
            gravity: 0.0,
            unbalance: 0.0,
            load: [0.0; 3],
            shaft_c: 0.0,
            ..RotorParams::default()
        }
    }

    /// The rotor released with the line carrying `f0` onto the disk (the disk displaced by
    /// −f0/k_s from the line's rest length), at rest.
    fn released(p: &RotorParams, f0: [f64; 2]) -> TlmRotor {
        let mut r = TlmRotor::new(p, 0.0, 1e-10).unwrap();
        r.line = TlmLine::at_rest(p.shaft_k, p.shaft_c, p.tlm_delay, f0).unwrap();
        r
    }

    /// Angular frequency of the disk's z velocity from its upward zero crossings (linear
    /// interpolation between steps), the journal held still.
    fn disk_frequency(t: f64, periods: f64) -> f64 {
        let p = quiet_tlm(t);
        let mut r = released(&p, [0.0, -100.0]);
        let w0 = (p.shaft_k / p.disk_mass).sqrt();
        let n = (periods * std::f64::consts::TAU / w0 / t).ceil() as usize;
        let mut crossings = Vec::new();
        let mut prev = (0.0, r.state()[3]);
        for k in 1..=n {
            r.step([0.0; 2], k as f64 * t).unwrap();
            let now = (r.t(), r.state()[3]);
            if prev.1 < 0.0 && now.1 >= 0.0 {
                crossings.push(prev.0 + (now.0 - prev.0) * prev.1 / (prev.1 - now.1));
            }
            prev = now;
        }
        assert!(crossings.len() >= 5, "{} crossings", crossings.len());
        let (a, b) = (crossings[0], crossings[crossings.len() - 1]);
        std::f64::consts::TAU * (crossings.len() - 1) as f64 / (b - a)
    }

    #[test]
    fn disk_on_the_line_against_a_still_journal_rings_at_the_shaft_frequency() {
        let p = quiet_tlm(1e-5);
        let w0 = (p.shaft_k / p.disk_mass).sqrt();
        let fine = disk_frequency(1e-5, 20.0) / w0 - 1.0;
        assert!(fine.abs() < 0.01, "T = 1e-5: ω/ω0 − 1 = {fine:e}");
        // the error is the line's parasitic mass: below k_s T² / m_d
        let bound = p.shaft_k * 1e-10 / p.disk_mass;
        assert!(fine < 0.0 && -fine < bound, "{fine:e} vs {bound:e}");
        // second order in T: ten times the delay, a hundred times the error
        let coarse = disk_frequency(1e-4, 20.0) / w0 - 1.0;
        let ratio = coarse / fine;
        assert!((70.0..140.0).contains(&ratio), "error ratio {ratio}");
    }

    #[test]
    fn the_line_against_a_rigid_wall_is_passive_at_a_coarse_delay() {
        // ω T = 0.5: the disk's energy plus the waves' on the line must not grow. Counted from
        // the samples (linear waves), the line's energy fluctuates inside a period by the
        // quadrature's O((ωT)²), about 1 % here; an unstable scheme would grow exponentially.
        let t = 1e-3;
        let p = quiet_tlm(t);
        let f0 = [60.0, -100.0];
        let mut r = released(&p, f0);
        let energy = |r: &TlmRotor| {
            let v = &r.state()[2..];
            0.5 * p.disk_mass * (v[0] * v[0] + v[1] * v[1]) + r.line().wave_energy([0.0; 2])
        };
        let e0 = energy(&r);
        let spring = (f0[0] * f0[0] + f0[1] * f0[1]) / (2.0 * p.shaft_k);
        assert!((e0 / spring - 1.0).abs() < 1e-14, "{e0} vs {spring}");
        let mut e = Vec::with_capacity(10_000);
        for k in 1..=10_000 {
            r.step([0.0; 2], k as f64 * t).unwrap();
            e.push(energy(&r));
        }
        let max = e.iter().cloned().fold(0.0, f64::max);
        assert!(max <= 1.015 * e0, "max energy {max} vs initial {e0}");
        let first = e[..1000].iter().cloned().fold(0.0, f64::max);
        let last = e[9000..].iter().cloned().fold(0.0, f64::max);
        assert!(last <= first, "energy grows: {last} after {first}");
        assert!(e[9999] <= e0);
    }

    #[test]
    fn at_rest_under_gravity_the_line_carries_the_disk_weight_unchanged() {
        let p = RotorParams {
            coupling: Coupling::Tlm,
            unbalance: 0.0,
            ..RotorParams::default()
        };
        let w = -p.disk_mass * p.gravity;
        let mut r = TlmRotor::new(&p, 0.5, 1e-8).unwrap();
        let o = r.outputs([0.0; 2]);
        assert_eq!((o.tlm_c0, o.tlm_c1), ([0.0, w], [0.0, w]));
        assert_eq!(o.tlm_zc, p.shaft_k * p.tlm_delay + p.shaft_c);
        let z0 = r.state()[1];
        for k in 1..=100 {
            r.step([0.0; 2], 0.5 + k as f64 * p.tlm_delay).unwrap();
            let o = r.outputs([0.0; 2]);
            for c in [o.tlm_c0, o.tlm_c1] {
                assert_eq!(c[0], 0.0);
                assert!((c[1] / w - 1.0).abs() <= 1e-9, "step {k}: {c:?}");
            }
            assert_eq!(o.disk_v, [0.0; 2]);
            assert_eq!(r.state()[1], z0);
        }
        // the disk hangs its sag below the journal
        assert!((z0 - (p.journal0[2] - p.disk_mass * p.gravity / p.shaft_k)).abs() < 1e-18);
    }

    #[test]
    fn the_journal_seen_through_the_line_is_the_trapezoidal_integral_of_its_velocity() {
        let t = 1e-4;
        let p = RotorParams {
            journal0: [1e-6, 2e-6, -3e-6],
            ..quiet_tlm(t)
        };
        let mut r = TlmRotor::new(&p, 0.0, 1e-8).unwrap();
        let o = r.outputs([0.3, -0.1]);
        assert_eq!(o.journal_x, p.journal0);
        assert_eq!(o.journal_v, [0.0, 0.3, -0.1]);
        assert_eq!(o.journal_a, [0.0; 3]);
        // v = (a_y t, a_z t): the trapezoidal rule is exact, x = x0 + a t²/2
        let acc = [2.0, -5.0];
        for k in 0..50 {
            let tk = k as f64 * t;
            r.step([acc[0] * tk, acc[1] * tk], tk + t).unwrap();
        }
        let tn = 50.0 * t;
        // before the input of the new point is set: extrapolated with the last sample
        let last = [acc[0] * 49.0 * t, acc[1] * 49.0 * t];
        let o = r.outputs(last);
        assert_eq!(o.journal_a[1..], [0.0, 0.0]);
        // with it
        let vn = [acc[0] * tn, acc[1] * tn];
        let o = r.outputs(vn);
        for a in 0..2 {
            let x = p.journal0[1 + a] + 0.5 * acc[a] * tn * tn;
            assert!((o.journal_x[1 + a] - x).abs() < 1e-18, "axis {a}");
            assert!((o.journal_a[1 + a] / acc[a] - 1.0).abs() < 1e-9);
            assert_eq!(o.journal_v[1 + a], vn[a]);
        }
        assert_eq!(o.journal_x[0], p.journal0[0]);
        assert_eq!((o.journal_v[0], o.journal_a[0]), (0.0, 0.0));
    }

    #[test]
    fn tlm_mode_needs_a_disk_a_shaft_and_a_delay() {
        let base = RotorParams {
            coupling: Coupling::Tlm,
            ..RotorParams::default()
        };
        assert!(base.validate().is_ok());
        let e = RotorParams {
            disk_mass: 0.0,
            ..base.clone()
        }
        .validate()
        .unwrap_err();
        assert!(
            e.0.starts_with("disk.mass = 0 kg") && e.0.contains("coupling = 1"),
            "{e}"
        );
        let e = RotorParams {
            shaft_k: 0.0,
            ..base.clone()
        }
        .validate()
        .unwrap_err();
        assert!(
            e.0.starts_with("shaft.k = 0 N/m") && e.0.contains("coupling = 1"),
            "{e}"
        );
        let e = RotorParams {
            tlm_delay: 0.0,
            ..base.clone()
        }
        .validate()
        .unwrap_err();
        assert!(e.0.starts_with("tlm.delay = 0 s"), "{e}");
        // the force mode does not care about the delay, and TlmRotor checks whatever the mode
        let force = RotorParams {
            tlm_delay: 0.0,
            coupling: Coupling::Force,
            ..base.clone()
        };
        assert!(force.validate().is_ok());
        assert!(TlmRotor::new(&force, 0.0, 1e-8).is_err());
        assert_eq!(Coupling::from_code(1), Some(Coupling::Tlm));
        assert_eq!(Coupling::from_code(0), Some(Coupling::Force));
        assert_eq!(Coupling::from_code(2), None);
        assert_eq!(Coupling::Tlm.code(), 1);
    }

    #[test]
    fn a_restored_snapshot_continues_bit_exactly() {
        let p = RotorParams {
            coupling: Coupling::Tlm,
            speed_rate: 3000.0,
            speed_final: 1500.0,
            ..RotorParams::default()
        };
        let t = p.tlm_delay;
        let vj = |k: usize| {
            [
                1e-3 * (k as f64 * 0.3).sin(),
                -2e-3 * (k as f64 * 0.2).cos(),
            ]
        };
        let mut a = TlmRotor::new(&p, 0.0, 1e-8).unwrap();
        for k in 0..30 {
            a.step(vj(k), (k + 1) as f64 * t).unwrap();
        }
        let snap = a.snapshot();
        let mut b = TlmRotor::new(&p, 0.0, 1e-8).unwrap();
        b.restore(&snap).unwrap();
        for k in 30..60 {
            a.step(vj(k), (k + 1) as f64 * t).unwrap();
            b.step(vj(k), (k + 1) as f64 * t).unwrap();
        }
        assert_eq!(a.state(), b.state());
        assert_eq!(a.outputs(vj(60)), b.outputs(vj(60)));
        assert_eq!(a.line(), b.line());
    }

    #[test]
    fn a_later_start_time_shifts_the_run() {
        // the speed ramp, the unbalance and the line all count from the start time
        let p = RotorParams {
            coupling: Coupling::Tlm,
            speed_initial: 300.0,
            speed_final: 1200.0,
            speed_rate: 20_000.0,
            ..RotorParams::default()
        };
        let t = p.tlm_delay;
        let t1 = 0.375;
        let mut a = TlmRotor::new(&p, 0.0, 1e-10).unwrap();
        let mut b = TlmRotor::new(&p, t1, 1e-10).unwrap();
        assert_eq!(b.params(), &p);
        for k in 0..40 {
            let v = [1e-4 * (k as f64 * 0.5).sin(), 0.0];
            a.step(v, (k + 1) as f64 * t).unwrap();
            b.step(v, t1 + (k + 1) as f64 * t).unwrap();
        }
        let (oa, ob) = (a.outputs([0.0; 2]), b.outputs([0.0; 2]));
        for i in 0..2 {
            assert!((oa.disk[i] - ob.disk[i]).abs() < 1e-12, "{oa:?} vs {ob:?}");
            assert!((oa.unbalance[i] - ob.unbalance[i]).abs() < 1e-9 * oa.unbalance[i].abs());
        }
        assert!((oa.speed - ob.speed).abs() < 1e-9 * oa.speed && oa.speed > 300.0);
        assert!((oa.angle - ob.angle).abs() < 1e-9);
        // its work counters are the integrator's
        let s = a.snapshot().integrator.stats;
        assert_eq!(a.stats(), (s.steps, s.rejected, s.rhs_evals));
        assert!(s.steps >= 40 && s.rhs_evals >= 6 * s.steps, "{s:?}");
        assert_eq!(Coupling::Tlm.name(), "tlm");
        assert_eq!(Coupling::Force.name(), "force");
    }

    #[test]
    fn a_step_that_does_not_go_forward_changes_nothing() {
        let p = RotorParams {
            coupling: Coupling::Tlm,
            ..RotorParams::default()
        };
        let mut r = TlmRotor::new(&p, 0.0, 1e-8).unwrap();
        r.step([1e-3, 0.0], 1e-4).unwrap();
        let before = r.snapshot();
        let e = r.step([1e-3, 0.0], 1e-4).unwrap_err();
        assert_eq!(e.t, 1e-4);
        assert_eq!(r.snapshot(), before);
    }
}

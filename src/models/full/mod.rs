//! L4: the full dynamic model of the paper (spec §1–§5, §7).
//!
//! Every ball is a rigid body with 9 states (position and velocity in inertial cylindrical
//! coordinates, inertial angular velocity); the inner ring translates and tilts with its spin
//! prescribed (C4); the outer ring moves with the 2-DOF pedestal (C3). Each ball touches each
//! race through a Hertz contact whose angle follows the geometry (§2.2), with contact damping
//! (C6) and strip traction from the slip of ball against race (§3). A spall on either race
//! removes the finite-ball drop from the approach, tilts the contact force and changes the
//! Hertz constant (§4). Centrifugal and Coriolis forces come from the cylindrical equations
//! of motion and gyroscopic moments through the contact friction moments (§5.1).
//!
//! Stages: [`layout`] (state vector), [`contact`] (geometry, Hertz, defect, strips),
//! [`init`] (initial state from L1, §7); this module holds the equations of motion (§5) and
//! the [`Model`] implementation, including the spall-edge state events (solvers.md).

pub mod contact;
pub mod init;
pub mod layout;
pub mod pass;
pub mod steady;
pub mod switches;

use self::contact::{cross, dot, sub, BallKin, ContactOut, RaceConst, RingPose, Strips, V3};
use self::layout::*;
use self::switches::{SwitchedModel, Switches};
use super::Model;
use crate::contact::traction::TractionCurve;
use crate::defect::Defect;
use crate::defect::DefectSpec;
use crate::geometry::{Bearing, Race};
use crate::models::{Inputs, SimError};
use crate::quasi_static::QuasiStatic;
use crate::scene::{Pulse, Scene};
use std::f64::consts::TAU;

/// Switches of the full model that are not part of a scene (diagnostics and tests).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FullOptions {
    /// Strip traction on (default) or frictionless contacts.
    pub traction: bool,
    /// Hold the inner-ring tilt at zero (as L1 does); off by default (the paper's model).
    pub lock_tilt: bool,
}

impl Default for FullOptions {
    fn default() -> Self {
        Self {
            traction: true,
            lock_tilt: false,
        }
    }
}

/// The L4 model.
pub struct FullModel {
    lay: Layout,
    z: usize,
    ball_mass: f64,
    ball_inertia: f64,
    ball_radius: f64,
    pitch_radius: f64,
    inner: RaceConst,
    outer: RaceConst,
    c_br: f64,
    traction: Option<(TractionCurve, Strips)>,
    m_ir: f64,
    lock_tilt: bool,
    i_polar: f64,
    i_diam: f64,
    m_p: f64,
    k_py: f64,
    k_pz: f64,
    c_py: f64,
    c_pz: f64,
    pulse: Option<Pulse>,
    defect: Option<Defect>,
    /// Semi-major-axis factor of the spall-edge contact.
    defect_a_star: f64,
    inputs: Inputs,
    /// Reference cage speed ratio ψ̇/Ω.
    cage_ratio: f64,
    /// The steady-rotation solve of the start ([`FullModel::settle_report`]).
    settle: Option<steady::SteadyReport>,
    /// Why the start is not the one this model normally takes ([`Model::start_note`]).
    start_note: Option<String>,
    /// Each ball's orbital rate under L1's outer-race control [rad/s] (where the
    /// steady-rotation solve starts).
    l1_orbit: Vec<f64>,
    /// Azimuth of ball 0 at ψ = 0 [rad].
    theta_start: f64,
    /// Frozen spall halves, blend sides and contact modes, and their switches.
    sw: Switches,
    /// Normal forces of the last RHS evaluation (inner, outer) [N].
    q_inner: Vec<f64>,
    q_outer: Vec<f64>,
    /// Initial state (from L1, §7).
    y0: Vec<f64>,
    /// Scratch derivative for outputs.
    scratch: Vec<f64>,
    /// Force of the bearing on the inner ring and its moment (last RHS) [N], [N m].
    ring_force: V3,
    ring_moment: V3,
    /// Coupling mode "motion": the ring translation is prescribed (zero translational
    /// acceleration); the tilt stays a free degree of freedom (or held by `lock_tilt`).
    prescribed: bool,
    /// A located ring's held axial displacement \[m\] (its axial acceleration is zero).
    held_axial: Option<f64>,
    /// The start puts the pedestal at rest instead of at its static deflection (the bearing
    /// taken on its own: [`FullModel::healthy`]).
    centred: bool,
    /// RHS scratch: every ball's frame and contacts, the strip traction in one batch.
    pass: pass::ContactPass,
}

/// Per-race constants from the bearing (spec §2.1, §2.3, C7).
pub(crate) fn race_const(b: &Bearing, race: Race) -> RaceConst {
    let (xg, rg) = b.groove_centre(race);
    let f = b.f(race);
    let e = (f - 0.5) * b.d;
    // groove_centre moves the inner circle by the play; keep the touch distance e.
    RaceConst {
        xg,
        rg,
        e: match race {
            Race::Inner => e - b.clearance,
            Race::Outer => e,
        }
        .max(1e-9),
        k: b.k(race),
        k_cbrt: b.k(race).cbrt(),
        a_star: b.hertz(race).semi_axis_factors().0,
        rs: 2.0 * f * b.d / (2.0 * f + 1.0),
        sign: match race {
            Race::Inner => -1.0,
            Race::Outer => 1.0,
        },
    }
}

impl FullModel {
    /// Builds the model for a scene with the default options.
    pub fn new(scene: &Scene, bearing: &Bearing, inputs: &Inputs) -> Result<Self, SimError> {
        Self::with_options(scene, bearing, inputs, FullOptions::default())
    }

    /// Builds the model with explicit [`FullOptions`].
    pub fn with_options(
        scene: &Scene,
        bearing: &Bearing,
        inputs: &Inputs,
        options: FullOptions,
    ) -> Result<Self, SimError> {
        let held = super::held_axial(scene, bearing, inputs)?;
        Self::build(
            bearing,
            inputs,
            options,
            scene.defect.as_ref(),
            scene.pulse.clone(),
            None,
            (true, held),
        )
    }

    /// The healthy bearing without a pulse at L1's start (balls in outer-race control, no
    /// steady-rotation solve), from a given L1 solution at `inputs` (or from a new one), with
    /// the pedestal at rest (the bearing on its own, whatever its support): the base of
    /// [`steady::steady_rotation`] for the kinematic levels' cage speed.
    pub fn healthy(
        bearing: &Bearing,
        inputs: &Inputs,
        options: FullOptions,
        l1: Option<&QuasiStatic>,
    ) -> Result<Self, SimError> {
        Self::build(bearing, inputs, options, None, None, l1, (false, None))
    }

    #[allow(clippy::too_many_arguments)]
    fn build(
        bearing: &Bearing,
        inputs: &Inputs,
        options: FullOptions,
        defect: Option<&DefectSpec>,
        pulse: Option<Pulse>,
        l1: Option<&QuasiStatic>,
        (settle, held_axial): (bool, Option<f64>),
    ) -> Result<Self, SimError> {
        let file = &bearing.file;
        let z = bearing.z;
        if z == 0 {
            return Err(SimError::Input("the bearing has no balls".into()));
        }
        let lay = Layout { z };
        let traction = if options.traction {
            let curve = TractionCurve::new(&file.traction)?;
            Some((
                curve,
                Strips::with_rule(file.contact.strip_rule, file.contact.n_strips as usize),
            ))
        } else {
            None
        };
        let defect = match defect {
            Some(spec) => Some(Defect::new(
                spec,
                bearing,
                init::reference_ball_load(bearing, inputs),
            )?),
            None => None,
        };
        let defect_a_star = defect
            .as_ref()
            .map_or(0.0, |d| d.corner_hertz().semi_axis_factors().0);
        let mut m = Self {
            lay,
            z,
            ball_mass: bearing.ball_mass,
            ball_inertia: bearing.ball_inertia,
            ball_radius: bearing.ball_radius(),
            pitch_radius: 0.5 * bearing.dm,
            inner: race_const(bearing, Race::Inner),
            outer: race_const(bearing, Race::Outer),
            c_br: file.contact.c_br,
            traction,
            m_ir: file.inner_ring.mass,
            lock_tilt: options.lock_tilt,
            i_polar: file.inner_ring.i_polar,
            i_diam: file.inner_ring.i_diam,
            m_p: file.pedestal.mass,
            k_py: file.pedestal.k_y,
            k_pz: file.pedestal.k_z,
            c_py: file.pedestal.c_y,
            c_pz: file.pedestal.c_z,
            pulse,
            defect,
            defect_a_star,
            inputs: *inputs,
            cage_ratio: 0.5 * (1.0 - bearing.gamma(bearing.alpha0)),
            settle: None,
            start_note: None,
            l1_orbit: vec![0.0; z],
            theta_start: 0.0,
            sw: Switches::new(z),
            q_inner: vec![0.0; z],
            q_outer: vec![0.0; z],
            y0: vec![0.0; lay.dim()],
            scratch: vec![0.0; lay.dim()],
            ring_force: [0.0; 3],
            ring_moment: [0.0; 3],
            prescribed: false,
            held_axial,
            centred: !settle,
            pass: pass::ContactPass::new(z),
        };
        m.theta_start = init::choose_theta_start(z, m.defect.as_ref());
        init::initial_state(&mut m, bearing, l1)?;
        if settle && m.traction.is_some() && inputs.shaft_speed > 0.0 {
            // Start the balls in their steady rotation under the traction (the state they
            // settle to in ≈ 20 ms from L1's outer-race control): a quiet start. Each ball at
            // its own orbital rate, as this cage-less model runs; where some ball has no steady
            // rotation of its own, all at the caged one (the report says which).
            let mut y = m.y0.clone();
            m.update_mode(0.0, &y);
            let r = match steady::steady_rotation(&mut m, &mut y, steady::Orbit::Free, None) {
                Ok(r) => r,
                Err(why) => {
                    m.start_note = Some(format!(
                        "the balls start at the caged rate of their steady rotation, not each at \
                         its own: {why}"
                    ));
                    y.copy_from_slice(&m.y0);
                    steady::steady_rotation(&mut m, &mut y, steady::Orbit::Caged, None).map_err(
                        |e| {
                            SimError::Input(format!(
                                "the balls' steady rotation (the full model's start) at {}: {e}",
                                super::operating_point(inputs)
                            ))
                        },
                    )?
                }
            };
            m.y0 = y;
            m.cage_ratio = r.cage_speed / inputs.shaft_speed;
            m.settle = Some(r);
        }
        Ok(m)
    }

    /// The solve of the balls' steady rotation at the start (None without traction or at zero
    /// speed: then the start is L1's outer-race control).
    pub fn settle_report(&self) -> Option<steady::SteadyReport> {
        self.settle
    }

    /// The axial displacement a located inner ring is held at (None: the axial load acts).
    pub fn held_axial(&self) -> Option<f64> {
        self.held_axial
    }

    /// Why the start is not the one this model normally takes, if it is not.
    pub fn start_note(&self) -> Option<&str> {
        self.start_note.as_deref()
    }

    /// The state layout.
    pub fn layout(&self) -> Layout {
        self.lay
    }

    /// Normal forces of the last evaluation: (inner, outer) per ball \[N\].
    pub fn contact_forces(&self) -> (&[f64], &[f64]) {
        (&self.q_inner, &self.q_outer)
    }

    /// True when ball j is inside the spall zone |θ_bd| < θ_e (as of the last
    /// [`Model::update_mode`]).
    pub fn in_defect_zone(&self, j: usize) -> bool {
        j < self.z && self.sw.side(j) != 0.0
    }

    /// Both contacts of ball j at state y (inner, outer), with the spall half of the last
    /// [`Model::update_mode`] (diagnostics).
    pub fn ball_contacts(&self, y: &[f64], j: usize) -> (ContactOut, ContactOut) {
        let (kin, _, _, _, w) = self.ball_kin(y, j);
        self.contacts_of(y, j, &kin, w, &self.inner_pose(y), &self.outer_pose(y))
    }

    /// Slip fields of both contacts of ball j at state y (inner, outer; `None` where Q = 0),
    /// with the frozen modes of the last [`Model::update_mode`] (diagnostics: the input of the
    /// strip quadrature, see [`contact::strip_sums`]).
    pub fn ball_slip_fields(
        &self,
        y: &[f64],
        j: usize,
    ) -> (Option<contact::SlipField>, Option<contact::SlipField>) {
        let (kin, _, _, _, w) = self.ball_kin(y, j);
        let (inner, outer) = (self.inner_pose(y), self.outer_pose(y));
        let field = |pose: &RingPose, rc: &RaceConst, race: Race, k: usize| {
            contact::slip_field_law(
                &kin,
                pose,
                rc,
                self.ball_radius,
                self.c_br,
                self.spall_view(y, j, race, w),
                self.sw.law(j, k),
            )
        };
        (
            field(&inner, &self.inner, Race::Inner, 0),
            field(&outer, &self.outer, Race::Outer, 1),
        )
    }

    /// The traction curve and strip rule (`None` for frictionless contacts).
    pub fn traction(&self) -> Option<&(TractionCurve, Strips)> {
        self.traction.as_ref()
    }

    /// Ball-to-spall angle θ_bd of ball j \[rad\] (NaN without a spall; diagnostics).
    pub fn ball_theta_bd(&self, y: &[f64], j: usize) -> f64 {
        self.defect
            .as_ref()
            .map_or(f64::NAN, |d| self.theta_bd(d, y, j).0)
    }

    /// The spall, if any.
    pub fn defect(&self) -> Option<&Defect> {
        self.defect.as_ref()
    }

    #[inline(always)]
    fn inner_pose(&self, y: &[f64]) -> RingPose {
        let r = self.lay.ring();
        RingPose {
            p: [y[r + RX], y[r + RX + 1], y[r + RX + 2]],
            v: [y[r + RV], y[r + RV + 1], y[r + RV + 2]],
            beta: [0.0, y[r + RBY], y[r + RBZ]],
            beta_rate: [0.0, y[r + RWY], y[r + RWZ]],
            spin: self.inputs.shaft_speed,
        }
    }

    #[inline(always)]
    fn outer_pose(&self, y: &[f64]) -> RingPose {
        let p = self.lay.pedestal();
        RingPose {
            p: [0.0, y[p + PY], y[p + PZ]],
            v: [0.0, y[p + PVY], y[p + PVZ]],
            beta: [0.0; 3],
            beta_rate: [0.0; 3],
            spin: 0.0,
        }
    }

    /// Reference azimuth of ball j (ψ + θ_start + 2πj/z).
    #[inline(always)]
    fn theta_ref(&self, y: &[f64], j: usize) -> f64 {
        y[self.lay.psi()] + self.theta_start + TAU * j as f64 / self.z as f64
    }

    /// Ball j's kinematics and its cylindrical triad (e_r, e_θ), radius and orbital rate.
    #[inline(always)]
    fn ball_kin(&self, y: &[f64], j: usize) -> (BallKin, V3, V3, f64, f64) {
        let b = self.lay.ball(j);
        let theta = self.theta_ref(y, j) + y[b + BTH];
        let (s, c) = theta.sin_cos();
        let er = [0.0, -s, c];
        let et = [0.0, -c, -s];
        let r = self.pitch_radius + y[b + BR];
        let w = y[b + BW];
        let (vx, vr) = (y[b + BVX], y[b + BVR]);
        let kin = BallKin {
            p: [y[b + BX], r * er[1], r * er[2]],
            v: [vx, vr * er[1] + r * w * et[1], vr * er[2] + r * w * et[2]],
            omega: [y[b + BOM], y[b + BOM + 1], y[b + BOM + 2]],
        };
        (kin, er, et, r, w)
    }

    /// Both contacts of ball j, traction included (one ball at a time, as
    /// [`contact::evaluate_law`] does it).
    fn contacts_of(
        &self,
        y: &[f64],
        j: usize,
        kin: &BallKin,
        w: f64,
        inner: &RingPose,
        outer: &RingPose,
    ) -> (ContactOut, ContactOut) {
        let tr = self.traction.as_ref();
        let [(mut ci, li), (mut co, lo)] =
            self.normal_contacts(y, j, kin, w, inner, outer, tr.is_some());
        if let Some((curve, strips)) = tr {
            for (c, loaded) in [(&mut ci, li), (&mut co, lo)] {
                if let Some((sf, frame)) = loaded {
                    contact::apply_traction(c, &frame, contact::strip_sums(curve, strips, &sf));
                }
            }
        }
        (ci, co)
    }

    /// Ball-to-spall angle θ_bd of ball j and its rate (uses the defective ring's frame).
    fn theta_bd(&self, d: &Defect, y: &[f64], j: usize) -> (f64, f64) {
        let (kin, _, _, _, w) = self.ball_kin(y, j);
        let (pose, rate) = match d.ring() {
            Race::Inner => (self.inner_pose(y), w - self.inputs.shaft_speed),
            Race::Outer => (self.outer_pose(y), w),
        };
        (d.theta_bd(pose.azimuth(kin.p), y[self.lay.phi()]), rate)
    }

    /// Total mechanical energy \[J\]: kinetic (balls incl. rotation, inner-ring translation and
    /// tilt, pedestal) + Hertz potential (2/5)Kδ^{5/2} of the intact contacts + pedestal springs
    /// − work of the constant loads. Conserved without traction, damping and spall (§10 item 4);
    /// the prescribed spin does no work.
    pub fn energy(&self, y: &[f64]) -> f64 {
        let inner = self.inner_pose(y);
        let outer = self.outer_pose(y);
        let mut e = 0.0;
        for j in 0..self.z {
            let (kin, _, _, _, _) = self.ball_kin(y, j);
            e += 0.5 * self.ball_mass * dot(kin.v, kin.v)
                + 0.5 * self.ball_inertia * dot(kin.omega, kin.omega);
            for (pose, race) in [(&inner, &self.inner), (&outer, &self.outer)] {
                let c = contact::evaluate(&kin, pose, race, self.ball_radius, 0.0, None, None);
                if c.delta > 0.0 {
                    e += 0.4 * race.k * c.delta * c.delta * c.delta.sqrt();
                }
            }
        }
        let r = self.lay.ring();
        let p = self.lay.pedestal();
        e += 0.5 * self.m_ir * dot(inner.v, inner.v)
            + 0.5 * self.i_diam * (y[r + RWY].powi(2) + y[r + RWZ].powi(2))
            + 0.5 * self.m_p * (y[p + PVY].powi(2) + y[p + PVZ].powi(2))
            + 0.5 * self.k_py * y[p + PY].powi(2)
            + 0.5 * self.k_pz * y[p + PZ].powi(2)
            - (self.inputs.fx * inner.p[0]
                + self.inputs.fy * inner.p[1]
                + self.inputs.fz * inner.p[2]);
        e
    }

    /// Sum of the Hertz potentials (2/5)Kδ^{5/2} of all intact contacts \[J\] (energy scale).
    pub fn hertz_potential(&self, y: &[f64]) -> f64 {
        let inner = self.inner_pose(y);
        let outer = self.outer_pose(y);
        let mut e = 0.0;
        for j in 0..self.z {
            let (kin, _, _, _, _) = self.ball_kin(y, j);
            for (pose, race) in [(&inner, &self.inner), (&outer, &self.outer)] {
                let c = contact::evaluate(&kin, pose, race, self.ball_radius, 0.0, None, None);
                if c.delta > 0.0 {
                    e += 0.4 * race.k * c.delta * c.delta * c.delta.sqrt();
                }
            }
        }
        e
    }

    /// Mean orbital speed of the balls, Σθ̇/z [rad/s].
    pub fn mean_orbital_speed(&self, y: &[f64]) -> f64 {
        (0..self.z).map(|j| y[self.lay.ball(j) + BW]).sum::<f64>() / self.z as f64
    }

    /// Bearing friction (drive) torque of the last right-hand side: minus the moment of the
    /// contacts on the inner ring about its axis [N m].
    pub fn friction_torque(&self) -> f64 {
        -self.ring_moment[0]
    }
}

switches::impl_switched_model!(FullModel);

impl Model for FullModel {
    fn dim(&self) -> usize {
        self.lay.dim()
    }

    fn start_note(&self) -> Option<String> {
        self.start_note.clone()
    }

    fn state_name(&self, i: usize) -> String {
        let (lay, ring, pedestal) = (self.lay, self.lay.ring(), self.lay.pedestal());
        match i {
            _ if i < ring => ball_state_name(i / PER_BALL, i % PER_BALL, &["ω_x", "ω_y", "ω_z"]),
            _ if i < pedestal => ring_state_name(i - ring),
            _ if i < lay.psi() => pedestal_state_name(i - pedestal),
            _ if i == lay.psi() => "reference cage angle ψ".into(),
            _ if i == lay.phi() => "shaft angle φ".into(),
            _ => format!("state component {i}"),
        }
    }

    fn nominal(&self, out: &mut [f64]) {
        // Deflection-scale positions 1e-5 m, velocities 1e-2 m/s, angle deviations 1e-3 rad
        // (atol 1e-9 rad at rtol 1e-6), orbital rates 100 rad/s, spins 1e3 rad/s, tilts 1e-3.
        for j in 0..self.z {
            let b = self.lay.ball(j);
            out[b + BX] = 1e-5;
            out[b + BR] = 1e-5;
            out[b + BTH] = 1e-3;
            out[b + BVX] = 1e-2;
            out[b + BVR] = 1e-2;
            out[b + BW] = 100.0;
            for k in 0..3 {
                out[b + BOM + k] = 1e3;
            }
        }
        let r = self.lay.ring();
        for k in 0..3 {
            out[r + RX + k] = 1e-5;
            out[r + RV + k] = 1e-2;
        }
        out[r + RBY] = 1e-3;
        out[r + RBZ] = 1e-3;
        out[r + RWY] = 1.0;
        out[r + RWZ] = 1.0;
        let p = self.lay.pedestal();
        out[p + PY] = 1e-5;
        out[p + PZ] = 1e-5;
        out[p + PVY] = 1e-2;
        out[p + PVZ] = 1e-2;
        out[self.lay.psi()] = 1.0;
        out[self.lay.phi()] = 1.0;
    }

    fn initial_state(&self, y: &mut [f64]) {
        y.copy_from_slice(&self.y0);
    }

    fn set_inputs(&mut self, inputs: &Inputs, _t: f64, _y: &[f64]) -> Result<(), SimError> {
        self.inputs = *inputs;
        Ok(())
    }

    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let inner = self.inner_pose(y);
        let outer = self.outer_pose(y);
        let psi_rate = self.cage_ratio * self.inputs.shaft_speed;
        let mut f_ring: V3 = [0.0; 3];
        let mut m_ring: V3 = [0.0; 3];
        let mut f_outer: V3 = [0.0; 3];
        let (m, jb) = (self.ball_mass, self.ball_inertia);
        // Every ball's normal contacts first, then the strip traction of all loaded contacts
        // in one batch, then the equations of motion.
        let mut pass = std::mem::take(&mut self.pass);
        let (race_in, race_out, _, _) = self.contact_constants();
        pass.evaluate(
            self.z,
            self.traction.as_ref().map(|(c, s)| (c, s)),
            [&inner, &outer],
            [race_in, race_out],
            |j| self.ball_kin(y, j),
            |j, kin, w, slip, grooves, out| {
                self.normal_contacts_into(y, j, kin, w, &inner, &outer, slip, grooves, out)
            },
        );
        for j in 0..self.z {
            let b = self.lay.ball(j);
            let (kin, er, et, r, w) = pass.frames[j];
            let (ci, co) = &pass.contacts[j];
            self.sw.note_stage(t, j, ci, co);
            // Inside a step the frozen law may give a round-off-small negative force just
            // before a located loss of contact: report it as 0.
            self.q_inner[j] = ci.q.max(0.0);
            self.q_outer[j] = co.q.max(0.0);
            let f = contact::add(ci.f, co.f);
            let mo = contact::add(ci.m, co.m);
            let vr = y[b + BVR];
            dydt[b + BX] = y[b + BVX];
            dydt[b + BR] = vr;
            dydt[b + BTH] = w - psi_rate;
            dydt[b + BVX] = f[0] / m;
            dydt[b + BVR] = dot(f, er) / m + r * w * w;
            dydt[b + BW] = (dot(f, et) / m - 2.0 * vr * w) / r;
            dydt[b + BOM] = mo[0] / jb;
            dydt[b + BOM + 1] = mo[1] / jb;
            dydt[b + BOM + 2] = mo[2] / jb;
            // Reactions: on the inner ring −F_i with moment (r_b − r_r) × (−F_i) − M_i, the
            // normal part taken with the ring-frame normal (exact conjugate of the tilt).
            f_ring = sub(f_ring, ci.f);
            let arm = sub(kin.p, inner.p);
            let f_t = contact::add(ci.f, ci.qn);
            m_ring = contact::add(m_ring, cross(arm, ci.qn_ring));
            m_ring = sub(sub(m_ring, cross(arm, f_t)), ci.m);
            f_outer = sub(f_outer, co.f);
        }
        self.pass = pass;
        self.ring_force = f_ring;
        self.ring_moment = m_ring;
        let r = self.lay.ring();
        let om = self.inputs.shaft_speed;
        let ext = [self.inputs.fx, self.inputs.fy, self.inputs.fz];
        for k in 0..3 {
            dydt[r + RX + k] = y[r + RV + k];
            dydt[r + RV + k] = if self.prescribed || (k == 0 && self.held_axial.is_some()) {
                0.0
            } else {
                (ext[k] + f_ring[k]) / self.m_ir
            };
        }
        dydt[r + RBY] = y[r + RWY];
        dydt[r + RBZ] = y[r + RWZ];
        dydt[r + RWY] = (m_ring[1] - self.i_polar * om * y[r + RWZ]) / self.i_diam;
        dydt[r + RWZ] = (m_ring[2] + self.i_polar * om * y[r + RWY]) / self.i_diam;
        if self.lock_tilt {
            dydt[r + RWY] = 0.0;
            dydt[r + RWZ] = 0.0;
        }
        let p = self.lay.pedestal();
        let pulse = self.pulse.as_ref().map_or(0.0, |pl| pl.force(t));
        dydt[p + PY] = y[p + PVY];
        dydt[p + PZ] = y[p + PVZ];
        dydt[p + PVY] = (f_outer[1] - self.k_py * y[p + PY] - self.c_py * y[p + PVY]) / self.m_p;
        dydt[p + PVZ] =
            (f_outer[2] - self.k_pz * y[p + PZ] - self.c_pz * y[p + PVZ] - pulse) / self.m_p;
        dydt[self.lay.psi()] = psi_rate;
        dydt[self.lay.phi()] = om;
    }

    switches::switched_model_events!();

    switches::ball_model_outputs!();

    /// Analytic for frictionless contacts ([`contact::ring_translation_jacobian`] per intact
    /// inner contact; a contact the spall alters by central differences of its normal force).
    /// With traction on, `None`: the simulation then differentiates the full reaction (traction
    /// included) by central differences.
    fn reaction_jacobian(&mut self, _t: f64, y: &[f64]) -> Option<super::ReactionJacobian> {
        if self.traction.is_some() {
            return None;
        }
        let inner = self.inner_pose(y);
        let mut jac = super::ReactionJacobian::default();
        for j in 0..self.z {
            let (kin, _, _, _, w) = self.ball_kin(y, j);
            let dv = self.spall_view(y, j, Race::Inner, w);
            let (dfdx, dfdv) = match contact::ring_translation_jacobian(
                &kin,
                &inner,
                &self.inner,
                self.ball_radius,
                self.c_br,
                dv,
            ) {
                Some(m) => m,
                None => {
                    // Central differences of this contact's force on the ring.
                    let f = |pose: &RingPose| {
                        let c = contact::evaluate(
                            &kin,
                            pose,
                            &self.inner,
                            self.ball_radius,
                            self.c_br,
                            None,
                            dv,
                        );
                        c.qn
                    };
                    let mut m = ([[0.0; 3]; 3], [[0.0; 3]; 3]);
                    for k in 0..3 {
                        for (h, vel) in [(1e-10, false), (1e-5, true)] {
                            let (mut pp, mut pm) = (inner, inner);
                            if vel {
                                pp.v[k] += h;
                                pm.v[k] -= h;
                            } else {
                                pp.p[k] += h;
                                pm.p[k] -= h;
                            }
                            let (fp, fm) = (f(&pp), f(&pm));
                            for i in 0..3 {
                                let d = (fp[i] - fm[i]) / (2.0 * h);
                                if vel {
                                    m.1[i][k] = d;
                                } else {
                                    m.0[i][k] = d;
                                }
                            }
                        }
                    }
                    m
                }
            };
            for i in 0..3 {
                for k in 0..3 {
                    jac.dfdx[i][k] += dfdx[i][k];
                    jac.dfdv[i][k] += dfdv[i][k];
                }
            }
        }
        Some(jac)
    }

    fn in_spall_zone(&self, j: usize) -> bool {
        self.in_defect_zone(j)
    }
}

//! L4: the full dynamic model of the paper (docs/model.md#frames, #geometry, #strips, #spall, #eom, #initial-state).
//!
//! Every ball is a rigid body with 9 states (position and velocity in inertial cylindrical
//! coordinates, inertial angular velocity); the inner ring translates and tilts with its spin
//! prescribed (docs/model.md#c4); the outer ring moves with the 2-DOF pedestal (docs/model.md#c3). Each ball touches each
//! race through a Hertz contact whose angle follows the geometry (docs/model.md#contact-geometry), with contact damping
//! (docs/model.md#c6) and strip traction from the slip of ball against race (docs/model.md#strips). A spall on either race
//! removes the finite-ball drop from the approach, tilts the contact force and changes the
//! Hertz constant (docs/model.md#spall). Centrifugal and Coriolis forces come from the cylindrical equations
//! of motion and gyroscopic moments through the contact friction moments (docs/model.md#eom-ball).
//!
//! The parts shared with the reduced model (state layout, contacts, frozen modes, outputs) are
//! in [`super::balls`]; here: the initial state from L1 ([`init`], docs/model.md#initial-state), the balls' steady
//! rotation ([`steady`]), the equations of motion (docs/model.md#eom) and the [`Model`] implementation.

pub mod init;
pub mod steady;

use super::balls::ball_contact::{
    self as contact, cross, dot, sub, ContactOut, RaceConst, RingPose, Strips, V3,
};
use super::balls::layout::*;
use super::balls::{forward_to_ball_core, BallCore, BallSpin};
use super::Model;
use crate::contact::TractionCurve;
use crate::defect::{Defect, DefectSpec};
use crate::geometry::{Bearing, Race};
use crate::load_distribution::QuasiStatic;
use crate::models::{ReactionJacobian, SimError};
use crate::operating::OperatingPoint;
use crate::scene::{Pulse, Scene};

/// Switches of the full model that are not part of a scene (diagnostics and tests).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FullOptions {
    /// Strip traction on (default) or frictionless contacts.
    pub traction: bool,
    /// Hold the inner-ring tilt at zero (as L1 does; the default, decision D1).
    pub lock_tilt: bool,
    /// Free tilt: the shaft's tilt inertia the ring carries besides its own \[kg m²\].
    pub shaft_tilt_inertia: f64,
    /// Free tilt: the shaft's tilt stiffness \[N m/rad\].
    pub tilt_stiffness: f64,
}

impl Default for FullOptions {
    fn default() -> Self {
        let s = crate::scene::FullSettings::default();
        Self {
            traction: s.traction,
            lock_tilt: s.lock_tilt,
            shaft_tilt_inertia: s.shaft_tilt_inertia,
            tilt_stiffness: s.tilt_stiffness,
        }
    }
}

/// The L4 model.
#[derive(Clone)]
pub struct FullModel {
    /// What it shares with the reduced model (see [`BallCore`]).
    core: BallCore,
    traction: Option<(TractionCurve, Strips)>,
    lock_tilt: bool,
    i_polar: f64,
    /// Diametral inertia of the tilt: the ring's own plus the shaft's \[kg m²\].
    i_diam: f64,
    /// Tilt stiffness of the shaft \[N m/rad\].
    k_tilt: f64,
    /// The steady-rotation solve of the start ([`FullModel::settle_report`]).
    settle: Option<steady::SteadyReport>,
    /// Each ball's orbital rate under L1's outer-race control [rad/s] (where the
    /// steady-rotation solve starts).
    l1_orbit: Vec<f64>,
    /// Moment of the contacts on the inner ring (last RHS) [N m].
    ring_moment: V3,
    /// The start puts the pedestal at rest instead of at its static deflection (the bearing
    /// taken on its own: [`FullModel::healthy`]).
    centred: bool,
}

impl FullModel {
    /// The right-hand side ([`Model::rhs`] runs it compiled for AVX2 where the processor has
    /// it).
    #[inline(always)]
    fn rhs_body(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let c = &mut self.core;
        let inner = c.inner_pose(y);
        let outer = c.outer_pose(y);
        let psi_rate = c.cage_speed();
        let mut f_ring: V3 = [0.0; 3];
        let mut m_ring: V3 = [0.0; 3];
        let mut f_outer: V3 = [0.0; 3];
        let jb = c.ball_inertia;
        // Every ball's normal contacts first, then the strip traction of all loaded contacts
        // in one batch, then the equations of motion.
        let pass = c.contact_pass(
            y,
            self.traction.as_ref().map(|(cv, st)| (cv, st)),
            &inner,
            &outer,
        );
        let (touch, cage) = c.after_pass(t, y, &pass, &inner, &outer, psi_rate, dydt);
        for j in 0..c.z {
            let b = c.lay.ball(j);
            let (kin, er, et, r, w) = pass.frames[j];
            let (ci, co) = &pass.contacts[j];
            let mut f = contact::add(ci.f, co.f);
            let mut mo = contact::add(ci.m, co.m);
            if let (true, Some(bb)) = (touch, &c.ball_ball) {
                f = contact::add(f, bb.force[j]);
            }
            if let Some(pc) = c
                .cage
                .as_ref()
                .map(|cg| &cg.pockets[j])
                .filter(|p| p.p > 0.0)
            {
                f = contact::add(f, pc.f);
                mo = contact::add(mo, pc.m);
            }
            c.ball_translation(y, j, f, er, et, r, w, psi_rate, dydt);
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
        c.pass = pass;
        if let Some(r) = cage {
            f_ring = contact::add(f_ring, r.on_inner);
            m_ring = contact::add(m_ring, r.inner_moment);
            f_outer = contact::add(f_outer, r.on_outer);
        }
        c.ring_force = f_ring;
        self.ring_moment = m_ring;
        let c = &self.core;
        c.rings(t, y, f_ring, f_outer, psi_rate, dydt);
        let r = c.lay.ring();
        let om = c.inputs.shaft_speed;
        dydt[r + RBY] = y[r + RWY];
        dydt[r + RBZ] = y[r + RWZ];
        // The ring's spin carries its own polar inertia; the shaft's tilt inertia and
        // stiffness act on the tilt (decision D1).
        dydt[r + RWY] =
            (m_ring[1] - self.k_tilt * y[r + RBY] - self.i_polar * om * y[r + RWZ]) / self.i_diam;
        dydt[r + RWZ] =
            (m_ring[2] - self.k_tilt * y[r + RBZ] + self.i_polar * om * y[r + RWY]) / self.i_diam;
        if self.lock_tilt {
            dydt[r + RWY] = 0.0;
            dydt[r + RWZ] = 0.0;
        }
        c.direction_rates(y, dydt);
    }

    /// Builds the model for a scene with the default options.
    pub fn new(
        scene: &Scene,
        bearing: &Bearing,
        inputs: &OperatingPoint,
    ) -> Result<Self, SimError> {
        Self::with_options(scene, bearing, inputs, FullOptions::default())
    }

    /// Builds the model with explicit [`FullOptions`].
    pub fn with_options(
        scene: &Scene,
        bearing: &Bearing,
        inputs: &OperatingPoint,
        options: FullOptions,
    ) -> Result<Self, SimError> {
        let held = super::held_axial(scene, bearing, inputs)?;
        Self::build(
            bearing,
            inputs,
            options,
            &scene
                .spalls()
                .map(|(d, m)| (d.clone(), m))
                .collect::<Vec<_>>(),
            scene.pulse.clone(),
            None,
            (true, held, scene.full.cage),
            Some(scene),
        )
    }

    /// The healthy bearing without a pulse at L1's start (balls in outer-race control, no
    /// steady-rotation solve), from a given L1 solution at `inputs` (or from a new one), with
    /// the pedestal at rest (the bearing on its own, whatever its support), without a cage
    /// body: the base of [`steady::steady_rotation`] for the kinematic levels' cage speed.
    pub fn healthy(
        bearing: &Bearing,
        inputs: &OperatingPoint,
        options: FullOptions,
        l1: Option<&QuasiStatic>,
    ) -> Result<Self, SimError> {
        Self::build(
            bearing,
            inputs,
            options,
            &[],
            None,
            l1,
            (false, None, false),
            None,
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn build(
        bearing: &Bearing,
        inputs: &OperatingPoint,
        options: FullOptions,
        defects: &[(DefectSpec, Option<crate::config::DefectMode>)],
        pulse: Option<Pulse>,
        l1: Option<&QuasiStatic>,
        (settle, held_axial, cage): (bool, Option<f64>, bool),
        distributed: Option<&Scene>,
    ) -> Result<Self, SimError> {
        let file = &bearing.file;
        let z = bearing.z;
        if z == 0 {
            return Err(SimError::Input("the bearing has no balls".into()));
        }
        let traction = if options.traction {
            let curve = TractionCurve::new(&file.traction)?;
            Some((
                curve,
                Strips::with_rule(file.contact.strip_rule, file.contact.n_strips as usize),
            ))
        } else {
            None
        };
        let mut core = BallCore::new(
            bearing,
            inputs,
            Layout::full(z).with_cage(cage),
            BallSpin::Free,
            true,
            defects,
            pulse,
            held_axial,
        )?;
        if let Some(scene) = distributed {
            // Before the start's steady-rotation solve, which then includes them.
            core.set_distributed(scene, bearing)?;
        }
        let mut m = Self {
            core,
            traction,
            lock_tilt: options.lock_tilt,
            i_polar: file.inner_ring.i_polar,
            i_diam: file.inner_ring.i_diam + options.shaft_tilt_inertia,
            k_tilt: options.tilt_stiffness,
            settle: None,
            l1_orbit: vec![0.0; z],
            ring_moment: [0.0; 3],
            centred: !settle,
        };
        m.l1_orbit = init::initial_state(&mut m.core, m.centred, bearing, l1)?;
        if settle && m.traction.is_some() && inputs.shaft_speed > 0.0 && cage {
            // With a cage the balls start in their caged steady rotation (one orbital rate, the
            // traction's orbital torques balanced over the balls, docs/model.md#cage-start),
            // solved without the cage's body; the cage turns with them.
            let mut y = m.core.y0.clone();
            m.update_mode(0.0, &y);
            let body = m.core.cage.take();
            let r = steady::steady_rotation(&mut m, &mut y, steady::Orbit::Caged, None);
            m.core.cage = body;
            let r = r.map_err(|e| {
                SimError::Input(format!(
                    "the balls' caged steady rotation (the full model's start) at {}: {e}",
                    super::operating_point(inputs)
                ))
            })?;
            y[m.core.lay.cage_block() + CW] = r.cage_speed;
            m.core.y0 = y;
            m.core.cage_ratio = r.cage_speed / inputs.shaft_speed;
            m.settle = Some(r);
        } else if settle && m.traction.is_some() && inputs.shaft_speed > 0.0 {
            // Start the balls in their steady rotation under the traction (the state they
            // settle to in ≈ 20 ms from L1's outer-race control): a quiet start. Each ball at
            // its own orbital rate, as this cage-less model runs; where some ball has no steady
            // rotation of its own, all at the caged one (the report says which).
            let mut y = m.core.y0.clone();
            m.update_mode(0.0, &y);
            let r = match steady::steady_rotation(&mut m, &mut y, steady::Orbit::Free, None) {
                Ok(r) => r,
                Err(why) => {
                    m.core.start_note = Some(format!(
                        "the balls start at the caged rate of their steady rotation, not each at \
                         its own: {why}"
                    ));
                    y.copy_from_slice(&m.core.y0);
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
            m.core.y0 = y;
            m.core.cage_ratio = r.cage_speed / inputs.shaft_speed;
            m.settle = Some(r);
        }
        m.core.init_ball_directions();
        Ok(m)
    }

    /// The solve of the balls' steady rotation at the start (None without traction or at zero
    /// speed: then the start is L1's outer-race control).
    pub fn settle_report(&self) -> Option<steady::SteadyReport> {
        self.settle
    }

    /// Puts the initial state back at L1's start (balls in outer-race control, before the
    /// steady-rotation solve), from the L1 solution `l1` at the model's inputs (or a new one).
    pub fn restart_from_l1(
        &mut self,
        bearing: &Bearing,
        l1: Option<&QuasiStatic>,
    ) -> Result<(), SimError> {
        self.l1_orbit = init::initial_state(&mut self.core, self.centred, bearing, l1)?;
        self.core.init_ball_directions();
        Ok(())
    }

    /// What the model shares with the reduced one: layout, poses, contacts, modes.
    pub fn core(&self) -> &BallCore {
        &self.core
    }

    /// The axial displacement a located inner ring is held at (None: the axial load acts).
    pub fn held_axial(&self) -> Option<f64> {
        self.core.held_axial()
    }

    /// Why the start is not the one this model normally takes, if it is not.
    pub fn start_note(&self) -> Option<&str> {
        self.core.start_note.as_deref()
    }

    /// The state layout.
    pub fn layout(&self) -> Layout {
        self.core.layout()
    }

    /// Normal forces of the last evaluation: (inner, outer) per ball \[N\].
    pub fn contact_forces(&self) -> (&[f64], &[f64]) {
        self.core.contact_forces()
    }

    /// True when ball j is inside the spall zone |θ_bd| < θ_e (as of the last
    /// [`Model::update_mode`]).
    pub fn in_defect_zone(&self, j: usize) -> bool {
        self.core.in_defect_zone(j)
    }

    /// Each ball's orbital rate under L1's outer-race control [rad/s] (where the
    /// steady-rotation solve starts).
    pub fn l1_orbit(&self) -> &[f64] {
        &self.l1_orbit
    }

    /// Both contacts of ball j at state y (inner, outer), with the spall half of the last
    /// [`Model::update_mode`] (diagnostics).
    pub fn ball_contacts(&self, y: &[f64], j: usize) -> (ContactOut, ContactOut) {
        let c = &self.core;
        let (kin, _, _, _, w) = c.ball_kin(y, j);
        let tr = self.traction.as_ref();
        let [(mut ci, li), (mut co, lo)] = c.normal_contacts(
            y,
            j,
            &kin,
            w,
            &c.inner_pose(y),
            &c.outer_pose(y),
            tr.is_some(),
        );
        if let Some((curve, strips)) = tr {
            for (c, loaded) in [(&mut ci, li), (&mut co, lo)] {
                if let Some((sf, frame)) = loaded {
                    contact::apply_traction(c, &frame, contact::strip_sums(curve, strips, &sf));
                }
            }
        }
        (ci, co)
    }

    /// Slip fields of both contacts of ball j at state y (inner, outer; `None` where Q = 0),
    /// with the frozen modes of the last [`Model::update_mode`] (diagnostics: the input of the
    /// strip quadrature, see [`contact::strip_sums`]).
    pub fn ball_slip_fields(
        &self,
        y: &[f64],
        j: usize,
    ) -> (Option<contact::SlipField>, Option<contact::SlipField>) {
        let c = &self.core;
        let (kin, _, _, _, w) = c.ball_kin(y, j);
        let (inner, outer) = (c.inner_pose(y), c.outer_pose(y));
        let field = |pose: &RingPose, rc: &RaceConst, race: Race, k: usize| {
            contact::slip_field_law(
                &kin,
                pose,
                rc,
                c.ball_radius,
                c.c_br,
                c.spall_view(y, j, race, w),
                c.added_approach(y, j, race, pose, &kin, w, None),
                c.sw.law(j, k),
            )
        };
        (
            field(&inner, &c.inner, Race::Inner, 0),
            field(&outer, &c.outer, Race::Outer, 1),
        )
    }

    /// The traction curve and strip rule (`None` for frictionless contacts).
    pub fn traction(&self) -> Option<&(TractionCurve, Strips)> {
        self.traction.as_ref()
    }

    /// Ball-to-spall angle θ_bd of ball j \[rad\] (NaN without a spall; diagnostics).
    pub fn ball_theta_bd(&self, y: &[f64], j: usize) -> f64 {
        self.core
            .defect()
            .map_or(f64::NAN, |d| self.core.theta_bd(d, y, j).0)
    }

    /// The spall, if any (the first of several).
    pub fn defect(&self) -> Option<&Defect> {
        self.core.defect()
    }

    /// Every spall.
    pub fn defects(&self) -> &[Defect] {
        self.core.defects()
    }

    /// Total mechanical energy \[J\]: kinetic (balls incl. rotation, inner-ring translation and
    /// tilt, pedestal, cage) + Hertz potential (2/5)Kδ^{5/2} of the intact contacts, of the
    /// ball-to-ball contacts and of the cage's pocket and land contacts + pedestal and tilt
    /// springs − work of the constant loads. Conserved without traction, damping and spall (docs/model.md#verification);
    /// the prescribed spin does no work.
    pub fn energy(&self, y: &[f64]) -> f64 {
        let c = &self.core;
        let inner = c.inner_pose(y);
        let outer = c.outer_pose(y);
        let mut e = 0.0;
        for j in 0..c.z {
            let (kin, _, _, _, _) = c.ball_kin(y, j);
            e += 0.5 * c.ball_mass * dot(kin.v, kin.v)
                + 0.5 * c.ball_inertia * dot(kin.omega, kin.omega);
            for (pose, race) in [(&inner, &c.inner), (&outer, &c.outer)] {
                let q = contact::evaluate(&kin, pose, race, c.ball_radius, 0.0, None, None);
                if q.delta > 0.0 {
                    e += 0.4 * race.k * q.delta * q.delta * q.delta.sqrt();
                }
            }
        }
        e += c.ball_ball_potential(y) + c.cage_energy(y);
        let r = c.lay.ring();
        let p = c.lay.pedestal();
        e += 0.5 * c.m_ir * dot(inner.v, inner.v)
            + 0.5 * self.i_diam * (y[r + RWY].powi(2) + y[r + RWZ].powi(2))
            + 0.5 * self.k_tilt * (y[r + RBY].powi(2) + y[r + RBZ].powi(2))
            + 0.5 * c.m_p * (y[p + PVY].powi(2) + y[p + PVZ].powi(2))
            + 0.5 * c.k_py * y[p + PY].powi(2)
            + 0.5 * c.k_pz * y[p + PZ].powi(2)
            - (c.inputs.fx * inner.p[0] + c.inputs.fy * inner.p[1] + c.inputs.fz * inner.p[2]);
        e
    }

    /// Sum of the Hertz potentials (2/5)Kδ^{5/2} of all intact contacts \[J\] (energy scale).
    pub fn hertz_potential(&self, y: &[f64]) -> f64 {
        self.core.hertz_potential(y)
    }

    /// Mean orbital speed of the balls, Σθ̇/z [rad/s].
    pub fn mean_orbital_speed(&self, y: &[f64]) -> f64 {
        self.core.mean_orbital_speed(y)
    }

    /// Bearing friction (drive) torque of the last right-hand side: minus the moment of the
    /// contacts on the inner ring about its axis [N m].
    pub fn friction_torque(&self) -> f64 {
        -self.ring_moment[0]
    }
}

impl Model for FullModel {
    forward_to_ball_core!();

    fn state_name(&self, i: usize) -> String {
        let lay = self.core.lay;
        let (ring, pedestal) = (lay.ring(), lay.pedestal());
        match i {
            _ if i < ring => ball_state_name(i / PER_BALL, i % PER_BALL, &["ω_x", "ω_y", "ω_z"]),
            _ if i < pedestal => ring_state_name(i - ring),
            _ if i < lay.psi() => pedestal_state_name(i - pedestal),
            _ if i == lay.psi() => "reference cage angle ψ".into(),
            _ if i == lay.phi() => "shaft angle φ".into(),
            _ if lay.cage && i >= lay.cage_block() && i < lay.spall_dir(0) => {
                cage_state_name(i - lay.cage_block())
            }
            _ => self
                .core
                .direction_state_name(i)
                .unwrap_or_else(|| format!("state component {i}")),
        }
    }

    fn nominal(&self, out: &mut [f64]) {
        // Deflection-scale positions 1e-5 m, velocities 1e-2 m/s, angle deviations 1e-3 rad
        // (atol 1e-9 rad at rtol 1e-6), orbital rates 100 rad/s, spins 1e3 rad/s, tilts 1e-3.
        let lay = self.core.lay;
        for j in 0..self.core.z {
            let b = lay.ball(j);
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
        let r = lay.ring();
        for k in 0..3 {
            out[r + RX + k] = 1e-5;
            out[r + RV + k] = 1e-2;
        }
        out[r + RBY] = 1e-3;
        out[r + RBZ] = 1e-3;
        out[r + RWY] = 1.0;
        out[r + RWZ] = 1.0;
        let p = lay.pedestal();
        out[p + PY] = 1e-5;
        out[p + PZ] = 1e-5;
        out[p + PVY] = 1e-2;
        out[p + PVZ] = 1e-2;
        out[lay.psi()] = 1.0;
        out[lay.phi()] = 1.0;
        self.core.cage_nominal(out);
        self.core.direction_nominal(out);
    }

    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        crate::vecmath::with_avx2(
            #[inline(always)]
            || self.rhs_body(t, y, dydt),
        )
    }

    /// Analytic for frictionless contacts (`ring_translation_jacobian` of `models/balls/ball_contact.rs` per intact
    /// inner contact; a contact the spall alters by central differences of its normal force).
    /// With traction on, `None`: the simulation then differentiates the full reaction (traction
    /// included) by central differences.
    fn reaction_jacobian(&mut self, _t: f64, y: &[f64]) -> Option<ReactionJacobian> {
        // Traction, or a cage riding on the inner ring's land: the simulation differentiates
        // the whole reaction by central differences instead.
        let inner_land = self
            .core
            .cage
            .as_ref()
            .is_some_and(|cg| cg.params.guidance == crate::config::CageGuidance::InnerLand);
        // The distributed defects' added approach turns with the ball's azimuth, which the
        // analytic form leaves out: central differences as well.
        let distributed = self.core.waviness.is_some() || self.core.roughness.is_some();
        if self.traction.is_some() || inner_land || distributed {
            return None;
        }
        let inner = self.core.inner_pose(y);
        let mut jac = ReactionJacobian::default();
        let c = &self.core;
        for j in 0..c.z {
            let (kin, _, _, _, w) = c.ball_kin(y, j);
            let dv = c.spall_view(y, j, Race::Inner, w);
            let (dfdx, dfdv) = match contact::ring_translation_jacobian(
                &kin,
                &inner,
                &c.inner,
                c.ball_radius,
                c.c_br,
                dv,
            ) {
                Some(m) => m,
                None => {
                    // Central differences of this contact's force on the ring.
                    let f = |pose: &RingPose| {
                        let c = contact::evaluate(
                            &kin,
                            pose,
                            &c.inner,
                            c.ball_radius,
                            c.c_br,
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

impl steady::SteadyBalls for FullModel {
    fn balls(&self) -> &BallCore {
        &self.core
    }

    fn l1_orbit(&self) -> &[f64] {
        &self.l1_orbit
    }

    fn ball_contacts(&self, y: &[f64], j: usize) -> (ContactOut, ContactOut) {
        FullModel::ball_contacts(self, y, j)
    }
}

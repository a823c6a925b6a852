//! L3: the reduced per-ball dynamic model (docs/model.md#l3).
//!
//! Every ball keeps the full model's translational states (x, r, θ and their rates in inertial
//! cylindrical coordinates) but only one rotational state: the spin rate ω_s about an attitude
//! axis `ê_s = cos β e_x − sin β e_r(θ)` whose angle β is fixed (from L1). The ball's inertial
//! angular velocity is `θ̇ e_x + ω_s ê_s`. The inner ring translates (no tilt, spin prescribed,
//! C4 (docs/model.md#c4)); the outer ring moves with the 2-DOF pedestal (docs/model.md#c3).
//!
//! The normal contacts are the full model's ([`super::balls::ball_contact::evaluate_law`]: geometry
//! with changing contact angles, Hertz with contact damping, the spall's three effects), with
//! the full model's frozen modes and their events ([`super::balls::switches::Switches`]), all held by the
//! [`BallCore`] it shares with the full model: the
//! contact switches (closing, opening), the spall half (edges and centre) and the C9 (docs/model.md#c9) blend
//! boundary are located on the dense output, and a frozen law holds between them.
//!
//! Traction is the full model's strip traction over the contact ellipse with [`L3_STRIPS`]
//! strips, the ball's angular velocity constrained to `θ̇ e_x + ω_s ê_s`. The spin obeys
//! `J ω̇_s = (Σ M_c)·ê_s` with M_c the contacts' moments about the ball centre; the other
//! components are taken up by the fixed-attitude constraint. Centrifugal and Coriolis forces
//! come from the cylindrical equations of motion (docs/model.md#eom-ball).
//!
//! This departs from docs/model.md#l3, which has one point at the ellipse centre with the rolling
//! component only, `F_t = −Q κ(|u2|) sign(u2) c2` (still available: [`ReducedOptions::strips`]
//! = 0): with nothing but the normal contacts acting across the groove, a ball's axial motion
//! rings on and runs over a spall do not converge with the tolerance, and without the spin and
//! the curvature across the ellipse the cage runs fast. The measurements are in
//! docs/research/spec-departures.md.
//!
//! The attitude β is not L1's outer-race control but the one the traction sets: the balls'
//! steady rotation solved on the full model at the start
//! ([`super::full::steady::steady_rotation`]), to which the full model's balls settle; with it
//! the cage speed and friction torque follow the full model's (docs/research/levels-reduced.md).
//!
//! State layout ([`Layout::reduced`]), deviations as in the full model (docs/model.md#tolerances): per ball j
//! (7 states from `7 j`): x, r − dm/2, θ − (ψ + θ_start + 2πj/z), ẋ, ṙ, θ̇, ω_s. Then the inner
//! ring (6 from `7 z`): x, y, z, ẋ, ẏ, ż; the pedestal (4 from `7 z + 6`): y_p, z_p, ẏ_p, ż_p;
//! the reference cage angle ψ (`7 z + 10`) and the shaft angle φ (`7 z + 11`). 7z + 12 states
//! (110 for z = 14; the 7z + 10 of docs/model.md#l3 plus the two bookkeeping angles the full model also has).
//!
//! The initial state is the full model's (docs/model.md#initial-state, from L1) with the balls' steady rotation,
//! reduced to these states.

use super::balls::ball_contact::{
    add, cross, dot, scale, sub, BallKin, ContactOut, RingPose, Strips, V3,
};
use super::balls::layout::{
    ball_state_name, cage_state_name, pedestal_state_name, ring_state_name, Layout, BOM, BR, BTH,
    BVR, BVX, BW, BX, CAGE_STATES, PVY, PVZ, PY, PZ, REDUCED_PER_BALL, RV, RX,
};
use super::balls::{forward_to_ball_core, BallCore, BallSpin};
use super::full::{steady::SteadyReport, FullModel, FullOptions};
use super::Model;
use crate::contact::TractionCurve;
use crate::defect::Defect;
use crate::geometry::Bearing;
use crate::models::SimError;
use crate::operating::OperatingPoint;
use crate::scene::Scene;
use std::f64::consts::TAU;

/// Traction strips of L3 by default ([`ReducedOptions::strips`]). Measured on the Sec. 3.5 outer
/// scene (0.1 s, DOP853 rtol 1e-6): mean cage speed 70.267 Hz with the original single rolling
/// point, 69.947 with 2 strips, 70.121 with 4, 70.127 with 10; the full model 70.030 (10 strips; 70.030 with 8).
pub const L3_STRIPS: usize = 4;

/// States per ball.
pub const PER_BALL: usize = REDUCED_PER_BALL;
/// Offset of the spin rate ω_s inside a ball's block (x, r, θ, ẋ, ṙ, θ̇ are at the full
/// model's offsets `layout::BX` … `layout::BW`).
pub const BWS: usize = BOM;
/// Switches of the reduced model that are not part of a scene (diagnostics and tests).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReducedOptions {
    /// Traction on (default) or frictionless contacts.
    pub traction: bool,
    /// Strips of the traction over the contact ellipse (default [`L3_STRIPS`]): the full
    /// model's strip traction (`evaluate_law` in `models/balls/ball_contact.rs`) with the ball's angular velocity
    /// constrained to `θ̇ e_x + ω_s ê_s`. 0 is the original L3 (docs/model.md#l3): one point at the
    /// ellipse centre, rolling component only. That variant leaves the ball's motion across the
    /// groove undamped and the cage 0.33 % fast; see the module notes.
    pub strips: usize,
}

impl Default for ReducedOptions {
    fn default() -> Self {
        Self {
            traction: true,
            strips: L3_STRIPS,
        }
    }
}

/// The L3 model.
#[derive(Clone)]
pub struct ReducedModel {
    /// What it shares with the full model (see [`BallCore`]).
    core: BallCore,
    traction: Option<TractionCurve>,
    /// Strip layout of the traction; `None`: one point, rolling component only (the original L3, docs/model.md#l3).
    strips: Option<Strips>,
    /// (cos β, sin β) of the fixed attitude angle.
    attitude: (f64, f64),
    /// The Newton solve of the balls' steady rotation behind the attitude (None without
    /// traction or at zero speed).
    settle: Option<SteadyReport>,
    /// Moment of the bearing on the inner ring about x (last RHS) [N m].
    ring_moment_x: f64,
}

/// One contact's rolling traction: force on the ball and the contact point relative to the
/// ball centre.
#[derive(Debug, Clone, Copy, Default)]
struct Traction {
    f: V3,
    r_cp: V3,
}

/// Rolling traction of one closed contact (single point, rolling component only) on a ball of
/// radius `ball_radius`.
#[inline(always)]
fn traction_of(
    ball_radius: f64,
    curve: &TractionCurve,
    kin: &BallKin,
    ring: &RingPose,
    c: &ContactOut,
) -> Traction {
    if c.q <= 0.0 {
        return Traction::default();
    }
    let n = scale(c.qn, 1.0 / c.q);
    // Rolling direction: the ring's circumferential direction at the ball; in a spall the
    // contact frame turns about c1 with the normal, c2 = n_q × c1.
    let rr = ring.to_ring(sub(kin.p, ring.p));
    let inv_rho = 1.0 / (rr[1] * rr[1] + rr[2] * rr[2]).sqrt();
    let c2_ring = ring.to_inertial([0.0, -rr[2] * inv_rho, rr[1] * inv_rho]);
    let c2 = if c.in_defect {
        let c1 = cross(c2_ring, n);
        cross(n, scale(c1, 1.0 / dot(c1, c1).sqrt()))
    } else {
        c2_ring
    };
    let r_cp = scale(n, ball_radius - 0.5 * c.delta);
    let v_ball = add(kin.v, cross(kin.omega, r_cp));
    let v_race = add(ring.v, cross(ring.omega(), sub(add(kin.p, r_cp), ring.p)));
    let u2 = dot(sub(v_ball, v_race), c2);
    let f2 = -c.q * curve.kappa_over_u(u2.abs()) * u2;
    Traction {
        f: scale(c2, f2),
        r_cp,
    }
}

impl ReducedModel {
    /// The right-hand side ([`Model::rhs`] runs it compiled for AVX2 where the processor has
    /// it).
    #[inline(always)]
    fn rhs_body(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let c = &mut self.core;
        let inner = c.inner_pose(y);
        let outer = c.outer_pose(y);
        let psi_rate = c.cage_speed();
        let (cb, sb) = self.attitude;
        let mut f_ring: V3 = [0.0; 3];
        let mut m_ring_x = 0.0;
        let mut f_outer: V3 = [0.0; 3];
        let jb = c.ball_inertia;
        let strip_traction = match (&self.traction, &self.strips) {
            (Some(curve), Some(strips)) => Some((curve, strips)),
            _ => None,
        };
        // Every ball's normal contacts first, then the strip traction of all loaded contacts
        // in one batch, then the equations of motion.
        let pass = c.contact_pass(y, strip_traction, &inner, &outer);
        let (touch, cage) = c.after_pass(t, y, &pass, &inner, &outer, psi_rate, dydt);
        for j in 0..c.z {
            let b = c.lay.ball(j);
            let (kin, er, et, r, w) = pass.frames[j];
            let (ci, co) = &pass.contacts[j];
            let (fi, fo, moment) = if strip_traction.is_some() {
                // Strip traction: the forces include it, the moments are about the ball centre.
                // Reaction on the inner ring about its axis, as in the full model.
                let arm = sub(kin.p, inner.p);
                let f_t = add(ci.f, ci.qn);
                let m = sub(sub(cross(arm, ci.qn_ring), cross(arm, f_t)), ci.m);
                m_ring_x += m[0];
                (ci.f, co.f, add(ci.m, co.m))
            } else {
                let (ti, to) = match &self.traction {
                    Some(curve) => (
                        traction_of(c.ball_radius, curve, &kin, &inner, ci),
                        traction_of(c.ball_radius, curve, &kin, &outer, co),
                    ),
                    None => (Traction::default(), Traction::default()),
                };
                let fi = add(ci.f, ti.f);
                let arm = sub(add(kin.p, ti.r_cp), inner.p);
                m_ring_x -= arm[1] * fi[2] - arm[2] * fi[1];
                (
                    fi,
                    add(co.f, to.f),
                    add(cross(ti.r_cp, ti.f), cross(to.r_cp, to.f)),
                )
            };
            let mut f = add(fi, fo);
            let mut moment = moment;
            if let (true, Some(bb)) = (touch, &c.ball_ball) {
                f = add(f, bb.force[j]);
            }
            if let Some(pc) = c
                .cage
                .as_ref()
                .map(|cg| &cg.pockets[j])
                .filter(|p| p.p > 0.0)
            {
                f = add(f, pc.f);
                moment = add(moment, pc.m);
            }
            let es = [cb, -sb * er[1], -sb * er[2]];
            c.ball_translation(y, j, f, er, et, r, w, psi_rate, dydt);
            dydt[b + BWS] = dot(moment, es) / jb;
            // Reactions: −F on the inner ring at the contact point, −F on the outer ring.
            f_ring = sub(f_ring, fi);
            f_outer = sub(f_outer, fo);
        }
        c.pass = pass;
        if let Some(r) = cage {
            f_ring = add(f_ring, r.on_inner);
            m_ring_x += r.inner_moment[0];
            f_outer = add(f_outer, r.on_outer);
        }
        c.ring_force = f_ring;
        self.ring_moment_x = m_ring_x;
        self.core.rings(t, y, f_ring, f_outer, psi_rate, dydt);
        self.core.direction_rates(y, dydt);
    }

    /// Builds the model for a scene with the default options.
    pub fn new(
        scene: &Scene,
        bearing: &Bearing,
        inputs: &OperatingPoint,
    ) -> Result<Self, SimError> {
        Self::with_options(scene, bearing, inputs, ReducedOptions::default())
    }

    /// Builds the model with explicit [`ReducedOptions`].
    pub fn with_options(
        scene: &Scene,
        bearing: &Bearing,
        inputs: &OperatingPoint,
        options: ReducedOptions,
    ) -> Result<Self, SimError> {
        let file = &bearing.file;
        let z = bearing.z;
        if z == 0 {
            return Err(SimError::Input("the bearing has no balls".into()));
        }
        // The full model's start (docs/model.md#initial-state: L1, pedestal and ring offsets, ball placement clear of
        // the spall) and its spall; without traction it builds no strip tables.
        let full = FullModel::with_options(
            scene,
            bearing,
            inputs,
            FullOptions {
                traction: options.traction,
                lock_tilt: true,
                ..FullOptions::default()
            },
        )?;
        let traction = if options.traction {
            Some(TractionCurve::new(&file.traction)?)
        } else {
            None
        };
        let mut core = BallCore::with_defect(
            bearing,
            inputs,
            Layout::reduced(z).with_cage(scene.full.cage),
            BallSpin::Fixed { cos: 1.0, sin: 0.0 },
            false,
            full.defects().to_vec(),
            full.core().ball_spalls.clone(),
            scene.pulse.clone(),
            full.held_axial(),
        );
        if inputs.shaft_speed > 0.0 {
            core.cage_ratio = full.cage_speed() / inputs.shaft_speed;
        }
        core.set_distributed(scene, bearing)?;
        let mut m = Self {
            core,
            traction,
            strips: (options.strips > 0).then(|| Strips::new(options.strips)),
            attitude: (1.0, 0.0),
            settle: None,
            ring_moment_x: 0.0,
        };
        m.reduce_initial_state(&full, bearing);
        m.core.init_ball_directions();
        Ok(m)
    }

    /// Maps the full model's initial state onto the reduced states. The ball spin of L1,
    /// `ω_b = ω_c e_x + ω_R ê_s(β_j)`, gives the attitude angle β (the mean over the balls; at
    /// zero speed, where L1 has no spin, the outer-race-control angle at α0) and ω_s = the spin
    /// part projected on the common axis.
    fn reduce_initial_state(&mut self, full: &FullModel, bearing: &Bearing) {
        let fl = full.layout();
        let mut yf = vec![0.0; fl.dim()];
        full.initial_state(&mut yf);
        // With traction the full model starts in the balls' steady rotation: the attitude the
        // traction sets, not L1's outer-race control (see the module notes).
        self.settle = full.settle_report();
        self.core.start_note = full.start_note().map(str::to_owned);
        let lay = self.core.lay;
        let (z, theta_start) = (self.core.z, self.core.theta_start);
        let y = &mut self.core.y0;
        y.iter_mut().for_each(|v| *v = 0.0);
        // Spin vectors w_j = ω_b − θ̇ e_x of the full start.
        let mut spins = Vec::with_capacity(z);
        let (mut beta_sum, mut n_beta) = (0.0, 0);
        for j in 0..z {
            let (bf, b) = (fl.ball(j), lay.ball(j));
            for k in [BX, BR, BTH, BVX, BVR, BW] {
                y[b + k] = yf[bf + k];
            }
            let theta = theta_start + TAU * j as f64 / z as f64 + yf[bf + BTH];
            let (s, c) = theta.sin_cos();
            let er = [0.0, -s, c];
            let w = [yf[bf + 6] - yf[bf + BW], yf[bf + 7], yf[bf + 8]];
            let norm = dot(w, w).sqrt();
            if norm > 0.0 {
                // ω_R < 0 for Ω > 0 (docs/model.md#l0): ê_s = w/ω_R = −w/|w|.
                let es = scale(w, -1.0 / norm);
                beta_sum += (-dot(es, er)).atan2(es[0]);
                n_beta += 1;
            }
            spins.push((w, er));
        }
        let beta = if n_beta > 0 {
            beta_sum / n_beta as f64
        } else {
            crate::fault_frequencies::outer_race_control(bearing, bearing.alpha0, bearing.alpha0)
                .beta
        };
        let (sb, cb) = beta.sin_cos();
        self.attitude = (cb, sb);
        self.core.spin = BallSpin::Fixed { cos: cb, sin: sb };
        for (j, (w, er)) in spins.into_iter().enumerate() {
            let es = [cb, -sb * er[1], -sb * er[2]];
            y[lay.ball(j) + BWS] = dot(w, es);
        }
        let (rf, r) = (fl.ring(), lay.ring());
        for k in 0..3 {
            y[r + RX + k] = yf[rf + RX + k];
            y[r + RV + k] = yf[rf + RV + k];
        }
        let (pf, p) = (fl.pedestal(), lay.pedestal());
        for k in [PY, PZ, PVY, PVZ] {
            y[p + k] = yf[pf + k];
        }
        y[lay.psi()] = yf[fl.psi()];
        y[lay.phi()] = yf[fl.phi()];
        if lay.cage {
            let (cf, c) = (fl.cage_block(), lay.cage_block());
            y[c..c + CAGE_STATES].copy_from_slice(&yf[cf..cf + CAGE_STATES]);
        }
    }

    /// What the model shares with the full one: layout, poses, contacts, modes.
    pub fn core(&self) -> &BallCore {
        &self.core
    }

    /// The state layout.
    pub fn layout(&self) -> Layout {
        self.core.layout()
    }

    /// The solve of the balls' steady rotation (None without traction or at zero speed).
    pub fn settle_report(&self) -> Option<SteadyReport> {
        self.settle
    }

    /// The fixed attitude angle β of the spin axis \[rad\].
    pub fn attitude_angle(&self) -> f64 {
        self.attitude.1.atan2(self.attitude.0)
    }

    /// Normal forces of the last evaluation: (inner, outer) per ball \[N\].
    pub fn contact_forces(&self) -> (&[f64], &[f64]) {
        self.core.contact_forces()
    }

    /// The spall, if any (the first of several).
    pub fn defect(&self) -> Option<&Defect> {
        self.core.defect()
    }

    /// Every spall.
    pub fn defects(&self) -> &[Defect] {
        self.core.defects()
    }

    /// Sum of the Hertz potentials (2/5)Kδ^{5/2} of all intact contacts \[J\].
    pub fn hertz_potential(&self, y: &[f64]) -> f64 {
        self.core.hertz_potential(y)
    }

    /// Total mechanical energy \[J\]: ball translation and spin ½Jω_s², inner-ring translation,
    /// pedestal, the cage, Hertz potential of the intact contacts, of the ball-to-ball contacts
    /// and of the cage's pocket and land contacts, pedestal springs, minus the work of the
    /// constant loads. Conserved without traction, damping and spall (the orbital part θ̇ e_x
    /// of the ball's angular velocity is kinematic here and carries no energy of its own).
    pub fn energy(&self, y: &[f64]) -> f64 {
        let c = &self.core;
        let inner = c.inner_pose(y);
        let mut e = c.hertz_potential(y) + c.ball_ball_potential(y) + c.cage_energy(y);
        for j in 0..c.z {
            let (kin, _, _, _, _) = c.ball_kin(y, j);
            let ws = y[c.lay.ball(j) + BWS];
            e += 0.5 * c.ball_mass * dot(kin.v, kin.v) + 0.5 * c.ball_inertia * ws * ws;
        }
        let p = c.lay.pedestal();
        e += 0.5 * c.m_ir * dot(inner.v, inner.v)
            + 0.5 * c.m_p * (y[p + PVY].powi(2) + y[p + PVZ].powi(2))
            + 0.5 * c.k_py * y[p + PY].powi(2)
            + 0.5 * c.k_pz * y[p + PZ].powi(2)
            - (c.inputs.fx * inner.p[0] + c.inputs.fy * inner.p[1] + c.inputs.fz * inner.p[2]);
        e
    }

    /// Mean orbital speed of the balls, Σθ̇/z [rad/s].
    pub fn mean_orbital_speed(&self, y: &[f64]) -> f64 {
        self.core.mean_orbital_speed(y)
    }

    /// Bearing friction (drive) torque of the last right-hand side: minus the moment of the
    /// contacts on the inner ring about its axis [N m].
    pub fn friction_torque(&self) -> f64 {
        -self.ring_moment_x
    }
}

impl Model for ReducedModel {
    forward_to_ball_core!();

    fn state_name(&self, i: usize) -> String {
        let lay = self.core.lay;
        let (ring, pedestal) = (lay.ring(), lay.pedestal());
        match i {
            _ if i < ring => ball_state_name(i / PER_BALL, i % PER_BALL, &["spin rate ω_s"]),
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
        // As the full model: deflection-scale positions 1e-5 m, velocities 1e-2 m/s, angle
        // deviations 1e-3 rad, orbital rates 100 rad/s, spins 1e3 rad/s.
        let lay = self.core.lay;
        for j in 0..self.core.z {
            let b = lay.ball(j);
            out[b + BX] = 1e-5;
            out[b + BR] = 1e-5;
            out[b + BTH] = 1e-3;
            out[b + BVX] = 1e-2;
            out[b + BVR] = 1e-2;
            out[b + BW] = 100.0;
            out[b + BWS] = 1e3;
        }
        let r = lay.ring();
        for k in 0..3 {
            out[r + RX + k] = 1e-5;
            out[r + RV + k] = 1e-2;
        }
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
}

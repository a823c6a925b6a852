//! The part of a ball-level model (full L4, reduced L3) that does not depend on how the balls
//! spin: [`BallCore`] holds the bearing's constants, the inputs, the spall and the frozen
//! modes, computes the ring poses, each ball's kinematics and contacts, the event functions
//! and the mode update, and fills the outputs. A model contains one and delegates to it; it
//! keeps only its equations of motion and what is its own (the full model's ring tilt and
//! traction options, the reduced model's fixed spin axis).

use super::ball_ball::BallBall;
use super::ball_contact::{
    self, dot, BallKin, ContactOut, DefectView, GroovePos, Law, RaceConst, RingPose, Strips, V3,
};
use super::cage::{Cage, CagePose, CageResult};
use super::layout::{
    Layout, BOM, BR, BTH, BVR, BVX, BW, BX, CA, CV, CW, CY, PVY, PVZ, PY, PZ, RBY, RBZ, RV, RWY,
    RWZ, RX,
};
use super::pass::{BallFrame, ContactPass, Loaded, Normal};
use super::switches::{contact_event, EventOf, Switches};
use crate::ball_spall::BallSpall;
use crate::config::DefectMode;
use crate::contact::TractionCurve;
use crate::defect::{Defect, DefectSpec};
use crate::geometry::{Bearing, Race};
use crate::models::{out, RingStates, SimError};
use crate::operating::{OperatingPoint, RingLoad};
use crate::roughness::Roughness;
use crate::scene::{Pulse, Scene};
use crate::vecmath;
use crate::waviness::Waviness;
use std::f64::consts::{FRAC_PI_2, TAU};

/// How a ball's angular velocity follows from its states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BallSpin {
    /// Three states ω_x, ω_y, ω_z at offset `BOM` of the ball's block (the full model).
    Free,
    /// One spin rate ω_s at offset `BOM` about the axis `cos β e_x − sin β e_r(θ)` with the
    /// fixed attitude (cos β, sin β): ω = θ̇ e_x + ω_s ê_s (the reduced model).
    Fixed { cos: f64, sin: f64 },
}

/// Per-race constants from the bearing (docs/model.md#geometry, #hertz, #c7).
pub fn race_const(b: &Bearing, race: Race) -> RaceConst {
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
        film: b.film(race).copied(),
    }
}

/// A representative ball load for the spall's blend length "b": the mean load of a ball carrying
/// the axial load or the peak load of the radial load zone (Stribeck), at least 10 N.
pub fn reference_ball_load(bearing: &Bearing, inputs: &OperatingPoint) -> f64 {
    let z = bearing.z as f64;
    let axial = inputs.fx.abs() / (z * bearing.alpha0.sin().max(0.1));
    let radial = 5.0 * inputs.fy.hypot(inputs.fz) / z;
    axial.max(radial).max(10.0)
}

/// Ball 0's start azimuth: 0 (where L1 puts it), or an offset when that puts a ball within
/// θ_e + 0.02 rad of the spall (docs/model.md#initial-state step 4).
pub fn choose_theta_start(z: usize, defect: Option<&Defect>) -> f64 {
    choose_theta_start_all(z, defect.map(std::slice::from_ref).unwrap_or_default())
}

/// [`choose_theta_start`] clear of every spall of `defects` (the first offset that is, else
/// half a spacing; 0 without spalls).
pub fn choose_theta_start_all(z: usize, defects: &[Defect]) -> f64 {
    if defects.is_empty() {
        return 0.0;
    }
    let spacing = TAU / z as f64;
    [0.0, 0.5 * spacing, 0.25 * spacing, 0.75 * spacing]
        .into_iter()
        .find(|&s| {
            defects.iter().all(|d| {
                let clear = d.half_angle() + 0.02;
                let theta0 = d.theta0();
                (0..z).all(|j| crate::defect::wrap(s + spacing * j as f64 - theta0).abs() > clear)
            })
        })
        .unwrap_or(0.5 * spacing)
}

/// What the ball-level models share (see the module documentation).
#[derive(Clone)]
pub struct BallCore {
    pub(crate) lay: Layout,
    pub(crate) z: usize,
    pub(crate) spin: BallSpin,
    /// The inner ring tilts (states `RBY` … `RWZ` of its block).
    pub(crate) tilt: bool,
    pub(crate) ball_mass: f64,
    pub(crate) ball_inertia: f64,
    pub(crate) ball_radius: f64,
    pub(crate) pitch_radius: f64,
    pub(crate) inner: RaceConst,
    pub(crate) outer: RaceConst,
    pub(crate) c_br: f64,
    pub(crate) m_ir: f64,
    pub(crate) m_p: f64,
    pub(crate) k_py: f64,
    pub(crate) k_pz: f64,
    pub(crate) c_py: f64,
    pub(crate) c_pz: f64,
    pub(crate) pulse: Option<Pulse>,
    /// The spalls (docs/model.md#several-spalls): each ball checks each.
    pub(crate) defects: Vec<Defect>,
    /// Race waviness and off-size balls (docs/model.md#waviness).
    pub(crate) waviness: Option<Waviness>,
    /// Track roughness (docs/model.md#roughness).
    pub(crate) roughness: Option<Roughness>,
    /// The spalls on balls (docs/model.md#ball-spall). Spall s's frozen modes are the
    /// switches' spall slots `defects.len() + 2s` (at its ball's outer contact) and
    /// `defects.len() + 2s + 1` (inner); its direction on the ball, the states from
    /// [`Layout::spall_dir`].
    pub(crate) ball_spalls: Vec<BallSpall>,
    /// Semi-major-axis factor of each spall slot's edge contact (the raceway spalls', then
    /// each spall on a ball's at the outer and the inner contact).
    pub(crate) defect_a_star: Vec<f64>,
    pub(crate) inputs: OperatingPoint,
    /// A force law on the inner ring added to `inputs`' load (force coupling).
    pub(crate) ring_load: Option<RingLoad>,
    /// Reference cage speed ratio ψ̇/Ω.
    pub(crate) cage_ratio: f64,
    /// Azimuth of ball 0 at ψ = 0 [rad].
    pub(crate) theta_start: f64,
    /// Why the start is not the one the model normally takes ([`crate::models::Model::start_note`]).
    pub(crate) start_note: Option<String>,
    /// Frozen spall halves, blend sides and contact modes, and their switches.
    pub(crate) sw: Switches,
    /// Normal forces of the last RHS evaluation (inner, outer) [N].
    pub(crate) q_inner: Vec<f64>,
    pub(crate) q_outer: Vec<f64>,
    /// Initial state.
    pub(crate) y0: Vec<f64>,
    /// Scratch derivative for outputs.
    pub(crate) scratch: Vec<f64>,
    /// Force of the bearing on the inner ring (last RHS) [N].
    pub(crate) ring_force: V3,
    /// Coupling mode "motion": the ring translation is prescribed (zero translational
    /// acceleration; the simulation writes the journal's position and velocity into the states).
    pub(crate) prescribed: bool,
    /// A located ring's held axial displacement \[m\] (its axial acceleration is zero).
    pub(crate) held_axial: Option<f64>,
    /// RHS scratch: every ball's frame and contacts, the strip traction in one batch.
    pub(crate) pass: ContactPass,
    /// Contacts between neighbouring balls (docs/model.md#ball-ball): the cage-less models'.
    pub(crate) ball_ball: Option<BallBall>,
    /// The cage (docs/model.md#cage), when the layout has its states.
    pub(crate) cage: Option<Cage>,
}

impl BallCore {
    /// The core for `bearing` at `inputs` with state layout `lay`, the spalls of `defects`, each
    /// in its mode (None: the bearing's; their
    /// blend length from [`reference_ball_load`]; overlapping spalls refused), ball 0 placed
    /// clear of them
    /// ([`choose_theta_start`]), the cage ratio of outer-race control at α0 until the model
    /// sets its own, and the initial state zero. A layout with the cage block gets the cage of
    /// the bearing file ([`Cage`]); one without gets the ball-to-ball contacts instead.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        bearing: &Bearing,
        inputs: &OperatingPoint,
        lay: Layout,
        spin: BallSpin,
        tilt: bool,
        defects: &[(DefectSpec, Option<DefectMode>)],
        pulse: Option<Pulse>,
        held_axial: Option<f64>,
    ) -> Result<Self, SimError> {
        let specs: Vec<_> = defects.iter().map(|(d, m)| (d, *m)).collect();
        let load = reference_ball_load(bearing, inputs);
        let races = crate::defect::build_races(&specs, bearing, load)?;
        let balls = crate::ball_spall::build_all(&specs, bearing, load)?;
        Ok(Self::with_defect(
            bearing, inputs, lay, spin, tilt, races, balls, pulse, held_axial,
        ))
    }

    /// [`BallCore::new`] with the spalls already built: those on the races and those on balls
    /// (the layout gets the latter's direction states).
    #[allow(clippy::too_many_arguments)]
    pub fn with_defect(
        bearing: &Bearing,
        inputs: &OperatingPoint,
        lay: Layout,
        spin: BallSpin,
        tilt: bool,
        defects: Vec<Defect>,
        ball_spalls: Vec<BallSpall>,
        pulse: Option<Pulse>,
        held_axial: Option<f64>,
    ) -> Self {
        let file = &bearing.file;
        let z = bearing.z;
        let lay = lay.with_ball_spalls(ball_spalls.len());
        let defect_a_star = defects
            .iter()
            .chain(
                ball_spalls
                    .iter()
                    .flat_map(|b| [b.at(Race::Outer), b.at(Race::Inner)]),
            )
            .map(|d| d.corner_hertz().semi_axis_factors().0)
            .collect();
        let theta_start = choose_theta_start_all(z, &defects);
        let sw = Switches::with_spalls(z, defects.len() + 2 * ball_spalls.len());
        Self {
            lay,
            z,
            spin,
            tilt,
            ball_mass: bearing.ball_mass,
            ball_inertia: bearing.ball_inertia,
            ball_radius: bearing.ball_radius(),
            pitch_radius: 0.5 * bearing.dm,
            inner: race_const(bearing, Race::Inner),
            outer: race_const(bearing, Race::Outer),
            c_br: file.contact.c_br,
            m_ir: file.inner_ring.mass,
            m_p: file.pedestal.mass,
            k_py: file.pedestal.k_y,
            k_pz: file.pedestal.k_z,
            c_py: file.pedestal.c_y,
            c_pz: file.pedestal.c_z,
            pulse,
            defects,
            ball_spalls,
            waviness: None,
            roughness: None,
            defect_a_star,
            inputs: *inputs,
            ring_load: None,
            cage_ratio: 0.5 * (1.0 - bearing.gamma(bearing.alpha0)),
            theta_start,
            start_note: None,
            sw,
            q_inner: vec![0.0; z],
            q_outer: vec![0.0; z],
            y0: vec![0.0; lay.dim()],
            scratch: vec![0.0; lay.dim()],
            ring_force: [0.0; 3],
            prescribed: false,
            held_axial,
            pass: ContactPass::new(z),
            ball_ball: (!lay.cage)
                .then(|| BallBall::new(z, bearing.d, bearing.e_prime, file.contact.c_br)),
            cage: lay.cage.then(|| Cage::new(bearing)),
        }
    }

    /// The state layout.
    pub fn layout(&self) -> Layout {
        self.lay
    }

    /// The frozen modes and their switches.
    pub fn switches(&self) -> &Switches {
        &self.sw
    }

    /// The spall, if any (the first of several).
    pub fn defect(&self) -> Option<&Defect> {
        self.defects.first()
    }

    /// Every spall.
    pub fn defects(&self) -> &[Defect] {
        &self.defects
    }

    /// Normal forces of the last evaluation: (inner, outer) per ball \[N\].
    pub fn contact_forces(&self) -> (&[f64], &[f64]) {
        (&self.q_inner, &self.q_outer)
    }

    /// The axial displacement a located inner ring is held at (None: the axial load acts).
    pub fn held_axial(&self) -> Option<f64> {
        self.held_axial
    }

    /// True when ball j is inside a spall zone |θ_bd| < θ_e (as of the last mode update).
    pub fn in_defect_zone(&self, j: usize) -> bool {
        j < self.z && self.sw.side(j) != 0.0
    }

    /// Pose of the inner ring at state y (tilted if the model has the tilt states).
    #[inline(always)]
    pub fn inner_pose(&self, y: &[f64]) -> RingPose {
        let r = self.lay.ring();
        let (beta, beta_rate) = if self.tilt {
            ([0.0, y[r + RBY], y[r + RBZ]], [0.0, y[r + RWY], y[r + RWZ]])
        } else {
            ([0.0; 3], [0.0; 3])
        };
        RingPose {
            p: [y[r + RX], y[r + RX + 1], y[r + RX + 2]],
            v: [y[r + RV], y[r + RV + 1], y[r + RV + 2]],
            beta,
            beta_rate,
            spin: self.inputs.shaft_speed,
        }
    }

    /// Pose of the outer ring (the pedestal) at state y.
    #[inline(always)]
    pub fn outer_pose(&self, y: &[f64]) -> RingPose {
        let p = self.lay.pedestal();
        RingPose {
            p: [0.0, y[p + PY], y[p + PZ]],
            v: [0.0, y[p + PVY], y[p + PVZ]],
            beta: [0.0; 3],
            beta_rate: [0.0; 3],
            spin: 0.0,
        }
    }

    /// The contacts of one RHS evaluation at state y with the rings at `inner` and `outer`
    /// ([`ContactPass::evaluate`]: every ball's frame and normal contacts, then the strip
    /// traction of the loaded ones in one batch when `traction` is on). Returns the pass, taken
    /// out of the core so that the models can read it while they write the core; they put it
    /// back (`self.pass = pass`) at the end of the evaluation.
    #[inline(always)]
    pub fn contact_pass(
        &mut self,
        y: &[f64],
        traction: Option<(&TractionCurve, &Strips)>,
        inner: &RingPose,
        outer: &RingPose,
    ) -> ContactPass {
        let mut pass = std::mem::take(&mut self.pass);
        let c = &*self;
        pass.evaluate(
            c.z,
            traction,
            [inner, outer],
            [&c.inner, &c.outer],
            #[inline(always)]
            |j| c.ball_azimuth(y, j),
            #[inline(always)]
            |j, sc| c.ball_kin_at(y, j, sc),
            #[inline(always)]
            |j, kin, w, slip, grooves, out| {
                c.normal_contacts_into(y, j, kin, w, inner, outer, slip, grooves, out)
            },
        );
        pass
    }

    /// Ball j's kinematics and its cylindrical triad (e_r, e_θ), radius and orbital rate.
    #[inline(always)]
    pub fn ball_kin(&self, y: &[f64], j: usize) -> BallFrame {
        self.ball_kin_at(y, j, vecmath::sin_cos(self.ball_azimuth(y, j)))
    }

    /// Ball j's azimuth θ_j (the cage angle, the ball's place in the cage and its offset) \[rad\].
    #[inline(always)]
    pub fn ball_azimuth(&self, y: &[f64], j: usize) -> f64 {
        let b = self.lay.ball(j);
        y[self.lay.psi()] + self.theta_start + TAU * j as f64 / self.z as f64 + y[b + BTH]
    }

    /// [`BallCore::ball_kin`] given (sin θ_j, cos θ_j) of [`BallCore::ball_azimuth`] by
    /// [`vecmath::sin_cos`] (one call per ball, or a batch of them for all balls).
    #[inline(always)]
    pub fn ball_kin_at(&self, y: &[f64], j: usize, (s, c): (f64, f64)) -> BallFrame {
        let b = self.lay.ball(j);
        let er = [0.0, -s, c];
        let et = [0.0, -c, -s];
        let r = self.pitch_radius + y[b + BR];
        let w = y[b + BW];
        let (vx, vr) = (y[b + BVX], y[b + BVR]);
        let omega = match self.spin {
            BallSpin::Free => [y[b + BOM], y[b + BOM + 1], y[b + BOM + 2]],
            BallSpin::Fixed { cos: cb, sin: sb } => {
                let ws = y[b + BOM];
                [w + ws * cb, -ws * sb * er[1], -ws * sb * er[2]]
            }
        };
        let kin = BallKin {
            p: [y[b + BX], r * er[1], r * er[2]],
            v: [vx, vr * er[1] + r * w * et[1], vr * er[2] + r * w * et[2]],
            omega,
        };
        (kin, er, et, r, w)
    }

    /// Ball-to-spall angle θ_bd of ball j and its rate (uses the defective ring's frame).
    pub fn theta_bd(&self, d: &Defect, y: &[f64], j: usize) -> (f64, f64) {
        let (kin, _, _, _, w) = self.ball_kin(y, j);
        let (pose, rate) = match d.ring() {
            Race::Inner => (self.inner_pose(y), w - self.inputs.shaft_speed),
            Race::Outer => (self.outer_pose(y), w),
        };
        (d.theta_bd(pose.azimuth(kin.p), y[self.lay.phi()]), rate)
    }

    /// The spall on `race` ball j is over in the frozen interval (orbital rate `w`), as it
    /// sees it (spalls on one race do not overlap: at most one).
    /// A spall on the ball over that contact takes the place of a raceway spall only when
    /// there is none (docs/model.md#ball-spall).
    #[inline(always)]
    pub fn spall_view(&self, y: &[f64], j: usize, race: Race, w: f64) -> Option<DefectView<'_>> {
        let Some((k, d)) = self
            .defects
            .iter()
            .enumerate()
            .find(|(k, d)| d.ring() == race && self.sw.side_of(*k, j) != 0.0)
        else {
            return self.ball_spall_view(y, j, race);
        };
        // θ_bd turns with the ball, less the shaft for an inner-race spall.
        let rate = match race {
            Race::Inner => w - self.inputs.shaft_speed,
            Race::Outer => w,
        };
        Some(DefectView {
            defect: d,
            side: self.sw.side_of(k, j),
            phi: y[self.lay.phi()],
            theta_bd_rate: rate,
            a_star: self.defect_a_star[k],
            blend: self.sw.blend_of(k, j),
            on_ball: None,
        })
    }

    /// The spall slot of spall `s` on a ball at its contact with `race`.
    #[inline(always)]
    fn ball_slot(&self, s: usize, race: Race) -> usize {
        self.defects.len() + 2 * s + usize::from(race == Race::Inner)
    }

    /// The spall on a ball and the contact that spall slot `slot` stands for (the inverse of
    /// [`BallCore::ball_slot`]), or `None` for a raceway spall's slot.
    #[inline(always)]
    fn ball_spall_of_slot(&self, slot: usize) -> Option<(usize, Race)> {
        let k = slot.checked_sub(self.defects.len())?;
        let race = if k % 2 == 0 { Race::Outer } else { Race::Inner };
        (k < 2 * self.ball_spalls.len()).then_some((k / 2, race))
    }

    /// A spall on ball j over its contact with `race` in the frozen interval (spalls on one
    /// ball do not overlap: at most one), placed by its direction states.
    #[inline(always)]
    fn ball_spall_view(&self, y: &[f64], j: usize, race: Race) -> Option<DefectView<'_>> {
        let (s, bs) =
            self.ball_spalls.iter().enumerate().find(|(s, b)| {
                b.ball() == j && self.sw.side_of(self.ball_slot(*s, race), j) != 0.0
            })?;
        let k = self.ball_slot(s, race);
        Some(DefectView {
            defect: bs.at(race),
            side: self.sw.side_of(k, j),
            phi: 0.0,
            theta_bd_rate: 0.0,
            a_star: self.defect_a_star[k],
            blend: self.sw.blend_of(k, j),
            on_ball: Some(self.ball_spall_angle_of(y, s, race, j)),
        })
    }

    /// The angle φ of a direction on ball j (states from `i`, a unit vector but for the
    /// integration error; its length does not matter) from the ball's contact with `race`:
    /// from the contact normal n (from the ball's centre towards the contact) towards the track
    /// direction c2, in their plane, in (−π, π]; and its rate, from the ball's spin relative to its orbit, ω − θ̇ e_x (n and
    /// c2 turn with the orbit). None while the states are not set (the start's solves).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn contact_angle(
        &self,
        y: &[f64],
        i: usize,
        kin: &BallKin,
        pose: &RingPose,
        rc: &RaceConst,
        w: f64,
        groove: Option<&GroovePos>,
    ) -> Option<(f64, f64)> {
        // φ and its rate do not depend on |u| (atan2 of two of its components, and their
        // rates over the same squared scale), so u is not normalised.
        let u = [y[i], y[i + 1], y[i + 2]];
        let n2 = dot(u, u);
        if n2.is_nan() || n2 < 0.25 {
            return None;
        }
        // (The ball's place in the groove when the caller has it: the same numbers.)
        let g = match groove {
            Some(g) => *g,
            None => ball_contact::groove_pos(kin.p, pose, rc),
        };
        let n = pose.to_inertial([g.n1, g.n3 * g.ey, g.n3 * g.ez]);
        let c2 = pose.to_inertial([0.0, -g.ez, g.ey]);
        let (a, b) = (dot(u, n), dot(u, c2));
        let w_rel = [kin.omega[0] - w, kin.omega[1], kin.omega[2]];
        let du = ball_contact::cross(w_rel, u);
        let den = a * a + b * b;
        // (Zero only for a direction along the spin axis, far from both contacts.)
        let rate = if den > 1e-12 * n2 {
            (a * dot(du, c2) - b * dot(du, n)) / den
        } else {
            0.0
        };
        Some((b.atan2(a), rate))
    }

    /// Where spall `s` on a ball stands at the ball's contact with `race`
    /// (docs/model.md#ball-spall): the θ_bd of the race's drop table whose along-track
    /// coordinate is the ball's over the spall, y_b = −(D/2)·φ with φ the spall centre's
    /// [`BallCore::contact_angle`] (clipped to ±π/2), and its rate. Direction states not set
    /// yet: far from the contact.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn ball_spall_angle(
        &self,
        y: &[f64],
        s: usize,
        race: Race,
        kin: &BallKin,
        pose: &RingPose,
        rc: &RaceConst,
        w: f64,
    ) -> (f64, f64) {
        let Some((phi, phi_rate)) =
            self.contact_angle(y, self.lay.spall_dir(s), kin, pose, rc, w, None)
        else {
            return (3.0, 0.0);
        };
        let (phi, phi_rate) = if phi.abs() > FRAC_PI_2 {
            (FRAC_PI_2.copysign(phi), 0.0)
        } else {
            (phi, phi_rate)
        };
        let d = self.ball_spalls[s].at(race);
        let tbd = d.theta_at_track(-self.ball_radius * phi);
        let rate = -self.ball_radius * phi_rate / d.along_track_rate(tbd, 1.0);
        (tbd, rate)
    }

    /// Ball j's waviness at its contact with `race` and its rate \[m, m/s\]
    /// (docs/model.md#waviness): the harmonics at spin angle ψ_j0 + π/2 ∓ φ (outer −, inner +),
    /// φ the [`BallCore::contact_angle`] of the ball's reference direction, which starts
    /// midway between the contacts: the outer contact sees r(ψ) and the inner r(ψ + π), ψ the
    /// spin angle turned since the start plus ψ_j0, as at the lumped level. Zero while the
    /// states are not set.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn ball_waviness(
        &self,
        wv: &Waviness,
        y: &[f64],
        j: usize,
        race: Race,
        kin: &BallKin,
        pose: &RingPose,
        w: f64,
        groove: Option<&GroovePos>,
    ) -> (f64, f64) {
        let rc = match race {
            Race::Inner => &self.inner,
            Race::Outer => &self.outer,
        };
        let Some((phi, rate)) =
            self.contact_angle(y, self.lay.ball_ref(j), kin, pose, rc, w, groove)
        else {
            return (0.0, 0.0);
        };
        let sign = match race {
            Race::Outer => -1.0,
            Race::Inner => 1.0,
        };
        let (v, d) = wv.ball_at(j, FRAC_PI_2 + sign * phi);
        (v, d * sign * rate)
    }

    /// Every direction state block: (its first state, its ball, its spin angle at the start):
    /// the spalls on balls' (at their θ0), then the balls' reference directions (at 0) when
    /// the layout has them.
    fn directions(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        let spalls = self.ball_spalls.iter().enumerate();
        let refs = if self.lay.ball_refs { self.z } else { 0 };
        spalls
            .map(|(s, b)| (self.lay.spall_dir(s), b.ball(), b.theta0()))
            .chain((0..refs).map(|j| (self.lay.ball_ref(j), j, 0.0)))
    }

    /// The direction states' rates u̇ = ω × u (ω the ball's angular velocity, inertial): the
    /// spalls on balls' and the balls' reference directions, written into `dydt`.
    #[inline]
    pub fn direction_rates(&self, y: &[f64], dydt: &mut [f64]) {
        for (i, j, _) in self.directions() {
            let omega = self.ball_kin(y, j).0.omega;
            let du = ball_contact::cross(omega, [y[i], y[i + 1], y[i + 2]]);
            dydt[i..i + 3].copy_from_slice(&du);
        }
    }

    /// Sets the direction states in the initial state `y0`: each spall on a ball's, and each
    /// ball's reference direction when the balls have waviness (docs/model.md#ball-spall):
    /// on the circle the ball turns, about its spin relative to its orbit at the start (the
    /// rolling circle's axis e_θ × n_o when it has none or it points elsewhere), at spin angle
    /// θ0 (the reference: 0) from its point midway between the contacts, a quarter turn ahead
    /// of the outer contact n_o (the outer contact at θ0 = π/2).
    pub fn init_ball_directions(&mut self) {
        let mut y0 = std::mem::take(&mut self.y0);
        for (i, j, psi) in self.directions() {
            let u = self.circle_point(&y0, j, psi);
            y0[i..i + 3].copy_from_slice(&u);
        }
        self.y0 = y0;
    }

    /// The point at spin angle `psi` on the circle ball j turns at state y (see
    /// [`BallCore::init_ball_directions`]), a unit vector.
    fn circle_point(&self, y: &[f64], j: usize, psi: f64) -> V3 {
        let outer = self.outer_pose(y);
        let (kin, _, et, _, w) = self.ball_kin(y, j);
        let g = ball_contact::groove_pos(kin.p, &outer, &self.outer);
        let n_o = outer.to_inertial([g.n1, g.n3 * g.ey, g.n3 * g.ez]);
        let unit = |v: V3| ball_contact::scale(v, 1.0 / dot(v, v).sqrt());
        let rolling = unit(ball_contact::cross(et, n_o));
        let w_rel = [kin.omega[0] - w, kin.omega[1], kin.omega[2]];
        let spin = dot(w_rel, w_rel).sqrt();
        let axis = if spin > 0.0 && dot(w_rel, rolling) > 0.5 * spin {
            ball_contact::scale(w_rel, 1.0 / spin)
        } else {
            rolling
        };
        let v = unit(ball_contact::sub(
            n_o,
            ball_contact::scale(axis, dot(n_o, axis)),
        ));
        let u = ball_contact::cross(v, axis);
        let (sp, cp) = psi.sin_cos();
        ball_contact::add(ball_contact::scale(u, cp), ball_contact::scale(v, sp))
    }

    /// Nominal values of the direction states (unit vectors): 1.
    pub fn direction_nominal(&self, out: &mut [f64]) {
        let start = self.lay.spall_dir(0);
        out[start..self.lay.dim()].iter_mut().for_each(|v| *v = 1.0);
    }

    /// Name of state `i` of the direction blocks, if it is one.
    pub fn direction_state_name(&self, i: usize) -> Option<String> {
        let start = self.lay.spall_dir(0);
        let refs = self.lay.ball_ref(0);
        if self.lay.ball_refs && i >= refs && i < self.lay.dim() {
            let (j, k) = ((i - refs) / 3, (i - refs) % 3);
            return Some(format!(
                "reference direction on ball {} ({} component)",
                j + 1,
                ["x", "y", "z"][k]
            ));
        }
        (i >= start && i < refs).then(|| {
            let (s, k) = ((i - start) / 3, (i - start) % 3);
            format!(
                "direction of spall {} on ball {} ({} component)",
                s + 1,
                self.ball_spalls[s].ball() + 1,
                ["x", "y", "z"][k]
            )
        })
    }

    /// The distributed defects' added approach at ball j's contact with `race` and its rate
    /// \[m, m/s\] (docs/model.md#distributed): the race's waviness and roughness at the ball's
    /// angle on the ring (the inner ring's own angle: azimuth less shaft angle), which moves
    /// past the ball at its orbital rate `w` (less the shaft speed on the inner ring), half
    /// the ball's diameter deviation, and the ball's waviness at the point it touches (`groove`:
    /// the ball's place in that groove when the caller has it). None without distributed
    /// defects.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn added_approach(
        &self,
        y: &[f64],
        j: usize,
        race: Race,
        pose: &RingPose,
        kin: &BallKin,
        w: f64,
        groove: Option<&GroovePos>,
    ) -> Option<(f64, f64)> {
        if self.waviness.is_none() && self.roughness.is_none() {
            return None;
        }
        let theta = pose.azimuth(kin.p);
        let (x, rate) = match race {
            Race::Inner => (theta - y[self.lay.phi()], w - self.inputs.shaft_speed),
            Race::Outer => (theta, w),
        };
        let (mut a, mut r) = (0.0, 0.0);
        if let Some(wv) = &self.waviness {
            let (v, d) = wv.race(race, x, rate);
            a += v + 0.5 * wv.deviation(j);
            r += d;
            if self.lay.ball_refs {
                let (v, d) = self.ball_waviness(wv, y, j, race, kin, pose, w, groove);
                a += v;
                r += d;
            }
        }
        if let Some(rg) = &self.roughness {
            let (v, d) = rg.race(race, x, rate);
            a += v;
            r += d;
        }
        Some((a, r))
    }

    /// Sets the distributed defects of a scene (docs/model.md#distributed): race waviness,
    /// off-size balls, ball waviness and roughness. Ball waviness adds each ball's reference
    /// direction to the layout (before the initial state is filled).
    pub fn set_distributed(&mut self, scene: &Scene, bearing: &Bearing) -> Result<(), SimError> {
        let waviness = match &scene.waviness {
            Some(w) => Waviness::new(w, bearing)?,
            None => None,
        };
        if waviness.is_some() && scene.waviness.as_ref().is_some_and(|w| !w.ball.is_empty()) {
            self.lay = self.lay.with_ball_refs(true);
            self.y0.resize(self.lay.dim(), 0.0);
            self.scratch.resize(self.lay.dim(), 0.0);
        }
        self.waviness = waviness;
        self.roughness = match &scene.roughness {
            Some(r) => Roughness::new(r, bearing)?,
            None => None,
        };
        Ok(())
    }

    /// Both normal contacts of ball j (inner, outer) under the frozen laws, with the slip fields
    /// of the loaded ones when `slip` (traction on): the first stage of
    /// [`ball_contact::evaluate_law`] one ball at a time ([`BallCore::normal_contacts_into`] for
    /// a [`ContactPass`]).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn normal_contacts(
        &self,
        y: &[f64],
        j: usize,
        kin: &BallKin,
        w: f64,
        inner: &RingPose,
        outer: &RingPose,
        slip: bool,
    ) -> [Normal; 2] {
        let grooves = [
            ball_contact::groove_pos(kin.p, inner, &self.inner),
            ball_contact::groove_pos(kin.p, outer, &self.outer),
        ];
        let mut out = Default::default();
        let [li, lo] =
            self.normal_contacts_into(y, j, kin, w, inner, outer, slip, &grooves, &mut out);
        [(out.0, li), (out.1, lo)]
    }

    /// [`BallCore::normal_contacts`] from the ball's place in both grooves
    /// ([`ball_contact::groove_pos`], inner and outer), writing the two contacts into `out`
    /// (inner, outer) and returning the slip fields and frames of the loaded ones.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn normal_contacts_into(
        &self,
        y: &[f64],
        j: usize,
        kin: &BallKin,
        w: f64,
        inner: &RingPose,
        outer: &RingPose,
        slip: bool,
        grooves: &[GroovePos; 2],
        out: &mut (ContactOut, ContactOut),
    ) -> [Option<Loaded>; 2] {
        [
            self.normal_contact(
                y,
                j,
                kin,
                w,
                slip,
                grooves,
                (0, inner, &self.inner, Race::Inner),
                &mut out.0,
            ),
            self.normal_contact(
                y,
                j,
                kin,
                w,
                slip,
                grooves,
                (1, outer, &self.outer, Race::Outer),
                &mut out.1,
            ),
        ]
    }

    /// One of [`BallCore::normal_contacts_into`]'s two contacts: `(k, pose, race, ring)` is
    /// the contact's index (0 inner, 1 outer), ring pose, race constants and race.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn normal_contact(
        &self,
        y: &[f64],
        j: usize,
        kin: &BallKin,
        w: f64,
        slip: bool,
        grooves: &[GroovePos; 2],
        (k, pose, race, ring): (usize, &RingPose, &RaceConst, Race),
        c: &mut ContactOut,
    ) -> Option<Loaded> {
        ball_contact::evaluate_normal_at(
            &grooves[k],
            kin,
            pose,
            race,
            self.ball_radius,
            self.c_br,
            self.spall_view(y, j, ring, w),
            self.added_approach(y, j, ring, pose, kin, w, Some(&grooves[k])),
            self.sw.law(j, k),
            slip,
            c,
        )
    }

    /// Contact event functions of ball j, (inner, outer): min(δ′, Q/S) with Q the unclamped
    /// force K δ′|δ′|^{1/2} + c δ̇′ under the frozen spall half and blend side. Positive exactly
    /// where the clamped law has a positive force; continuous, so the loss of a contact (Q
    /// reaching 0) and its return (δ′ reaching 0 with the damping jump c δ̇′, or Q rising
    /// through 0) are its roots. Also the unclamped forces.
    #[inline(always)]
    pub fn contact_events(
        &self,
        y: &[f64],
        j: usize,
        inner: &RingPose,
        outer: &RingPose,
    ) -> [(f64, f64); 2] {
        let (kin, _, _, _, w) = self.ball_kin(y, j);
        [
            self.contact_event_at(y, j, &kin, w, inner, Race::Inner),
            self.contact_event_at(y, j, &kin, w, outer, Race::Outer),
        ]
    }

    /// One contact of [`BallCore::contact_events`]: its event function and unclamped force,
    /// from ball j's kinematics `kin` and orbital rate `w` ([`BallCore::ball_kin`]).
    #[inline(always)]
    fn contact_event_at(
        &self,
        y: &[f64],
        j: usize,
        kin: &BallKin,
        w: f64,
        pose: &RingPose,
        ring: Race,
    ) -> (f64, f64) {
        let race = match ring {
            Race::Inner => &self.inner,
            Race::Outer => &self.outer,
        };
        let c = ball_contact::evaluate_law(
            kin,
            pose,
            race,
            self.ball_radius,
            self.c_br,
            None,
            self.spall_view(y, j, ring, w),
            self.added_approach(y, j, ring, pose, kin, w, None),
            Law::Closed,
        );
        (contact_event(&c), c.q_raw)
    }

    /// Re-derives the frozen modes at state y (at time t): spall halves and blend sides, then
    /// the contact modes under the new halves. Fills the switches' buffers in place (taken out
    /// and put back, no allocation).
    pub fn update_mode(&mut self, t: f64, y: &[f64]) {
        let z = self.z;
        let defects = std::mem::take(&mut self.defects);
        for (k, d) in defects.iter().enumerate() {
            let mut angles = std::mem::take(&mut self.sw.angles);
            for (j, a) in angles[k * z..(k + 1) * z].iter_mut().enumerate() {
                *a = self.theta_bd(d, y, j);
            }
            self.sw.angles = angles;
            self.sw.update_spall(t, k, d);
        }
        self.defects = defects;
        for s in 0..self.ball_spalls.len() {
            for race in [Race::Outer, Race::Inner] {
                let k = self.ball_slot(s, race);
                let mut angles = std::mem::take(&mut self.sw.angles);
                for (j, a) in angles[k * z..(k + 1) * z].iter_mut().enumerate() {
                    *a = self.ball_spall_angle_of(y, s, race, j);
                }
                self.sw.angles = angles;
                self.sw.update_spall(t, k, self.ball_spalls[s].at(race));
            }
        }
        let (inner, outer) = (self.inner_pose(y), self.outer_pose(y));
        let mut events = std::mem::take(&mut self.sw.contact_events);
        for (j, e) in events.iter_mut().enumerate().take(z) {
            *e = self.contact_events(y, j, &inner, &outer);
        }
        self.sw.contact_events = events;
        self.sw.update_contacts(t);
    }

    /// The event functions ([`super::switches`] lists the indices) at state y.
    pub fn events(&self, y: &[f64], g: &mut [f64]) {
        let (inner, outer) = (self.inner_pose(y), self.outer_pose(y));
        for j in 0..self.z {
            let [(gi, _), (go, _)] = self.contact_events(y, j, &inner, &outer);
            g[2 * j] = gi;
            g[2 * j + 1] = go;
        }
        for (k, d) in self.defects.iter().enumerate() {
            for j in 0..self.z {
                let (tbd, _) = self.theta_bd(d, y, j);
                self.sw.spall_events(d, k, j, tbd, g);
            }
        }
        for (s, bs) in self.ball_spalls.iter().enumerate() {
            for race in [Race::Outer, Race::Inner] {
                let k = self.ball_slot(s, race);
                for j in 0..self.z {
                    let (tbd, _) = self.ball_spall_angle_of(y, s, race, j);
                    self.sw.spall_events(bs.at(race), k, j, tbd, g);
                }
            }
        }
    }

    /// Event function `i` of [`BallCore::events`] alone, bit for bit (`g` is scratch): one
    /// contact, or one ball's functions of one spall slot.
    pub fn event(&self, i: usize, y: &[f64], g: &mut [f64]) -> f64 {
        match self.sw.event_of(i) {
            EventOf::Contact { ball, .. } => {
                let (kin, _, _, _, w) = self.ball_kin(y, ball);
                let (pose, ring) = if i.is_multiple_of(2) {
                    (self.inner_pose(y), Race::Inner)
                } else {
                    (self.outer_pose(y), Race::Outer)
                };
                self.contact_event_at(y, ball, &kin, w, &pose, ring).0
            }
            EventOf::Spall { slot, ball, .. } => {
                match self.ball_spall_of_slot(slot) {
                    None => {
                        let d = &self.defects[slot];
                        let (tbd, _) = self.theta_bd(d, y, ball);
                        self.sw.spall_events(d, slot, ball, tbd, g);
                    }
                    Some((s, race)) => {
                        let (tbd, _) = self.ball_spall_angle_of(y, s, race, ball);
                        self.sw
                            .spall_events(self.ball_spalls[s].at(race), slot, ball, tbd, g);
                    }
                }
                g[i]
            }
        }
    }

    /// [`BallCore::ball_spall_angle`] of spall `s` on a ball as ball j sees it at `race`: the
    /// spalled ball's, and far from every contact (a constant) for the other balls.
    fn ball_spall_angle_of(&self, y: &[f64], s: usize, race: Race, j: usize) -> (f64, f64) {
        if self.ball_spalls[s].ball() != j {
            return (3.0, 0.0);
        }
        let (kin, _, _, _, w) = self.ball_kin(y, j);
        let (pose, rc) = match race {
            Race::Inner => (self.inner_pose(y), &self.inner),
            Race::Outer => (self.outer_pose(y), &self.outer),
        };
        self.ball_spall_angle(y, s, race, &kin, &pose, rc, w)
    }

    /// Number of event functions.
    pub fn n_events(&self) -> usize {
        self.sw
            .n_events(self.defects.len() + 2 * self.ball_spalls.len())
    }

    /// What event function `i` watches: the switches' names, with a spall on a ball's slots
    /// named by its ball and contact.
    pub fn event_name(&self, i: usize) -> String {
        if let EventOf::Spall { slot, what, .. } = self.sw.event_of(i) {
            if let Some((s, race)) = self.ball_spall_of_slot(slot) {
                return format!(
                    "the {what} of ball spall {} (on ball {}) at its {} contact",
                    s + 1,
                    self.ball_spalls[s].ball() + 1,
                    race.name()
                );
            }
        }
        self.sw.event_name(i)
    }

    /// The next kink of the pulse after t, if not after `t_max` (a stop).
    pub fn next_stop(&self, t: f64, t_max: f64) -> Option<f64> {
        self.pulse.as_ref()?.next_kink(t).filter(|&tp| tp <= t_max)
    }

    /// Whether any ball still carries load: both its contacts with a positive force under the
    /// clamped law (the contact event functions positive).
    pub fn diagnose(&self, y: &[f64]) -> Option<String> {
        let (inner, outer) = (self.inner_pose(y), self.outer_pose(y));
        let carrying = (0..self.z)
            .filter(|&j| {
                let [(gi, _), (go, _)] = self.contact_events(y, j, &inner, &outer);
                gi > 0.0 && go > 0.0
            })
            .count();
        (carrying == 0).then(|| {
            format!(
                "contact is lost at every ball (none of the {} balls presses on both races)",
                self.z
            )
        })
    }

    /// The frozen modes and their switch memory (nothing else changes in an advance).
    pub fn checkpoint(&self, b: &mut Vec<f64>) {
        b.clear();
        self.sw.checkpoint(b);
    }

    /// Puts back what [`BallCore::checkpoint`] wrote.
    pub fn rollback(&mut self, b: &[f64]) -> Result<(), String> {
        self.sw.rollback(b)
    }

    /// Fills the outputs from the state y, its derivative `dydt` (for the pedestal
    /// acceleration), the ring force and the contact forces of the last evaluation, and the
    /// model's friction torque.
    pub fn outputs(&self, y: &[f64], dydt: &[f64], friction_torque: f64, o: &mut [f64]) {
        let p = self.lay.pedestal();
        let r = self.lay.ring();
        o[out::PEDESTAL_A_Y] = dydt[p + PVY];
        o[out::PEDESTAL_A_Z] = dydt[p + PVZ];
        o[out::PEDESTAL_Y] = y[p + PY];
        o[out::PEDESTAL_Z] = y[p + PZ];
        o[out::PEDESTAL_V_Y] = y[p + PVY];
        o[out::PEDESTAL_V_Z] = y[p + PVZ];
        o[out::RING_X] = y[r + RX];
        o[out::RING_Y] = y[r + RX + 1];
        o[out::RING_Z] = y[r + RX + 2];
        o[out::BEARING_F_X] = self.ring_force[0];
        o[out::BEARING_F_Y] = self.ring_force[1];
        o[out::BEARING_F_Z] = self.ring_force[2];
        o[out::FRICTION_TORQUE] = friction_torque;
        o[out::CAGE_SPEED] = match &self.cage {
            Some(_) => y[self.lay.cage_block() + CW],
            None => self.mean_orbital_speed(y),
        };
        if !out::has_ball_block(o, self.z) {
            return;
        }
        for j in 0..self.z {
            o[out::CONTACT_START + j] = self.q_inner[j];
            o[out::CONTACT_START + self.z + j] = self.q_outer[j];
            o[out::orbit_speed(self.z, j)] = y[self.lay.ball(j) + BW];
        }
        out::set_separation_flags(o, self.z);
        if !out::has_cage_block(o, self.z) {
            return;
        }
        let block = &mut o[out::cage_y(self.z)..out::cage_end(self.z)];
        match &self.cage {
            Some(cage) => {
                let c = self.lay.cage_block();
                block[0] = y[c + CY];
                block[1] = y[c + CY + 1];
                for (v, p) in block[2..].iter_mut().zip(&cage.pockets) {
                    *v = if p.p > 0.0 {
                        p.p * p.offset.signum()
                    } else {
                        0.0
                    };
                }
            }
            None => block.iter_mut().for_each(|v| *v = 0.0),
        }
    }

    /// The reference cage speed [rad/s].
    #[inline(always)]
    pub fn cage_speed(&self) -> f64 {
        self.cage_ratio * self.inputs.shaft_speed
    }

    /// The inner ring's translation states.
    pub fn ring_states(&self) -> RingStates {
        let r = self.lay.ring();
        RingStates {
            pos: [r + RX, r + RX + 1, r + RX + 2],
            vel: [r + RV, r + RV + 1, r + RV + 2],
        }
    }

    /// Mean orbital speed of the balls, Σθ̇/z [rad/s].
    pub fn mean_orbital_speed(&self, y: &[f64]) -> f64 {
        (0..self.z).map(|j| y[self.lay.ball(j) + BW]).sum::<f64>() / self.z as f64
    }

    /// The cage (None without one); its last evaluation is the last right-hand side's.
    pub fn cage(&self) -> Option<&Cage> {
        self.cage.as_ref()
    }

    /// The cage's pose at state y (meaningful when the layout has the cage block).
    #[inline(always)]
    pub fn cage_pose(&self, y: &[f64]) -> CagePose {
        let c = self.lay.cage_block();
        CagePose {
            angle: y[self.lay.psi()] + y[c + CA] + self.theta_start,
            c: [0.0, y[c + CY], y[c + CY + 1]],
            w: y[c + CW],
            v: [0.0, y[c + CV], y[c + CV + 1]],
        }
    }

    /// What follows the contact pass of an RHS evaluation at time t, state y, in both ball
    /// models: the neighbouring balls pressing on each other (cage-less,
    /// docs/model.md#ball-ball; true when any do, the forces in [`BallBall::force`]) or the
    /// cage ([`BallCore::cage_rhs`], its rates into `dydt`); each ball's contacts noted for the
    /// switches, and their normal forces for the outputs (a round-off-small negative force of
    /// the frozen law just before a located loss of contact reported as 0).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn after_pass(
        &mut self,
        t: f64,
        y: &[f64],
        pass: &ContactPass,
        inner: &RingPose,
        outer: &RingPose,
        psi_rate: f64,
        dydt: &mut [f64],
    ) -> (bool, Option<CageResult>) {
        let z = self.z;
        let touch = self
            .ball_ball
            .as_mut()
            .is_some_and(|bb| bb.evaluate(&pass.frames[..z]));
        let cage = self.cage_rhs(y, &pass.frames[..z], inner, outer, psi_rate, dydt);
        for (j, (ci, co)) in pass.contacts[..z].iter().enumerate() {
            self.sw.note_stage(t, j, ci, co);
            self.q_inner[j] = ci.q.max(0.0);
            self.q_outer[j] = co.q.max(0.0);
        }
        (touch, cage)
    }

    /// The cage's pocket and land contacts with the balls' frames and the rings at state y,
    /// its equations of motion written into `dydt` (the reference cage angle turning at
    /// `psi_rate`), and the land's reaction on the rings; None without a cage (a layout with
    /// the cage block but no cage body gets zero rates there). The pocket forces and moments on
    /// the balls are in [`Cage::pockets`].
    #[inline]
    pub fn cage_rhs(
        &mut self,
        y: &[f64],
        frames: &[super::pass::BallFrame],
        inner: &RingPose,
        outer: &RingPose,
        psi_rate: f64,
        dydt: &mut [f64],
    ) -> Option<CageResult> {
        let c = self.lay.cage_block();
        if self.cage.is_none() {
            // The cage's states without its body (while the start solves the balls' steady
            // rotation): they stay where they are.
            if self.lay.cage {
                dydt[c..c + super::layout::CAGE_STATES]
                    .iter_mut()
                    .for_each(|d| *d = 0.0);
            }
            return None;
        }
        let pose = self.cage_pose(y);
        let cage = self.cage.as_mut()?;
        let r = cage.evaluate(&pose, frames, inner, outer);
        dydt[c + CA] = pose.w - psi_rate;
        dydt[c + CY] = pose.v[1];
        dydt[c + CY + 1] = pose.v[2];
        dydt[c + CW] = r.w_dot;
        dydt[c + CV] = r.a[1];
        dydt[c + CV + 1] = r.a[2];
        Some(r)
    }

    /// Nominal values of the cage block (docs/model.md#tolerances): the angle deviation
    /// 1e-3 rad, the centre 1e-5 m, the rate 100 rad/s, the centre's velocity 1e-2 m/s.
    pub fn cage_nominal(&self, out: &mut [f64]) {
        if self.lay.cage {
            let c = self.lay.cage_block();
            out[c..c + super::layout::CAGE_STATES]
                .copy_from_slice(&[1e-3, 1e-5, 1e-5, 100.0, 1e-2, 1e-2]);
        }
    }

    /// The cage's kinetic energy and the elastic potential of its pocket and land contacts
    /// at state y \[J\] (0 without a cage).
    pub fn cage_energy(&self, y: &[f64]) -> f64 {
        let Some(cage) = &self.cage else {
            return 0.0;
        };
        let pose = self.cage_pose(y);
        let k = &cage.params;
        let e = |stiff: f64, d: f64| {
            if d > 0.0 {
                0.4 * stiff * d * d * d.sqrt()
            } else {
                0.0
            }
        };
        let mut sum = 0.5 * k.mass * dot(pose.v, pose.v) + 0.5 * k.inertia * pose.w * pose.w;
        for j in 0..self.z {
            let kin = self.ball_kin(y, j).0;
            let phi = pose.angle + TAU * j as f64 / self.z as f64;
            sum += e(
                k.pocket_stiffness,
                cage.pocket(&pose, phi, kin.p, kin.v, kin.omega).delta,
            );
        }
        let land = match k.guidance {
            crate::config::CageGuidance::Balls => return sum,
            crate::config::CageGuidance::InnerLand => {
                cage.land_contact(&pose, &self.inner_pose(y), -1.0)
            }
            crate::config::CageGuidance::OuterLand => {
                cage.land_contact(&pose, &self.outer_pose(y), 1.0)
            }
        };
        sum + e(k.land_stiffness, land.delta)
    }

    /// The ball-to-ball contacts (None when a cage keeps the balls apart); their last
    /// evaluation is the last right-hand side's.
    pub fn ball_ball(&self) -> Option<&BallBall> {
        self.ball_ball.as_ref()
    }

    /// Elastic potential of the ball-to-ball contacts at state y \[J\] (0 with a cage).
    pub fn ball_ball_potential(&self, y: &[f64]) -> f64 {
        let Some(bb) = &self.ball_ball else {
            return 0.0;
        };
        (0..self.z)
            .map(|j| {
                let next = (j + 1) % self.z;
                let p = bb.pair(&self.ball_kin(y, j).0, &self.ball_kin(y, next).0);
                bb.potential(p.delta)
            })
            .sum()
    }

    /// Smallest centre distance between neighbouring balls at state y, minus D \[m\]
    /// (negative: the balls overlap elastically).
    pub fn min_ball_gap(&self, y: &[f64]) -> f64 {
        (0..self.z)
            .map(|j| {
                let a = self.ball_kin(y, j).0.p;
                let b = self.ball_kin(y, (j + 1) % self.z).0.p;
                let r = ball_contact::sub(b, a);
                dot(r, r).sqrt() - 2.0 * self.ball_radius
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Sum of the Hertz potentials (2/5)Kδ^{5/2} of all intact contacts \[J\] (energy scale).
    pub fn hertz_potential(&self, y: &[f64]) -> f64 {
        let inner = self.inner_pose(y);
        let outer = self.outer_pose(y);
        let mut e = 0.0;
        for j in 0..self.z {
            let (kin, _, _, _, _) = self.ball_kin(y, j);
            for (pose, race) in [(&inner, &self.inner), (&outer, &self.outer)] {
                let c = ball_contact::evaluate(&kin, pose, race, self.ball_radius, 0.0, None, None);
                if c.delta > 0.0 {
                    e += 0.4 * race.k * c.delta * c.delta * c.delta.sqrt();
                }
            }
        }
        e
    }

    /// The translational part of the equations of motion common to both models, for ball j
    /// at state y with the total contact force `f` on it: ẋ, ṙ, θ − ψ, and the cylindrical
    /// accelerations (centrifugal and Coriolis terms included), written into `dydt`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn ball_translation(
        &self,
        y: &[f64],
        j: usize,
        f: V3,
        er: V3,
        et: V3,
        r: f64,
        w: f64,
        psi_rate: f64,
        dydt: &mut [f64],
    ) {
        let b = self.lay.ball(j);
        let m = self.ball_mass;
        let vr = y[b + BVR];
        dydt[b + BX] = y[b + BVX];
        dydt[b + BR] = vr;
        dydt[b + BTH] = w - psi_rate;
        dydt[b + BVX] = f[0] / m;
        dydt[b + BVR] = dot(f, er) / m + r * w * w;
        dydt[b + BW] = (dot(f, et) / m - 2.0 * vr * w) / r;
    }

    /// The inner ring's translation and the pedestal's equations of motion (and ψ̇, φ̇) from the
    /// force of the balls on the inner ring `f_ring` and on the outer ring `f_outer`.
    #[inline(always)]
    pub fn rings(
        &self,
        t: f64,
        y: &[f64],
        f_ring: V3,
        f_outer: V3,
        psi_rate: f64,
        dydt: &mut [f64],
    ) {
        let r = self.lay.ring();
        let ext = [self.inputs.fx, self.inputs.fy, self.inputs.fz];
        for k in 0..3 {
            dydt[r + RX + k] = y[r + RV + k];
            dydt[r + RV + k] = if self.prescribed || (k == 0 && self.held_axial.is_some()) {
                0.0
            } else if let Some(law) = &self.ring_load {
                (ext[k] + law.force(k, t, y[r + RV + k]) + f_ring[k]) / self.m_ir
            } else {
                (ext[k] + f_ring[k]) / self.m_ir
            };
        }
        let p = self.lay.pedestal();
        let pulse = self.pulse.as_ref().map_or(0.0, |pl| pl.force(t));
        dydt[p + PY] = y[p + PVY];
        dydt[p + PZ] = y[p + PVZ];
        dydt[p + PVY] = (f_outer[1] - self.k_py * y[p + PY] - self.c_py * y[p + PVY]) / self.m_p;
        dydt[p + PVZ] =
            (f_outer[2] - self.k_pz * y[p + PZ] - self.c_pz * y[p + PVZ] - pulse) / self.m_p;
        dydt[self.lay.psi()] = psi_rate;
        dydt[self.lay.phi()] = self.inputs.shaft_speed;
    }
}

/// The [`crate::models::Model`] methods the ball-level models (reduced, full) share, each
/// forwarding to the model's `core: BallCore`; expanded inside each model's `impl Model`
/// (`outputs` evaluates that model's own right-hand side and friction torque first).
macro_rules! forward_to_ball_core {
    () => {
        fn dim(&self) -> usize {
            self.core.lay.dim()
        }

        fn start_note(&self) -> Option<String> {
            self.core.start_note.clone()
        }

        fn initial_state(&self, y: &mut [f64]) {
            y.copy_from_slice(&self.core.y0);
        }

        fn set_inputs(
            &mut self,
            inputs: &$crate::operating::OperatingPoint,
            _t: f64,
            _y: &[f64],
        ) -> Result<(), $crate::models::SimError> {
            self.core.inputs = *inputs;
            Ok(())
        }

        fn next_stop(&self, t: f64, _y: &[f64], t_max: f64) -> Option<f64> {
            self.core.next_stop(t, t_max)
        }

        fn update_mode(&mut self, t: f64, y: &[f64]) {
            self.core.update_mode(t, y);
        }

        fn begin_step(&mut self) {
            self.core.sw.begin_step();
        }

        fn suspect(&mut self, t_old: f64, t_new: f64) -> Option<f64> {
            self.core.sw.suspect(t_old, t_new)
        }

        fn event_fired(&mut self, index: usize) {
            self.core.sw.event_fired(index);
        }

        fn mode_sign(&self, index: usize) -> Option<f64> {
            self.core.sw.mode_sign(index)
        }

        fn diagnose(&mut self, _t: f64, y: &[f64]) -> Option<String> {
            self.core.diagnose(y)
        }

        fn checkpoint(&self, b: &mut Vec<f64>) {
            self.core.checkpoint(b);
        }

        fn rollback(&mut self, b: &[f64], _t: f64, _y: &[f64]) -> Result<(), String> {
            self.core.rollback(b)
        }

        fn n_events(&self) -> usize {
            self.core.n_events()
        }

        fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
            self.core.events(y, g);
        }

        fn event(&mut self, i: usize, _t: f64, y: &[f64], g: &mut [f64]) -> f64 {
            self.core.event(i, y, g)
        }

        fn event_name(&self, i: usize) -> String {
            self.core.event_name(i)
        }

        fn outputs(&mut self, t: f64, y: &[f64], o: &mut [f64]) {
            let mut dydt = std::mem::take(&mut self.core.scratch);
            self.rhs(t, y, &mut dydt);
            self.core.outputs(y, &dydt, self.friction_torque(), o);
            self.core.scratch = dydt;
        }

        fn cage_speed(&self) -> f64 {
            self.core.cage_speed()
        }

        fn has_cage(&self) -> bool {
            self.core.cage.is_some()
        }

        fn ring_states(&self) -> Option<$crate::models::RingStates> {
            Some(self.core.ring_states())
        }

        fn set_prescribed_ring(&mut self, on: bool) {
            self.core.prescribed = on;
        }

        fn set_ring_load(&mut self, law: Option<$crate::operating::RingLoad>) -> bool {
            self.core.ring_load = law;
            true
        }
    };
}
pub(crate) use forward_to_ball_core;

#[cfg(test)]
mod tests {
    use crate::geometry::{Bearing, Race};
    use crate::models::full::FullModel;
    use crate::models::Model;
    use crate::scene::Scene;

    /// The rates the ball levels use for a spall on a ball and for ball waviness are the time
    /// derivatives of the quantities themselves: central differences along the model's own
    /// motion (y ± h ẏ) at the start, at both contacts, for a spall 0.37 rad ahead of the outer
    /// contact (inside the quarter turn where its angle is not clipped there; clipped, with
    /// rate 0, at the inner one) and an order-3 ball waviness.
    #[test]
    fn direction_rates_are_the_derivatives_of_the_angles_and_the_waviness() {
        let mut sc = Scene::default_scene();
        sc.fidelity = crate::scene::Fidelity::Full;
        sc.set_defects(vec![crate::defect::DefectSpec {
            ring: crate::defect::Site::Ball(2),
            width: 1.0e-3,
            depth: 0.2e-3,
            theta0: 1.2,
        }]);
        sc.waviness = Some(crate::waviness::WavinessSpec {
            ball: vec![crate::waviness::Harmonic(3.0, 1e-7, 0.4)],
            ..Default::default()
        });
        let b = Bearing::new(&sc.bearing).unwrap();
        let mut m = FullModel::new(&sc, &b, &sc.operating).unwrap();
        let n = m.dim();
        let mut y = vec![0.0; n];
        m.initial_state(&mut y);
        let mut f = vec![0.0; n];
        m.rhs(0.0, &y, &mut f);
        let h = 1e-8;
        let at = |k: f64| -> Vec<f64> { y.iter().zip(&f).map(|(v, d)| v + k * h * d).collect() };
        let (yp, ym) = (at(1.0), at(-1.0));
        let c = m.core();
        let j = 1;
        for race in [Race::Outer, Race::Inner] {
            let (pose, rc) = match race {
                Race::Inner => (c.inner_pose(&y), &c.inner),
                Race::Outer => (c.outer_pose(&y), &c.outer),
            };
            let pose_of = |y: &[f64]| match race {
                Race::Inner => c.inner_pose(y),
                Race::Outer => c.outer_pose(y),
            };
            let kin_of = |y: &[f64]| c.ball_kin(y, j);
            let (kin, _, _, _, w) = kin_of(&y);
            let spall = |y: &[f64]| {
                let (kin, _, _, _, w) = kin_of(y);
                c.ball_spall_angle(y, 0, race, &kin, &pose_of(y), rc, w)
            };
            let (tbd, rate) = c.ball_spall_angle(&y, 0, race, &kin, &pose, rc, w);
            let fd = (spall(&yp).0 - spall(&ym).0) / (2.0 * h);
            // The direction counts, not its length (the integration lets |u| drift).
            let mut y2 = y.clone();
            let i = c.lay.spall_dir(0);
            y2[i..i + 3].iter_mut().for_each(|v| *v *= 1.5);
            let (tbd2, rate2) = c.ball_spall_angle(&y2, 0, race, &kin, &pose, rc, w);
            assert!((tbd2 - tbd).abs() <= 1e-12 && (rate2 - rate).abs() <= 1e-9 * rate.abs());
            match race {
                Race::Outer => {
                    // The spall 0.37 rad ahead of the contact along e_θ (φ = π/2 − θ0): y_b =
                    // −(D/2)·φ, negative as for a ball before a raceway spall, which it nears
                    // (within 1 %: the circle is the spin's, the contact the groove's).
                    let y_b = c.ball_spalls[0].at(race).along_track(tbd);
                    let expected = -c.ball_radius * (std::f64::consts::FRAC_PI_2 - 1.2);
                    assert!(
                        (y_b - expected).abs() < 0.01 * expected.abs(),
                        "y_b {y_b}, expected {expected}"
                    );
                    assert!(rate.abs() > 1.0, "rate {rate}");
                }
                Race::Inner => assert_eq!((tbd, rate), (tbd, 0.0), "clipped there"),
            }
            // (The rates leave out the contact normal's own motion beyond the orbit's turn, the
            // contact angle's drift: 5e-5 of the spall's rate here, 3e-4 of the waviness's,
            // whose reference direction is a quarter turn from the contact.)
            assert!(
                (rate - fd).abs() <= 1e-3 * rate.abs().max(1.0),
                "{race:?}: spall rate {rate} against {fd}"
            );
            let wv = c.waviness.as_ref().unwrap();
            let wavy = |y: &[f64]| {
                let (kin, _, _, _, w) = kin_of(y);
                c.ball_waviness(wv, y, j, race, &kin, &pose_of(y), w, None)
            };
            let (v, d) = wavy(&y);
            let fd = (wavy(&yp).0 - wavy(&ym).0) / (2.0 * h);
            // At the start the reference direction is midway between the contacts: the outer
            // contact sees r(ψ_j0) = A cos(0.4), the inner r(ψ_j0 + π) = A cos(3π + 0.4) (ψ_j0 = 0
            // without a phase seed; within 1 %: the contacts are not exactly opposite).
            let expected = match race {
                Race::Outer => 1e-7 * 0.4f64.cos(),
                Race::Inner => 1e-7 * (3.0 * std::f64::consts::PI + 0.4).cos(),
            };
            assert!(
                (v - expected).abs() < 0.01 * expected.abs() && d.abs() > 1e-5,
                "{race:?}: waviness {v} (expected {expected}), rate {d}"
            );
            assert!(
                (d - fd).abs() <= 1e-3 * d.abs(),
                "{race:?}: waviness rate {d} against {fd}"
            );
        }
    }
}

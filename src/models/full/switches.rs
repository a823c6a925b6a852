//! The frozen discrete modes of a ball-level model (full and reduced levels) and their switches.
//!
//! The clamped contact law, the C9 compliance blend and the spall halves are not smooth in the
//! state; a model that owns a [`Switches`] evaluates a frozen law inside each step
//! ([`Switches::law`], [`Switches::blend`], [`Switches::side`]) and locates the switches as
//! state events. Event indices, per ball j of z: 2j, 2j + 1 the inner and outer contact
//! (min(δ′, Q/S)); with a spall 2z + 2j the zone edge, 2z + 2j + 1 the spall centre and
//! 4z + j the blend boundary.
//!
//! A model fills [`Switches::angles`] (θ_bd and its rate per ball) and, after
//! [`Switches::update_spall`], [`Switches::contact_events`] (the contact functions under the new
//! halves) before [`Switches::update_contacts`]; nothing here allocates after construction.

use super::contact::{self, BallKin, ContactOut, DefectView, Law, RaceConst, RingPose};
use crate::defect::Defect;
use crate::geometry::Race;

/// Scale of the force part of the contact event function min(δ′, Q/S) [N/m]: only the sign and
/// the continuity of the function matter (the same value as the lumped level's).
pub const EVENT_FORCE_SCALE: f64 = 1e8;

/// How far beyond its root \[m\] a stage must find a contact's event function before the step
/// is suspected of a short loss or touch (located roots sit within ~1e-13 m at rtol 1e-6).
pub const EVENT_ROOT_TOL: f64 = 1e-10;

/// Frozen modes and event bookkeeping of z balls.
#[derive(Debug, Clone, Default)]
pub struct Switches {
    z: usize,
    /// Frozen spall half per ball: 0 outside, −1 / +1 the sign of y_b.
    sides: Vec<f64>,
    /// Balls whose half changed in the last mode update (their contact functions jump there).
    sides_changed: Vec<bool>,
    /// Frozen side of the edge-constant blend per ball (true: within ℓ_b of an edge, C9);
    /// its boundary is a state event (index 4z + j) like the contact switches.
    in_blend: Vec<bool>,
    /// Frozen contact modes per ball, (inner, outer): true = in contact (the unclamped force
    /// law), false = open (no normal force). Set by the mode update once `modes_set`; before
    /// that (the initial state) the clamped law is used.
    closed: Vec<[bool; 2]>,
    modes_set: bool,
    /// Events that fired since the last mode update: those switches flip.
    fired: Vec<bool>,
    /// Time of each switch's last flip: a driver that updates the mode once per fired event
    /// (several events at one located time) must not re-derive an already flipped switch
    /// from the sign of its function, which sits within round-off of 0 there.
    flipped_at: Vec<f64>,
    /// The stage time of the current step attempt at which a contact's frozen mode was most
    /// clearly invalid (closed with min(δ′, Q/S) < −[`EVENT_ROOT_TOL`], open with it above),
    /// and by how much: a short loss or touch inside one step has two roots that the sign test
    /// at the step end misses, so the integrator also tests this time.
    suspect: Option<(f64, f64)>,
    /// Per ball: θ_bd and its rate at the state of the mode update (filled by the model).
    pub angles: Vec<(f64, f64)>,
    /// Per ball: the contact event functions and unclamped forces (inner, outer) at the state
    /// of the mode update under the updated halves (filled by the model).
    pub contact_events: Vec<[(f64, f64); 2]>,
}

/// The contact event function min(δ′, Q/S) of one evaluation (Q unclamped).
#[inline(always)]
pub fn contact_event(c: &ContactOut) -> f64 {
    c.delta.min(c.q_raw / EVENT_FORCE_SCALE)
}

impl Switches {
    /// Modes for z balls: all outside the spall, contacts under the clamped law until the
    /// first mode update.
    pub fn new(z: usize) -> Self {
        Self {
            z,
            sides: vec![0.0; z],
            sides_changed: vec![false; z],
            in_blend: vec![false; z],
            closed: vec![[true; 2]; z],
            modes_set: false,
            fired: vec![false; 5 * z],
            flipped_at: vec![f64::NAN; 5 * z],
            suspect: None,
            angles: vec![(0.0, 0.0); z],
            contact_events: vec![[(0.0, 0.0); 2]; z],
        }
    }

    /// Number of event functions: the contacts, and with a spall the edges, centres and blends.
    pub fn n_events(&self, spall: bool) -> usize {
        if spall {
            5 * self.z
        } else {
            2 * self.z
        }
    }

    /// Frozen spall half of ball j (0 outside the zone).
    #[inline(always)]
    pub fn side(&self, j: usize) -> f64 {
        self.sides[j]
    }

    /// Frozen blend side of ball j (`None` before the first mode update: by the position).
    #[inline(always)]
    pub fn blend(&self, j: usize) -> Option<bool> {
        self.modes_set.then(|| self.in_blend[j])
    }

    /// The normal-force law of ball j's contact `k` (0 inner, 1 outer) in the frozen mode.
    #[inline(always)]
    pub fn law(&self, j: usize, k: usize) -> Law {
        if !self.modes_set {
            Law::Clamped
        } else if self.closed[j][k] {
            Law::Closed
        } else {
            Law::Open
        }
    }

    /// Records a stage evaluation of ball j's contacts at time t: the stage where a frozen
    /// mode is most clearly invalid becomes the step's suspect time.
    #[inline(always)]
    pub fn note_stage(&mut self, t: f64, j: usize, ci: &ContactOut, co: &ContactOut) {
        if !self.modes_set {
            return;
        }
        for (k, c) in [ci, co].into_iter().enumerate() {
            let g = contact_event(c);
            let excess = if self.closed[j][k] { -g } else { g };
            if excess > EVENT_ROOT_TOL && self.suspect.is_none_or(|(_, e)| excess > e) {
                self.suspect = Some((t, excess));
            }
        }
    }

    /// Start of a step attempt: forget the suspect time.
    pub fn begin_step(&mut self) {
        self.suspect = None;
    }

    /// The suspect time of the step just accepted, if inside (t_old, t_new).
    pub fn suspect(&self, t_old: f64, t_new: f64) -> Option<f64> {
        self.suspect
            .map(|(t, _)| t)
            .filter(|&t| t > t_old && t < t_new)
    }

    /// Appends the frozen modes and the switch memory to `b` (a model's
    /// [`crate::models::Model::checkpoint`]); [`Switches::CHECKPOINT_PER_BALL`] values per ball
    /// and 4 more. No allocation once `b` has its size.
    pub fn checkpoint(&self, b: &mut Vec<f64>) {
        let flag = |on: bool| f64::from(u8::from(on));
        let (has, t, e) = self.suspect.map_or((0.0, 0.0, 0.0), |(t, e)| (1.0, t, e));
        b.extend_from_slice(&[flag(self.modes_set), has, t, e]);
        b.extend_from_slice(&self.sides);
        b.extend(self.sides_changed.iter().map(|&v| flag(v)));
        b.extend(self.in_blend.iter().map(|&v| flag(v)));
        b.extend(self.closed.iter().flat_map(|c| [flag(c[0]), flag(c[1])]));
        b.extend(self.fired.iter().map(|&v| flag(v)));
        b.extend_from_slice(&self.flipped_at);
    }

    /// Values per ball in [`Switches::checkpoint`] (sides, their changes, blends, two contacts,
    /// and five events' flags and flip times).
    pub const CHECKPOINT_PER_BALL: usize = 15;

    /// Puts back what [`Switches::checkpoint`] wrote (exactly `4 + 15 z` values).
    pub fn rollback(&mut self, b: &[f64]) -> Result<(), String> {
        let z = self.z;
        if b.len() != 4 + Self::CHECKPOINT_PER_BALL * z {
            return Err(format!(
                "mode checkpoint has {} values, got {}",
                4 + Self::CHECKPOINT_PER_BALL * z,
                b.len()
            ));
        }
        self.modes_set = b[0] != 0.0;
        self.suspect = (b[1] != 0.0).then_some((b[2], b[3]));
        let (sides, b) = b[4..].split_at(z);
        let (changed, b) = b.split_at(z);
        let (blend, b) = b.split_at(z);
        let (closed, b) = b.split_at(2 * z);
        let (fired, flipped) = b.split_at(5 * z);
        self.sides.copy_from_slice(sides);
        for (v, &x) in self.sides_changed.iter_mut().zip(changed) {
            *v = x != 0.0;
        }
        for (v, &x) in self.in_blend.iter_mut().zip(blend) {
            *v = x != 0.0;
        }
        for (c, x) in self.closed.iter_mut().zip(closed.chunks_exact(2)) {
            *c = [x[0] != 0.0, x[1] != 0.0];
        }
        for (v, &x) in self.fired.iter_mut().zip(fired) {
            *v = x != 0.0;
        }
        self.flipped_at.copy_from_slice(flipped);
        Ok(())
    }

    /// Event `index` fired at the located time.
    pub fn event_fired(&mut self, index: usize) {
        if let Some(f) = self.fired.get_mut(index) {
            *f = true;
        }
    }

    /// Spall event functions of ball j at θ_bd = `tbd` (index 2z + 2j, 2z + 2j + 1, 4z + j):
    /// θ_e − |θ_bd| (edge crossings); while the ball is in the zone θ_bd clipped to ±0.5 rad
    /// (the centre, where the ball changes corners; 1 outside the zone, where the wrap of θ_bd
    /// at ±π would fire a spurious event once per orbit of every ball); the blend boundary
    /// ([`Defect::blend_margin`]).
    #[inline(always)]
    pub fn spall_events(&self, d: &Defect, j: usize, tbd: f64, g: &mut [f64]) {
        let z2 = 2 * self.z;
        g[z2 + 2 * j] = d.zone_margin(tbd);
        g[z2 + 2 * j + 1] = if self.sides[j] != 0.0 {
            tbd.clamp(-0.5, 0.5)
        } else {
            1.0
        };
        g[2 * z2 + j] = d.blend_margin(tbd);
    }

    /// Re-derives the frozen spall halves and blend sides from [`Switches::angles`] (at time
    /// t). A ball whose centre event just fired changes halves and one whose edge event fired
    /// enters (on the side of θ_bd) or leaves the zone: at the located state θ_bd sits within
    /// the location tolerance of the boundary on either side (the state is re-integrated by the
    /// method, not taken from the interpolant), so its sign alone could keep the old half for
    /// the rest of the pass. Every other ball takes its half from θ_bd (a position a hair ahead
    /// along the motion decides at a boundary). Blend sides likewise: a fired blend event
    /// flips, others follow the sign of the blend function.
    pub fn update_spall(&mut self, t: f64, d: &Defect) {
        let te = d.half_angle();
        let z2 = 2 * self.z;
        let hair = |(tbd, rate): (f64, f64)| {
            tbd + 1e-12 * rate.signum() * f64::from(u8::from(rate != 0.0))
        };
        for j in 0..self.z {
            let (tbd, rate) = self.angles[j];
            let (edge, centre) = (z2 + 2 * j, z2 + 2 * j + 1);
            let fired = |i: usize| self.modes_set && self.fired[i];
            let kept = |i: usize| self.modes_set && self.flipped_at[i] == t;
            let before = self.sides[j];
            let (side, flipped) = if fired(centre) && before != 0.0 {
                (-before, Some(centre))
            } else if fired(edge) {
                let side = if before != 0.0 {
                    0.0
                } else if tbd < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                (side, Some(edge))
            } else if kept(centre) || kept(edge) {
                (before, None)
            } else {
                let a = hair((tbd, rate));
                let side = if a.is_nan() || a.abs() >= te {
                    0.0
                } else if a < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                (side, None)
            };
            if let Some(i) = flipped {
                self.flipped_at[i] = t;
            }
            self.sides[j] = side;
            self.sides_changed[j] = side != before;
        }
        let z4 = 4 * self.z;
        for j in 0..self.z {
            let i = z4 + j;
            if self.modes_set && self.fired[i] {
                self.in_blend[j] = !self.in_blend[j];
                self.flipped_at[i] = t;
            } else if !(self.modes_set && self.flipped_at[i] == t) {
                self.in_blend[j] = d.blend_margin(hair(self.angles[j])) < 0.0;
            }
        }
    }

    /// Re-derives the frozen contact modes from [`Switches::contact_events`] (at time t) and
    /// ends the mode update: a contact whose event just fired flips (at the located state its
    /// function sits within the location accuracy of 0, on either side); every other one
    /// follows the sign of its event function (on an exact 0 the sign of the unclamped force
    /// decides), and so do both contacts of a ball that changed spall halves at this update (a
    /// contact event located at the same time as the spall centre fired under the old half;
    /// with the new one the function jumps).
    pub fn update_contacts(&mut self, t: f64) {
        for j in 0..self.z {
            // A ball that changed halves at this update has new contact functions: only
            // their signs tell the modes.
            let flip = self.modes_set && !self.sides_changed[j];
            for k in 0..2 {
                let (g, q) = self.contact_events[j][k];
                let i = 2 * j + k;
                if flip && self.fired[i] {
                    self.closed[j][k] = !self.closed[j][k];
                    self.flipped_at[i] = t;
                } else if !(flip && self.flipped_at[i] == t) {
                    self.closed[j][k] = g > 0.0 || (g == 0.0 && q > 0.0);
                }
            }
        }
        self.fired.iter_mut().for_each(|f| *f = false);
        self.modes_set = true;
    }
}

/// Implements [`SwitchedModel`] for a ball-level model through the members the full and the
/// reduced model both have: the fields `z`, `sw`, `defect`, `inner`, `outer`, `ball_radius`,
/// `c_br`, `inputs`, `lay`, `defect_a_star` and the methods `inner_pose`, `outer_pose`,
/// `ball_kin`, `theta_bd`.
macro_rules! impl_switched_model {
    ($model:ty) => {
        impl $crate::models::full::switches::SwitchedModel for $model {
            fn n_balls(&self) -> usize {
                self.z
            }

            fn switches(&self) -> &$crate::models::full::switches::Switches {
                &self.sw
            }

            fn switch_parts(
                &mut self,
            ) -> (
                &mut $crate::models::full::switches::Switches,
                Option<&$crate::defect::Defect>,
            ) {
                (&mut self.sw, self.defect.as_ref())
            }

            fn spall(&self) -> Option<&$crate::defect::Defect> {
                self.defect.as_ref()
            }

            fn ring_poses(
                &self,
                y: &[f64],
            ) -> (
                $crate::models::full::contact::RingPose,
                $crate::models::full::contact::RingPose,
            ) {
                (self.inner_pose(y), self.outer_pose(y))
            }

            #[inline(always)]
            fn ball_state(
                &self,
                y: &[f64],
                j: usize,
            ) -> ($crate::models::full::contact::BallKin, f64) {
                let (kin, _, _, _, w) = self.ball_kin(y, j);
                (kin, w)
            }

            fn contact_constants(
                &self,
            ) -> (
                &$crate::models::full::contact::RaceConst,
                &$crate::models::full::contact::RaceConst,
                f64,
                f64,
            ) {
                (&self.inner, &self.outer, self.ball_radius, self.c_br)
            }

            #[inline(always)]
            fn spall_view(
                &self,
                y: &[f64],
                j: usize,
                race: $crate::geometry::Race,
                w: f64,
            ) -> Option<$crate::models::full::contact::DefectView<'_>> {
                let d = self.defect.as_ref()?;
                if d.ring() != race || self.sw.side(j) == 0.0 {
                    return None;
                }
                // θ_bd turns with the ball, less the shaft for an inner-race spall.
                let rate = match race {
                    $crate::geometry::Race::Inner => w - self.inputs.shaft_speed,
                    $crate::geometry::Race::Outer => w,
                };
                Some($crate::models::full::contact::DefectView {
                    defect: d,
                    side: self.sw.side(j),
                    phi: y[self.lay.phi()],
                    theta_bd_rate: rate,
                    a_star: self.defect_a_star,
                    blend: self.sw.blend(j),
                })
            }

            fn spall_angle(&self, d: &$crate::defect::Defect, y: &[f64], j: usize) -> (f64, f64) {
                self.theta_bd(d, y, j)
            }
        }
    };
}
pub(crate) use impl_switched_model;

/// The event part of [`crate::models::Model`] for a [`SwitchedModel`] with a `pulse` field,
/// written once for the full and the reduced model: the pulse's kinks are stops, the modes live
/// in the model's [`Switches`]. Expands to methods inside `impl Model for …`.
macro_rules! switched_model_events {
    () => {
        fn next_stop(&self, t: f64, _y: &[f64], t_max: f64) -> Option<f64> {
            self.pulse.as_ref()?.next_kink(t).filter(|&tp| tp <= t_max)
        }

        fn update_mode(&mut self, t: f64, y: &[f64]) {
            self.update_switches(t, y);
        }

        fn begin_step(&mut self) {
            self.sw.begin_step();
        }

        fn suspect(&mut self, t_old: f64, t_new: f64) -> Option<f64> {
            self.sw.suspect(t_old, t_new)
        }

        fn event_fired(&mut self, index: usize) {
            self.sw.event_fired(index);
        }

        /// Whether any ball still carries load: both its contacts with a positive force under
        /// the clamped law (the contact event functions positive).
        fn diagnose(&mut self, _t: f64, y: &[f64]) -> Option<String> {
            use $crate::models::full::switches::SwitchedModel;
            let (inner, outer) = self.ring_poses(y);
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
        fn checkpoint(&self, b: &mut Vec<f64>) {
            b.clear();
            self.sw.checkpoint(b);
        }

        fn rollback(&mut self, b: &[f64], _t: f64, _y: &[f64]) -> Result<(), String> {
            self.sw.rollback(b)
        }

        fn n_events(&self) -> usize {
            self.sw.n_events(self.defect.is_some())
        }

        /// Per ball (index 2j, 2j + 1): the contact events of the inner and outer contact
        /// (`contact_events`). With a spall, then per ball (index 2z + 2j, 2z + 2j + 1):
        /// θ_e − |θ_bd| (edge crossings) and, while the ball is in the zone, θ_bd clipped to
        /// ±0.5 rad (the centre, where the ball changes corners; 1 outside the zone, where the
        /// wrap of θ_bd at ±π used to fire a spurious event once per orbit of every ball); then
        /// per ball (index 4z + j) the blend boundary (`Defect::blend_margin`).
        fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
            self.switch_events(y, g);
        }
    };
}
pub(crate) use switched_model_events;

/// The output part of [`crate::models::Model`] for the full and the reduced model, whose state
/// vectors share the ball, ring and pedestal offsets of [`super::layout`]: `outputs` (pedestal
/// acceleration from the right-hand side, the states, the ring force of the last evaluation, the
/// per-ball contact forces and orbital speeds), `cage_speed`, `ring_states` and
/// `set_prescribed_ring`. Expands to methods inside `impl Model for …`; the model provides
/// `scratch`, `lay`, `ring_force`, `q_inner`, `q_outer`, `z`, `cage_ratio`, `inputs`,
/// `prescribed`, `mean_orbital_speed(y)` and `friction_torque()`.
macro_rules! ball_model_outputs {
    () => {
        fn outputs(&mut self, t: f64, y: &[f64], o: &mut [f64]) {
            use $crate::models::full::layout::{BW, PVY, PVZ, PY, PZ, RX};
            use $crate::models::out;
            let mut dydt = std::mem::take(&mut self.scratch);
            self.rhs(t, y, &mut dydt);
            let p = self.lay.pedestal();
            let r = self.lay.ring();
            o[out::PEDESTAL_A_Y] = dydt[p + PVY];
            o[out::PEDESTAL_A_Z] = dydt[p + PVZ];
            self.scratch = dydt;
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
            o[out::FRICTION_TORQUE] = self.friction_torque();
            o[out::CAGE_SPEED] = self.mean_orbital_speed(y);
            if !out::has_ball_block(o, self.z) {
                return;
            }
            for j in 0..self.z {
                o[out::CONTACT_START + j] = self.q_inner[j];
                o[out::CONTACT_START + self.z + j] = self.q_outer[j];
                o[out::orbit_speed(self.z, j)] = y[self.lay.ball(j) + BW];
            }
            out::set_separation_flags(o, self.z);
        }

        fn cage_speed(&self) -> f64 {
            self.cage_ratio * self.inputs.shaft_speed
        }

        fn ring_states(&self) -> Option<$crate::models::RingStates> {
            use $crate::models::full::layout::{RV, RX};
            let r = self.lay.ring();
            Some($crate::models::RingStates {
                pos: [r + RX, r + RX + 1, r + RX + 2],
                vel: [r + RV, r + RV + 1, r + RV + 2],
            })
        }

        fn set_prescribed_ring(&mut self, on: bool) {
            self.prescribed = on;
        }
    };
}
pub(crate) use ball_model_outputs;

/// A ball-level model whose frozen modes live in a [`Switches`] (full and reduced levels): it
/// gives the per-ball contact geometry, and the contact event functions, the mode update and the
/// event vector are written once here.
pub trait SwitchedModel {
    /// Number of balls z.
    fn n_balls(&self) -> usize;
    /// The switches.
    fn switches(&self) -> &Switches;
    /// The switches and the spall, borrowed apart.
    fn switch_parts(&mut self) -> (&mut Switches, Option<&Defect>);
    /// The spall, if any.
    fn spall(&self) -> Option<&Defect>;
    /// The inner- and outer-ring poses at state y.
    fn ring_poses(&self, y: &[f64]) -> (RingPose, RingPose);
    /// Ball j's kinematics and orbital rate at state y.
    fn ball_state(&self, y: &[f64], j: usize) -> (BallKin, f64);
    /// Inner and outer race constants, ball radius \[m\] and contact damping c_br [N s/m].
    fn contact_constants(&self) -> (&RaceConst, &RaceConst, f64, f64);
    /// The spall as seen by ball j on `race` in the frozen interval (orbital rate `w`).
    fn spall_view(&self, y: &[f64], j: usize, race: Race, w: f64) -> Option<DefectView<'_>>;
    /// Ball-to-spall angle θ_bd of ball j and its rate.
    fn spall_angle(&self, d: &Defect, y: &[f64], j: usize) -> (f64, f64);

    /// Both normal contacts of ball j (inner, outer) under the frozen laws, with the slip fields
    /// of the loaded ones when `slip` (traction on): the first stage of [`contact::evaluate_law`]
    /// one ball at a time ([`SwitchedModel::normal_contacts_into`] for a
    /// [`super::pass::ContactPass`]).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn normal_contacts(
        &self,
        y: &[f64],
        j: usize,
        kin: &BallKin,
        w: f64,
        inner: &RingPose,
        outer: &RingPose,
        slip: bool,
    ) -> [super::pass::Normal; 2] {
        let (race_in, race_out, _, _) = self.contact_constants();
        let grooves = [
            contact::groove_pos(kin.p, inner, race_in),
            contact::groove_pos(kin.p, outer, race_out),
        ];
        let mut out = Default::default();
        let [li, lo] =
            self.normal_contacts_into(y, j, kin, w, inner, outer, slip, &grooves, &mut out);
        [(out.0, li), (out.1, lo)]
    }

    /// [`SwitchedModel::normal_contacts`] from the ball's place in both grooves
    /// ([`contact::groove_pos`], inner and outer), writing the two contacts into `out` (inner,
    /// outer) and returning the slip fields and frames of the loaded ones.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn normal_contacts_into(
        &self,
        y: &[f64],
        j: usize,
        kin: &BallKin,
        w: f64,
        inner: &RingPose,
        outer: &RingPose,
        slip: bool,
        grooves: &[contact::GroovePos; 2],
        out: &mut (ContactOut, ContactOut),
    ) -> [Option<super::pass::Loaded>; 2] {
        let (race_in, race_out, radius, c_br) = self.contact_constants();
        let sw = self.switches();
        let normal =
            |k: usize, pose: &RingPose, race: &RaceConst, ring: Race, c: &mut ContactOut| {
                contact::evaluate_normal_at(
                    &grooves[k],
                    kin,
                    pose,
                    race,
                    radius,
                    c_br,
                    self.spall_view(y, j, ring, w),
                    sw.law(j, k),
                    slip,
                    c,
                )
            };
        [
            normal(0, inner, race_in, Race::Inner, &mut out.0),
            normal(1, outer, race_out, Race::Outer, &mut out.1),
        ]
    }

    /// Contact event functions of ball j, (inner, outer): min(δ′, Q/S) with Q the unclamped
    /// force K δ′|δ′|^{1/2} + c δ̇′ under the frozen spall half and blend side. Positive exactly
    /// where the clamped law has a positive force; continuous, so the loss of a contact (Q
    /// reaching 0) and its return (δ′ reaching 0 with the damping jump c δ̇′, or Q rising
    /// through 0) are its roots. Also the unclamped forces.
    #[inline(always)]
    fn contact_events(
        &self,
        y: &[f64],
        j: usize,
        inner: &RingPose,
        outer: &RingPose,
    ) -> [(f64, f64); 2] {
        let (kin, w) = self.ball_state(y, j);
        let (race_in, race_out, radius, c_br) = self.contact_constants();
        let ev = |pose: &RingPose, race: &RaceConst, ring: Race| {
            let c = contact::evaluate_law(
                &kin,
                pose,
                race,
                radius,
                c_br,
                None,
                self.spall_view(y, j, ring, w),
                Law::Closed,
            );
            (contact_event(&c), c.q_raw)
        };
        [
            ev(inner, race_in, Race::Inner),
            ev(outer, race_out, Race::Outer),
        ]
    }

    /// Re-derives the frozen modes at state y (at time t): spall halves and blend sides, then
    /// the contact modes under the new halves. Fills the switches' buffers in place (taken out
    /// and put back, no allocation).
    fn update_switches(&mut self, t: f64, y: &[f64]) {
        let z = self.n_balls();
        if self.spall().is_some() {
            let mut angles = std::mem::take(&mut self.switch_parts().0.angles);
            if let Some(d) = self.spall() {
                for (j, a) in angles.iter_mut().enumerate().take(z) {
                    *a = self.spall_angle(d, y, j);
                }
            }
            let (sw, d) = self.switch_parts();
            sw.angles = angles;
            if let Some(d) = d {
                sw.update_spall(t, d);
            }
        }
        let (inner, outer) = self.ring_poses(y);
        let mut events = std::mem::take(&mut self.switch_parts().0.contact_events);
        for (j, e) in events.iter_mut().enumerate().take(z) {
            *e = self.contact_events(y, j, &inner, &outer);
        }
        let (sw, _) = self.switch_parts();
        sw.contact_events = events;
        sw.update_contacts(t);
    }

    /// Writes the event functions (indices in the module documentation) into `g`.
    fn switch_events(&self, y: &[f64], g: &mut [f64]) {
        let (inner, outer) = self.ring_poses(y);
        for j in 0..self.n_balls() {
            let [(gi, _), (go, _)] = self.contact_events(y, j, &inner, &outer);
            g[2 * j] = gi;
            g[2 * j + 1] = go;
        }
        let Some(d) = self.spall() else { return };
        for j in 0..self.n_balls() {
            let (tbd, _) = self.spall_angle(d, y, j);
            self.switches().spall_events(d, j, tbd, g);
        }
    }
}

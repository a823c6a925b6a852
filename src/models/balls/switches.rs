//! The frozen discrete modes of a ball-level model (full and reduced levels) and their switches
//! (held by the [`BallCore`](super::core::BallCore)).
//!
//! The clamped contact law, the C9 (docs/model.md#c9) compliance blend and the spall halves are not smooth in the
//! state; a model that owns a [`Switches`] evaluates a frozen law inside each step
//! ([`Switches::law`], [`Switches::blend`], [`Switches::side`]) and locates the switches as
//! state events. Event indices, per ball j of z: 2j, 2j + 1 the inner and outer contact
//! (min(δ′, Q/S)); with spalls, spall k's block starts at b = 2z + 3zk: b + 2j the zone edge,
//! b + 2j + 1 the spall centre and b + 2z + j the blend boundary (with one spall 2z + 2j,
//! 2z + 2j + 1 and 4z + j). Each ball has its own frozen half and blend side per spall.
//!
//! A model fills [`Switches::angles`] (θ_bd and its rate per spall and ball) and, after
//! [`Switches::update_spall`], [`Switches::contact_events`] (the contact functions under the new
//! halves) before [`Switches::update_contacts`]; nothing here allocates after construction.

use super::ball_contact::{ContactOut, Law};
use crate::defect::Defect;

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
    /// Spall slots: the number of spalls, at least 1 (the buffers of a healthy model keep
    /// the one-spall size, which its checkpoint has always had).
    spalls: usize,
    /// Frozen spall half of ball j for spall k at `k z + j`: 0 outside, −1 / +1 the sign of y_b.
    sides: Vec<f64>,
    /// Balls whose half changed in the last mode update (their contact functions jump there).
    sides_changed: Vec<bool>,
    /// Frozen side of the edge-constant blend per ball (true: within ℓ_b of an edge, docs/model.md#c9);
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
    /// Per spall k and ball j (at `k z + j`): θ_bd and its rate at the state of the mode
    /// update (filled by the model).
    pub angles: Vec<(f64, f64)>,
    /// Per ball: the contact event functions and unclamped forces (inner, outer) at the state
    /// of the mode update under the updated halves (filled by the model).
    pub contact_events: Vec<[(f64, f64); 2]>,
}

/// What an event function watches ([`Switches::event_of`]; balls and slots from 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EventOf {
    /// The `race` ("inner" or "outer") contact of a ball.
    Contact { ball: usize, race: &'static str },
    /// A spall slot's `what` ("edge", "centre" or "blend") for a ball.
    Spall {
        slot: usize,
        ball: usize,
        what: &'static str,
    },
}

/// The contact event function min(δ′, Q/S) of one evaluation (Q unclamped).
#[inline(always)]
pub fn contact_event(c: &ContactOut) -> f64 {
    c.delta.min(c.q_raw / EVENT_FORCE_SCALE)
}

impl Switches {
    /// Modes for z balls and one spall slot: all outside the spall, contacts under the
    /// clamped law until the first mode update.
    pub fn new(z: usize) -> Self {
        Self::with_spalls(z, 1)
    }

    /// [`Switches::new`] with `spalls` spall slots (at least 1 is kept).
    pub fn with_spalls(z: usize, spalls: usize) -> Self {
        let n = spalls.max(1);
        let events = 2 * z + 3 * z * n;
        Self {
            z,
            spalls: n,
            sides: vec![0.0; n * z],
            sides_changed: vec![false; n * z],
            in_blend: vec![false; n * z],
            closed: vec![[true; 2]; z],
            modes_set: false,
            fired: vec![false; events],
            flipped_at: vec![f64::NAN; events],
            suspect: None,
            angles: vec![(0.0, 0.0); n * z],
            contact_events: vec![[(0.0, 0.0); 2]; z],
        }
    }

    /// Number of event functions: the contacts, and per spall (`spalls` of them) the edges,
    /// centres and blends.
    pub fn n_events(&self, spalls: usize) -> usize {
        2 * self.z + 3 * self.z * spalls.min(self.spalls)
    }

    /// Where event function `i` sits in the layout of [`Switches::n_events`]: the contact
    /// of a ball (balls from 0), or what a spall slot watches for a ball.
    pub fn event_of(&self, i: usize) -> EventOf {
        let z = self.z;
        if i < 2 * z {
            let race = if i.is_multiple_of(2) {
                "inner"
            } else {
                "outer"
            };
            return EventOf::Contact { ball: i / 2, race };
        }
        let (slot, r) = ((i - 2 * z) / (3 * z), (i - 2 * z) % (3 * z));
        let (what, ball) = if r < 2 * z {
            (
                if r.is_multiple_of(2) {
                    "edge"
                } else {
                    "centre"
                },
                r / 2,
            )
        } else {
            ("blend", r - 2 * z)
        };
        EventOf::Spall { slot, ball, what }
    }

    /// What event function `i` watches (the layout of [`Switches::n_events`]; balls and spalls
    /// counted from 1).
    pub fn event_name(&self, i: usize) -> String {
        match self.event_of(i) {
            EventOf::Contact { ball, race } => format!("the {race} contact of ball {}", ball + 1),
            EventOf::Spall { slot, ball, what } => {
                format!("ball {} at the {what} of spall {}", ball + 1, slot + 1)
            }
        }
    }

    /// Frozen spall half of ball j (0 outside every spall's zone; else the half of the first
    /// spall it is over).
    #[inline(always)]
    pub fn side(&self, j: usize) -> f64 {
        (0..self.spalls)
            .map(|k| self.sides[k * self.z + j])
            .find(|&s| s != 0.0)
            .unwrap_or(0.0)
    }

    /// Frozen half of ball j on spall k (0 outside its zone).
    #[inline(always)]
    pub fn side_of(&self, k: usize, j: usize) -> f64 {
        self.sides[k * self.z + j]
    }

    /// Frozen blend side of ball j on the first spall (`None` before the first mode update).
    #[inline(always)]
    pub fn blend(&self, j: usize) -> Option<bool> {
        self.blend_of(0, j)
    }

    /// Frozen blend side of ball j on spall k (`None` before the first mode update: by the
    /// position).
    #[inline(always)]
    pub fn blend_of(&self, k: usize, j: usize) -> Option<bool> {
        self.modes_set.then(|| self.in_blend[k * self.z + j])
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
    /// [`crate::models::Model::checkpoint`]); [`Switches::checkpoint_len`] values
    /// ([`Switches::CHECKPOINT_PER_BALL`] per ball and 4 more with one spall slot). No
    /// allocation once `b` has its size.
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

    /// Values per ball in [`Switches::checkpoint`] with one spall slot (sides, their changes,
    /// blends, two contacts, and five events' flags and flip times).
    pub const CHECKPOINT_PER_BALL: usize = 15;

    /// Length of [`Switches::checkpoint`]: 4 + z (2 + 2·2 + 9 n) for n spall slots (4 + 15 z
    /// with one).
    pub fn checkpoint_len(&self) -> usize {
        4 + self.z * (6 + 9 * self.spalls)
    }

    /// Puts back what [`Switches::checkpoint`] wrote (exactly [`Switches::checkpoint_len`]
    /// values).
    pub fn rollback(&mut self, b: &[f64]) -> Result<(), String> {
        let z = self.z;
        let n = self.spalls;
        if b.len() != self.checkpoint_len() {
            return Err(format!(
                "mode checkpoint has {} values, got {}",
                self.checkpoint_len(),
                b.len()
            ));
        }
        self.modes_set = b[0] != 0.0;
        self.suspect = (b[1] != 0.0).then_some((b[2], b[3]));
        let (sides, b) = b[4..].split_at(n * z);
        let (changed, b) = b.split_at(n * z);
        let (blend, b) = b.split_at(n * z);
        let (closed, b) = b.split_at(2 * z);
        let (fired, flipped) = b.split_at(2 * z + 3 * n * z);
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

    /// The sign event function `index` has in the frozen modes (±1; None before the first
    /// mode update): a closed contact's min(δ′, Q/S) is positive, an open one's negative; a
    /// spall's zone margin is positive while the ball is in its zone, its centre function has
    /// the sign of the ball's half there (1 outside), its blend margin is negative inside the
    /// blend. After such an event fires, the integrator restarts with this sign as its
    /// reference, so a function that touches 0 and comes back is an event (see
    /// `raceway_solver::EventSystem::mode_sign`).
    pub fn mode_sign(&self, index: usize) -> Option<f64> {
        if !self.modes_set || index >= self.fired.len() {
            return None;
        }
        let z = self.z;
        let sign = |on: bool| if on { 1.0 } else { -1.0 };
        if index < 2 * z {
            return Some(sign(self.closed[index / 2][index % 2]));
        }
        let (k, r) = ((index - 2 * z) / (3 * z), (index - 2 * z) % (3 * z));
        let at = k * z;
        Some(if r >= 2 * z {
            sign(!self.in_blend[at + r - 2 * z])
        } else if r % 2 == 0 {
            sign(self.sides[at + r / 2] != 0.0)
        } else {
            match self.sides[at + r / 2] {
                0.0 => 1.0,
                side => side,
            }
        })
    }

    /// Event `index` fired at the located time.
    pub fn event_fired(&mut self, index: usize) {
        if let Some(f) = self.fired.get_mut(index) {
            *f = true;
        }
    }

    /// Spall event functions of ball j on spall k at θ_bd = `tbd` (index b + 2j, b + 2j + 1,
    /// b + 2z + j with b = 2z + 3zk; with one spall 2z + 2j, 2z + 2j + 1, 4z + j):
    /// θ_e − |θ_bd| (edge crossings); while the ball is in the zone θ_bd clipped to ±0.5 rad
    /// (the centre, where the ball changes corners; 1 outside the zone, where the wrap of θ_bd
    /// at ±π would fire a spurious event once per orbit of every ball); the blend boundary
    /// ([`Defect::blend_margin`]).
    #[inline(always)]
    pub fn spall_events(&self, d: &Defect, k: usize, j: usize, tbd: f64, g: &mut [f64]) {
        let z2 = 2 * self.z;
        let b = z2 + 3 * self.z * k;
        g[b + 2 * j] = d.zone_margin(tbd);
        g[b + 2 * j + 1] = if self.sides[k * self.z + j] != 0.0 {
            tbd.clamp(-0.5, 0.5)
        } else {
            1.0
        };
        g[b + z2 + j] = d.blend_margin(tbd);
    }

    /// Re-derives the frozen halves and blend sides of spall k from [`Switches::angles`] (at
    /// time t). A ball whose centre event just fired changes halves and one whose edge event fired
    /// enters (on the side of θ_bd) or leaves the zone: at the located state θ_bd sits within
    /// the location tolerance of the boundary on either side (the state is re-integrated by the
    /// method, not taken from the interpolant), so its sign alone could keep the old half for
    /// the rest of the pass. Every other ball takes its half from θ_bd (a position a hair ahead
    /// along the motion decides at a boundary). Blend sides likewise: a fired blend event
    /// flips, others follow the sign of the blend function.
    pub fn update_spall(&mut self, t: f64, k: usize, d: &Defect) {
        let te = d.half_angle();
        let z = self.z;
        let z2 = 2 * z;
        let base = 3 * z * k;
        let at = k * z;
        let hair = |(tbd, rate): (f64, f64)| {
            tbd + 1e-12 * rate.signum() * f64::from(u8::from(rate != 0.0))
        };
        for j in 0..z {
            let (tbd, rate) = self.angles[at + j];
            let (edge, centre) = (base + z2 + 2 * j, base + z2 + 2 * j + 1);
            let fired = |i: usize| self.modes_set && self.fired[i];
            let kept = |i: usize| self.modes_set && self.flipped_at[i] == t;
            let before = self.sides[at + j];
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
            self.sides[at + j] = side;
            self.sides_changed[at + j] = side != before;
        }
        let z4 = base + 4 * z;
        for j in 0..z {
            let i = z4 + j;
            if self.modes_set && self.fired[i] {
                self.in_blend[at + j] = !self.in_blend[at + j];
                self.flipped_at[i] = t;
            } else if !(self.modes_set && self.flipped_at[i] == t) {
                self.in_blend[at + j] = d.blend_margin(hair(self.angles[at + j])) < 0.0;
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
            let changed = (0..self.spalls).any(|k| self.sides_changed[k * self.z + j]);
            let flip = self.modes_set && !changed;
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

#[cfg(test)]
mod tests {
    use super::Switches;

    #[test]
    fn mode_signs_follow_the_frozen_modes() {
        // 3 balls, 2 spall slots: contacts 0..6, then per slot edges/centres 2z and blends z.
        let mut sw = Switches::with_spalls(3, 2);
        assert_eq!(sw.mode_sign(0), None, "before the first mode update");
        sw.modes_set = true;
        sw.closed[1] = [true, false];
        sw.closed[2] = [false, true];
        let contacts: Vec<_> = (0..6).map(|i| sw.mode_sign(i).unwrap()).collect();
        assert_eq!(contacts, [1.0, 1.0, 1.0, -1.0, -1.0, 1.0]);
        // Ball 2 in slot 1's zone on the − half, ball 3 on the − half in its blend.
        sw.sides[3 + 1] = -1.0;
        sw.sides[3 + 2] = -1.0;
        sw.in_blend[3 + 2] = true;
        let b = 6 + 9;
        assert_eq!(sw.mode_sign(b), Some(-1.0), "ball 1 outside: edge");
        assert_eq!(sw.mode_sign(b + 1), Some(1.0), "ball 1 outside: centre");
        assert_eq!(sw.mode_sign(b + 2), Some(1.0), "ball 2 inside: edge");
        assert_eq!(
            sw.mode_sign(b + 3),
            Some(-1.0),
            "ball 2 on the − half: centre"
        );
        assert_eq!(
            sw.mode_sign(b + 5),
            Some(-1.0),
            "ball 3 on the − half: centre"
        );
        assert_eq!(sw.mode_sign(b + 6), Some(1.0), "ball 1 out of the blend");
        assert_eq!(sw.mode_sign(b + 8), Some(-1.0), "ball 3 in the blend");
        // Slot 0 untouched: every ball outside, no blend.
        assert_eq!(sw.mode_sign(6), Some(-1.0), "the first spall function");
        assert_eq!(sw.mode_sign(6 + 2), Some(-1.0));
        assert_eq!(sw.mode_sign(6 + 3), Some(1.0));
        assert_eq!(sw.mode_sign(6 + 6 + 1), Some(1.0));
        assert_eq!(sw.mode_sign(6 + 18), None, "beyond the functions");
    }

    #[test]
    fn event_names_follow_the_layout() {
        // 3 balls, 2 spalls: contacts 0..6, then per spall edges/centres 2z and blends z.
        let mut sw = Switches::new(3);
        sw.spalls = 2;
        assert_eq!(sw.n_events(2), 6 + 2 * 9);
        assert_eq!(sw.event_name(0), "the inner contact of ball 1");
        assert_eq!(sw.event_name(5), "the outer contact of ball 3");
        assert_eq!(sw.event_name(6), "ball 1 at the edge of spall 1");
        assert_eq!(sw.event_name(9), "ball 2 at the centre of spall 1");
        assert_eq!(sw.event_name(12), "ball 1 at the blend of spall 1");
        assert_eq!(sw.event_name(14), "ball 3 at the blend of spall 1");
        assert_eq!(sw.event_name(15), "ball 1 at the edge of spall 2");
        assert_eq!(sw.event_name(23), "ball 3 at the blend of spall 2");
    }
}

//! L1 as a level of the ladder (docs/model.md#l1): the outputs are the quasi-static (Jones–Harris)
//! solution at the current inputs.
//!
//! The model integrates only the cage angle θ_c and the shaft angle φ (two states with constant
//! rates between input changes, so every explicit Runge–Kutta method integrates them exactly).
//! The balls sit at θ_j = θ_start + 2πj/z + θ_c and rotate with the cage; each ball's contact
//! forces are the L1 load distribution at its azimuth (linear interpolation over azimuth between
//! L1's z equally spaced balls), so a ball's Q moves through the load zone as the cage turns.
//! L1 is re-solved when an input changes by more than 2 % (speed or load); an operating point
//! where it has no solution is an error (the model keeps the last one).
//!
//! Static outputs (constant between input changes): the pedestal sits at its static deflection
//! F/k_p with zero velocity and acceleration, the inner ring at pedestal + L1 displacement, the
//! bearing force on the shaft is minus the external load, the friction torque is 0 (no traction
//! at L1) and the cage speed is the solved cage-to-shaft ratio times the current shaft speed
//! (the traction's caged balance or L1's mean ω_c, `lumped.cage_speed`).

use super::Model;
use crate::geometry::Bearing;
use crate::load_distribution::QuasiStatic;
use crate::models::{out, SimError};
use crate::operating::OperatingPoint;
use crate::scene::{CageSpeed, Scene};
use std::f64::consts::TAU;

const CAGE: usize = 0;
const SHAFT: usize = 1;

/// The L1 solution reduced to what the cheap levels need, as a function of azimuth.
#[derive(Debug, Clone)]
pub struct L1Table {
    /// Inner and outer contact force of L1's ball j at azimuth 2πj/z [N].
    q_inner: Vec<f64>,
    q_outer: Vec<f64>,
    /// Mean loaded cage speed [rad/s] (the kinematic outer-race-control one at zero speed).
    pub cage_speed: f64,
    /// Inner-ring displacement relative to the outer ring (δ_a, δ_y, δ_z) \[m\].
    pub offset: [f64; 3],
    /// Radial stiffness ∂F_z/∂δ_z of the ball set [N/m].
    pub k_zz: f64,
    /// Load-zone parameter ε = ½(1 + δ_a tan α / δ_r) (∞ without radial displacement).
    pub epsilon: f64,
    /// Largest inner contact force \[N\].
    pub q_max: f64,
    /// Mean inner contact angle of the loaded balls \[rad\].
    pub alpha: f64,
    /// Inputs the table was solved for.
    pub inputs: OperatingPoint,
    /// Where `cage_speed` comes from.
    pub cage: CageSpeed,
    /// The axial displacement a located inner ring is held at \[m\] (None: the axial load acts).
    pub held: Option<f64>,
    /// The bearing's axial force on the shaft \[N\]: minus the axial load, or for a located
    /// ring the axial reaction of its location.
    pub bearing_fx: f64,
}

impl L1Table {
    /// Solves L1 at `inputs` with the inner ring held axially at `held` if given, with the cage
    /// speed from `cage` (the traction solve starts from `previous`'s cage-to-shaft ratio, a
    /// table solved nearby, if given).
    pub fn solve(
        bearing: &Bearing,
        inputs: &OperatingPoint,
        cage: CageSpeed,
        held: Option<f64>,
        previous: Option<&L1Table>,
    ) -> Result<Self, SimError> {
        let qs = super::solve_l1_held(bearing, inputs, held, "the quasi-static (L1) solve")?;
        let mut t = Self::from_solution(bearing, &qs, inputs);
        t.cage = cage;
        t.held = held;
        if held.is_some() {
            t.bearing_fx = -qs.ring_force()[0];
        }
        if inputs.shaft_speed > 0.0 {
            let ratio = previous
                .filter(|p| p.inputs.shaft_speed > 0.0 && p.cage_speed > 0.0)
                .map(|p| p.cage_speed / p.inputs.shaft_speed);
            t.cage_speed = super::kinematic_levels_cage_speed(bearing, inputs, &qs, cage, ratio)?;
        }
        Ok(t)
    }

    /// The cage speed at shaft speed `speed` [rad/s]: the solved cage-to-shaft ratio times the
    /// speed, so that the cage follows a speed ramp between re-solves (0 for a table solved at
    /// rest).
    pub fn cage_speed_at(&self, speed: f64) -> f64 {
        if self.inputs.shaft_speed > 0.0 {
            self.cage_speed / self.inputs.shaft_speed * speed
        } else {
            0.0
        }
    }

    /// The table's part of a model's discrete state: the inputs it was solved at and its cage
    /// speed (kept, so that a restored run continues with the same bits whatever guess the
    /// traction solve would start from now).
    pub fn state(&self) -> [f64; 5] {
        let i = &self.inputs;
        [i.shaft_speed, i.fx, i.fy, i.fz, self.cage_speed]
    }

    /// Restores [`L1Table::state`] (the cage speed may be missing in states saved before it was
    /// kept; it is then solved again).
    pub fn restore(&mut self, bearing: &Bearing, s: &[f64]) -> Result<(), String> {
        let inputs = OperatingPoint {
            shaft_speed: s[0],
            fx: s[1],
            fy: s[2],
            fz: s[3],
        };
        if inputs != self.inputs {
            *self = L1Table::solve(bearing, &inputs, self.cage, self.held, Some(self))
                .map_err(|e| e.to_string())?;
        }
        if let Some(&w) = s.get(4) {
            self.cage_speed = w;
        }
        Ok(())
    }

    fn from_solution(bearing: &Bearing, qs: &QuasiStatic, inputs: &OperatingPoint) -> Self {
        let loaded: Vec<_> = qs.loaded_balls().collect();
        let alpha = if loaded.is_empty() {
            bearing.alpha0
        } else {
            loaded.iter().map(|b| b.alpha_inner).sum::<f64>() / loaded.len() as f64
        };
        let cage_speed = if inputs.shaft_speed > 0.0 {
            qs.cage_speed
        } else {
            0.0
        };
        let dr = qs.delta_radial();
        let epsilon = if dr > 0.0 {
            0.5 * (1.0 + qs.delta_axial.abs() * alpha.tan() / dr)
        } else {
            f64::INFINITY
        };
        Self {
            q_inner: qs.balls.iter().map(|b| b.q_inner).collect(),
            q_outer: qs.balls.iter().map(|b| b.q_outer).collect(),
            cage_speed,
            offset: [qs.delta_axial, qs.delta_y, qs.delta_z],
            k_zz: qs.stiffness[2][2],
            epsilon,
            q_max: qs.balls.iter().map(|b| b.q_inner).fold(0.0, f64::max),
            alpha,
            inputs: *inputs,
            cage: CageSpeed::OuterRaceControl,
            held: None,
            bearing_fx: -inputs.fx,
        }
    }

    /// (Q_inner, Q_outer) at azimuth θ, interpolated linearly between L1's balls.
    pub fn loads_at(&self, theta: f64) -> (f64, f64) {
        let z = self.q_inner.len();
        if z == 0 {
            return (0.0, 0.0);
        }
        let u = theta.rem_euclid(TAU) / TAU * z as f64;
        let j = (u.floor() as usize).min(z - 1);
        let s = u - j as f64;
        let k = (j + 1) % z;
        (
            (1.0 - s) * self.q_inner[j] + s * self.q_inner[k],
            (1.0 - s) * self.q_outer[j] + s * self.q_outer[k],
        )
    }

    /// True when `new` differs from the solved inputs by more than 2 % in speed or load.
    pub fn moved(&self, new: &OperatingPoint) -> bool {
        let old = &self.inputs;
        let load = |x: f64, y: f64, z: f64| (x * x + y * y + z * z).sqrt();
        (new.shaft_speed - old.shaft_speed).abs() > 0.02 * old.shaft_speed.abs().max(1.0)
            || load(new.fx - old.fx, new.fy - old.fy, new.fz - old.fz)
                > 0.02 * load(old.fx, old.fy, old.fz).max(1.0)
    }
}

/// Fills the static outputs shared by the kinematic and quasi-static levels: pedestal at its
/// static deflection (zero rates), ring at pedestal + L1 offset, bearing force = −load,
/// friction torque 0, cage speed, and per-ball contact forces at the balls' azimuths
/// `θ_start + 2πj/z + cage`.
pub(crate) fn static_outputs(
    table: &L1Table,
    bearing: &Bearing,
    inputs: &OperatingPoint,
    theta_start: f64,
    cage: f64,
    o: &mut [f64],
) {
    let p = &bearing.file.pedestal;
    let yp = inputs.fy / p.k_y;
    let zp = inputs.fz / p.k_z;
    o[out::PEDESTAL_A_Y] = 0.0;
    o[out::PEDESTAL_A_Z] = 0.0;
    o[out::PEDESTAL_Y] = yp;
    o[out::PEDESTAL_Z] = zp;
    o[out::PEDESTAL_V_Y] = 0.0;
    o[out::PEDESTAL_V_Z] = 0.0;
    o[out::RING_X] = table.offset[0];
    o[out::RING_Y] = yp + table.offset[1];
    o[out::RING_Z] = zp + table.offset[2];
    o[out::BEARING_F_X] = if table.held.is_some() {
        table.bearing_fx
    } else {
        -inputs.fx
    };
    o[out::BEARING_F_Y] = -inputs.fy;
    o[out::BEARING_F_Z] = -inputs.fz;
    o[out::FRICTION_TORQUE] = 0.0;
    let cage_speed = table.cage_speed_at(inputs.shaft_speed);
    o[out::CAGE_SPEED] = cage_speed;
    let z = bearing.z;
    if table.q_inner.len() != z || z == 0 || !out::has_ball_block(o, z) {
        return;
    }
    // The balls are equally spaced like L1's: ball j sits j table entries after ball 0, with the
    // same interpolation weight (one wrap for all balls).
    // frac(θ/2π)·z by a floor, not rem_euclid (a software fmod whose cost grows with the
    // number of turns); the difference is a rounding of θ/2π.
    let turns = (theta_start + cage) / TAU;
    let u = (turns - floor(turns)) * z as f64;
    let j0 = (floor(u) as usize).min(z - 1);
    let s = u - j0 as f64;
    let block = &mut o[out::CONTACT_START..out::orbit_speed(z, z)];
    let (q_in, rest) = block.split_at_mut(z);
    let (q_out, orbit) = rest.split_at_mut(z);
    interpolate_rotated(&table.q_inner, j0, s, q_in);
    interpolate_rotated(&table.q_outer, j0, s, q_out);
    orbit.fill(cage_speed);
    out::set_separation_flags(o, z);
}

/// `out[j] = (1 − s)·q[(j0 + j) mod z] + s·q[(j0 + j + 1) mod z]` for j < z = q.len() = out.len(),
/// j0 < z: the table rotated by j0 entries, as two contiguous runs and the wrap between them
/// (no index arithmetic per ball; this runs at every output sample).
#[inline(always)]
fn interpolate_rotated(q: &[f64], j0: usize, s: f64, out: &mut [f64]) {
    let z = q.len();
    let w = 1.0 - s;
    let (head, tail) = out.split_at_mut(z - 1 - j0);
    for ((o, qa), qb) in head.iter_mut().zip(&q[j0..z - 1]).zip(&q[j0 + 1..]) {
        *o = w * qa + s * qb;
    }
    tail[0] = w * q[z - 1] + s * q[0];
    for ((o, qa), qb) in tail[1..].iter_mut().zip(&q[..j0]).zip(&q[1..=j0]) {
        *o = w * qa + s * qb;
    }
}

/// `x.floor()` for |x| < 2⁶³ without the libm call that `f64::floor` becomes on the baseline
/// x86-64 target (no SSE4.1 `roundsd`); [`static_outputs`] runs it twice per output sample.
#[inline(always)]
fn floor(x: f64) -> f64 {
    let t = x as i64 as f64;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// The quasi-static level.
#[derive(Clone)]
pub struct QuasiStaticModel {
    bearing: Bearing,
    table: L1Table,
    inputs: OperatingPoint,
}

impl QuasiStaticModel {
    /// Solves L1 at the scene's inputs.
    pub fn new(
        scene: &Scene,
        bearing: &Bearing,
        inputs: &OperatingPoint,
    ) -> Result<Self, SimError> {
        Ok(Self {
            bearing: bearing.clone(),
            table: L1Table::solve(
                bearing,
                inputs,
                scene.lumped.cage_speed,
                super::held_axial(scene, bearing, inputs)?,
                None,
            )?,
            inputs: *inputs,
        })
    }

    /// The L1 solution currently in use.
    pub fn table(&self) -> &L1Table {
        &self.table
    }
}

impl Model for QuasiStaticModel {
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

    fn set_inputs(&mut self, inputs: &OperatingPoint, _t: f64, _y: &[f64]) -> Result<(), SimError> {
        if self.table.moved(inputs) {
            self.table = L1Table::solve(
                &self.bearing,
                inputs,
                self.table.cage,
                self.table.held,
                Some(&self.table),
            )?;
        }
        self.inputs = *inputs;
        Ok(())
    }

    fn rhs(&mut self, _t: f64, _y: &[f64], dydt: &mut [f64]) {
        dydt[CAGE] = self.table.cage_speed_at(self.inputs.shaft_speed);
        dydt[SHAFT] = self.inputs.shaft_speed;
    }

    fn next_stop(&self, _t: f64, _y: &[f64], _t_max: f64) -> Option<f64> {
        None
    }

    fn update_mode(&mut self, _t: f64, _y: &[f64]) {}

    fn outputs(&mut self, _t: f64, y: &[f64], o: &mut [f64]) {
        static_outputs(&self.table, &self.bearing, &self.inputs, 0.0, y[CAGE], o);
    }

    fn discrete_state(&self) -> Vec<f64> {
        self.table.state().to_vec()
    }

    fn set_discrete_state(&mut self, s: &[f64]) -> Result<(), String> {
        if !(4..=5).contains(&s.len()) || s.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "quasi-static model state has 5 finite values, got {}",
                s.len()
            ));
        }
        self.table.restore(&self.bearing, s)
    }

    /// Nothing: the L1 table changes only with the inputs, between advances.
    fn checkpoint(&self, b: &mut Vec<f64>) {
        b.clear();
    }

    fn rollback(&mut self, _b: &[f64], _t: f64, _y: &[f64]) -> Result<(), String> {
        Ok(())
    }

    fn cage_speed(&self) -> f64 {
        self.table.cage_speed_at(self.inputs.shaft_speed)
    }

    fn contacts_follow_inputs(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::{floor, interpolate_rotated};

    #[test]
    fn rotated_interpolation_matches_the_wrapped_index_formula() {
        for z in 1..=20usize {
            let q: Vec<f64> = (0..z).map(|i| 100.0 + (i * i) as f64 * 1.7).collect();
            for j0 in 0..z {
                for s in [0.0, 0.3125, 0.9, 1.0] {
                    let mut out = vec![f64::NAN; z];
                    interpolate_rotated(&q, j0, s, &mut out);
                    for (j, o) in out.iter().enumerate() {
                        let (a, b) = ((j0 + j) % z, (j0 + j + 1) % z);
                        let want = (1.0 - s) * q[a] + s * q[b];
                        assert_eq!(o.to_bits(), want.to_bits(), "z {z} j0 {j0} s {s} j {j}");
                    }
                }
            }
        }
    }

    #[test]
    fn fast_floor_is_floor() {
        for x in [
            0.0,
            -0.0,
            0.5,
            1.0,
            1.5,
            -0.5,
            -1.0,
            -1.5,
            2.999_999_999,
            -2.000_000_1,
            1e15 + 0.5,
            -1e15 - 0.5,
            123_456.789,
        ] {
            assert_eq!(floor(x), x.floor(), "{x}");
        }
    }
}

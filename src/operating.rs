//! The operating point: the shaft speed and the external force on the inner ring, in SI units.
//!
//! One type carries it from the scene file (which states the speed in rpm and the radial load
//! as a magnitude) through the quasi-static solution and the models to the FMU's inputs
//! (`shaft.speed`, `load.Fx/Fy/Fz`), so no layer converts units on the way.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Shaft speed and the external force on the inner ring.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct OperatingPoint {
    /// Shaft (inner-ring) speed about +x \[rad/s\].
    pub shaft_speed: f64,
    /// Force on the inner ring along +x \[N\] (the axial load Fa).
    pub fx: f64,
    /// Force on the inner ring along +y \[N\].
    pub fy: f64,
    /// Force on the inner ring along +z \[N\] (a radial load Fr is applied as `fz = −Fr`).
    pub fz: f64,
}

impl OperatingPoint {
    /// The usual load case of an angular-contact bearing: `fa` along +x, the radial load `fr`
    /// along −z, the speed in rpm.
    pub fn from_rpm(speed_rpm: f64, fa: f64, fr: f64) -> Self {
        Self {
            shaft_speed: rpm_to_rad_s(speed_rpm),
            fx: fa,
            fy: 0.0,
            fz: -fr,
        }
    }

    /// Shaft speed \[rpm\].
    pub fn speed_rpm(&self) -> f64 {
        self.shaft_speed * 30.0 / PI
    }

    /// Rejects non-finite or impossible values, naming the input as the FMU does.
    pub fn check(&self) -> Result<(), String> {
        for (name, v) in [
            ("shaft.speed", self.shaft_speed),
            ("load.Fx", self.fx),
            ("load.Fy", self.fy),
            ("load.Fz", self.fz),
        ] {
            if !v.is_finite() {
                return Err(format!("{name} = {v} is not a finite number"));
            }
        }
        if self.shaft_speed < 0.0 {
            return Err(format!(
                "shaft.speed = {} rad/s: the model supports speeds ≥ 0",
                self.shaft_speed
            ));
        }
        Ok(())
    }
}

/// rpm → rad/s (the one conversion of the library).
pub fn rpm_to_rad_s(rpm: f64) -> f64 {
    rpm * PI / 30.0
}

/// A force on the inner ring that changes over a communication step, added to the operating
/// point's constant load: `f(t, v) = f0 + (f1 − f0)(t − t0)/h − damping ⊙ v`, with `v` the
/// ring's velocity. It is how a partner model's line or impedance acts on the ring (the FMU's
/// transmission-line coupling: the line's wave over the step and its characteristic impedance).
/// Outside `[t0, t0 + h]` the line is extrapolated.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RingLoad {
    t0: f64,
    f0: [f64; 3],
    rate: [f64; 3],
    damping: [f64; 3],
}

impl RingLoad {
    /// The law that goes from `f0` at `t0` to `f1` at `t0 + h` (`h` > 0), minus `damping` ⊙ v
    /// (per axis, N s/m, ≥ 0). Errors name the bad value.
    pub fn linear(
        t0: f64,
        h: f64,
        f0: [f64; 3],
        f1: [f64; 3],
        damping: [f64; 3],
    ) -> Result<Self, String> {
        if !(h > 0.0 && h.is_finite()) {
            return Err(format!("the load's interval h = {h} s must be > 0"));
        }
        let finite = f0.iter().chain(&f1).chain(&damping).all(|v| v.is_finite());
        if !finite || !t0.is_finite() {
            return Err(format!(
                "the ring load from {f0:?} to {f1:?} N with damping {damping:?} N s/m is not finite"
            ));
        }
        if damping.iter().any(|&c| c < 0.0) {
            return Err(format!(
                "the ring load's damping {damping:?} N s/m must be >= 0 (a negative one feeds energy in)"
            ));
        }
        let mut rate = [0.0; 3];
        for k in 0..3 {
            rate[k] = (f1[k] - f0[k]) / h;
        }
        Ok(Self {
            t0,
            f0,
            rate,
            damping,
        })
    }

    /// Component `k` of the force at time `t` on a ring moving at `v` along that axis.
    #[inline(always)]
    pub fn force(&self, k: usize, t: f64, v: f64) -> f64 {
        self.f0[k] + self.rate[k] * (t - self.t0) - self.damping[k] * v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_load_interpolates_and_damps() {
        let l = RingLoad::linear(
            1.0,
            0.5,
            [1.0, 2.0, 3.0],
            [3.0, 2.0, -1.0],
            [0.0, 10.0, 20.0],
        )
        .unwrap();
        assert_eq!(l.force(0, 1.0, 5.0), 1.0);
        assert_eq!(l.force(0, 1.5, 5.0), 3.0);
        assert_eq!(l.force(2, 1.25, 0.0), 1.0);
        assert_eq!(l.force(1, 1.25, 0.5), 2.0 - 5.0);
        assert_eq!(l.force(2, 1.5, -0.1), -1.0 + 2.0);
    }

    #[test]
    fn ring_load_refuses_bad_values() {
        let z = [0.0; 3];
        assert!(RingLoad::linear(0.0, 0.0, z, z, z)
            .unwrap_err()
            .contains("h = 0"));
        assert!(RingLoad::linear(0.0, 1.0, [f64::NAN, 0.0, 0.0], z, z).is_err());
        assert!(RingLoad::linear(0.0, 1.0, z, z, [0.0, -1.0, 0.0])
            .unwrap_err()
            .contains(">= 0"));
        assert!(RingLoad::linear(f64::INFINITY, 1.0, z, z, z).is_err());
    }
}

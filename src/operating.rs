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

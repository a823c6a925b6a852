//! Plausibility limits of an operating point: the basic static load rating of ISO 76 (a warning
//! beyond it) and the contact pressure beyond which the model's elastic Hertz contacts no
//! longer describe hardened bearing steel (an error).
//!
//! - Static load rating (ISO 76:2006, radial and angular-contact ball bearings):
//!   `C0r = f0 · i · Z · Dw² · cos α` with f0 from the standard's table over `Dw cos α / Dpw`
//!   (one row here, i = 1), and the static equivalent load `P0 = max(X0 Fr + Y0 Fa, Fr)`
//!   (deep groove: X0 = 0.6, Y0 = 0.5; angular contact: X0 = 0.5, Y0 from 0.46 at 15° to 0.22
//!   at 45°). P0 = C0 is the load at which the most heavily loaded contact reaches 4200 MPa,
//!   with a permanent deformation of about 1e-4 of the ball diameter.
//! - Contact pressure limit: the largest Hertz pressure the model accepts,
//!   [`MAX_CONTACT_PRESSURE`]. Catalogues allow P0 up to 2 C0 (5.3 GPa) for smooth running;
//!   6.5 GPa is about P0 = 3.2 C0, where the races take gross plastic deformation.

use crate::geometry::{Bearing, Race};

/// Peak Hertz pressure at P0 = C0 (ISO 76, ball bearings other than self-aligning) \[Pa\].
pub const RATING_PRESSURE: f64 = 4.2e9;

/// The largest peak Hertz pressure the model accepts at any contact \[Pa\].
pub const MAX_CONTACT_PRESSURE: f64 = 6.5e9;

/// ISO 76 factor f0 of radial and angular-contact ball bearings at `Dw cos α / Dpw` = 0, 0.01,
/// …, 0.40 (linear in between).
const F0: [f64; 41] = [
    14.7, 14.9, 15.1, 15.3, 15.5, 15.7, 15.9, 16.1, 16.3, 16.5, 16.4, 16.1, 15.9, 15.6, 15.4, 15.2,
    14.9, 14.7, 14.4, 14.2, 14.0, 13.7, 13.5, 13.2, 13.0, 12.8, 12.5, 12.3, 12.1, 11.8, 11.6, 11.4,
    11.2, 10.9, 10.7, 10.5, 10.3, 10.0, 9.8, 9.6, 9.4,
];

/// ISO 76 factor Y0 of single-row angular-contact ball bearings at α = 15°, 20°, …, 45°.
const Y0_ANGULAR: [f64; 7] = [0.46, 0.42, 0.38, 0.33, 0.29, 0.26, 0.22];

/// The ISO 76 static rating of a bearing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticRating {
    /// Basic static radial load rating C0r \[N\].
    pub c0: f64,
    /// Radial factor X0 of the static equivalent load P0 = X0 Fr + Y0 Fa.
    pub x0: f64,
    /// Axial factor Y0 of the static equivalent load P0 = X0 Fr + Y0 Fa.
    pub y0: f64,
}

impl StaticRating {
    /// The rating of `b` from its geometry (Z, Dw, Dpw, α0).
    pub fn of(b: &Bearing) -> Self {
        let u = (b.d * b.alpha0.cos() / b.dm).clamp(0.0, 0.4) * 100.0;
        let k = (u.floor() as usize).min(F0.len() - 2);
        let f0 = F0[k] + (u - k as f64) * (F0[k + 1] - F0[k]);
        let c0 = f0 * b.z as f64 * (b.d * 1e3).powi(2) * b.alpha0.cos();
        let deg = b.alpha0.to_degrees();
        let (x0, y0) = if deg <= 0.0 {
            (0.6, 0.5)
        } else {
            let s = ((deg - 15.0) / 5.0).clamp(0.0, 6.0);
            let k = (s.floor() as usize).min(5);
            (
                0.5,
                Y0_ANGULAR[k] + (s - k as f64) * (Y0_ANGULAR[k + 1] - Y0_ANGULAR[k]),
            )
        };
        Self { c0, x0, y0 }
    }

    /// Static equivalent load P0 = max(X0 Fr + Y0 |Fa|, Fr) \[N\] of an axial load `fa` and a
    /// radial load `fr`.
    pub fn equivalent_load(&self, fa: f64, fr: f64) -> f64 {
        (self.x0 * fr + self.y0 * fa.abs()).max(fr)
    }
}

/// The most heavily stressed contact among per-ball normal forces (inner `q_inner[j]`, outer
/// `q_outer[j]`): (peak Hertz pressure \[Pa\], ball j, race, Q \[N\]).
pub fn peak_contact(b: &Bearing, q_inner: &[f64], q_outer: &[f64]) -> (f64, usize, Race, f64) {
    let mut worst = (0.0, 0, Race::Inner, 0.0);
    for (race, qs) in [(Race::Inner, q_inner), (Race::Outer, q_outer)] {
        let h = b.hertz(race);
        for (j, &q) in qs.iter().enumerate() {
            let p = h.peak_pressure(q);
            if p > worst.0 {
                worst = (p, j, race, q);
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f0_table_ends_and_interpolation() {
        let b = Bearing::load("niu2014-table1").unwrap();
        let r = StaticRating::of(&b);
        // Dw cos α / Dpw = 12.7 cos 30° / 70 = 0.1571: between 14.9 (0.16) and 15.2 (0.15).
        let f0 = r.c0 / (14.0 * 12.7_f64.powi(2) * 30f64.to_radians().cos());
        assert!((f0 - (15.2 - 0.71 * 0.3)).abs() < 0.01, "{f0}");
        assert_eq!(r.x0, 0.5);
        assert!((r.y0 - 0.33).abs() < 1e-12);
        assert!((r.equivalent_load(4000.0, 1000.0) - (0.5 * 1000.0 + 0.33 * 4000.0)).abs() < 1e-9);
        assert_eq!(r.equivalent_load(0.0, 1000.0), 1000.0);
    }
}

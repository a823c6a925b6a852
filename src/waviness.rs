//! Harmonic waviness of the races and the balls, and off-size balls (docs/model.md#waviness).
//!
//! Each enters as an added approach at a ball's contacts (the contact deflection grows where
//! the surface stands proud), per component a list of harmonics (order n, amplitude A \[m\],
//! phase φ \[rad\]):
//! - outer race (fixed): `δ_o = Σ A cos(n θ_j + φ)` at ball j's azimuth θ_j;
//! - inner race (turns with the shaft, angle φ_s): `δ_i = Σ A cos(n (θ_j − φ_s) + φ)`;
//! - ball, along the great circle its spin turns through the contacts at spin angle ψ_j: the
//!   outer contact sees `r(ψ)`, the inner one the opposite point `r(ψ + π)`, so the ball adds
//!   `Σ A [cos(n ψ + φ) + cos(n (ψ + π) + φ)]` (odd orders cancel, even ones double);
//! - a ball `ΔD_j` larger than nominal in the same grooves: the groove-centre distance at which
//!   it touches both races, r_i + r_o − D, shrinks by ΔD_j, so its approach grows by ΔD_j
//!   (ΔD_j/2 at each contact).
//!
//! [`WavinessSpec`] is the scene's `[waviness]` table; [`Waviness`] is the form the models
//! evaluate (no allocation).

use crate::config::ConfigError;
use crate::geometry::{Bearing, Race};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Largest waviness amplitude accepted \[m\]: waviness is a µm-scale form error; anything near
/// the Hertz deflections (~10 µm) or larger is not waviness.
pub const MAX_AMPLITUDE: f64 = 1e-4;

/// Highest waviness order accepted (an order is a count of lobes around the circumference).
pub const MAX_ORDER: f64 = 10_000.0;

/// One harmonic as written: `[order n, amplitude A [m], phase φ [rad]]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Harmonic(pub f64, pub f64, pub f64);

/// The scene table `[waviness]`: harmonics per component and the balls' diameter deviations.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WavinessSpec {
    /// Inner-race harmonics (angle on the ring, C1 convention, at shaft angle 0).
    #[serde(default)]
    pub inner: Vec<Harmonic>,
    /// Outer-race harmonics (azimuth, C1 convention).
    #[serde(default)]
    pub outer: Vec<Harmonic>,
    /// Ball harmonics along the spin great circle, the same on every ball; each ball's spin
    /// angle starts at 0 (all in phase) or, with `ball_phase_seed`, at a random angle.
    #[serde(default)]
    pub ball: Vec<Harmonic>,
    /// Seed of each ball's random start spin angle (uniform in [0, 2π)); None: all start at 0.
    #[serde(default)]
    pub ball_phase_seed: Option<u64>,
    /// Diameter deviation of each ball from D \[m\] (empty: all nominal; otherwise one per ball).
    #[serde(default)]
    pub ball_diameter_deviation: Vec<f64>,
}

impl WavinessSpec {
    /// Whether the table adds nothing (no harmonic, every deviation zero).
    pub fn is_empty(&self) -> bool {
        self.inner.is_empty()
            && self.outer.is_empty()
            && self.ball.is_empty()
            && self.ball_diameter_deviation.iter().all(|&d| d == 0.0)
    }

    /// Checks the values on their own; the error names the field (`waviness.inner[2]`):
    /// orders integers in [1, 10 000], amplitudes finite with |A| ≤ 0.1 mm, phases finite,
    /// deviations finite with |ΔD| ≤ 0.1 mm. [`Waviness::new`] checks the deviations' count.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (name, list) in [
            ("inner", &self.inner),
            ("outer", &self.outer),
            ("ball", &self.ball),
        ] {
            for (i, &Harmonic(n, a, phi)) in list.iter().enumerate() {
                let field = format!("waviness.{name}[{i}]");
                if !(n.is_finite() && n.fract() == 0.0 && (1.0..=MAX_ORDER).contains(&n)) {
                    return Err(ConfigError::new(
                        field,
                        format!("order {n} must be an integer in [1, {MAX_ORDER}]"),
                    ));
                }
                if !(a.is_finite() && a.abs() <= MAX_AMPLITUDE) {
                    return Err(ConfigError::new(
                        field,
                        format!("amplitude {a} m must be finite and at most {MAX_AMPLITUDE} m"),
                    ));
                }
                if !phi.is_finite() {
                    return Err(ConfigError::new(
                        field,
                        format!("phase {phi} is not a finite angle"),
                    ));
                }
            }
        }
        for (j, &d) in self.ball_diameter_deviation.iter().enumerate() {
            if !(d.is_finite() && d.abs() <= MAX_AMPLITUDE) {
                return Err(ConfigError::new(
                    format!("waviness.ball_diameter_deviation[{j}]"),
                    format!("{d} m must be finite and at most {MAX_AMPLITUDE} m"),
                ));
            }
        }
        Ok(())
    }
}

/// The waviness of a bearing, ready to evaluate.
#[derive(Debug, Clone)]
pub struct Waviness {
    inner: Vec<Harmonic>,
    outer: Vec<Harmonic>,
    /// Ball harmonics with the two contacts' sum folded in: even orders at 2A, odd ones dropped.
    ball: Vec<Harmonic>,
    /// Ball harmonics as given (one contact's).
    ball_each: Vec<Harmonic>,
    /// Each ball's spin angle at the start \[rad\].
    ball_phase: Vec<f64>,
    /// ΔD per ball (zeros when none given) \[m\].
    deviation: Vec<f64>,
    /// Ball spin angle per orbital angle, (dm/D)(1 + γ0): pure rolling on the fixed outer race.
    spin_per_orbit: f64,
}

/// A uniform number in [0, 1) from a seed and an index (splitmix64 of their mix).
fn unit(seed: u64, index: u64) -> f64 {
    let mut x = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(index.wrapping_mul(0xD1B5_4A32_D192_ED03))
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^= x >> 31;
    (x >> 11) as f64 / (1u64 << 53) as f64
}

/// Σ A cos(n x + φ) and its derivative in x.
#[inline(always)]
fn series(list: &[Harmonic], x: f64) -> (f64, f64) {
    let (mut v, mut d) = (0.0, 0.0);
    for &Harmonic(n, a, phi) in list {
        let (s, c) = (n * x + phi).sin_cos();
        v += a * c;
        d -= a * n * s;
    }
    (v, d)
}

impl Waviness {
    /// The evaluable form for `bearing`; `None` when the table adds nothing (no harmonics, all
    /// deviations zero). The deviation list must be empty or have one entry per ball.
    pub fn new(spec: &WavinessSpec, bearing: &Bearing) -> Result<Option<Self>, ConfigError> {
        spec.validate()?;
        let z = bearing.z;
        let dev = &spec.ball_diameter_deviation;
        if !dev.is_empty() && dev.len() != z {
            return Err(ConfigError::new(
                "waviness.ball_diameter_deviation",
                format!(
                    "has {} entries; the bearing has {z} balls (give one per ball, or none)",
                    dev.len()
                ),
            ));
        }
        let ball: Vec<Harmonic> = spec
            .ball
            .iter()
            .filter(|h| h.0 % 2.0 == 0.0)
            .map(|&Harmonic(n, a, phi)| Harmonic(n, 2.0 * a, phi))
            .collect();
        if spec.is_empty() {
            return Ok(None);
        }
        Ok(Some(Self {
            inner: spec.inner.clone(),
            outer: spec.outer.clone(),
            ball,
            ball_each: spec.ball.clone(),
            ball_phase: (0..z)
                .map(|j| match spec.ball_phase_seed {
                    Some(seed) => TAU * unit(seed, j as u64),
                    None => 0.0,
                })
                .collect(),
            deviation: if dev.is_empty() {
                vec![0.0; z]
            } else {
                dev.clone()
            },
            spin_per_orbit: bearing.kinematic_spin_per_orbit(),
        }))
    }

    /// Added approach of ball j (both contacts) and its rate \[m, m/s\]: the ball at azimuth
    /// `theta` (rate `theta_rate`) having orbited `orbit` since the start, the shaft at angle
    /// `shaft` (rate `shaft_rate`).
    #[inline]
    pub fn added(
        &self,
        j: usize,
        theta: f64,
        theta_rate: f64,
        orbit: f64,
        shaft: f64,
        shaft_rate: f64,
    ) -> (f64, f64) {
        let (vo, dvo) = self.race(Race::Outer, theta, theta_rate);
        let (vi, dvi) = self.race(Race::Inner, theta - shaft, theta_rate - shaft_rate);
        let (vb, dvb) = self.ball(j, orbit, theta_rate);
        (vo + vi + vb + self.deviation[j], dvo + dvi + dvb)
    }

    /// One race's waviness and its rate at angle `x` on the ring (the inner ring's own angle:
    /// azimuth less shaft angle) moving past the ball at `x_rate` \[m, m/s\].
    #[inline]
    pub fn race(&self, race: Race, x: f64, x_rate: f64) -> (f64, f64) {
        let list = match race {
            Race::Inner => &self.inner,
            Race::Outer => &self.outer,
        };
        let (v, d) = series(list, x);
        (v, d * x_rate)
    }

    /// Ball j's waviness summed over its two contacts at orbital angle `orbit` since the start
    /// (spin angle ψ_j0 + (dm/D)(1 + γ0)·orbit) and orbital rate `orbit_rate` \[m, m/s\].
    #[inline]
    pub fn ball(&self, j: usize, orbit: f64, orbit_rate: f64) -> (f64, f64) {
        let (v, d) = series(&self.ball, self.ball_phase[j] + self.spin_per_orbit * orbit);
        (v, d * self.spin_per_orbit * orbit_rate)
    }

    /// Ball j's waviness at one contact, at spin angle `psi` from its start angle ψ_j0 (in the
    /// convention of [`Waviness::ball`]: the outer contact at ψ, the inner at ψ + π), every
    /// order as given, and its derivative in ψ \[m, m/rad\]: the ball levels' (they take ψ
    /// from the ball's own rotation, one contact at a time).
    #[inline]
    pub fn ball_at(&self, j: usize, psi: f64) -> (f64, f64) {
        series(&self.ball_each, self.ball_phase[j] + psi)
    }

    /// Whether the balls have waviness (a harmonic of even order).
    pub fn has_ball_harmonics(&self) -> bool {
        !self.ball.is_empty()
    }

    /// Diameter deviation ΔD of ball j \[m\] (its approach grows by ΔD over both contacts).
    #[inline]
    pub fn deviation(&self, j: usize) -> f64 {
        self.deviation[j]
    }

    /// Ball spin angle per orbital angle at the kinematic levels, (dm/D)(1 + γ0).
    pub fn spin_per_orbit(&self) -> f64 {
        self.spin_per_orbit
    }
}

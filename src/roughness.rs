//! Random roughness of the race tracks (docs/model.md#roughness): a seeded, reproducible
//! surface-height field along each track, entering as an added approach at each ball's contact
//! on that race (like waviness, [`crate::waviness`], but broadband).
//!
//! The field of a track of radius R is periodic in the track angle x:
//! `h(x) = Σ_{m≥1} a_m cos(m x + ψ_m)` with phases ψ_m uniform from the seed and amplitudes
//! from a Gaussian autocorrelation `R(s) = σ² exp(−s²/ℓ²)` along the track (s = R x): its
//! spectrum is ∝ exp(−k²ℓ²/4), so `a_m² ∝ exp(−(m ℓ/R)²/4)`, scaled so that Σ a_m²/2 = σ². The
//! autocorrelation of such a sum is Σ a_m²/2 cos(m s/R) whatever the phases, which is the
//! Gaussian sampled at the track's harmonics. The field is summed once at construction by an
//! inverse FFT onto a periodic table (at least 13 points per ℓ) and read by cubic (Catmull–Rom)
//! interpolation, C¹, so the right-hand side stays smooth and allocation-free.

use crate::config::ConfigError;
use crate::geometry::{Bearing, Race};
use rustfft::num_complex::Complex;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Largest roughness RMS accepted \[m\] (a µm-scale surface property; not a form error).
pub const MAX_RMS: f64 = 1e-4;

/// Largest table: fields needing more points (a correlation length too short for the track)
/// are refused.
pub const MAX_TABLE: usize = 1 << 21;

/// Harmonics are kept while exp(−(mℓ/R)²/4) > e^(−27.6) ≈ 1e-12, i.e. up to m ℓ/R = 10.5.
const CUTOFF: f64 = 10.5;

/// Table points per period of the highest kept harmonic.
const POINTS_PER_WAVE: usize = 8;

/// One track's roughness as written.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackRoughness {
    /// RMS height σ \[m\].
    pub rms: f64,
    /// Correlation length ℓ along the track \[m\] (autocorrelation σ² e^(−s²/ℓ²)).
    pub correlation_length: f64,
    /// Seed of the random phases (the same seed on the two races still gives two fields).
    #[serde(default)]
    pub seed: u64,
}

/// The scene table `[roughness]`: `[roughness.inner]` and/or `[roughness.outer]`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughnessSpec {
    /// The inner race track's roughness.
    #[serde(default)]
    pub inner: Option<TrackRoughness>,
    /// The outer race track's roughness.
    #[serde(default)]
    pub outer: Option<TrackRoughness>,
}

impl RoughnessSpec {
    /// Whether no race has a nonzero RMS.
    pub fn is_empty(&self) -> bool {
        [self.inner, self.outer]
            .iter()
            .all(|t| t.is_none_or(|t| t.rms == 0.0))
    }

    /// Checks the values on their own; the error names the field (`roughness.inner.rms`):
    /// rms finite in [0, 0.1 mm], correlation length finite and > 0. [`Roughness::new`] checks
    /// the correlation length against the track.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (name, t) in [("inner", &self.inner), ("outer", &self.outer)] {
            let Some(t) = t else { continue };
            if !(t.rms.is_finite() && (0.0..=MAX_RMS).contains(&t.rms)) {
                return Err(ConfigError::new(
                    format!("roughness.{name}.rms"),
                    format!("{} m must be finite and in [0, {MAX_RMS}] m", t.rms),
                ));
            }
            if !(t.correlation_length.is_finite() && t.correlation_length > 0.0) {
                return Err(ConfigError::new(
                    format!("roughness.{name}.correlation_length"),
                    format!("{} m must be finite and > 0", t.correlation_length),
                ));
            }
        }
        Ok(())
    }
}

/// One track's height field on a periodic table.
#[derive(Debug, Clone)]
pub struct TrackField {
    /// h at x_k = 2πk/N for k = −1..=N+1 (one point of wrap-around on each side, two after).
    table: Vec<f64>,
    /// N/(2π): table points per radian.
    per_rad: f64,
    n: f64,
}

fn splitmix64(s: &mut u64) -> u64 {
    *s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut x = *s;
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

impl TrackField {
    /// The field of `spec` on a track of radius `radius` \[m\]; `salt` separates the races.
    /// `field` names the table in errors.
    pub fn new(
        spec: &TrackRoughness,
        radius: f64,
        salt: u64,
        field: &str,
    ) -> Result<Self, ConfigError> {
        let ratio = spec.correlation_length / radius; // ℓ/R
        let m_max = (CUTOFF / ratio).ceil();
        let need = m_max * POINTS_PER_WAVE as f64;
        if need > MAX_TABLE as f64 {
            return Err(ConfigError::new(
                format!("{field}.correlation_length"),
                format!(
                    "{} m is too short for a track of radius {radius:.4} m (at least {:.3e} m)",
                    spec.correlation_length,
                    CUTOFF * POINTS_PER_WAVE as f64 * radius / MAX_TABLE as f64
                ),
            ));
        }
        let m_max = m_max as usize;
        let n = (need as usize).next_power_of_two().max(64);
        let weight = |m: usize| (-(m as f64 * ratio).powi(2) / 4.0).exp();
        let total: f64 = (1..=m_max).map(weight).sum();
        let mut s = spec.seed ^ salt.wrapping_mul(0xD1B5_4A32_D192_ED03);
        let mut spectrum = vec![Complex::new(0.0, 0.0); n];
        for (m, bin) in spectrum.iter_mut().enumerate().take(m_max + 1).skip(1) {
            // a_m = σ √(2 w_m / Σw): Σ a_m²/2 = σ².
            let a = spec.rms * (2.0 * weight(m) / total).sqrt();
            let psi = TAU * (splitmix64(&mut s) >> 11) as f64 / (1u64 << 53) as f64;
            *bin = Complex::from_polar(a, psi);
        }
        // Unnormalised inverse FFT: Σ_m X_m e^{+2πi m k/N}; its real part is h(x_k).
        rustfft::FftPlanner::new()
            .plan_fft_inverse(n)
            .process(&mut spectrum);
        let mut table = Vec::with_capacity(n + 3);
        table.push(spectrum[n - 1].re);
        table.extend(spectrum.iter().map(|c| c.re));
        table.push(spectrum[0].re);
        table.push(spectrum[1].re);
        Ok(Self {
            table,
            per_rad: n as f64 / TAU,
            n: n as f64,
        })
    }

    /// Height h(x) \[m\] and dh/dx \[m/rad\] at track angle x (any real).
    #[inline]
    pub fn at(&self, x: f64) -> (f64, f64) {
        let u = (x * self.per_rad).rem_euclid(self.n);
        let i = (u.floor() as usize).min(self.n as usize - 1);
        let t = u - i as f64;
        let (p0, p1, p2, p3) = (
            self.table[i],
            self.table[i + 1],
            self.table[i + 2],
            self.table[i + 3],
        );
        // Catmull–Rom between p1 (t = 0) and p2 (t = 1).
        let (c1, c2, c3) = (
            0.5 * (p2 - p0),
            p0 - 2.5 * p1 + 2.0 * p2 - 0.5 * p3,
            0.5 * (p3 - p0) + 1.5 * (p1 - p2),
        );
        let h = p1 + t * (c1 + t * (c2 + t * c3));
        let dh = c1 + t * (2.0 * c2 + t * 3.0 * c3);
        (h, dh * self.per_rad)
    }

    /// The table's points h(2πk/N), k = 0..N (for tests of the field's statistics).
    pub fn points(&self) -> &[f64] {
        &self.table[1..self.table.len() - 2]
    }
}

/// The roughness of both tracks, ready to evaluate.
#[derive(Debug, Clone)]
pub struct Roughness {
    inner: Option<TrackField>,
    outer: Option<TrackField>,
}

/// Radius of a race's contact track at the free contact angle \[m\].
pub fn track_radius(bearing: &Bearing, race: Race) -> f64 {
    let r = 0.5 * bearing.d * bearing.alpha0.cos();
    match race {
        Race::Inner => 0.5 * bearing.dm - r,
        Race::Outer => 0.5 * bearing.dm + r,
    }
}

impl Roughness {
    /// The fields of `spec` on `bearing`'s tracks; `None` when no race has a nonzero RMS.
    pub fn new(spec: &RoughnessSpec, bearing: &Bearing) -> Result<Option<Self>, ConfigError> {
        spec.validate()?;
        let build = |t: &Option<TrackRoughness>, race: Race, salt: u64, field: &str| {
            t.filter(|t| t.rms > 0.0)
                .map(|t| TrackField::new(&t, track_radius(bearing, race), salt, field))
                .transpose()
        };
        if spec.is_empty() {
            return Ok(None);
        }
        let inner = build(&spec.inner, Race::Inner, 1, "roughness.inner")?;
        let outer = build(&spec.outer, Race::Outer, 2, "roughness.outer")?;
        Ok(Some(Self { inner, outer }))
    }

    /// Added approach of a ball at azimuth `theta` (rate `theta_rate`) with the shaft at angle
    /// `shaft` (rate `shaft_rate`), and its rate \[m, m/s\].
    #[inline]
    pub fn added(&self, theta: f64, theta_rate: f64, shaft: f64, shaft_rate: f64) -> (f64, f64) {
        let (vo, ro) = self.race(Race::Outer, theta, theta_rate);
        let (vi, ri) = self.race(Race::Inner, theta - shaft, theta_rate - shaft_rate);
        (vo + vi, ro + ri)
    }

    /// One race's height and its rate at angle `x` on the ring (the inner ring's own angle)
    /// moving past the ball at `x_rate` \[m, m/s\]; 0 for a smooth race.
    #[inline]
    pub fn race(&self, race: Race, x: f64, x_rate: f64) -> (f64, f64) {
        match self.track(race) {
            Some(f) => {
                let (h, dh) = f.at(x);
                (h, dh * x_rate)
            }
            None => (0.0, 0.0),
        }
    }

    /// The field of one race, if it has one.
    pub fn track(&self, race: Race) -> Option<&TrackField> {
        match race {
            Race::Inner => self.inner.as_ref(),
            Race::Outer => self.outer.as_ref(),
        }
    }
}

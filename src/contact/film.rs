//! Lubricant film at a ball–race point contact (docs/model.md#film).
//!
//! - **Film thickness**: Hamrock & Dowson (1977) for an isothermal, fully flooded elliptical
//!   EHL contact,
//!
//!   `h_c/R_x = 2.69 U^0.67 G^0.53 W^−0.067 (1 − 0.61 e^(−0.73 k))` (central),
//!   `h_min/R_x = 3.63 U^0.68 G^0.49 W^−0.073 (1 − e^(−0.68 k))` (minimum),
//!
//!   with `U = η0 u/(E′ R_x)`, `G = α E′`, `W = Q/(E′ R_x²)`, u the entraining (mean rolling)
//!   velocity, R_x the reduced radius in the rolling direction and k = a/b the ellipticity.
//! - **Film stiffness**: the load–thickness slope of the same formula,
//!   `k_f = −∂Q/∂h_c = Q/(0.067 h_c)`, in series with the Hertz contact's `k_H = 1.5 K δ^½`.
//! - **Film damping**: the squeeze film of the contact's equivalent sphere of radius R_x
//!   approaching a plane (Reynolds' lubrication limit, Brenner 1961),
//!   `c_f = 6π η0 R_x²/h`.
//!
//! `h` in the laws is `max(h_c, σ)`, σ the composite roughness: below it the contact is in
//! mixed lubrication, where none of the formulas hold. Everything here is scalar arithmetic
//! (no allocation); [`FilmContact::law`] costs one `ln` and one `exp`.

use crate::config::{ConfigError, LubricationSection};
use crate::contact::HertzContact;
use std::f64::consts::PI;

/// Exponent of W in the central film thickness; the film stiffness is `Q/(HC_W_EXP·h_c)`.
pub const HC_W_EXP: f64 = 0.067;

/// `k_H/k_f = SERIES_RATIO · h_c/δ` for a Hertz contact `Q = K δ^{3/2}` (1.5 × 0.067).
pub const SERIES_RATIO: f64 = 1.5 * HC_W_EXP;

/// Kinematic viscosity ν [mm²/s] at `t_c` [°C] from two points (ν₁ at t₁, ν₂ at t₂, in mm²/s
/// and °C) by the ASTM D341 (Walther) relation `log10 log10(ν + 0.7) = A − B log10 T`, T in
/// kelvin. Meant for mineral and synthetic hydrocarbon oils above about 2 mm²/s.
pub fn walther_viscosity(nu1: f64, t1: f64, nu2: f64, t2: f64, t_c: f64) -> f64 {
    let ll = |nu: f64| (nu + 0.7).log10().log10();
    let lt = |t: f64| (t + 273.15).log10();
    let b = (ll(nu1) - ll(nu2)) / (lt(t2) - lt(t1));
    let a = ll(nu1) + b * lt(t1);
    10f64.powf(10f64.powf(a - b * lt(t_c))) - 0.7
}

/// The lubricant at the operating temperature, from a `[lubrication]` section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lubricant {
    /// Dynamic viscosity η0 at the operating temperature and ambient pressure \[Pa s\].
    pub viscosity: f64,
    /// Pressure–viscosity coefficient α \[1/Pa\].
    pub pressure_viscosity: f64,
    /// Composite rms roughness σ of ball and race \[m\]: the least film the laws use.
    pub roughness: f64,
}

impl Lubricant {
    /// The lubricant of a (validated) `[lubrication]` section: η0 given, or ν(T) from the
    /// 40 °C and 100 °C viscosities by [`walther_viscosity`] times the density.
    pub fn new(s: &LubricationSection) -> Result<Self, ConfigError> {
        s.validate()?;
        let viscosity = match (s.dynamic_viscosity, s.viscosity_40, s.viscosity_100) {
            (Some(eta), _, _) => eta,
            (None, Some(n40), Some(n100)) => {
                let nu = walther_viscosity(n40, 40.0, n100, 100.0, s.temperature);
                nu * 1e-6 * s.density
            }
            _ => unreachable!("validate asks for dynamic_viscosity or both viscosities"),
        };
        Ok(Self {
            viscosity,
            pressure_viscosity: s.pressure_viscosity,
            roughness: s.roughness,
        })
    }
}

/// The film's quantities at one contact state (see [`FilmContact::state`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmState {
    /// Dimensionless speed U = η0 u/(E′ R_x).
    pub u: f64,
    /// Dimensionless material parameter G = α E′.
    pub g: f64,
    /// Dimensionless load W = Q/(E′ R_x²).
    pub w: f64,
    /// Central film thickness h_c \[m\].
    pub h_central: f64,
    /// Minimum film thickness h_min \[m\].
    pub h_min: f64,
    /// Film stiffness k_f = Q/(0.067 max(h_c, σ)) \[N/m\].
    pub stiffness: f64,
    /// Film damping c_f = 6π η0 R_x²/max(h_c, σ) \[N s/m\].
    pub damping: f64,
}

/// The film of one race's contacts: the Hertz geometry (R_x, k at α0, docs/model.md#c5) and
/// the lubricant, with everything that does not depend on load and speed precomputed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmContact {
    /// Reduced radius in the rolling direction R_x \[m\].
    pub rx: f64,
    /// Ellipticity k = a/b.
    pub ellipticity: f64,
    /// Reduced modulus E′ \[Pa\].
    pub e_prime: f64,
    /// The lubricant.
    pub lubricant: Lubricant,
    /// `h_c = hc_coef · u^0.67 · Q^−0.067` (u in m/s, Q in N).
    hc_coef: f64,
    /// `h_min = hmin_coef · u^0.68 · Q^−0.073`.
    hmin_coef: f64,
    /// `c_f = c_coef / h`: 6π η0 R_x².
    c_coef: f64,
}

/// Smallest speed and load the laws take (a zero would give 0 · ∞) [m/s], \[N\].
const U_FLOOR: f64 = 1e-9;
const Q_FLOOR: f64 = 1e-6;

impl FilmContact {
    /// The film of a contact with Hertz solution `hertz` and lubricant `lub`.
    pub fn new(hertz: &HertzContact, lub: Lubricant) -> Self {
        let rx = 1.0 / hertz.inv_rx;
        let e = hertz.e_prime;
        let k = hertz.ellipticity;
        let g = lub.pressure_viscosity * e;
        let u_per_speed = lub.viscosity / (e * rx);
        let w_per_load = 1.0 / (e * rx * rx);
        let hc_coef = rx
            * 2.69
            * u_per_speed.powf(0.67)
            * g.powf(0.53)
            * w_per_load.powf(-HC_W_EXP)
            * (1.0 - 0.61 * (-0.73 * k).exp());
        let hmin_coef = rx
            * 3.63
            * u_per_speed.powf(0.68)
            * g.powf(0.49)
            * w_per_load.powf(-0.073)
            * (1.0 - (-0.68 * k).exp());
        Self {
            rx,
            ellipticity: k,
            e_prime: e,
            lubricant: lub,
            hc_coef,
            hmin_coef,
            c_coef: 6.0 * PI * lub.viscosity * rx * rx,
        }
    }

    /// Central film thickness h_c \[m\] at load `q` \[N\] and entraining speed `u` [m/s].
    pub fn central_thickness(&self, q: f64, u: f64) -> f64 {
        let (q, u) = (q.max(Q_FLOOR), u.abs().max(U_FLOOR));
        self.hc_coef * u.powf(0.67) * q.powf(-HC_W_EXP)
    }

    /// Minimum film thickness h_min \[m\] at load `q` \[N\] and entraining speed `u` [m/s].
    pub fn minimum_thickness(&self, q: f64, u: f64) -> f64 {
        let (q, u) = (q.max(Q_FLOOR), u.abs().max(U_FLOOR));
        self.hmin_coef * u.powf(0.68) * q.powf(-0.073)
    }

    /// Everything at load `q` \[N\] and entraining speed `u` [m/s] (diagnostics and tests).
    pub fn state(&self, q: f64, u: f64) -> FilmState {
        let e = self.e_prime;
        let lub = &self.lubricant;
        let h_central = self.central_thickness(q, u);
        let h = h_central.max(lub.roughness);
        FilmState {
            u: lub.viscosity * u.abs() / (e * self.rx),
            g: lub.pressure_viscosity * e,
            w: q / (e * self.rx * self.rx),
            h_central,
            h_min: self.minimum_thickness(q, u),
            stiffness: q.max(Q_FLOOR) / (HC_W_EXP * h),
            damping: self.c_coef / h,
        }
    }

    /// The film thickness the laws use, `max(h_c, σ)` \[m\], and the film damping
    /// `c_f = 6π η0 R_x²/max(h_c, σ)` [N s/m], at Hertz load `q` and entraining speed `u`:
    /// one `ln` and one `exp`, as `u^0.67 Q^−0.067 = exp(0.067 ln(u^10/Q))` (u ≥ 1e-9 m/s and
    /// Q ≥ 1e-6 N keep u^10/Q within 1e-84 … 1e36 for any speed below 1 km/s).
    #[inline(always)]
    pub fn law(&self, q: f64, u: f64) -> (f64, f64) {
        let (q, u) = (q.max(Q_FLOOR), u.abs().max(U_FLOOR));
        let u2 = u * u;
        let u4 = u2 * u2;
        let u10 = u4 * u4 * u2;
        let h = (self.hc_coef * (HC_W_EXP * (u10 / q).ln()).exp()).max(self.lubricant.roughness);
        (h, self.c_coef / h)
    }

    /// The factor `φ = k_f/(k_H + k_f) = δ/(δ + 0.1005 h)` by which the film in series scales
    /// the Hertz force `K δ^{3/2}` at approach `delta` (0 for δ ≤ 0), for film thickness `h`.
    #[inline(always)]
    pub fn series_factor(delta: f64, h: f64) -> f64 {
        let d = delta.max(0.0);
        d / (d + SERIES_RATIO * h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::HertzSolution;

    #[test]
    fn walther_goes_through_its_two_points() {
        let nu = walther_viscosity(68.0, 40.0, 8.7, 100.0, 40.0);
        assert!((nu - 68.0).abs() < 1e-9, "{nu}");
        let nu = walther_viscosity(68.0, 40.0, 8.7, 100.0, 100.0);
        assert!((nu - 8.7).abs() < 1e-9, "{nu}");
    }

    #[test]
    fn law_matches_state() {
        let h = HertzContact::new(186.84, 4.59, 2.286e11, HertzSolution::Exact);
        let f = FilmContact::new(
            &h,
            Lubricant {
                viscosity: 0.02,
                pressure_viscosity: 2e-8,
                roughness: 1e-8,
            },
        );
        let s = f.state(600.0, 17.0);
        let (hh, c) = f.law(600.0, 17.0);
        assert!((hh / s.h_central - 1.0).abs() < 1e-12);
        assert!((c / s.damping - 1.0).abs() < 1e-12);
        // The series factor is k_f/(k_H + k_f) with k_H = 1.5 K δ^½ and k_f = K δ^{3/2}/(0.067 h).
        let (k, d) = (3.6e10_f64, 5e-6_f64);
        let (kh, kf) = (1.5 * k * d.sqrt(), k * d.powf(1.5) / (0.067 * hh));
        let phi = FilmContact::series_factor(d, hh);
        assert!((phi - kf / (kh + kf)).abs() < 1e-12);
        assert_eq!(FilmContact::series_factor(-1e-7, hh), 0.0);
    }
}

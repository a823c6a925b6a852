//! Lubricant traction law: traction coefficient κ as a function of the slip speed u (docs/model.md#traction,
//! docs/model.md#c8).
//!
//! The default law is Gupta/ADORE-type,
//!
//! `κ(u) = (A + B u) e^(−C u) + D`,  u = |u| ≥ 0,
//!
//! with the coefficients set from four physical numbers: κ0 (traction at zero slip), κm (the
//! maximum, reached at slip speed u_m) and κ∞ (traction at large slip):
//!
//! - `A = κ0 − κ∞`, `D = κ∞`, `C = B/(A + B u_m)` (this makes dκ/du vanish at u_m);
//! - B is the root of `(A + B u_m) e^(−C u_m) + D = κm`, bracketed in (1e-6, 100) s/m.
//!
//! With the defaults (0, 0.08, 0.5 m/s, 0.05): A = −0.05, B = 0.34522 s/m, C = 2.81560 s/m,
//! D = 0.05. The alternative "piecewise" law (C⁰ only, for comparison) is κ = κm·u/u_m up to u_m,
//! then linear to κ∞ at 10·u_m and constant after; it ignores κ0.
//!
//! The run-time methods ([`TractionCurve::kappa`], [`TractionCurve::kappa_over_u`],
//! [`TractionCurve::force`]) are allocation-free, cost one `exp` and never divide by zero.

use crate::config::{ConfigError, TractionLaw, TractionSection};
use crate::vecmath;

/// Below this value of C·u, `(1 − e^(−x))/x` is evaluated by its Taylor series.
const SERIES_LIMIT: f64 = 1e-3;

/// The traction curve κ(u) of one lubricated contact, precomputed from a `[traction]` section.
///
/// The same curve is used at both races (docs/model.md#c8). All methods take the slip *speed* u ≥ 0 \[m/s\];
/// a negative argument is treated as |u|.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TractionCurve {
    /// Which law is evaluated.
    pub law: TractionLaw,
    /// ADORE coefficient A = κ0 − κ∞ (zero for the piecewise law, which does not use it).
    pub a: f64,
    /// ADORE coefficient B \[s/m\] (zero for the piecewise law).
    pub b: f64,
    /// ADORE coefficient C \[s/m\] (zero for the piecewise law).
    pub c: f64,
    /// ADORE coefficient D = κ∞ (zero for the piecewise law).
    pub d: f64,
    /// κ0: traction at zero slip.
    pub kappa_0: f64,
    /// κm: maximum traction.
    pub kappa_max: f64,
    /// u_m: slip speed of the maximum \[m/s\].
    pub u_max: f64,
    /// κ∞: traction at large slip.
    pub kappa_inf: f64,
    /// Regularisation speed for a non-zero κ0 in [`TractionCurve::kappa_over_u`] \[m/s\]
    /// (0.01·u_m; unused when κ0 = 0).
    pub u_reg: f64,
}

/// `φ(x) = (1 − e^(−x))/x`, given `e = e^(−x)`, accurate and smooth down to x = 0 (φ(0) = 1).
#[inline(always)]
fn one_minus_exp_over_x(x: f64, e: f64) -> f64 {
    if x < SERIES_LIMIT {
        // 1 − x/2 + x²/6 − x³/24 + x⁴/120; truncation error below x⁵/720 ≈ 1.4e-18.
        1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x / 120.0)))
    } else {
        (1.0 - e) / x
    }
}

impl TractionCurve {
    /// Builds the curve from a `[traction]` section.
    ///
    /// Errors name the field: non-finite or out-of-range values (`traction.kappa_0`,
    /// `traction.kappa_max`, `traction.u_max`, `traction.kappa_inf`), and — for the ADORE law —
    /// a (κ0, κm, u_m, κ∞) combination for which the equation for B has no root in
    /// (1e-6, 100) s/m (`traction.kappa_max`).
    pub fn new(t: &TractionSection) -> Result<Self, ConfigError> {
        let check = |field: &str, v: f64, positive: bool| -> Result<(), ConfigError> {
            if !v.is_finite() {
                return Err(ConfigError::new(
                    field,
                    format!("{v} is not a finite number"),
                ));
            }
            if positive && v <= 0.0 {
                return Err(ConfigError::new(field, format!("{v} must be > 0")));
            }
            if v < 0.0 {
                return Err(ConfigError::new(field, format!("{v} must be ≥ 0")));
            }
            Ok(())
        };
        check("traction.kappa_0", t.kappa_0, false)?;
        check("traction.kappa_max", t.kappa_max, true)?;
        check("traction.u_max", t.u_max, true)?;
        check("traction.kappa_inf", t.kappa_inf, false)?;
        if t.kappa_max < t.kappa_inf || t.kappa_max < t.kappa_0 {
            return Err(ConfigError::new(
                "traction.kappa_max",
                format!(
                    "{} must be ≥ kappa_0 ({}) and ≥ kappa_inf ({}): it is the curve's maximum",
                    t.kappa_max, t.kappa_0, t.kappa_inf
                ),
            ));
        }
        let mut curve = Self {
            law: t.law,
            a: 0.0,
            b: 0.0,
            c: 0.0,
            d: 0.0,
            kappa_0: t.kappa_0,
            kappa_max: t.kappa_max,
            u_max: t.u_max,
            kappa_inf: t.kappa_inf,
            u_reg: 0.01 * t.u_max,
        };
        if t.law == TractionLaw::Adore {
            let (a, b, c, d) = adore_coefficients(t.kappa_0, t.kappa_max, t.u_max, t.kappa_inf)?;
            curve.a = a;
            curve.b = b;
            curve.c = c;
            curve.d = d;
        }
        Ok(curve)
    }

    /// The ADORE coefficients (A, B, C, D); all zero for the piecewise law.
    pub fn coefficients(&self) -> (f64, f64, f64, f64) {
        (self.a, self.b, self.c, self.d)
    }

    /// Traction coefficient κ(u) at slip speed `u` \[m/s\] (exact law, κ(0) = κ0 for ADORE).
    #[inline]
    pub fn kappa(&self, u: f64) -> f64 {
        let u = u.abs();
        match self.law {
            TractionLaw::Adore => (self.a + self.b * u) * vecmath::exp(-self.c * u) + self.d,
            TractionLaw::Piecewise => self.piecewise(u),
        }
    }

    /// κ(u)/u \[s/m\], finite and smooth down to u = 0, where it equals dκ/du(0) = B − C·A.
    ///
    /// This is what the strip method needs: the traction force is `−Q (κ/u) u⃗`, with no
    /// division by |u⃗|. For the ADORE law it is evaluated as
    /// `B e^(−Cu) − A C (1 − e^(−Cu))/(Cu) + κ0/u`, with a series for small C·u.
    ///
    /// With κ0 > 0 the exact law has a finite traction at zero slip in an undefined direction
    /// (κ/u → ∞); the κ0 part is then regularised as `κ0/√(u² + u_reg²)`, u_reg = 0.01·u_m,
    /// so that the force stays finite and continuous. κ0 = 0 (the default, docs/model.md#c8) is exact.
    #[inline]
    pub fn kappa_over_u(&self, u: f64) -> f64 {
        match self.law {
            TractionLaw::Adore => self.adore_over_u(u),
            TractionLaw::Piecewise => {
                let u = u.abs();
                if u <= self.u_max {
                    self.kappa_max / self.u_max
                } else {
                    self.piecewise(u) / u
                }
            }
        }
    }

    /// [`TractionCurve::kappa_over_u`] of every element of `u`, in place: what the strip
    /// traction of all contacts of an RHS evaluation needs. The ADORE law runs as one loop that
    /// the compiler vectorises, four strips at a time where the processor has AVX2, with the
    /// same bits as the scalar call on any processor (its `exp` is a fixed sequence of IEEE
    /// operations, not the C library's).
    #[inline]
    pub fn kappa_over_u_in_place(&self, u: &mut [f64]) {
        match self.law {
            TractionLaw::Adore => vecmath::map_in_place(
                u,
                #[inline(always)]
                |v| self.adore_over_u(v),
            ),
            TractionLaw::Piecewise => u.iter_mut().for_each(|v| *v = self.kappa_over_u(*v)),
        }
    }

    /// κ(u)/u of the ADORE law ([`TractionCurve::kappa_over_u`]): plain IEEE operations and
    /// the vectorisable `exp`, so that a loop of it vectorises.
    #[inline(always)]
    fn adore_over_u(&self, u: f64) -> f64 {
        let u = u.abs();
        let x = self.c * u;
        let e = vecmath::exp(-x);
        // κ(u) − κ0 = A(e^(−Cu) − 1) + B u e^(−Cu).
        let mut r = self.b * e - self.a * self.c * one_minus_exp_over_x(x, e);
        if self.kappa_0 != 0.0 {
            r += self.kappa_0 / (u * u + self.u_reg * self.u_reg).sqrt();
        }
        r
    }

    /// Initial slope dκ/du at u = 0⁺ \[s/m\]: B − C·A (ADORE; 0.486 s/m by default) or κm/u_m
    /// (piecewise). It sets the slip relaxation rate (docs/model.md#stiffness).
    pub fn dkappa_du0(&self) -> f64 {
        match self.law {
            TractionLaw::Adore => self.b - self.c * self.a,
            TractionLaw::Piecewise => self.kappa_max / self.u_max,
        }
    }

    /// Traction force components on the body whose slip is `(u1, u2)` \[m/s\] under normal load
    /// `q` \[N\]: `−q κ(|u|) u/|u|` (docs/model.md#forces), i.e. opposite to the slip. Zero slip gives zero
    /// force (no division by zero).
    #[inline]
    pub fn force(&self, u1: f64, u2: f64, q: f64) -> (f64, f64) {
        let s = -q * self.kappa_over_u((u1 * u1 + u2 * u2).sqrt());
        (s * u1, s * u2)
    }

    /// The piecewise law for u ≥ 0.
    #[inline]
    fn piecewise(&self, u: f64) -> f64 {
        if u <= self.u_max {
            self.kappa_max * u / self.u_max
        } else if u < 10.0 * self.u_max {
            let t = (u - self.u_max) / (9.0 * self.u_max);
            self.kappa_max + (self.kappa_inf - self.kappa_max) * t
        } else {
            self.kappa_inf
        }
    }
}

/// Solves the ADORE mapping (κ0, κm, u_m, κ∞) → (A, B, C, D) by bisection on B.
///
/// On the admissible branch (A + B u_m > max(A, 0), i.e. B > 0 and C > 0) the left side
/// `h(B) = (A + B u_m) e^(−C u_m) + D − κm` rises monotonically, so a sign change in the bracket
/// (1e-6, 100) s/m is both necessary and sufficient for the unique root.
fn adore_coefficients(
    kappa_0: f64,
    kappa_max: f64,
    u_max: f64,
    kappa_inf: f64,
) -> Result<(f64, f64, f64, f64), ConfigError> {
    let a = kappa_0 - kappa_inf;
    let d = kappa_inf;
    let h = |b: f64| {
        let s = a + b * u_max;
        let c = b / s;
        s * (-c * u_max).exp() + d - kappa_max
    };
    // Keep A + B u_m > 0 (else C < 0 and u_m would be a minimum, not a maximum).
    let b_min = if a < 0.0 {
        (-a / u_max) * (1.0 + 1e-12) + f64::MIN_POSITIVE
    } else {
        0.0
    };
    let mut lo = b_min.max(1e-6);
    let mut hi = 100.0_f64;
    let no_root = || {
        ConfigError::new(
            "traction.kappa_max",
            format!(
                "no ADORE traction curve κ(u) = (A + B u)e^(−C u) + D peaks at kappa_max = \
                 {kappa_max} for u_max = {u_max} m/s, kappa_0 = {kappa_0}, kappa_inf = \
                 {kappa_inf} (the root B must lie in (1e-6, 100) s/m)"
            ),
        )
    };
    if lo >= hi {
        return Err(no_root());
    }
    let (h_lo, h_hi) = (h(lo), h(hi));
    if !(h_lo.is_finite() && h_hi.is_finite()) || h_lo > 0.0 || h_hi < 0.0 {
        return Err(no_root());
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if h(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    let b = 0.5 * (lo + hi);
    let c = b / (a + b * u_max);
    if !(b.is_finite() && c.is_finite() && c > 0.0) {
        return Err(no_root());
    }
    Ok((a, b, c, d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_and_closed_form_agree_at_the_switch() {
        let x = SERIES_LIMIT;
        let e = (-x).exp();
        let series = one_minus_exp_over_x(x * (1.0 - 1e-12), e);
        let closed = (1.0 - e) / x;
        assert!((series - closed).abs() < 1e-12, "{series} vs {closed}");
    }
}

//! Hertz point contact between two elastic bodies of the same steel (docs/model.md#hertz).
//!
//! Given the curvature sums in the two principal planes, [`HertzContact`] gives the load–deflection
//! constant `K` in `Q = K δ^{3/2}`, the contact-ellipse semi-axes and the peak pressure, either from
//! the exact elliptic-integral solution or from the Hamrock–Brewe curve fits.

use std::f64::consts::PI;

/// Complete elliptic integrals of the first and second kind, `K(m)` and `E(m)`, with parameter
/// `m = k²` in `[0, 1)`, by the arithmetic–geometric mean (quadratic convergence, full precision).
pub fn elliptic_ke(m: f64) -> (f64, f64) {
    assert!(
        (0.0..1.0).contains(&m),
        "elliptic parameter m = {m} outside [0, 1)"
    );
    let mut a = 1.0_f64;
    let mut b = (1.0 - m).sqrt();
    let mut c = m.sqrt();
    let mut sum = 0.5 * c * c; // Σ 2^(n−1) c_n², n = 0 term
    let mut pow2 = 0.5_f64;
    for _ in 0..64 {
        if c.abs() < 1e-17 * a {
            break;
        }
        let an = 0.5 * (a + b);
        let bn = (a * b).sqrt();
        // c_{n+1} = (a_n − b_n)/2 = c_n²/(4 a_{n+1}), free of cancellation.
        c = c * c / (4.0 * an);
        a = an;
        b = bn;
        pow2 *= 2.0;
        sum += pow2 * c * c;
    }
    let k = PI / (2.0 * a);
    let e = k * (1.0 - sum);
    (k, e)
}

/// Ellipticity solve and the resulting constants of one contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    /// Curvature sum in the plane of the ellipse's minor axis, 1/R_x (the larger sum) [1/m].
    pub inv_rx: f64,
    /// Curvature sum in the plane of the major axis, 1/R_y [1/m].
    pub inv_ry: f64,
    /// Effective radius R = (1/R_x + 1/R_y)⁻¹ \[m\].
    pub r_eff: f64,
    /// Reduced modulus E′ = E/(1−ν²) \[Pa\].
    pub e_prime: f64,
    /// Ellipticity k = a/b.
    pub ellipticity: f64,
    /// Complete elliptic integral of the second kind ℰ (or its fit).
    pub ell_e: f64,
    /// Complete elliptic integral of the first kind 𝓕 (or its fit).
    pub ell_f: f64,
    /// Load–deflection constant K in Q = K δ^{3/2} [N/m^1.5].
    pub stiffness: f64,
    /// Whether the major axis lies in the plane of the second curvature passed to the
    /// constructor (for ball–race contacts: transverse to rolling, the usual case).
    pub major_along_second: bool,
}

/// How the ellipticity and the elliptic integrals are obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HertzSolution {
    /// The ellipticity solved exactly with the complete elliptic integrals.
    Exact,
    /// The Hamrock–Brewe curve fits.
    HamrockBrewe,
}

impl HertzContact {
    /// Contact of two bodies whose summed principal curvatures are `sum1` (plane 1, e.g. rolling)
    /// and `sum2` (plane 2, e.g. transverse) [1/m], both ≥ 0 with a positive total, and the reduced
    /// modulus `e_prime`.
    pub fn new(sum1: f64, sum2: f64, e_prime: f64, solution: HertzSolution) -> Self {
        assert!(
            sum1 >= 0.0 && sum2 >= 0.0 && sum1 + sum2 > 0.0,
            "curvature sums must be non-negative with a positive total (got {sum1}, {sum2})"
        );
        let (inv_rx, inv_ry, major_along_second) = if sum1 >= sum2 {
            (sum1, sum2, true)
        } else {
            (sum2, sum1, false)
        };
        let r_eff = 1.0 / (inv_rx + inv_ry);
        let (k, ell_e, ell_f) = match solution {
            HertzSolution::Exact => exact_ellipticity(inv_rx, inv_ry),
            HertzSolution::HamrockBrewe => {
                // Hamrock–Brewe fits in terms of R_y/R_x = inv_rx/inv_ry (≥ 1).
                let ratio = if inv_ry > 0.0 { inv_rx / inv_ry } else { 1e12 };
                (
                    1.0339 * ratio.powf(0.6360),
                    1.0003 + 0.5968 / ratio,
                    1.5277 + 0.6023 * ratio.ln(),
                )
            }
        };
        let stiffness = PI * k * e_prime * (2.0 * ell_e * r_eff / (9.0 * ell_f.powi(3))).sqrt();
        Self {
            inv_rx,
            inv_ry,
            r_eff,
            e_prime,
            ellipticity: k,
            ell_e,
            ell_f,
            stiffness,
            major_along_second,
        }
    }

    /// Semi-major axis a and semi-minor axis b \[m\] at normal load `q` \[N\].
    pub fn semi_axes(&self, q: f64) -> (f64, f64) {
        let (a_star, b_star) = self.semi_axis_factors();
        let c = q.max(0.0).cbrt();
        (a_star * c, b_star * c)
    }

    /// `(a*, b*)` with `a = a* Q^{1/3}`, `b = b* Q^{1/3}`: precomputed once per race.
    pub fn semi_axis_factors(&self) -> (f64, f64) {
        let k = self.ellipticity;
        let base = 6.0 * self.ell_e * self.r_eff / (PI * self.e_prime);
        ((base * k * k).cbrt(), (base / k).cbrt())
    }

    /// Peak Hertz pressure p0 = 3Q/(2πab) \[Pa\].
    pub fn peak_pressure(&self, q: f64) -> f64 {
        let (a, b) = self.semi_axes(q);
        if a * b > 0.0 {
            1.5 * q / (PI * a * b)
        } else {
            0.0
        }
    }

    /// Normal approach δ \[m\] at load `q` \[N\].
    pub fn deflection(&self, q: f64) -> f64 {
        (q.max(0.0) / self.stiffness).powf(2.0 / 3.0)
    }

    /// Harris' dimensionless deflection δ* = (2𝓕/π)(π/(2k²ℰ))^{1/3}.
    pub fn harris_delta_star(&self) -> f64 {
        let k = self.ellipticity;
        (2.0 * self.ell_f / PI) * (PI / (2.0 * k * k * self.ell_e)).cbrt()
    }
}

/// Solves `F(ρ) = [(k²+1)ℰ(m) − 2𝓕(m)] / [(k²−1)ℰ(m)]`, `m = 1 − 1/k²`, for k ∈ (1, 1e4)
/// by bisection on ln k (the right side rises monotonically from 0 to 1).
fn exact_ellipticity(inv_rx: f64, inv_ry: f64) -> (f64, f64, f64) {
    let f_rho = (inv_rx - inv_ry) / (inv_rx + inv_ry);
    if f_rho <= 1e-12 {
        // Circular contact: k = 1, ℰ = 𝓕 = π/2.
        return (1.0, PI / 2.0, PI / 2.0);
    }
    let g = |k: f64| {
        let m = 1.0 - 1.0 / (k * k);
        let (kk, ee) = elliptic_ke(m);
        ((k * k + 1.0) * ee - 2.0 * kk) / ((k * k - 1.0) * ee)
    };
    let (mut lo, mut hi) = (1e-9_f64, 1e4_f64.ln());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid.exp()) < f_rho {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-15 {
            break;
        }
    }
    let k = (0.5 * (lo + hi)).exp();
    let (kk, ee) = elliptic_ke(1.0 - 1.0 / (k * k));
    (k, ee, kk)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elliptic_integrals_closed_forms() {
        let (k, e) = elliptic_ke(0.0);
        assert!((k - PI / 2.0).abs() < 1e-15 && (e - PI / 2.0).abs() < 1e-15);
        // Known values at m = 0.5 (Abramowitz & Stegun table 17.1).
        let (k, e) = elliptic_ke(0.5);
        assert!((k - 1.854_074_677_301_372).abs() < 1e-13, "K(0.5) = {k}");
        assert!((e - 1.350_643_881_047_675_5).abs() < 1e-13, "E(0.5) = {e}");
        // Legendre's relation K E' + E K' − K K' = π/2 at m = 0.3.
        let (k1, e1) = elliptic_ke(0.3);
        let (k2, e2) = elliptic_ke(0.7);
        assert!((k1 * e2 + e1 * k2 - k1 * k2 - PI / 2.0).abs() < 1e-13);
    }

    #[test]
    fn circular_contact_matches_sphere_on_flat() {
        // Sphere of radius r on a flat of the same material: Q = (4/3) E* √r δ^{3/2} with
        // E* = E/(2(1−ν²)) = E′/2, i.e. K = (2/3) E′ √r.
        let r = 0.01;
        let e_prime = 2.0e11;
        let c = HertzContact::new(1.0 / r, 1.0 / r, e_prime, HertzSolution::Exact);
        let k_closed = 2.0 / 3.0 * e_prime * r.sqrt();
        assert!(
            (c.stiffness / k_closed - 1.0).abs() < 1e-12,
            "{}",
            c.stiffness
        );
    }
}

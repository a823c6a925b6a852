//! Butcher tableaus as const data, shared by every method.
//!
//! Stage *slots* are numbered: `0..stages` the main stages (slot 0 is `f(t, y)`), then, when
//! the method is not FSAL, one slot for `f(t + h, y1)` (the "end derivative", which is also the
//! next step's slot 0), then any extra stages used only for dense output. A FSAL method's last
//! main stage is `f(t + h, y1)` itself.

/// An explicit Runge–Kutta method with its error estimator and dense output.
#[derive(Debug)]
pub struct Tableau {
    /// Method name.
    pub name: &'static str,
    /// Order of the propagated solution.
    pub order: u32,
    /// Number of main stages (computed on every step attempt).
    pub stages: usize,
    /// The last main stage is `f(t + h, y1)` (first same as last).
    pub fsal: bool,
    /// Nodes `c` of every slot.
    pub c: &'static [f64],
    /// Rows of `A` for every slot: row `i` holds the coefficients of slots `0..row.len()`
    /// (`row.len() <= i`). The end-derivative slot of a non-FSAL method has an empty row.
    pub a: &'static [&'static [f64]],
    /// Weights of the propagated solution (length `stages`).
    pub b: &'static [f64],
    /// Error-estimator weights (`b - b_hat`, length `stages`); empty without estimator.
    pub e: &'static [f64],
    /// Second (lower-order) estimator of DOP853's combined norm; empty otherwise.
    pub e3: &'static [f64],
    /// Order `q` of the error estimate: the controller exponent is `1/(q+1)`.
    pub err_order: u32,
    /// PI coefficient scaling: the exponent is `1/(q+1) - beta_scale * beta` (Hairer).
    pub beta_scale: f64,
    /// Hairer's stiffness detection: boundary of `h·ρ` (ρ estimated from the last two
    /// evaluations at `t + h`, the last main stage with `c = 1` and the end derivative) above
    /// which a step counts as limited by stability (DOPRI5 3.25, DOP853 6.1); 0: no detection.
    pub stiff_bound: f64,
    /// Dense-output rows `d` over slots (beyond the cubic Hermite base; see [`crate::dense`]).
    pub dense: &'static [&'static [f64]],
}

impl Tableau {
    /// Slot holding `f(t + h, y1)`.
    pub fn end_slot(&self) -> usize {
        if self.fsal {
            self.stages - 1
        } else {
            self.stages
        }
    }

    /// Total number of slots (main, end derivative, extra dense stages).
    pub fn slots(&self) -> usize {
        self.c.len()
    }

    /// Whether the method has an embedded error estimator.
    pub fn has_error_estimate(&self) -> bool {
        !self.e.is_empty()
    }

    /// Stability function `R(z) = 1 + z bᵀ (I − zA)⁻¹ 1` of the propagated solution at the complex
    /// point `z = re + i·im`; returns `(Re R, Im R)`.
    pub fn stability_function(&self, re: f64, im: f64) -> (f64, f64) {
        let mut g = [(0.0f64, 0.0f64); 32];
        let s = self.stages.min(32);
        for i in 0..s {
            let (mut sr, mut si) = (0.0, 0.0);
            for (j, &a) in self.a[i].iter().enumerate() {
                sr += a * g[j].0;
                si += a * g[j].1;
            }
            // g_i = 1 + z * sum
            g[i] = (1.0 + re * sr - im * si, re * si + im * sr);
        }
        let (mut sr, mut si) = (0.0, 0.0);
        for (j, &b) in self.b.iter().enumerate().take(s) {
            sr += b * g[j].0;
            si += b * g[j].1;
        }
        (1.0 + re * sr - im * si, re * si + im * sr)
    }

    /// Largest `x` such that `|R(i y)| <= 1 + tol` for all `0 < y <= x`, scanning up to `x_max`
    /// (the imaginary-axis stability reach). Found by a scan with step `dx` and bisection.
    pub fn imaginary_stability_reach(&self, tol: f64, dx: f64, x_max: f64) -> f64 {
        self.stability_reach((0.0, 1.0), tol, dx, x_max)
    }

    /// Largest `s` such that `|R(s·d)| <= 1 + tol` for all `0 < s' <= s` along the unit direction
    /// `d = (re, im)` of the complex plane (e.g. the direction of a Jacobian eigenvalue, so that
    /// `h_crit = s / |λ|`), scanning with step `dx` up to `x_max`, refined by bisection.
    pub fn stability_reach(&self, direction: (f64, f64), tol: f64, dx: f64, x_max: f64) -> f64 {
        let (dr, di) = direction;
        let unstable = |x: f64| {
            let (r, i) = self.stability_function(x * dr, x * di);
            (r * r + i * i).sqrt() > 1.0 + tol
        };
        let mut x = dx;
        while x <= x_max {
            if unstable(x) {
                let (mut lo, mut hi) = (x - dx, x);
                for _ in 0..100 {
                    let mid = 0.5 * (lo + hi);
                    if unstable(mid) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return lo;
            }
            x += dx;
        }
        x_max
    }
}

#[cfg(test)]
mod tests {
    use crate::Method;

    /// Row sums equal nodes, weights sum to one, estimators sum to zero, FSAL rows equal `b`.
    #[test]
    fn tableaus_are_consistent() {
        for m in Method::ALL {
            let t = m.tableau();
            assert_eq!(t.a.len(), t.slots(), "{}", t.name);
            assert_eq!(t.b.len(), t.stages, "{}", t.name);
            assert!(t.e.is_empty() || t.e.len() == t.stages);
            assert!(t.e3.is_empty() || t.e3.len() == t.stages);
            for (i, row) in t.a.iter().enumerate() {
                assert!(row.len() <= i, "{} row {i}", t.name);
                if i == t.end_slot() && !t.fsal {
                    assert!(row.is_empty());
                    assert_eq!(t.c[i], 1.0);
                    continue;
                }
                let s: f64 = row.iter().sum();
                assert!(
                    (s - t.c[i]).abs() < 1e-13,
                    "{} row {i}: {s} vs {}",
                    t.name,
                    t.c[i]
                );
            }
            let sb: f64 = t.b.iter().sum();
            assert!((sb - 1.0).abs() < 1e-14, "{} sum b {sb}", t.name);
            for e in [t.e, t.e3] {
                let se: f64 = e.iter().sum();
                assert!(se.abs() < 1e-13, "{} sum e {se}", t.name);
            }
            if t.fsal {
                let last = t.a[t.stages - 1];
                for (j, &bj) in t.b.iter().enumerate() {
                    assert_eq!(last.get(j).copied().unwrap_or(0.0), bj);
                }
            }
            for row in t.dense {
                assert_eq!(row.len(), t.slots());
            }
        }
    }

    /// Bushy-tree order conditions sum b_i c_i^k = 1/(k+1) up to the method's order.
    #[test]
    fn quadrature_conditions() {
        for m in Method::ALL {
            let t = m.tableau();
            for k in 0..t.order as i32 {
                let s: f64 = t.b.iter().zip(t.c).map(|(b, c)| b * c.powi(k)).sum();
                let want = 1.0 / (k as f64 + 1.0);
                assert!((s - want).abs() < 1e-12, "{} k={k}: {s} vs {want}", t.name);
            }
        }
    }

    #[test]
    fn rk4_reach_is_2_sqrt_2() {
        let r = Method::Rk4
            .tableau()
            .imaginary_stability_reach(1e-12, 1e-3, 10.0);
        assert!((r - 8f64.sqrt()).abs() < 1e-6, "{r}");
    }
}

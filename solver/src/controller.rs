//! Error norm, step-size controller (I or PI, after Hairer) and the automatic initial step.

use super::options::Options;
use super::tableau::Tableau;

/// Hairer's RMS error norm with `sc_i = atol_i + rtol_i * max(|y0_i|, |y1_i|)`.
/// `err5` is the main error vector (already multiplied by h); `err3`, when given, is DOP853's
/// 3rd-order estimate and the combined norm `E5 / sqrt(n (E5 + 0.01 E3))` is returned.
pub fn error_norm(
    y0: &[f64],
    y1: &[f64],
    atol: &[f64],
    rtol: &[f64],
    err5: &[f64],
    err3: Option<&[f64]>,
) -> f64 {
    let n = y0.len();
    let mut e5 = 0.0;
    let mut e3 = 0.0;
    for i in 0..n {
        let sc = (atol[i] + rtol[i] * y0[i].abs().max(y1[i].abs())).max(f64::MIN_POSITIVE);
        let r = err5[i] / sc;
        e5 += r * r;
        if let Some(e) = err3 {
            let r3 = e[i] / sc;
            e3 += r3 * r3;
        }
    }
    let nf = n.max(1) as f64;
    if err3.is_some() {
        let mut deno = e5 + 0.01 * e3;
        if deno <= 0.0 {
            deno = 1.0;
        }
        e5 / (nf * deno).sqrt()
    } else {
        (e5 / nf).sqrt()
    }
}

/// The component with the largest weighted error |err5_i| / sc_i (`sc_i` as in [`error_norm`])
/// and that ratio: where an attempt's error estimate is largest.
pub fn largest_weighted_error(
    y0: &[f64],
    y1: &[f64],
    atol: &[f64],
    rtol: &[f64],
    err5: &[f64],
) -> (usize, f64) {
    let mut best = (0, f64::NEG_INFINITY);
    for i in 0..y0.len() {
        let sc = (atol[i] + rtol[i] * y0[i].abs().max(y1[i].abs())).max(f64::MIN_POSITIVE);
        let r = (err5[i] / sc).abs();
        if r > best.1 {
            best = (i, r);
        }
    }
    best
}

/// Controller memory and decisions.
#[derive(Clone, Copy, Debug)]
pub struct Controller {
    /// Previous accepted error (Hairer's `facold`), for the PI controller.
    pub err_old: f64,
    /// The previous attempt was rejected (then the step may not grow on the next acceptance).
    pub last_rejected: bool,
    /// Step size and error of the previous rejected attempt of the current step (only with
    /// [`Options::observed_order_on_reject`]; cleared on acceptance, so never part of a snapshot
    /// taken between steps).
    pub rej_prev: Option<(f64, f64)>,
}

impl Default for Controller {
    fn default() -> Self {
        Controller {
            err_old: 1e-4,
            last_rejected: false,
            rej_prev: None,
        }
    }
}

impl Controller {
    fn exponent(tab: &Tableau, o: &Options) -> f64 {
        1.0 / (tab.err_order as f64 + 1.0) - tab.beta_scale * o.pi_beta
    }

    /// Step size after accepting a step of size `h` with error `err <= 1`.
    pub fn accept(&mut self, tab: &Tableau, o: &Options, h: f64, err: f64) -> f64 {
        let fac11 = err.powf(Self::exponent(tab, o));
        let fac = fac11 / self.err_old.powf(o.pi_beta);
        let fac = (fac / o.safety).clamp(1.0 / o.fac_max, 1.0 / o.fac_min);
        let mut h_new = h / fac;
        self.err_old = err.max(1e-4);
        if self.last_rejected {
            h_new = h_new.min(h);
        }
        self.last_rejected = false;
        self.rej_prev = None;
        h_new
    }

    /// Step size after rejecting a step of size `h` with error `err > 1` (or non-finite).
    pub fn reject(&mut self, tab: &Tableau, o: &Options, h: f64, err: f64) -> f64 {
        self.last_rejected = true;
        let prev = self.rej_prev.take();
        if !err.is_finite() {
            return h * o.fac_min;
        }
        let q1 = tab.err_order as f64 + 1.0;
        let mut p = q1;
        if o.observed_order_on_reject {
            if let Some((h0, e0)) = prev {
                if h < h0 && e0.is_finite() && e0 > err {
                    p = ((e0 / err).ln() / (h0 / h).ln()).clamp(1.0, q1);
                }
            }
            self.rej_prev = Some((h, err));
        }
        let fac11 = err.powf(1.0 / p);
        h / (1.0 / o.fac_min).min(fac11 / o.safety)
    }
}

/// Hairer's initial-step heuristic (`hinit`): `f0 = f(t, y0)` is given; `eval` computes
/// `f(t + h, y0 + h f0)` into its output and the buffer `y1` is scratch. Returns the step size.
#[allow(clippy::too_many_arguments)]
pub fn initial_step(
    order: u32,
    y0: &[f64],
    f0: &[f64],
    atol: &[f64],
    rtol: &[f64],
    h_max: f64,
    y1: &mut [f64],
    f1: &mut [f64],
    mut eval: impl FnMut(f64, &[f64], &mut [f64]),
) -> f64 {
    let n = y0.len();
    let sk = |i: usize| (atol[i] + rtol[i] * y0[i].abs()).max(f64::MIN_POSITIVE);
    let (mut dnf, mut dny) = (0.0, 0.0);
    for i in 0..n {
        dnf += (f0[i] / sk(i)).powi(2);
        dny += (y0[i] / sk(i)).powi(2);
    }
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(h_max);
    for i in 0..n {
        y1[i] = y0[i] + h * f0[i];
    }
    eval(h, y1, f1);
    let mut der2 = 0.0;
    for i in 0..n {
        der2 += ((f1[i] - f0[i]) / sk(i)).powi(2);
    }
    let der2 = der2.sqrt() / h;
    if !der2.is_finite() {
        // The probe left the region where f is finite: start small and let the controller work.
        return (h * 1e-3).min(h_max);
    }
    let der12 = der2.abs().max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(1.0 / order as f64)
    };
    (100.0 * h).min(h1).min(h_max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Method;

    #[test]
    fn norm_is_rms() {
        let y = [0.0, 0.0];
        let n = error_norm(&y, &y, &[1.0, 1.0], &[0.0, 0.0], &[3.0, 4.0], None);
        assert!((n - (12.5f64).sqrt()).abs() < 1e-15);
        // rtol uses max(|y0|, |y1|)
        let n = error_norm(&[1.0], &[-3.0], &[0.0], &[1.0], &[3.0], None);
        assert!((n - 1.0).abs() < 1e-15);
    }

    #[test]
    fn controller_limits() {
        let o = Options::new(Method::Dopri5, 1e-6, vec![1e-6]);
        let tab = Method::Dopri5.tableau();
        let mut c = Controller::default();
        assert!((c.accept(tab, &o, 1.0, 0.0) - 10.0).abs() < 1e-12);
        assert!((c.reject(tab, &o, 1.0, 1e30) - 0.2).abs() < 1e-12);
        assert!((c.reject(tab, &o, 1.0, f64::NAN) - 0.2).abs() < 1e-12);
        // after a rejection the step may not grow
        assert!(c.accept(tab, &o, 1.0, 1e-8) <= 1.0);
        // I-controller: h_new = h * 0.9 * err^(-1/5)
        let h = c.accept(tab, &o, 1.0, 0.5);
        assert!((h - 0.9 * 0.5f64.powf(-0.2)).abs() < 1e-12);
    }
}

//! Integrator options and their validation.

use super::error::SolverError;
use super::method::Method;

/// Integrator options. Build with [`Options::new`] and adjust fields; validated by
/// [`crate::Integrator::new`].
#[derive(Clone, Debug)]
pub struct Options {
    /// Integration method.
    pub method: Method,
    /// Relative tolerance (>= 0).
    pub rtol: f64,
    /// Absolute tolerances: one per component, or a single value broadcast to all (>= 0 each).
    pub atol: Vec<f64>,
    /// Per-component factors on `rtol` (empty: all 1). Use 0 for unbounded angles that should be
    /// controlled by `atol` only. Length 0, 1 or the dimension.
    pub rtol_scale: Vec<f64>,
    /// Initial step; `None`: automatic (Hairer's `hinit`).
    pub h_init: Option<f64>,
    /// Largest step size (default `f64::INFINITY`).
    pub h_max: f64,
    /// Step-size underflow threshold. The effective floor at time `t` is
    /// `max(h_min * max(1, |t|), 4 ε |t|)`: absolute below `|t| = 1`, relative above, and never
    /// below the round-off limit. A controller proposal below it fails with
    /// [`SolverError::StepSizeUnderflow`]. Default `1e-14`. Steps shortened to land on an end
    /// time or an event are exempt.
    pub h_min: f64,
    /// Step budget (accepted plus rejected steps) per advance call; default `10_000_000`.
    pub max_steps: u64,
    /// Safety factor of the step-size controller (default 0.9).
    pub safety: f64,
    /// Smallest step-size change factor per step (default 0.2).
    pub fac_min: f64,
    /// Largest step-size change factor per step (default 10).
    pub fac_max: f64,
    /// PI-controller coefficient (Hairer's β); 0 gives the I-controller (default 0).
    pub pi_beta: f64,
    /// `Some(h)`: no error control, constant step `h` (the last step is shortened to land).
    pub fixed_step: Option<f64>,
    /// Absolute time tolerance of event location (default `1e-13`; never below a few ulps of t).
    pub event_tol: f64,
    /// After a discontinuity (a located event, a stop, [`crate::Integrator::discontinuity`])
    /// restart the controller: fresh automatic initial step (Hairer's `hinit`) and cleared PI
    /// memory, instead of continuing with the step proposed before the discontinuity
    /// (default `false`).
    pub restart_after_discontinuity: bool,
    /// After two rejections in a row, size the next attempt with the local order observed from
    /// the two rejected attempts (`p = ln(err1/err2) / ln(h1/h2)`, clamped to `[1, q+1]`)
    /// instead of the method's nominal `q+1`: near a kink of the right-hand side the error
    /// falls more slowly than `h^{q+1}` and the nominal exponent shrinks too little
    /// (default `false`).
    pub observed_order_on_reject: bool,
    /// Zeno guard of [`crate::Integrator::advance_with_events`]: this many steps ending in an
    /// event (of any functions) in a row, each within [`Options::chatter_steps`] accepted steps
    /// of the one before and all within [`Options::chatter_span`] of time, stop the call with
    /// [`SolverError::Chattering`] instead of creeping on at a few steps per event. 0 (default)
    /// turns it off: a system whose events are legitimately a step or two apart (a polynomial
    /// flight between bounces takes one step) must not use it without a span that tells
    /// chatter from physics.
    pub chatter_events: u32,
    /// See [`Options::chatter_events`] (default 3).
    pub chatter_steps: u64,
    /// See [`Options::chatter_events`]: the run must fit in this time \[s\] (default ∞).
    pub chatter_span: f64,
}

impl Options {
    /// Options with the defaults documented on each field.
    pub fn new(method: Method, rtol: f64, atol: Vec<f64>) -> Self {
        Options {
            method,
            rtol,
            atol,
            rtol_scale: Vec::new(),
            h_init: None,
            h_max: f64::INFINITY,
            h_min: 1e-14,
            max_steps: 10_000_000,
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 10.0,
            pi_beta: 0.0,
            fixed_step: None,
            event_tol: 1e-13,
            restart_after_discontinuity: false,
            observed_order_on_reject: false,
            chatter_events: 0,
            chatter_steps: 3,
            chatter_span: f64::INFINITY,
        }
    }

    /// Fixed-step options (no error control): `Options::new(method, 0, [1])` with `fixed_step = h`.
    pub fn fixed(method: Method, h: f64) -> Self {
        let mut o = Options::new(method, 0.0, vec![1.0]);
        o.fixed_step = Some(h);
        o
    }

    /// Check the options for a system of dimension `n`.
    pub fn validate(&self, n: usize) -> Result<(), SolverError> {
        let bad = |m: String| Err(SolverError::InvalidOptions(m));
        if let Some(h) = self.fixed_step {
            if !(h.is_finite() && h > 0.0) {
                return bad(format!("fixed_step must be finite and > 0, got {h}"));
            }
        } else {
            if !self.method.is_adaptive() {
                return bad(format!(
                    "method {} has no error estimator: set fixed_step",
                    self.method
                ));
            }
            if !(self.rtol.is_finite() && self.rtol >= 0.0) {
                return bad(format!("rtol must be finite and >= 0, got {}", self.rtol));
            }
            check_atol(&self.atol, n)?;
            check_rtol_scale(&self.rtol_scale, n)?;
            if self.rtol == 0.0 && self.atol.iter().all(|&a| a == 0.0) {
                return bad("rtol and atol are all zero".into());
            }
        }
        if let Some(h) = self.h_init {
            if !(h.is_finite() && h > 0.0) {
                return bad(format!("h_init must be finite and > 0, got {h}"));
            }
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return bad(format!("h_max must be > 0, got {}", self.h_max));
        }
        if !(self.h_min.is_finite() && self.h_min >= 0.0) {
            return bad(format!("h_min must be finite and >= 0, got {}", self.h_min));
        }
        if self.h_min > self.h_max {
            return bad(format!("h_min {} exceeds h_max {}", self.h_min, self.h_max));
        }
        if self.max_steps == 0 {
            return bad("max_steps must be > 0".into());
        }
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return bad(format!("safety must be in (0, 1], got {}", self.safety));
        }
        if !(self.fac_min > 0.0 && self.fac_min <= 1.0) {
            return bad(format!("fac_min must be in (0, 1], got {}", self.fac_min));
        }
        if !(self.fac_max >= 1.0 && self.fac_max.is_finite()) {
            return bad(format!(
                "fac_max must be finite and >= 1, got {}",
                self.fac_max
            ));
        }
        if !(0.0..=0.2).contains(&self.pi_beta) {
            return bad(format!("pi_beta must be in [0, 0.2], got {}", self.pi_beta));
        }
        if !(self.event_tol.is_finite() && self.event_tol > 0.0) {
            return bad(format!(
                "event_tol must be finite and > 0, got {}",
                self.event_tol
            ));
        }
        if self.chatter_span.is_nan() || self.chatter_span < 0.0 {
            return bad(format!(
                "chatter_span must be ≥ 0 (∞ for no limit), got {}",
                self.chatter_span
            ));
        }
        Ok(())
    }
}

/// Validate an absolute-tolerance vector for dimension `n` (length 1 or `n`, finite, >= 0).
pub(crate) fn check_atol(atol: &[f64], n: usize) -> Result<(), SolverError> {
    if atol.len() != 1 && atol.len() != n {
        return Err(SolverError::InvalidOptions(format!(
            "atol has {} entries, expected 1 or {n}",
            atol.len()
        )));
    }
    if let Some((i, a)) = atol
        .iter()
        .enumerate()
        .find(|(_, a)| !(a.is_finite() && **a >= 0.0))
    {
        return Err(SolverError::InvalidOptions(format!(
            "atol[{i}] must be finite and >= 0, got {a}"
        )));
    }
    Ok(())
}

/// Validate an rtol-scale vector for dimension `n` (length 0, 1 or `n`, finite, >= 0).
pub(crate) fn check_rtol_scale(s: &[f64], n: usize) -> Result<(), SolverError> {
    if s.len() > 1 && s.len() != n {
        return Err(SolverError::InvalidOptions(format!(
            "rtol_scale has {} entries, expected 0, 1 or {n}",
            s.len()
        )));
    }
    if s.iter().any(|a| !(a.is_finite() && *a >= 0.0)) {
        return Err(SolverError::InvalidOptions(
            "rtol_scale entries must be finite and >= 0".into(),
        ));
    }
    Ok(())
}

/// Broadcast a length-0/1/n vector to length `n` into `out` (empty gives `default`).
pub(crate) fn broadcast(src: &[f64], default: f64, out: &mut [f64]) {
    match src.len() {
        0 => out.fill(default),
        1 => out.fill(src[0]),
        _ => out.copy_from_slice(src),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_options() {
        let ok = Options::new(Method::Dopri5, 1e-6, vec![1e-9]);
        assert!(ok.validate(3).is_ok());
        let mut o = ok.clone();
        o.atol = vec![1.0, 2.0];
        assert!(o.validate(3).is_err());
        let mut o = ok.clone();
        o.rtol = f64::NAN;
        assert!(o.validate(3).is_err());
        let mut o = ok.clone();
        o.fac_min = 0.0;
        assert!(o.validate(3).is_err());
        let o = Options::new(Method::Rk4, 1e-6, vec![1e-9]);
        assert!(o.validate(3).is_err());
        assert!(Options::fixed(Method::Rk4, 0.1).validate(3).is_ok());
        assert!(Options::fixed(Method::Rk4, -0.1).validate(3).is_err());
    }
}

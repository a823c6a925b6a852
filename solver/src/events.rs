//! Event location on the dense output and [`Integrator::advance_with_events`].
//!
//! After every accepted step the event functions are evaluated at its end. A function whose sign
//! changed strictly (or that reached exactly 0 from a non-zero value) has an event in the step; its
//! root is bracketed on the dense output with the Illinois variant of regula falsi (with bisection
//! safeguard) to within [`crate::Options::event_tol`], the mode staying frozen. The
//! integrator takes the bracket end where the sign has already changed as the event time,
//! re-integrates from the step start to exactly that time with the method itself (so the event
//! state has the method's accuracy, not the interpolant's), calls
//! [`EventSystem::handle_event`] for every function that changed sign by then (index order),
//! and restarts there. Functions that just fired count as 0 at the restart, so a state that sits
//! on the far side by round-off (a bouncing ball's height) does not fire again; a function that
//! is exactly 0 at a step start takes its reference sign from a probe just inside the step
//! (`t_old + max(1e-3 h, 100 event_tol)`), so leaving zero is not an event but coming back is.
//! A function whose event only switches a mode ([`EventSystem::mode_sign`]) restarts instead
//! with the sign of its new mode: coming back to the old side is an event even before the probe
//! (a function that touches 0 and returns within the probe's distance would otherwise leave the
//! mode switched against its sign until some other event).
//! Like every sign-change detector, two roots of one function inside one step are not seen.

use super::dense::{DenseOutput, StepView};
use super::error::SolverError;
use super::integrator::{AdvanceOutcome, Integrator};
use super::system::{EventAction, EventSystem};

/// The reference value of event function `i` at a restart after it fired: the smallest
/// number of the sign of its mode ([`EventSystem::mode_sign`]), or 0 (see the module notes).
fn restart_value<S: EventSystem + ?Sized>(sys: &S, i: usize) -> f64 {
    sys.mode_sign(i)
        .map_or(0.0, |s| f64::MIN_POSITIVE.copysign(s))
}

/// A sign change from `a` to `b` counts as an event (`a == 0` never does).
pub fn crosses(a: f64, b: f64) -> bool {
    (a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0)
}

/// Locate the root of event `index` in `[a, b]` (`g(a) = ga`, `g(b) = gb` of opposite sign, or
/// `gb == 0`) on the dense output; returns the end of the final bracket on the side of `b`.
#[allow(clippy::too_many_arguments)]
pub(super) fn locate<S: EventSystem + ?Sized>(
    sys: &mut S,
    dense: &DenseOutput,
    index: usize,
    mut a: f64,
    mut ga: f64,
    mut b: f64,
    mut gb: f64,
    tol: f64,
    y: &mut [f64],
    g: &mut [f64],
) -> f64 {
    if gb == 0.0 {
        return b;
    }
    let mut side = 0i8;
    let mut width = b - a;
    for it in 0..200 {
        let tol_here = tol.max(4.0 * f64::EPSILON * b.abs());
        if b - a <= tol_here {
            break;
        }
        let mut m = b - gb * (b - a) / (gb - ga);
        // Bisection safeguard: every third iteration unless the bracket at least halved.
        if !(m > a && m < b) || (it % 3 == 2 && b - a > 0.5 * width) {
            m = 0.5 * (a + b);
        }
        if it % 3 == 2 {
            width = b - a;
        }
        // Keep the probe strictly inside the bracket, a few ulps away from its ends.
        let guard = 4.0 * f64::EPSILON * a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
        m = m.clamp(a + guard.min(0.5 * (b - a)), b - guard.min(0.5 * (b - a)));
        dense.eval(m, y);
        let gm = sys.event(index, m, y, g);
        if gm == 0.0 {
            return m;
        }
        if (gm < 0.0) == (ga < 0.0) {
            a = m;
            ga = gm;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            b = m;
            gb = gm;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
    }
    b
}

impl Integrator {
    /// Zeno guard ([`crate::Options::chatter_events`]): event `i` fires now.
    fn check_chatter(&mut self, i: usize) -> Result<(), SolverError> {
        if self.opts.chatter_events == 0 {
            return Ok(());
        }
        let steps = self.stats.steps;
        let last = self.chatter_step;
        if last == steps {
            // another event of the same step
            return Ok(());
        }
        let close = last != u64::MAX
            && steps.saturating_sub(last) <= self.opts.chatter_steps
            && self.t - self.chatter_t0 <= self.opts.chatter_span;
        if close {
            self.chatter_run += 1;
        } else {
            self.chatter_run = 1;
            self.chatter_t0 = self.t;
        }
        self.chatter_step = steps;
        if self.chatter_run >= self.opts.chatter_events {
            let events = self.chatter_run;
            self.reset_chatter();
            return Err(SolverError::Chattering {
                t: self.t,
                index: i,
                events,
                steps: self.opts.chatter_steps,
                span: self.t - self.chatter_t0,
            });
        }
        Ok(())
    }

    /// Forget the firing history of the Zeno guard (a state put in from outside).
    pub(super) fn reset_chatter(&mut self) {
        self.chatter_step = u64::MAX;
        self.chatter_run = 0;
    }

    fn prepare_events(&mut self, m: usize) {
        if self.g_old.len() != m {
            self.g_old = vec![0.0; m];
            self.g_new = vec![0.0; m];
            self.g_tmp = vec![0.0; m];
            self.g_ref = vec![0.0; m];
            self.g_sus = vec![0.0; m];
            self.fired = vec![false; m];
        }
        if self.event_mask.capacity() < m {
            self.event_mask.reserve(m - self.event_mask.len());
        }
    }

    /// Like [`Integrator::advance`], locating events (sign changes of `g`) on the dense output to
    /// within `event_tol`, landing on the event time, calling `handle_event`, then continuing
    /// ([`EventAction::Continue`]) or returning early ([`EventAction::Stop`]). The observer sees a
    /// step cut at an event as ending at the event time, with the state before `handle_event`.
    pub fn advance_with_events<S: EventSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t_end: f64,
        mut observer: Option<&mut dyn FnMut(&StepView)>,
    ) -> Result<AdvanceOutcome, SolverError> {
        self.check_target(sys.dim(), t_end)?;
        let m = sys.n_events();
        self.prepare_events(m);
        sys.events(self.t, &self.y, &mut self.g_old);
        if self.event_mask.len() == m {
            for (i, (g, &fired)) in self.g_old.iter_mut().zip(&self.event_mask).enumerate() {
                if fired {
                    *g = restart_value(sys, i);
                }
            }
        }
        let mut attempts = 0u64;
        // Without an observer the dense output (3 extra stages per DOP853 step) is built only
        // for the steps that need it: a function that changed sign at the step end or sits at
        // 0 at its start. The stepping is the same either way; an FSAL method builds it always
        // (its stage 0 is gone after the step, and its dense output costs no extra stage).
        // With a sample grid ([`Integrator::set_sample_grid`]) the observer needs it only for
        // the steps that contain a grid point.
        let lazy = observer.is_some() && self.lazy_dense();
        let always_dense = (observer.is_some() && !lazy) || self.tab.fsal;
        while self.t < t_end {
            let t_old = self.step(sys, t_end, always_dense, &mut attempts)?;
            sys.events(self.t, &self.y, &mut self.g_new);
            // A time inside the step where the system suspects a sign change and back.
            let suspect = sys
                .suspect(t_old, self.t)
                .filter(|&ts| ts > t_old && ts < self.t);
            if !always_dense
                && (suspect.is_some()
                    || self.g_old.contains(&0.0)
                    || (0..m).any(|i| crosses(self.g_old[i], self.g_new[i]))
                    || (lazy && self.grid_hit(t_old, self.t)))
            {
                self.dense_after_step(sys, t_old);
            }
            // Functions sitting exactly at 0 at the step start (just fired) take their reference
            // sign from a probe just inside the step.
            let h = self.t - t_old;
            let t_probe = t_old + (1e-3 * h).max(100.0 * self.opts.event_tol).min(0.5 * h);
            self.g_ref.copy_from_slice(&self.g_old);
            if self.g_old.contains(&0.0) {
                self.dense.eval(t_probe, &mut self.ytmp);
                sys.events(t_probe, &self.ytmp, &mut self.g_tmp);
                for i in 0..m {
                    if self.g_old[i] == 0.0 {
                        self.g_ref[i] = self.g_tmp[i];
                    }
                }
            }
            // At a suspect time with a sign change since the start, the roots are located
            // before it (the end's signs may hide a sign change and back).
            let mut t_b = self.t;
            if let Some(ts) = suspect.filter(|&ts| ts > t_probe) {
                self.dense.eval(ts, &mut self.ytmp);
                sys.events(ts, &self.ytmp, &mut self.g_sus);
                if (0..m).any(|i| crosses(self.g_ref[i], self.g_sus[i])) {
                    t_b = ts;
                    self.g_new.copy_from_slice(&self.g_sus);
                }
            }
            // Earliest root among the functions that changed sign.
            let mut t_ev = f64::INFINITY;
            let mut first = usize::MAX;
            for i in 0..m {
                let a = if self.g_old[i] == 0.0 { t_probe } else { t_old };
                if crosses(self.g_ref[i], self.g_new[i]) {
                    let r = locate(
                        sys,
                        &self.dense,
                        i,
                        a,
                        self.g_ref[i],
                        t_b,
                        self.g_new[i],
                        self.opts.event_tol,
                        &mut self.ytmp,
                        &mut self.g_tmp,
                    );
                    if r < t_ev {
                        t_ev = r;
                        first = i;
                    }
                }
            }
            if first == usize::MAX {
                if let Some(obs) = observer.as_mut() {
                    obs(&StepView {
                        dense: &self.dense,
                        t_start: t_old,
                        t_end: self.t,
                        y_end: &self.y,
                    });
                }
                std::mem::swap(&mut self.g_old, &mut self.g_new);
                continue;
            }
            // Land on the event: re-integrate from the step start to the event time with the
            // method itself (error-controlled, mode still frozen), so the state handed to
            // handle_event has the method's accuracy rather than the interpolant's.
            if t_ev < self.t {
                std::mem::swap(&mut self.y, &mut self.y_new);
                self.t = t_old;
                self.fsal_valid = false;
                let h_keep = self.h_next;
                while self.t < t_ev {
                    self.step(sys, t_ev, false, &mut attempts)?;
                }
                self.h_next = h_keep;
            }
            sys.events(self.t, &self.y, &mut self.g_tmp);
            for i in 0..m {
                let started_here = self.g_old[i] != 0.0 || t_ev >= t_probe;
                self.fired[i] =
                    i == first || (started_here && crosses(self.g_ref[i], self.g_tmp[i]));
            }
            if let Some(obs) = observer.as_mut() {
                obs(&StepView {
                    dense: &self.dense,
                    t_start: t_old,
                    t_end: self.t,
                    y_end: &self.y,
                });
            }
            let mut stop = None;
            for i in 0..m {
                if self.fired[i] {
                    self.check_chatter(i)?;
                    self.stats.events += 1;
                    if sys.handle_event(i, self.t, &mut self.y) == EventAction::Stop
                        && stop.is_none()
                    {
                        stop = Some(i);
                    }
                }
            }
            self.discontinuity();
            sys.events(self.t, &self.y, &mut self.g_old);
            self.event_mask.clear();
            self.event_mask.extend_from_slice(&self.fired);
            for (i, (g, &fired)) in self.g_old.iter_mut().zip(&self.fired).enumerate() {
                if fired {
                    *g = restart_value(sys, i);
                }
            }
            if let Some(index) = stop {
                return Ok(AdvanceOutcome::Stopped { t: self.t, index });
            }
        }
        Ok(AdvanceOutcome::Reached)
    }
}

#[cfg(test)]
mod tests {
    use super::crosses;

    #[test]
    fn crossing_rules() {
        assert!(crosses(-1.0, 1.0));
        assert!(crosses(1.0, 0.0));
        assert!(!crosses(0.0, 1.0));
        assert!(!crosses(0.0, -1.0));
        assert!(!crosses(1.0, 2.0));
    }
}

//! The generic tableau-driven stepping engine.

use super::controller::{error_norm, initial_step, largest_weighted_error, Controller};
use super::dense::{DenseOutput, StepView};
use super::error::{SolverError, StepLimit};
use super::options::{broadcast, check_atol, check_rtol_scale, Options};
use super::state::{IntegratorState, Stats};
use super::system::System;
use super::tableau::Tableau;

/// Result of [`Integrator::advance_with_events`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AdvanceOutcome {
    /// The requested end time was reached.
    Reached,
    /// An event handler returned [`crate::EventAction::Stop`] at time `t`.
    Stopped {
        /// Event time (the integrator's current time).
        t: f64,
        /// Index of the event that stopped the integration.
        index: usize,
    },
}

/// Explicit Runge–Kutta integrator owning all its buffers (no allocation while stepping).
#[derive(Clone, Debug)]
pub struct Integrator {
    pub(super) opts: Options,
    pub(super) tab: &'static Tableau,
    pub(super) n: usize,
    pub(super) t: f64,
    pub(super) y: Vec<f64>,
    pub(super) y_new: Vec<f64>,
    pub(super) ytmp: Vec<f64>,
    /// Stage slots, `slots * n`; slot 0 is `f(t, y)` when `fsal_valid`.
    pub(super) k: Vec<f64>,
    pub(super) err5: Vec<f64>,
    pub(super) err3: Vec<f64>,
    pub(super) atol: Vec<f64>,
    pub(super) rtol: Vec<f64>,
    pub(super) h_next: f64,
    pub(super) fsal_valid: bool,
    pub(super) ctrl: Controller,
    pub(super) stats: Stats,
    pub(super) dense: DenseOutput,
    pub(super) g_old: Vec<f64>,
    pub(super) g_new: Vec<f64>,
    pub(super) g_tmp: Vec<f64>,
    pub(super) g_ref: Vec<f64>,
    pub(super) g_sus: Vec<f64>,
    pub(super) event_mask: Vec<bool>,
    pub(super) fired: Vec<bool>,
    /// Sample spacing of an observer that interpolates only at multiples of it
    /// ([`Integrator::set_sample_grid`]).
    pub(super) sample_grid: Option<f64>,
    /// Zeno guard: accepted-step count at the last event (`u64::MAX`: none), events in a row
    /// close together, and the time the run began.
    pub(super) chatter_step: u64,
    pub(super) chatter_run: u32,
    pub(super) chatter_t0: f64,
}

/// The integrator's state at one time (time, state, proposed step, FSAL stage, controller and
/// event memory, work counters), in buffers that [`Integrator::checkpoint`] reuses: for putting
/// the integrator back exactly where it was ([`Integrator::rollback`]) without allocating, e.g.
/// when a communication step fails and has to leave no trace. Unlike [`IntegratorState`] it is
/// not serializable.
#[derive(Clone, Debug, Default)]
pub struct Checkpoint {
    t: f64,
    y: Vec<f64>,
    h_next: f64,
    fsal: Vec<f64>,
    fsal_valid: bool,
    ctrl: Controller,
    event_mask: Vec<bool>,
    stats: Stats,
}

impl Checkpoint {
    /// An empty checkpoint with room for a state of dimension `dim` and `n_events` event
    /// functions: taking one then never allocates (the default one grows on first use).
    pub fn with_capacity(dim: usize, n_events: usize) -> Self {
        Self {
            y: Vec::with_capacity(dim),
            fsal: Vec::with_capacity(dim),
            event_mask: Vec::with_capacity(n_events),
            ..Self::default()
        }
    }

    /// The time it was taken at.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// The work counters at that time.
    pub fn stats(&self) -> Stats {
        self.stats
    }
}

/// Index of the first non-finite entry.
pub(super) fn first_non_finite(v: &[f64]) -> Option<usize> {
    v.iter().position(|x| !x.is_finite())
}

/// `out = y + h * Σ_j coef_j k_j` over the slots `k` (each of length `y.len()`).
fn combine(y: &[f64], h: f64, coef: &[f64], k: &[f64], out: &mut [f64]) {
    let n = y.len();
    out.copy_from_slice(y);
    for (j, &c) in coef.iter().enumerate() {
        if c != 0.0 {
            let hc = h * c;
            for (o, &kv) in out.iter_mut().zip(&k[j * n..(j + 1) * n]) {
                *o += hc * kv;
            }
        }
    }
}

/// Hairer's `h·ρ`: `h |f(t+h, y1) - f(t+h, ys)| / |y1 - ys|` (Euclidean norms); 0 when `y1 = ys`.
fn h_rho(h: f64, f1: &[f64], fs: &[f64], y1: &[f64], ys: &[f64]) -> f64 {
    let mut num = 0.0;
    let mut den = 0.0;
    for i in 0..y1.len() {
        num += (f1[i] - fs[i]).powi(2);
        den += (y1[i] - ys[i]).powi(2);
    }
    if den > 0.0 {
        h.abs() * (num / den).sqrt()
    } else {
        0.0
    }
}

/// `out = h * Σ_j coef_j k_j`.
fn weighted(h: f64, coef: &[f64], k: &[f64], out: &mut [f64]) {
    let n = out.len();
    out.fill(0.0);
    for (j, &c) in coef.iter().enumerate() {
        if c != 0.0 {
            for (o, &kv) in out.iter_mut().zip(&k[j * n..(j + 1) * n]) {
                *o += c * kv;
            }
        }
    }
    for o in out.iter_mut() {
        *o *= h;
    }
}

impl Integrator {
    /// Validate `options` and allocate every buffer for the state `y0` at time `t0`.
    pub fn new(options: Options, t0: f64, y0: &[f64]) -> Result<Self, SolverError> {
        let n = y0.len();
        options.validate(n)?;
        if !t0.is_finite() {
            return Err(SolverError::InvalidOptions(format!(
                "t0 must be finite, got {t0}"
            )));
        }
        if let Some(i) = first_non_finite(y0) {
            return Err(SolverError::InvalidOptions(format!(
                "initial state component {i} is not finite ({})",
                y0[i]
            )));
        }
        let tab = options.method.tableau();
        let mut atol = vec![0.0; n];
        let mut rtol = vec![0.0; n];
        if options.fixed_step.is_none() {
            broadcast(&options.atol, 0.0, &mut atol);
            broadcast(&options.rtol_scale, 1.0, &mut rtol);
            rtol.iter_mut().for_each(|r| *r *= options.rtol);
        }
        Ok(Integrator {
            tab,
            n,
            t: t0,
            y: y0.to_vec(),
            y_new: vec![0.0; n],
            ytmp: vec![0.0; n],
            k: vec![0.0; tab.slots() * n],
            err5: vec![0.0; n],
            err3: vec![0.0; n],
            atol,
            rtol,
            h_next: options.h_init.unwrap_or(0.0),
            fsal_valid: false,
            ctrl: Controller::default(),
            stats: Stats::default(),
            dense: DenseOutput::new(n, tab),
            g_old: Vec::new(),
            g_new: Vec::new(),
            g_tmp: Vec::new(),
            g_ref: Vec::new(),
            g_sus: Vec::new(),
            event_mask: Vec::new(),
            fired: Vec::new(),
            sample_grid: None,
            chatter_step: u64::MAX,
            chatter_run: 0,
            chatter_t0: 0.0,
            opts: options,
        })
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Current state.
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// Work counters.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The options in use.
    pub fn options(&self) -> &Options {
        &self.opts
    }

    /// Dimension of the state.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Step size the controller proposes for the next step (0 before the first step when the
    /// initial step is automatic).
    pub fn h_next(&self) -> f64 {
        self.h_next
    }

    /// Declares that the observer of [`Integrator::advance`] / `advance_with_events` reads the
    /// dense output only at the multiples k·dt inside a step (t_start < k·dt ≤ t_end), as a
    /// sampler at a fixed rate does; `None` (the default): anywhere. With a grid, a method
    /// whose dense output costs extra stages (DOP853: 3) builds it only for the steps that
    /// contain a grid point (or need it for an event); the steps, and the dense output of the
    /// steps that have it, are the same. A non-positive or non-finite `dt` clears the grid.
    pub fn set_sample_grid(&mut self, dt: Option<f64>) {
        self.sample_grid = dt.filter(|d| d.is_finite() && *d > 0.0);
    }

    /// True if the dense output is built lazily ([`Integrator::set_sample_grid`]; not for an
    /// FSAL method, whose stage 0 is gone after the step and whose dense output is free).
    pub(super) fn lazy_dense(&self) -> bool {
        self.sample_grid.is_some() && !self.tab.fsal
    }

    /// True if the step (t_old, t_new] holds a grid point ([`super::grid_points`]).
    pub(super) fn grid_hit(&self, t_old: f64, t_new: f64) -> bool {
        self.sample_grid
            .is_none_or(|dt| super::grid_points(dt, t_old, t_new).next().is_some())
    }

    /// Change the step budget of each call (see [`Options::max_steps`]); at least 1.
    pub fn set_max_steps(&mut self, max_steps: u64) {
        self.opts.max_steps = max_steps.max(1);
    }

    /// Change the relative tolerance (takes effect on the next step).
    pub fn set_rtol(&mut self, rtol: f64) -> Result<(), SolverError> {
        let mut o = self.opts.clone();
        o.rtol = rtol;
        o.validate(self.n)?;
        self.opts = o;
        self.refresh_tolerances();
        Ok(())
    }

    /// Change the absolute tolerances (one value, or one per component).
    pub fn set_atol(&mut self, atol: &[f64]) -> Result<(), SolverError> {
        check_atol(atol, self.n)?;
        let mut o = self.opts.clone();
        o.atol = atol.to_vec();
        o.validate(self.n)?;
        self.opts = o;
        self.refresh_tolerances();
        Ok(())
    }

    /// Change the per-component factors on `rtol` (see [`Options::rtol_scale`]).
    pub fn set_rtol_scale(&mut self, scale: &[f64]) -> Result<(), SolverError> {
        check_rtol_scale(scale, self.n)?;
        self.opts.rtol_scale = scale.to_vec();
        self.refresh_tolerances();
        Ok(())
    }

    fn refresh_tolerances(&mut self) {
        if self.opts.fixed_step.is_none() {
            broadcast(&self.opts.atol, 0.0, &mut self.atol);
            broadcast(&self.opts.rtol_scale, 1.0, &mut self.rtol);
            let r = self.opts.rtol;
            self.rtol.iter_mut().for_each(|x| *x *= r);
        }
    }

    /// The right-hand side changed discontinuously (inputs changed, mode switched): drop the
    /// FSAL stage so the next step re-evaluates `f(t, y)`.
    /// With [`Options::restart_after_discontinuity`] the controller also restarts.
    pub fn discontinuity(&mut self) {
        self.fsal_valid = false;
        if self.opts.restart_after_discontinuity && self.opts.fixed_step.is_none() {
            self.restart_controller();
        }
    }

    /// Forget the proposed step and the PI memory: the next step starts with a fresh automatic
    /// initial step (one extra RHS evaluation, plus `f(t, y)` if not yet known).
    pub(super) fn restart_controller(&mut self) {
        self.h_next = 0.0;
        self.ctrl = Controller::default();
    }

    /// Change the step-size controller settings (`safety`, `fac_min`, `fac_max`, `pi_beta`,
    /// `restart_after_discontinuity`, `observed_order_on_reject` of `c`; its other fields are
    /// ignored). Validated like
    /// [`Integrator::new`]; takes effect on the next step.
    pub fn set_step_control(&mut self, c: &Options) -> Result<(), SolverError> {
        let mut o = self.opts.clone();
        o.safety = c.safety;
        o.fac_min = c.fac_min;
        o.fac_max = c.fac_max;
        o.pi_beta = c.pi_beta;
        o.restart_after_discontinuity = c.restart_after_discontinuity;
        o.observed_order_on_reject = c.observed_order_on_reject;
        o.validate(self.n)?;
        self.opts = o;
        Ok(())
    }

    /// Replace the state (drops the FSAL stage and the event memory; keeps the proposed step).
    /// Components of `y` beyond the dimension are ignored, missing ones keep their value; use
    /// [`Integrator::try_set_state`] to have that checked.
    pub fn set_state(&mut self, t: f64, y: &[f64]) {
        let m = y.len().min(self.n);
        self.y[..m].copy_from_slice(&y[..m]);
        self.t = t;
        self.fsal_valid = false;
        self.event_mask.clear();
        self.reset_chatter();
    }

    /// [`Integrator::set_state`] with checks of the length and finiteness.
    pub fn try_set_state(&mut self, t: f64, y: &[f64]) -> Result<(), SolverError> {
        if y.len() != self.n {
            return Err(SolverError::DimensionMismatch {
                expected: self.n,
                found: y.len(),
            });
        }
        if !t.is_finite() || first_non_finite(y).is_some() {
            return Err(SolverError::InvalidOptions("state must be finite".into()));
        }
        self.set_state(t, y);
        Ok(())
    }

    /// Serializable full solver state.
    pub fn snapshot(&self) -> IntegratorState {
        IntegratorState {
            method: self.opts.method,
            t: self.t,
            y: self.y.clone(),
            h_next: self.h_next,
            fsal: if self.fsal_valid {
                self.k[..self.n].to_vec()
            } else {
                Vec::new()
            },
            fsal_valid: self.fsal_valid,
            err_old: self.ctrl.err_old,
            last_rejected: self.ctrl.last_rejected,
            event_mask: self.event_mask.clone(),
            stats: self.stats,
        }
    }

    /// Copies the state into `c` (no allocation once `c` has held a state of this dimension).
    pub fn checkpoint(&self, c: &mut Checkpoint) {
        c.t = self.t;
        c.y.clear();
        c.y.extend_from_slice(&self.y);
        c.h_next = self.h_next;
        c.fsal_valid = self.fsal_valid;
        // Room for the FSAL stage even when it is not valid now, so that a later checkpoint
        // holding it does not allocate.
        c.fsal.clear();
        c.fsal.reserve(self.n);
        if self.fsal_valid {
            c.fsal.extend_from_slice(&self.k[..self.n]);
        }
        c.ctrl = self.ctrl;
        c.event_mask.clear();
        c.event_mask.extend_from_slice(&self.event_mask);
        c.stats = self.stats;
    }

    /// Puts the state back to `c` (taken from this integrator): the next step is the one that
    /// would have followed the checkpoint, and the work counters are those of the checkpoint
    /// (read [`Integrator::stats`] before to know the work done since). The options stay as
    /// they are. No allocation.
    pub fn rollback(&mut self, c: &Checkpoint) {
        debug_assert_eq!(c.y.len(), self.n, "a checkpoint of another integrator");
        self.t = c.t;
        self.y.copy_from_slice(&c.y);
        self.h_next = c.h_next;
        self.fsal_valid = c.fsal_valid;
        if c.fsal_valid {
            self.k[..self.n].copy_from_slice(&c.fsal);
        }
        self.ctrl = c.ctrl;
        self.event_mask.clear();
        self.event_mask.extend_from_slice(&c.event_mask);
        self.stats = c.stats;
        self.reset_chatter();
    }

    /// Restore a snapshot (same method and dimension; the options stay those of `self`).
    pub fn restore(&mut self, s: &IntegratorState) -> Result<(), SolverError> {
        if s.method != self.opts.method {
            return Err(SolverError::method_mismatch(self.opts.method, s.method));
        }
        if s.y.len() != self.n || (s.fsal_valid && s.fsal.len() != self.n) {
            return Err(SolverError::StateMismatch(format!(
                "snapshot has dimension {}, integrator has {}",
                s.y.len(),
                self.n
            )));
        }
        if !s.t.is_finite()
            || first_non_finite(&s.y).is_some()
            || s.h_next.is_nan()
            || s.h_next < 0.0
        {
            return Err(SolverError::StateMismatch("snapshot is not finite".into()));
        }
        self.t = s.t;
        self.y.copy_from_slice(&s.y);
        self.h_next = s.h_next;
        self.fsal_valid = s.fsal_valid;
        if s.fsal_valid {
            self.k[..self.n].copy_from_slice(&s.fsal);
        }
        self.ctrl.err_old = s.err_old;
        self.ctrl.last_rejected = s.last_rejected;
        self.event_mask.clone_from(&s.event_mask);
        self.stats = s.stats;
        self.reset_chatter();
        Ok(())
    }

    pub(super) fn check_target(&self, dim: usize, t_end: f64) -> Result<(), SolverError> {
        if dim != self.n {
            return Err(SolverError::DimensionMismatch {
                expected: self.n,
                found: dim,
            });
        }
        if !t_end.is_finite() || t_end < self.t {
            return Err(SolverError::InvalidTarget { t: self.t, t_end });
        }
        Ok(())
    }

    /// Integrate to exactly `t_end` (the last step is shortened to land on it; the un-shortened
    /// proposed step size is retained for the next call, and the FSAL stage is kept).
    /// `observer` (if given) is called after every accepted step with a view that can
    /// interpolate the dense output anywhere in `[t_old, t_new]`. On error, [`Integrator::t`] /
    /// [`Integrator::y`] stay at the last accepted step.
    pub fn advance<S: System + ?Sized>(
        &mut self,
        sys: &mut S,
        t_end: f64,
        mut observer: Option<&mut dyn FnMut(&StepView)>,
    ) -> Result<(), SolverError> {
        self.check_target(sys.dim(), t_end)?;
        let lazy = observer.is_some() && self.lazy_dense();
        let want_dense = observer.is_some() && !lazy;
        let mut attempts = 0u64;
        while self.t < t_end {
            let t_old = self.step(sys, t_end, want_dense, &mut attempts)?;
            if lazy && self.grid_hit(t_old, self.t) {
                self.dense_after_step(sys, t_old);
            }
            if let Some(obs) = observer.as_mut() {
                let view = StepView {
                    dense: &self.dense,
                    t_start: t_old,
                    t_end: self.t,
                    y_end: &self.y,
                };
                obs(&view);
            }
        }
        Ok(())
    }

    /// Smallest step the controller may propose at the current time (see [`Options::h_min`]).
    pub(super) fn h_floor(&self) -> f64 {
        let at = self.t.abs();
        (self.opts.h_min * at.max(1.0)).max(4.0 * f64::EPSILON * at)
    }

    /// Make slot 0 hold `f(t, y)`.
    fn ensure_fsal<S: System + ?Sized>(&mut self, sys: &mut S) -> Result<(), SolverError> {
        if !self.fsal_valid {
            let n = self.n;
            sys.rhs(self.t, &self.y, &mut self.k[..n]);
            self.stats.rhs_evals += 1;
            if let Some(i) = first_non_finite(&self.k[..n]) {
                return Err(SolverError::NonFinite {
                    t: self.t,
                    component: i,
                    derivative: true,
                });
            }
            self.fsal_valid = true;
        }
        Ok(())
    }

    fn initial_h<S: System + ?Sized>(&mut self, sys: &mut S, t_end: f64) -> f64 {
        let n = self.n;
        let t = self.t;
        let mut evals = 0;
        let h = initial_step(
            self.tab.err_order + 1,
            &self.y,
            &self.k[..n],
            &self.atol,
            &self.rtol,
            self.opts.h_max,
            &mut self.ytmp,
            &mut self.err5,
            |h, y1, f1| {
                evals += 1;
                sys.rhs(t + h, y1, f1)
            },
        );
        self.stats.rhs_evals += evals;
        let dist = t_end - t;
        let h = if dist > 0.0 { h.min(dist) } else { h };
        h.max(self.h_floor())
    }

    /// Main stages of a step of size `h` ending at `t_new`; fills `y_new`.
    fn stages<S: System + ?Sized>(&mut self, sys: &mut S, h: f64, t_new: f64) {
        let n = self.n;
        let tab = self.tab;
        for s in 1..tab.stages {
            let (done, rest) = self.k.split_at_mut(s * n);
            let ks = &mut rest[..n];
            if tab.fsal && s == tab.stages - 1 {
                combine(&self.y, h, tab.b, done, &mut self.y_new);
                sys.rhs(t_new, &self.y_new, ks);
            } else {
                combine(&self.y, h, tab.a[s], done, &mut self.ytmp);
                sys.rhs(self.t + tab.c[s] * h, &self.ytmp, ks);
            }
        }
        self.stats.rhs_evals += (tab.stages - 1) as u64;
        if !tab.fsal {
            combine(&self.y, h, tab.b, &self.k, &mut self.y_new);
        }
    }

    /// What limited the attempt of size `h` just rejected with error norm `err` (its stages,
    /// trial state and error vector are still in the buffers): the first stage whose derivative
    /// is non-finite, else a non-finite trial state, else the largest weighted error component.
    /// Only on the failure path.
    fn step_limit(&self, h: f64, err: f64) -> StepLimit {
        let n = self.n;
        if !err.is_finite() {
            // Slot 0 is f(t, y), finite (checked when computed).
            for s in 1..self.tab.stages {
                if let Some(i) = first_non_finite(&self.k[s * n..(s + 1) * n]) {
                    return StepLimit::NonFiniteDerivative {
                        component: i,
                        t: self.t + self.tab.c[s] * h,
                    };
                }
            }
            if let Some(i) = first_non_finite(&self.y_new) {
                return StepLimit::NonFiniteState { component: i };
            }
        }
        let (component, ratio) =
            largest_weighted_error(&self.y, &self.y_new, &self.atol, &self.rtol, &self.err5);
        StepLimit::Error { component, ratio }
    }

    /// Error norm of the step just computed.
    fn error(&mut self, h: f64) -> f64 {
        let tab = self.tab;
        weighted(h, tab.e, &self.k, &mut self.err5);
        let e3 = if tab.e3.is_empty() {
            None
        } else {
            weighted(h, tab.e3, &self.k, &mut self.err3);
            Some(&self.err3[..])
        };
        error_norm(&self.y, &self.y_new, &self.atol, &self.rtol, &self.err5, e3)
    }

    /// End derivative (if not yet computed) and extra stages, then the dense coefficients.
    fn prepare_dense<S: System + ?Sized>(&mut self, sys: &mut S, h: f64, t_new: f64) {
        let n = self.n;
        let tab = self.tab;
        let end = tab.end_slot();
        if !tab.fsal {
            sys.rhs(t_new, &self.y_new, &mut self.k[end * n..(end + 1) * n]);
            self.stats.rhs_evals += 1;
            // `ytmp` still holds the input of the last main stage (c = 1).
            let last = tab.stages - 1;
            if tab.stiff_bound > 0.0 && tab.c[last] == 1.0 {
                let r = h_rho(
                    h,
                    &self.k[end * n..(end + 1) * n],
                    &self.k[last * n..(last + 1) * n],
                    &self.y_new,
                    &self.ytmp,
                );
                if r > tab.stiff_bound {
                    self.stats.stiff_steps += 1;
                }
            }
        }
        for s in end + 1..tab.slots() {
            let (done, rest) = self.k.split_at_mut(s * n);
            combine(&self.y, h, tab.a[s], done, &mut self.ytmp);
            sys.rhs(self.t + tab.c[s] * h, &self.ytmp, &mut rest[..n]);
            self.stats.rhs_evals += 1;
        }
        self.dense
            .build(tab, self.t, h, &self.y, &self.y_new, &self.k);
    }

    /// Builds the dense output of the step just accepted by [`Integrator::step`] without it
    /// (`self.y` its end, `self.y_new` its start, the stages still in `self.k`): what a step with
    /// `want_dense` would have built, and slot 0 then holds `f(t, y)` as after such a step.
    /// A method whose stage 0 was already overwritten (FSAL) always builds its dense output.
    pub(super) fn dense_after_step<S: System + ?Sized>(&mut self, sys: &mut S, t_old: f64) {
        let t_new = self.t;
        // The step's own size (t_new − t_old may differ from it by round-off).
        let h = self.stats.h_last;
        std::mem::swap(&mut self.y, &mut self.y_new);
        self.t = t_old;
        self.prepare_dense(sys, h, t_new);
        std::mem::swap(&mut self.y, &mut self.y_new);
        self.t = t_new;
        let e = self.tab.end_slot() * self.n;
        self.k.copy_within(e..e + self.n, 0);
        self.fsal_valid = true;
    }

    /// Take one accepted step towards `t_end` (retrying rejected attempts). Returns the start time
    /// of the accepted step; `self.t`/`self.y` are its end. With `want_dense` the dense output of
    /// the step is built.
    pub(super) fn step<S: System + ?Sized>(
        &mut self,
        sys: &mut S,
        t_end: f64,
        want_dense: bool,
        attempts: &mut u64,
    ) -> Result<f64, SolverError> {
        self.ensure_fsal(sys)?;
        let fixed = self.opts.fixed_step;
        if fixed.is_none() && (self.h_next.is_nan() || self.h_next <= 0.0) {
            self.h_next = self.initial_h(sys, t_end);
        }
        loop {
            if *attempts >= self.opts.max_steps {
                return Err(SolverError::StepBudget {
                    t: self.t,
                    steps: *attempts,
                });
            }
            *attempts += 1;
            let (h_prop, stretch) = match fixed {
                Some(h) => (h, 1.0 + 1e-9),
                None => (self.h_next.min(self.opts.h_max), 1.01),
            };
            let dist = t_end - self.t;
            let last = h_prop * stretch >= dist;
            let h = if last { dist } else { h_prop };
            let t_new = if last { t_end } else { self.t + h };
            if t_new == self.t {
                return Err(SolverError::StepSizeUnderflow {
                    t: self.t,
                    h,
                    h_min: self.h_floor(),
                    limit: StepLimit::Unknown,
                });
            }
            sys.begin_step();
            self.stages(sys, h, t_new);
            let bad = first_non_finite(&self.y_new);
            if fixed.is_some() {
                if let Some(i) = bad {
                    return Err(SolverError::NonFinite {
                        t: self.t,
                        component: i,
                        derivative: false,
                    });
                }
            } else {
                let err = if bad.is_some() {
                    f64::INFINITY
                } else {
                    self.error(h)
                };
                if err.is_nan() || err > 1.0 {
                    self.stats.rejected += 1;
                    let h_new = self.ctrl.reject(self.tab, &self.opts, h, err);
                    if h_new < self.h_floor() {
                        return Err(SolverError::StepSizeUnderflow {
                            t: self.t,
                            h: h_new,
                            h_min: self.h_floor(),
                            limit: self.step_limit(h, err),
                        });
                    }
                    self.h_next = h_new;
                    continue;
                }
                let h_new = self
                    .ctrl
                    .accept(self.tab, &self.opts, h, err)
                    .min(self.opts.h_max);
                // A step shortened to land keeps the un-shortened proposal unless the controller
                // wants to shrink even the shortened step.
                self.h_next = if last && h < h_prop && h_new >= h {
                    h_prop
                } else {
                    h_new
                };
            }
            self.stats.record_accepted(h);
            if fixed.is_none() && self.tab.fsal && self.tab.stiff_bound > 0.0 {
                // FSAL: slot `stages-1` is f(t+h, y_new), slot `stages-2` the last main stage
                // (c = 1) evaluated at `ytmp`.
                let (n, s) = (self.n, self.tab.stages);
                if self.tab.c[s - 2] == 1.0 {
                    let r = h_rho(
                        h,
                        &self.k[(s - 1) * n..s * n],
                        &self.k[(s - 2) * n..(s - 1) * n],
                        &self.y_new,
                        &self.ytmp,
                    );
                    if r > self.tab.stiff_bound {
                        self.stats.stiff_steps += 1;
                    }
                }
            }
            let t_old = self.t;
            if want_dense {
                self.prepare_dense(sys, h, t_new);
            }
            std::mem::swap(&mut self.y, &mut self.y_new);
            self.t = t_new;
            if self.tab.fsal || want_dense {
                let e = self.tab.end_slot() * self.n;
                self.k.copy_within(e..e + self.n, 0);
                self.fsal_valid = true;
            } else {
                self.fsal_valid = false;
            }
            self.event_mask.clear();
            return Ok(t_old);
        }
    }
}

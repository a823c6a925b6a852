//! Integration tests of the RK engine against closed forms (no stored outputs).

use raceway_solver::*;
use std::f64::consts::PI;

// ---------------------------------------------------------------- test systems

/// Kepler problem, GM = 1.
struct Kepler;
impl System for Kepler {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r3 = r2 * r2.sqrt();
        d[0] = y[2];
        d[1] = y[3];
        d[2] = -y[0] / r3;
        d[3] = -y[1] / r3;
    }
}

/// Kepler orbit with semi-major axis 1 starting at pericentre: closed form via Kepler's equation.
fn kepler_exact(e: f64, t: f64) -> [f64; 4] {
    let mut ea = t;
    for _ in 0..60 {
        ea -= (ea - e * ea.sin() - t) / (1.0 - e * ea.cos());
    }
    let s = (1.0 - e * e).sqrt();
    let d = 1.0 - e * ea.cos();
    [ea.cos() - e, s * ea.sin(), -ea.sin() / d, s * ea.cos() / d]
}

/// Harmonic oscillator x'' = -w^2 x as [x, v].
struct Osc {
    w: f64,
}
impl System for Osc {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
        d[0] = y[1];
        d[1] = -self.w * self.w * y[0];
    }
}

/// Restricted three-body problem of Hairer's Arenstorf orbit.
struct Arenstorf;
const MU: f64 = 0.012277471;
impl System for Arenstorf {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
        let mu1 = 1.0 - MU;
        let d1 = ((y[0] + MU).powi(2) + y[1] * y[1]).powf(1.5);
        let d2 = ((y[0] - mu1).powi(2) + y[1] * y[1]).powf(1.5);
        d[0] = y[2];
        d[1] = y[3];
        d[2] = y[0] + 2.0 * y[3] - mu1 * (y[0] + MU) / d1 - MU * (y[0] - mu1) / d2;
        d[3] = y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - MU * y[1] / d2;
    }
}
#[allow(clippy::excessive_precision)]
const ARENSTORF_Y0: [f64; 4] = [0.994, 0.0, 0.0, -2.00158510637908252240537862224];
#[allow(clippy::excessive_precision)]
const ARENSTORF_T: f64 = 17.0652165601579625588917206249;

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Least-squares slope of log(err) against log(h).
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for &(h, e) in points {
        let (x, y) = (h.ln(), e.ln());
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    (n * sxy - sx * sy) / (n * sxx - sx * sx)
}

// ---------------------------------------------------------------- 1. order of convergence

/// Fixed-step global error at t = 5 (DOP853: t = 20) on a Kepler orbit (e = 0.1) against the closed form; the
/// step counts per method are chosen in each method's asymptotic range, above round-off.
#[test]
fn observed_order_of_convergence() {
    let e = 0.1;
    let y0 = kepler_exact(e, 0.0);
    let cases: [(Method, f64, &[usize]); 4] = [
        (Method::Rkf45, 5.0, &[90, 128, 181, 256, 362, 512]),
        (Method::Dopri5, 5.0, &[128, 181, 256, 362, 512]),
        (Method::Dop853, 20.0, &[128, 160, 200, 256]),
        (Method::Rk4, 5.0, &[128, 181, 256, 362, 512, 724]),
    ];
    for (m, t_end, ns) in cases {
        let exact = kepler_exact(e, t_end);
        let pts: Vec<(f64, f64)> = ns
            .iter()
            .map(|&n| {
                let h = t_end / n as f64;
                let mut it = Integrator::new(Options::fixed(m, h), 0.0, &y0).unwrap();
                it.advance(&mut Kepler, t_end, None).unwrap();
                assert_eq!(it.stats().steps, n as u64, "{m}");
                (h, max_diff(it.y(), &exact))
            })
            .collect();
        let p = slope(&pts);
        let nominal = m.order() as f64;
        assert!(
            (p - nominal).abs() <= 0.3,
            "{m}: observed order {p:.3}, nominal {nominal}; errors {pts:?}"
        );
    }
}

// ---------------------------------------------------------------- 2. Arenstorf orbit

/// The Arenstorf orbit closes after one period. Measured final errors at rtol = atol = 1e-10:
/// RKF45 1.4e-5, DOPRI5 3.3e-6, DOP853 1.3e-6 (the close lunar passages amplify local errors by
/// ~1e4). Bounds are the measured values with a margin of about 3-7x.
#[test]
fn arenstorf_orbit_closes() {
    let mut steps = Vec::new();
    for (m, bound) in [
        (Method::Rkf45, 1e-4),
        (Method::Dopri5, 2e-5),
        (Method::Dop853, 1e-5),
    ] {
        let mut it =
            Integrator::new(Options::new(m, 1e-10, vec![1e-10]), 0.0, &ARENSTORF_Y0).unwrap();
        it.advance(&mut Arenstorf, ARENSTORF_T, None).unwrap();
        assert_eq!(it.t(), ARENSTORF_T);
        let err = max_diff(it.y(), &ARENSTORF_Y0);
        assert!(err < bound, "{m}: error {err:e} >= {bound:e}");
        steps.push(it.stats().rhs_evals);
    }
    // The 8th-order method needs the fewest right-hand sides at this tolerance.
    assert!(steps[2] < steps[1] && steps[2] < steps[0], "{steps:?}");
}

// ---------------------------------------------------------------- 3. stability threshold

/// Imaginary-axis reach from the stability polynomial of the tableau, then a fixed-step
/// oscillator at 0.98 and 1.02 times h_crit = reach / w: bounded below, growing above.
#[test]
fn fixed_step_stability_threshold() {
    let w = 2.0 * PI * 1000.0;
    for (m, expected) in [(Method::Rk4, Some(8f64.sqrt())), (Method::Dop853, None)] {
        let reach = m.tableau().imaginary_stability_reach(1e-12, 1e-3, 20.0);
        if let Some(x) = expected {
            assert!((reach - x).abs() < 1e-9, "{m}: {reach}");
        } else {
            // Hairer's DOP853 reaches about 6 on the imaginary axis (docs/model.md#methods).
            assert!((5.5..6.5).contains(&reach), "{m}: {reach}");
        }
        let h_crit = reach / w;
        // amplitude after 2000 steps; overflow (NonFinite) counts as unbounded growth
        let amp = |factor: f64| {
            let h = factor * h_crit;
            let mut it = Integrator::new(Options::fixed(m, h), 0.0, &[1.0, 0.0]).unwrap();
            match it.advance(&mut Osc { w }, h * 2000.0, None) {
                Ok(()) => {
                    let y = it.y();
                    (y[0] * y[0] + (y[1] / w).powi(2)).sqrt()
                }
                Err(SolverError::NonFinite { .. }) => f64::INFINITY,
                Err(e) => panic!("{e}"),
            }
        };
        let below = amp(0.98);
        let above = amp(1.02);
        assert!(below <= 1.0, "{m}: amplitude {below} at 0.98 h_crit");
        assert!(above > 1e6, "{m}: amplitude {above} at 1.02 h_crit");
    }
}

// ---------------------------------------------------------------- 4. events

/// y' = 1 with one event g = t - t_e (and a bystander that never fires).
struct Clock {
    t_e: f64,
    seen: Vec<f64>,
}
impl System for Clock {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, _y: &[f64], d: &mut [f64]) {
        d[0] = (3.0 * t).cos();
    }
}
impl EventSystem for Clock {
    fn n_events(&self) -> usize {
        2
    }
    fn events(&mut self, t: f64, _y: &[f64], g: &mut [f64]) {
        g[0] = t - self.t_e;
        g[1] = 1.0;
    }
    fn handle_event(&mut self, index: usize, t: f64, _y: &mut [f64]) -> EventAction {
        assert_eq!(index, 0);
        self.seen.push(t);
        EventAction::Continue
    }
}

#[test]
fn event_time_located_to_1e_12() {
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        let t_e = PI / 7.0 + 1e-3 * 2f64.sqrt();
        let mut sys = Clock {
            t_e,
            seen: Vec::new(),
        };
        let mut it = Integrator::new(Options::new(m, 1e-6, vec![1e-6]), 0.0, &[0.0]).unwrap();
        let out = it.advance_with_events(&mut sys, 2.0, None).unwrap();
        assert_eq!(out, AdvanceOutcome::Reached);
        assert_eq!(sys.seen.len(), 1, "{m}");
        assert!(
            (sys.seen[0] - t_e).abs() < 1e-12,
            "{m}: {}",
            sys.seen[0] - t_e
        );
        assert_eq!(it.t(), 2.0);
        assert_eq!(it.stats().events, 1);
        // the state is still the smooth solution y = sin(3t)/3 (event landed without a kink)
        assert!((it.y()[0] - (6.0f64).sin() / 3.0).abs() < 1e-5);
    }
}

/// Oscillator x = cos t crossing the level 0.3: roots at ±acos(0.3) + 2πk.
struct Level {
    times: Vec<f64>,
}
impl System for Level {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
        d[0] = y[1];
        d[1] = -y[0];
    }
}
impl EventSystem for Level {
    fn n_events(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0] - 0.3;
    }
    fn handle_event(&mut self, _i: usize, t: f64, _y: &mut [f64]) -> EventAction {
        self.times.push(t);
        EventAction::Continue
    }
}

#[test]
fn level_crossings_of_oscillator_match_closed_form() {
    let a = 0.3f64.acos();
    let mut exact = Vec::new();
    for k in 0..4 {
        let base = 2.0 * PI * k as f64;
        exact.extend([base + a, base + 2.0 * PI - a]);
    }
    exact.retain(|&t| t < 20.0);
    for (m, tol) in [(Method::Dop853, 1e-9), (Method::Dopri5, 1e-7)] {
        let mut sys = Level { times: Vec::new() };
        let mut it =
            Integrator::new(Options::new(m, 1e-12, vec![1e-12]), 0.0, &[1.0, 0.0]).unwrap();
        // many communication points to also exercise event state across calls
        for i in 1..=40 {
            it.advance_with_events(&mut sys, 0.5 * i as f64, None)
                .unwrap();
        }
        assert_eq!(sys.times.len(), exact.len(), "{m}: {:?}", sys.times);
        for (t, te) in sys.times.iter().zip(&exact) {
            assert!((t - te).abs() < tol, "{m}: {t} vs {te}");
        }
    }
}

/// Bouncing ball (x'' = -g, impact at x = 0 reverses v with restitution r), exact impact times
/// t_1 = sqrt(2 H / g), t_{k+1} = t_k + 2 r^k v_1 / g. Stops after `max_bounces`.
struct Ball {
    g: f64,
    r: f64,
    bounces: usize,
    max_bounces: usize,
    times: Vec<f64>,
}
impl System for Ball {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, _y: &[f64], d: &mut [f64]) {
        d[0] = _y[1];
        d[1] = -self.g;
    }
}
impl EventSystem for Ball {
    fn n_events(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
    fn handle_event(&mut self, _i: usize, t: f64, y: &mut [f64]) -> EventAction {
        self.times.push(t);
        self.bounces += 1;
        y[1] *= -self.r;
        if self.bounces >= self.max_bounces {
            EventAction::Stop
        } else {
            EventAction::Continue
        }
    }
}

#[test]
fn bouncing_ball_impacts_and_stop() {
    let (g, r, h0): (f64, f64, f64) = (9.81, 0.8, 2.0);
    let t1 = (2.0 * h0 / g).sqrt();
    let v1 = g * t1;
    let mut exact = vec![t1];
    for k in 1..8 {
        let last = *exact.last().unwrap();
        exact.push(last + 2.0 * r.powi(k) * v1 / g);
    }
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        let mut ball = Ball {
            g,
            r,
            bounces: 0,
            max_bounces: 8,
            times: Vec::new(),
        };
        let mut it = Integrator::new(Options::new(m, 1e-8, vec![1e-8]), 0.0, &[h0, 0.0]).unwrap();
        let mut outcome = AdvanceOutcome::Reached;
        let mut t = 0.0;
        while outcome == AdvanceOutcome::Reached {
            t += 0.37;
            outcome = it.advance_with_events(&mut ball, t, None).unwrap();
        }
        let AdvanceOutcome::Stopped { t: ts, index } = outcome else {
            unreachable!()
        };
        assert_eq!(index, 0);
        assert_eq!(ts, it.t());
        assert_eq!(ball.times.len(), 8, "{m}: {:?}", ball.times);
        for (k, (t, te)) in ball.times.iter().zip(&exact).enumerate() {
            assert!((t - te).abs() < 1e-12, "{m}: bounce {k}: {t} vs {te}");
        }
        // after the stop, the ball is at the floor moving up with r^8 v1
        assert!(it.y()[0].abs() < 1e-11);
        assert!((it.y()[1] - r.powi(8) * v1).abs() < 1e-9);
        // resuming does not re-fire the event at the floor
        ball.max_bounces = 100;
        let before = ball.times.len();
        it.advance_with_events(&mut ball, ts + 0.01, None).unwrap();
        assert_eq!(ball.times.len(), before, "{m}");
    }
}

/// Zeno: a ball bouncing with restitution r = 0.8 comes to rest at t* = t_1 (1 + r)/(1 − r) after
/// infinitely many bounces, t_k = t_1 + Σ_{j<k} 2 r^j v_1 / g. Steps are at most h_max = 1 ms (a
/// parabola is exact for the method, so that bound sets them). With the guard on (50 steps ending
/// in an event, each within 3 steps of the one before) the call stops with
/// [`SolverError::Chattering`] at a bounce time, every one of the 50 flights of the run at most
/// 3 h_max long, before t*. Off (the default), or with a span shorter than those 50 flights, it
/// goes on past that bounce (and a later stop's run fits in the span).
#[test]
fn zeno_guard_stops_a_chattering_call_at_a_bounce() {
    let (g, r, h0): (f64, f64, f64) = (9.81, 0.8, 2.0);
    let t1 = (2.0 * h0 / g).sqrt();
    let v1 = g * t1;
    let t_star = t1 * (1.0 + r) / (1.0 - r);
    let flight = |j: i32| 2.0 * r.powi(j) * v1 / g;
    let bounce = |k: i32| t1 + (1..k).map(flight).sum::<f64>();
    let h_max = 1e-3;
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        // To t* with the guard's settings; with `pause`, first to that time and the state put
        // back there (rollback to a checkpoint taken there).
        let run_paused = |guard: u32, span: f64, pause: Option<f64>| {
            let mut ball = Ball {
                g,
                r,
                bounces: 0,
                max_bounces: usize::MAX,
                times: Vec::new(),
            };
            let mut o = Options::new(m, 1e-10, vec![1e-12]);
            o.h_max = h_max;
            o.chatter_events = guard;
            o.chatter_span = span;
            let mut it = Integrator::new(o, 0.0, &[h0, 0.0]).unwrap();
            if let Some(tp) = pause {
                let first = it.advance_with_events(&mut ball, tp, None);
                assert_eq!(first, Ok(AdvanceOutcome::Reached), "{m}");
                let mut c = Checkpoint::default();
                it.checkpoint(&mut c);
                it.rollback(&c);
            }
            let e = it.advance_with_events(&mut ball, t_star, None);
            (e, ball.times)
        };
        let run = |guard: u32, span: f64| run_paused(guard, span, None);
        let mut o = Options::new(m, 1e-10, vec![1e-12]);
        o.chatter_span = f64::NAN;
        let bad = Integrator::new(o, 0.0, &[h0, 0.0]).unwrap_err().to_string();
        assert!(bad.contains("chatter_span"), "{bad}");
        let (e, times) = run(50, f64::INFINITY);
        let Err(SolverError::Chattering {
            t, index, events, ..
        }) = e
        else {
            panic!("{m}: {e:?} after {} bounces", times.len());
        };
        assert_eq!((index, events), (0, 50), "{m}");
        // the stopping event is not handled: it is bounce k = len + 1
        let k = times.len() as i32 + 1;
        assert!(
            (t - bounce(k)).abs() < 1e-9 && t < t_star,
            "{m}: {t} vs {}",
            bounce(k)
        );
        assert!(
            flight(k - 50) <= 3.0 * h_max,
            "{m}: flight {}",
            flight(k - 50)
        );
        let msg = e.unwrap_err().to_string();
        assert!(
            msg.contains("50 steps") && msg.contains("event function 0"),
            "{msg}"
        );
        let span = bounce(k) - bounce(k - 49);
        let (e, more) = run(0, f64::INFINITY);
        assert!(
            !matches!(e, Err(SolverError::Chattering { .. })) && more.len() > times.len() + 1,
            "{m}: {e:?} after {} bounces",
            more.len()
        );
        // A span that holds the run: the same stop.
        let (e2, times2) = run(50, 2.0 * span);
        assert!(
            matches!(e2, Err(SolverError::Chattering { t: t2, .. }) if t2 == t)
                && times2.len() == times.len(),
            "{m}: {e2:?}"
        );
        // A state put back (rollback) starts the count afresh: stopped in the flight before
        // bounce k − 40 (inside the run) and put back, the stop comes 49 bounces after that
        // bounce, at k + 9.
        let t_mid = 0.5 * (bounce(k - 41) + bounce(k - 40));
        let (again, after) = run_paused(50, f64::INFINITY, Some(t_mid));
        assert!(
            matches!(again, Err(SolverError::Chattering { .. })),
            "{m}: {again:?}"
        );
        assert_eq!(after.len(), times.len() + 9, "{m}");
        // A shorter span: past bounce k, and a later stop fits in it.
        let (e, more) = run(50, 0.5 * span);
        assert!(
            more.len() > times.len() + 1,
            "{m}: {e:?} after {} bounces",
            more.len()
        );
        if let Err(SolverError::Chattering { span: s, .. }) = e {
            assert!(s <= 0.5 * span, "{m}: {s} > {}", 0.5 * span);
        }
    }
}

/// Relay with a discrete mode: heating y' = +1 until y = 1, cooling y' = -2 until y = 0. The mode
/// only changes in handle_event; events are functions of the frozen mode. Exact switch times
/// 1, 1.5, 2.5, 3, 4, 4.5, ...
struct Relay {
    heating: bool,
    switches: Vec<f64>,
    rhs_modes_ok: bool,
    mode_at_step: Option<bool>,
}
impl System for Relay {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, _y: &[f64], d: &mut [f64]) {
        if let Some(m) = self.mode_at_step {
            self.rhs_modes_ok &= m == self.heating;
        }
        d[0] = if self.heating { 1.0 } else { -2.0 };
    }
}
impl EventSystem for Relay {
    fn n_events(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = if self.heating { y[0] - 1.0 } else { y[0] };
    }
    fn handle_event(&mut self, _i: usize, t: f64, _y: &mut [f64]) -> EventAction {
        self.switches.push(t);
        self.heating = !self.heating;
        self.mode_at_step = Some(self.heating);
        EventAction::Continue
    }
}

#[test]
fn mode_switching_events_with_frozen_mode() {
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        let mut sys = Relay {
            heating: true,
            switches: Vec::new(),
            rhs_modes_ok: true,
            mode_at_step: Some(true),
        };
        let mut it = Integrator::new(Options::new(m, 1e-8, vec![1e-8]), 0.0, &[0.0]).unwrap();
        it.advance_with_events(&mut sys, 9.8, None).unwrap();
        let mut exact = Vec::new();
        for k in 0..7 {
            exact.extend([1.0 + 1.5 * k as f64, 1.5 + 1.5 * k as f64]);
        }
        exact.retain(|&t| t <= 9.8);
        assert_eq!(sys.switches.len(), exact.len(), "{m}: {:?}", sys.switches);
        for (t, te) in sys.switches.iter().zip(&exact) {
            assert!((t - te).abs() < 1e-12, "{m}: {t} vs {te}");
        }
        assert!(sys.rhs_modes_ok);
        // final state on the exact saw-tooth: heating since the switch at t = 9
        assert!((it.y()[0] - 0.8).abs() < 1e-11, "{m}: {}", it.y()[0]);
        // every step is polynomial in the frozen mode: nothing to reject
        assert_eq!(it.stats().rejected, 0, "{m}");
    }
}

// ---------------------------------------------------------------- 5. forced failure

struct Blowup;
impl System for Blowup {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
        d[0] = y[0] * y[0];
    }
}

#[test]
fn singularity_fails_fast_with_clear_error() {
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        let start = std::time::Instant::now();
        let mut it = Integrator::new(Options::new(m, 1e-6, vec![1e-6]), 0.0, &[1.0]).unwrap();
        let err = it.advance(&mut Blowup, 2.0, None).unwrap_err();
        let wall = start.elapsed().as_secs_f64();
        assert!(wall < 1.0, "{m}: took {wall} s");
        assert!(
            matches!(
                err,
                SolverError::StepSizeUnderflow { .. } | SolverError::NonFinite { .. }
            ),
            "{m}: {err:?}"
        );
        // The numerical solution's own blow-up time is shifted from 1 by its global error
        // (measured: DOP853 at 1 + 1.1e-7 with rtol 1e-6), so the last good time is near 1.
        let t = it.t();
        assert!((t - 1.0).abs() < 1e-5, "{m}: stopped at {t}");
        // the state is the last accepted step, far up the blow-up y = 1/(1-t)
        assert!(it.y()[0] > 1e3, "{m}: {}", it.y()[0]);
        assert!(!err.to_string().is_empty());
        // the error reports the time of the last good step
        if let SolverError::StepSizeUnderflow { t: te, .. } = err {
            assert_eq!(te, t);
        }
    }
}

#[test]
fn step_budget_and_bad_input_do_not_panic() {
    let mut o = Options::new(Method::Dop853, 1e-10, vec![1e-10]);
    o.max_steps = 20;
    let mut it = Integrator::new(o, 0.0, &ARENSTORF_Y0).unwrap();
    let err = it.advance(&mut Arenstorf, ARENSTORF_T, None).unwrap_err();
    assert!(
        matches!(err, SolverError::StepBudget { steps: 20, .. }),
        "{err:?}"
    );
    assert!(it.t() > 0.0 && it.t() < ARENSTORF_T);

    let bad = |o: Options| Integrator::new(o, 0.0, &[1.0, 2.0]).unwrap_err();
    let mut o = Options::new(Method::Dopri5, f64::NAN, vec![1e-6]);
    assert!(matches!(bad(o.clone()), SolverError::InvalidOptions(_)));
    o.rtol = 1e-6;
    o.atol = vec![1e-6; 3];
    assert!(matches!(bad(o.clone()), SolverError::InvalidOptions(_)));
    o.atol = vec![1e-6];
    o.h_init = Some(-1.0);
    assert!(matches!(bad(o.clone()), SolverError::InvalidOptions(_)));
    assert!(matches!(
        bad(Options::new(Method::Rk4, 1e-6, vec![1e-6])),
        SolverError::InvalidOptions(_)
    ));
    assert!(Integrator::new(Options::fixed(Method::Rk4, 0.1), 0.0, &[f64::NAN]).is_err());

    let mut it = Integrator::new(
        Options::new(Method::Dopri5, 1e-6, vec![1e-6]),
        1.0,
        &[1.0, 0.0],
    )
    .unwrap();
    assert!(matches!(
        it.advance(&mut Osc { w: 1.0 }, 0.5, None),
        Err(SolverError::InvalidTarget { .. })
    ));
    assert!(matches!(
        it.advance(&mut Osc { w: 1.0 }, f64::NAN, None),
        Err(SolverError::InvalidTarget { .. })
    ));
    assert!(matches!(
        it.advance(&mut Blowup, 2.0, None),
        Err(SolverError::DimensionMismatch { .. })
    ));
    assert!(it.set_rtol(-1.0).is_err());
    assert!(it.set_atol(&[1.0, 2.0, 3.0]).is_err());
    assert!(it.try_set_state(0.0, &[1.0]).is_err());
    // a non-finite right-hand side at the current state is reported, not looped on
    struct NanRhs;
    impl System for NanRhs {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, _y: &[f64], d: &mut [f64]) {
            d[0] = 0.0;
            d[1] = f64::NAN;
        }
    }
    assert!(matches!(
        it.advance(&mut NanRhs, 2.0, None),
        Err(SolverError::NonFinite { component: 1, .. })
    ));
}

// ---------------------------------------------------------------- 6. landing and FSAL reuse

#[test]
fn lands_exactly_and_communication_step_does_not_matter() {
    let w = 2.0 * PI * 1000.0;
    let exact = |t: f64| [(w * t).cos(), -w * (w * t).sin()];
    // Measured (relative to amplitude) regular vs irregular: RKF45 2.7e-8, DOPRI5 5e-10, DOP853
    // 1.8e-9; against the closed form after 10 periods: 1.2e-6, 2.5e-8, 7.9e-9.
    for (m, bound) in [
        (Method::Rkf45, 5e-6),
        (Method::Dopri5, 1e-7),
        (Method::Dop853, 5e-8),
    ] {
        let rtol = 1e-9;
        let o = Options::new(m, rtol, vec![1e-9, 1e-9 * w]);
        let mut reg = Integrator::new(o.clone(), 0.0, &[1.0, 0.0]).unwrap();
        let mut irr = Integrator::new(o, 0.0, &[1.0, 0.0]).unwrap();
        let mut sys = Osc { w };
        let mut k_irr = 0u32;
        let (mut worst_d, mut worst_e) = (0.0f64, 0.0f64);
        for j in 1..=10 {
            let tc = 1e-3 * j as f64;
            // regular: 1e-4 communication steps
            for i in 1..=10 {
                let t = 1e-3 * (j - 1) as f64 + 1e-4 * i as f64;
                let t = if i == 10 { tc } else { t };
                reg.advance(&mut sys, t, None).unwrap();
                assert_eq!(reg.t(), t);
            }
            // irregular: pseudo-random sub-steps, then the common time
            let t0 = irr.t();
            for _ in 0..3 {
                k_irr += 1;
                let frac = (k_irr as f64 * 0.754877666).fract();
                let t = t0 + (tc - t0) * frac;
                if t > irr.t() {
                    irr.advance(&mut sys, t, None).unwrap();
                    assert_eq!(irr.t(), t);
                }
            }
            irr.advance(&mut sys, tc, None).unwrap();
            assert_eq!(irr.t(), tc);
            let ex = exact(tc);
            let scale = [1.0, w];
            for c in 0..2 {
                let d = (reg.y()[c] - irr.y()[c]).abs() / scale[c];
                worst_d = worst_d.max(d);
                worst_e = worst_e.max((reg.y()[c] - ex[c]).abs() / scale[c]);
            }
        }
        assert!(worst_d < 1e-7, "{m}: regular vs irregular {worst_d:e}");
        assert!(worst_e < bound, "{m}: vs closed form {worst_e:e}");
        // advancing to the current time is a no-op
        let s = reg.stats();
        reg.advance(&mut sys, reg.t(), None).unwrap();
        assert_eq!(reg.stats(), s);
    }
}

/// Exact RHS accounting. Always 1 evaluation of f(t0, y0) plus 1 in the initial-step heuristic,
/// then:
/// - DOPRI5: 6 per attempt (FSAL, also across calls);
/// - DOP853 without dense output: 11 per attempt, plus 1 per accepted step except the last
///   (f at the new point, evaluated lazily by the next step);
/// - DOP853 with an observer: 11 per attempt, plus 4 per accepted step (f at the new point and
///   3 dense stages).
#[test]
fn fsal_reuse_and_rhs_accounting() {
    let run = |m: Method, with_observer: bool| {
        let mut it = Integrator::new(
            Options::new(m, 1e-8, vec![1e-8]),
            0.0,
            &kepler_exact(0.5, 0.0),
        )
        .unwrap();
        let mut n_obs = 0u64;
        let mut obs = |_: &StepView| n_obs += 1;
        for i in 1..=50 {
            let t = 0.1 * i as f64;
            if with_observer {
                it.advance(&mut Kepler, t, Some(&mut obs)).unwrap();
            } else {
                it.advance(&mut Kepler, t, None).unwrap();
            }
        }
        let s = it.stats();
        if with_observer {
            assert_eq!(n_obs, s.steps);
        }
        s
    };
    let s = run(Method::Dopri5, false);
    assert_eq!(s.rhs_evals, 2 + 6 * (s.steps + s.rejected), "{s:?}");
    let per_step = s.rhs_evals as f64 / s.steps as f64;
    assert!((6.0..7.0).contains(&per_step), "dopri5 {per_step}");

    let s = run(Method::Dopri5, true);
    assert_eq!(s.rhs_evals, 2 + 6 * (s.steps + s.rejected), "{s:?}");

    let s = run(Method::Dop853, false);
    assert_eq!(
        s.rhs_evals,
        2 + 11 * (s.steps + s.rejected) + (s.steps - 1),
        "{s:?}"
    );
    let per_step = s.rhs_evals as f64 / s.steps as f64;
    assert!((12.0..13.5).contains(&per_step), "dop853 {per_step}");

    let s = run(Method::Dop853, true);
    assert_eq!(
        s.rhs_evals,
        2 + 11 * (s.steps + s.rejected) + 4 * s.steps,
        "{s:?}"
    );

    let s = run(Method::Rkf45, false);
    assert_eq!(
        s.rhs_evals,
        2 + 5 * (s.steps + s.rejected) + (s.steps - 1),
        "{s:?}"
    );
}

#[test]
fn discontinuity_and_set_state_drop_fsal() {
    let mut it = Integrator::new(
        Options::new(Method::Dopri5, 1e-8, vec![1e-8]),
        0.0,
        &[1.0, 0.0],
    )
    .unwrap();
    let mut sys = Osc { w: 1.0 };
    it.advance(&mut sys, 1.0, None).unwrap();
    let s = it.stats();
    it.discontinuity();
    it.advance(&mut sys, 2.0, None).unwrap();
    let s2 = it.stats();
    assert_eq!(
        s2.rhs_evals,
        s.rhs_evals + 1 + 6 * (s2.steps + s2.rejected - s.steps - s.rejected)
    );
    it.set_state(5.0, &[0.0, 1.0]);
    assert_eq!((it.t(), it.y()), (5.0, &[0.0, 1.0][..]));
    it.advance(&mut sys, 5.0 + PI, None).unwrap();
    assert!(max_diff(it.y(), &[0.0, -1.0]) < 1e-6);
}

// ---------------------------------------------------------------- 7. snapshot / restore

#[test]
fn snapshot_restore_through_json_is_bit_identical() {
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        let o = Options::new(m, 1e-9, vec![1e-9]);
        let mut a = Integrator::new(o.clone(), 0.0, &ARENSTORF_Y0).unwrap();
        let mut obs = |_: &StepView| {};
        for i in 1..=7 {
            a.advance(&mut Arenstorf, 0.31 * i as f64, Some(&mut obs))
                .unwrap();
        }
        let json = serde_json::to_string(&a.snapshot()).unwrap();
        let state: IntegratorState = serde_json::from_str(&json).unwrap();
        assert_eq!(state, a.snapshot());
        let mut b = Integrator::new(o, 99.0, &[0.0; 4]).unwrap();
        b.restore(&state).unwrap();
        assert_eq!(b.stats(), a.stats());
        for i in 8..=40 {
            let t = 0.31 * i as f64;
            a.advance(&mut Arenstorf, t, None).unwrap();
            b.advance(&mut Arenstorf, t, None).unwrap();
            assert_eq!(a.t().to_bits(), b.t().to_bits());
            for (x, y) in a.y().iter().zip(b.y()) {
                assert_eq!(x.to_bits(), y.to_bits(), "{m} at t = {t}");
            }
        }
        assert_eq!(a.stats(), b.stats());
        // mismatches are errors
        let mut wrong_dim =
            Integrator::new(Options::new(m, 1e-9, vec![1e-9]), 0.0, &[0.0; 2]).unwrap();
        assert!(matches!(
            wrong_dim.restore(&state),
            Err(SolverError::StateMismatch(_))
        ));
        let other = if m == Method::Dop853 {
            Method::Dopri5
        } else {
            Method::Dop853
        };
        let mut wrong_method =
            Integrator::new(Options::new(other, 1e-9, vec![1e-9]), 0.0, &[0.0; 4]).unwrap();
        assert!(wrong_method.restore(&state).is_err());
    }
}

// ---------------------------------------------------------------- 8. per-component atol

/// Two decoupled oscillators, slow (w = 1) and fast (w = 40). With a huge atol on the fast one the
/// step is set by the slow one alone: far fewer steps, slow component still accurate.
#[test]
fn per_component_atol_is_honoured() {
    struct Two;
    impl System for Two {
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
            d[0] = y[1];
            d[1] = -y[0];
            d[2] = y[3];
            d[3] = -1600.0 * y[2];
        }
    }
    let run = |atol: Vec<f64>| {
        let mut it = Integrator::new(
            Options::new(Method::Dop853, 1e-9, atol),
            0.0,
            &[1.0, 0.0, 1e-3, 0.0],
        )
        .unwrap();
        it.advance(&mut Two, 10.0, None).unwrap();
        let slow_err = max_diff(&it.y()[..2], &[10f64.cos(), -10f64.sin()]);
        (it.stats().steps, slow_err)
    };
    let (tight_steps, tight_err) = run(vec![1e-9]);
    let (loose_steps, loose_err) = run(vec![1e-9, 1e-9, 1e9, 1e9]);
    assert!(
        tight_err < 1e-7 && loose_err < 1e-7,
        "{tight_err} {loose_err}"
    );
    assert!(
        loose_steps * 5 < tight_steps,
        "loose {loose_steps} vs tight {tight_steps}"
    );
}

// ---------------------------------------------------------------- dense output

/// Dense output of each method against the closed form between the steps (rtol 1e-11).
/// Measured worst errors: DOP853 5.8e-10, DOPRI5 6.1e-10, RKF45 (cubic Hermite) 9.0e-9.
#[test]
fn dense_output_accuracy() {
    for (m, tol) in [
        (Method::Dop853, 5e-9),
        (Method::Dopri5, 5e-9),
        (Method::Rkf45, 1e-7),
    ] {
        let mut it = Integrator::new(
            Options::new(m, 1e-11, vec![1e-11]),
            0.0,
            &kepler_exact(0.3, 0.0),
        )
        .unwrap();
        let mut worst = 0.0f64;
        let mut buf = [0.0; 4];
        let mut obs = |v: &StepView| {
            for j in 0..=8 {
                let t = v.t_start() + (v.t_end() - v.t_start()) * j as f64 / 8.0;
                v.interpolate(t, &mut buf);
                worst = worst.max(max_diff(&buf, &kepler_exact(0.3, t)));
            }
            assert_eq!(v.y_end().len(), 4);
        };
        it.advance(&mut Kepler, 6.0, Some(&mut obs)).unwrap();
        assert!(worst < tol, "{m}: dense error {worst:e}");
    }
}

#[test]
fn pi_controller_works() {
    let mut o = Options::new(Method::Dopri5, 1e-8, vec![1e-8]);
    o.pi_beta = 0.04;
    let mut it = Integrator::new(o, 0.0, &ARENSTORF_Y0).unwrap();
    it.advance(&mut Arenstorf, ARENSTORF_T, None).unwrap();
    assert!(max_diff(it.y(), &ARENSTORF_Y0) < 1e-2);
}

/// With a sample grid the dense output is built only for the steps that contain a grid point
/// (and the event steps), and the samples are bitwise those of the always-dense run: DOP853 on
/// the Kepler orbit (e = 0.5, sampled 64 times per unit time, steps longer than the spacing)
/// and on the level-crossing oscillator with events. The stages the lazy run saves are exactly
/// 3 (DOP853's extra dense stages) per step without a grid point.
#[test]
fn sample_grid_builds_dense_output_only_where_sampled() {
    fn sampled<S: EventSystem>(
        sys: &mut S,
        y0: &[f64],
        grid: bool,
        with_events: bool,
    ) -> (Vec<f64>, Stats, usize) {
        let dt = 1.0 / 64.0;
        let mut it = Integrator::new(
            Options::new(Method::Dop853, 1e-9, vec![1e-12; y0.len()]),
            0.0,
            y0,
        )
        .unwrap();
        if grid {
            it.set_sample_grid(Some(dt));
        }
        let mut samples = Vec::new();
        let mut with_point = 0;
        let mut buf = vec![0.0; y0.len()];
        for i in 1..=10 {
            let mut obs = |v: &StepView| {
                let mut k = (v.t_start() / dt).floor() as i64 + 1;
                let mut hit = false;
                loop {
                    let ts = k as f64 * dt;
                    if ts > v.t_end() * (1.0 + 1e-15) {
                        break;
                    }
                    if ts > v.t_start() {
                        v.interpolate(ts.min(v.t_end()), &mut buf);
                        samples.extend_from_slice(&buf);
                        hit = true;
                    }
                    k += 1;
                }
                with_point += usize::from(hit);
            };
            if with_events {
                it.advance_with_events(sys, i as f64, Some(&mut obs))
                    .unwrap();
            } else {
                it.advance(sys, i as f64, Some(&mut obs)).unwrap();
            }
        }
        (samples, it.stats(), with_point)
    }
    struct Plain(Kepler);
    impl System for Plain {
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&mut self, t: f64, y: &[f64], d: &mut [f64]) {
            self.0.rhs(t, y, d)
        }
    }
    impl EventSystem for Plain {
        fn n_events(&self) -> usize {
            0
        }
        fn events(&mut self, _t: f64, _y: &[f64], _g: &mut [f64]) {}
        fn handle_event(&mut self, _i: usize, _t: f64, _y: &mut [f64]) -> EventAction {
            EventAction::Continue
        }
    }
    let e: f64 = 0.5;
    let k0 = [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()];
    for with_events in [false, true] {
        let (a, sa, _) = sampled(&mut Plain(Kepler), &k0, false, with_events);
        let (b, sb, with_point) = sampled(&mut Plain(Kepler), &k0, true, with_events);
        assert_eq!(a, b, "Kepler samples (events path: {with_events})");
        assert_eq!(sa.steps, sb.steps);
        let without = sb.steps as usize - with_point;
        assert!(
            without > 0,
            "every step holds a sample: the test does not test"
        );
        assert_eq!(
            sa.rhs_evals - sb.rhs_evals,
            3 * without as u64,
            "saved stages (events path: {with_events})"
        );
    }
    let (a, _, _) = sampled(&mut Level { times: Vec::new() }, &[1.0, 0.0], false, true);
    let (b, _, _) = sampled(&mut Level { times: Vec::new() }, &[1.0, 0.0], true, true);
    assert_eq!(a, b, "oscillator with level events");
}

/// A collapsed step says what limited it, by component: the error estimate's largest component
/// when the solution blows up in one component only, and the first non-finite derivative (its
/// component and stage time) when the right-hand side stops being defined.
#[test]
fn a_collapsed_step_names_the_limiting_component() {
    // y0' = −y0 is tame; y1' = y1² blows up at t = 1.
    struct Pair;
    impl System for Pair {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
            d[0] = -y[0];
            d[1] = y[1] * y[1];
        }
    }
    // y0 = t; y1' = √(0.5 − y0) has no value past t = 0.5.
    struct Edge;
    impl System for Edge {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) {
            d[0] = 1.0;
            d[1] = (0.5 - y[0]).sqrt();
        }
    }
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        let o = Options::new(m, 1e-6, vec![1e-6]);
        let mut it = Integrator::new(o.clone(), 0.0, &[1.0, 1.0]).unwrap();
        match it.advance(&mut Pair, 2.0, None).unwrap_err() {
            SolverError::StepSizeUnderflow { limit, .. } => match limit {
                StepLimit::Error { component, ratio } => {
                    assert_eq!(component, 1, "{m}");
                    assert!(ratio > 1.0, "{m}: {ratio}");
                }
                StepLimit::NonFiniteDerivative { component, .. }
                | StepLimit::NonFiniteState { component } => assert_eq!(component, 1, "{m}"),
                StepLimit::Unknown => panic!("{m}: no limit named"),
            },
            SolverError::NonFinite { component, .. } => assert_eq!(component, 1, "{m}"),
            e => panic!("{m}: {e}"),
        }
        let mut it = Integrator::new(o, 0.0, &[0.0, 0.0]).unwrap();
        let e = it.advance(&mut Edge, 1.0, None).unwrap_err();
        match e {
            SolverError::StepSizeUnderflow {
                limit: StepLimit::NonFiniteDerivative { component, t },
                ..
            } => {
                assert_eq!(component, 1, "{m}");
                assert!(t > 0.5 && t < 0.5 + 1e-6, "{m}: {t}");
            }
            e => panic!("{m}: {e:?}"),
        }
        assert!(e.to_string().contains("non-finite"), "{m}: {e}");
    }
}

/// A mode that follows the sign of g(t) = (t − 1)² − ε²: on while g > 0. The function touches 0
/// and comes back 2ε later, much sooner than the probe the integrator takes inside the first
/// step after the event. `with_sign` reports the mode's sign ([`EventSystem::mode_sign`]).
struct Touch {
    on: bool,
    switches: Vec<f64>,
    with_sign: bool,
}
const TOUCH_EPS: f64 = 2e-12;
impl System for Touch {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, _y: &[f64], d: &mut [f64]) {
        d[0] = 1.0;
    }
}
impl EventSystem for Touch {
    fn n_events(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = (y[0] - 1.0).powi(2) - TOUCH_EPS * TOUCH_EPS;
    }
    fn handle_event(&mut self, _i: usize, t: f64, _y: &mut [f64]) -> EventAction {
        self.switches.push(t);
        self.on = !self.on;
        // As the simulation does: return at the event, switch, call again.
        EventAction::Stop
    }
    fn mode_sign(&self, _i: usize) -> Option<f64> {
        self.with_sign.then_some(if self.on { 1.0 } else { -1.0 })
    }
}

#[test]
fn a_mode_switch_that_touches_zero_and_returns_switches_back() {
    for m in [Method::Rkf45, Method::Dopri5, Method::Dop853] {
        for with_sign in [true, false] {
            let mut sys = Touch {
                on: true,
                switches: Vec::new(),
                with_sign,
            };
            let mut it = Integrator::new(Options::new(m, 1e-8, vec![1e-8]), 0.0, &[0.0]).unwrap();
            // A step ends at t = 1, inside the dip: the first root is seen there.
            it.advance_with_events(&mut sys, 1.0, None).unwrap();
            while it.advance_with_events(&mut sys, 2.0, None).unwrap() != AdvanceOutcome::Reached {}
            let first = sys.switches[0];
            assert!((first - (1.0 - TOUCH_EPS)).abs() < 5e-13, "{m}: {first}");
            if with_sign {
                // The return is an event: the mode is back on, with g > 0.
                assert_eq!(sys.switches.len(), 2, "{m}: {:?}", sys.switches);
                let second = sys.switches[1];
                assert!((second - (1.0 + TOUCH_EPS)).abs() < 5e-13, "{m}: {second}");
                assert!(sys.on, "{m}");
            } else {
                // Without the mode's sign the return hides inside the probe: the mode stays off
                // while g > 0 (what mode_sign exists for).
                assert_eq!(sys.switches.len(), 1, "{m}: {:?}", sys.switches);
                assert!(!sys.on, "{m}");
            }
        }
    }
}

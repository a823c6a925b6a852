//! Step-control options: Hairer's stiffness detection, the controller restart after a
//! discontinuity, and validation of `Integrator::set_step_control`.

use raceway::solver::*;

/// Linear test equation y' = -lambda (y - cos t), solution tends to cos t.
struct Lin {
    lambda: f64,
}
impl System for Lin {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, y: &[f64], d: &mut [f64]) {
        d[0] = -self.lambda * (y[0] - t.cos());
    }
}

fn stiff_share(method: Method, lambda: f64, rtol: f64) -> (f64, f64) {
    let mut sys = Lin { lambda };
    let mut it = Integrator::new(Options::new(method, rtol, vec![rtol]), 0.0, &[0.0]).unwrap();
    // With an observer the dense output (and DOP853's end derivative) is built every step.
    let mut obs = |_: &StepView| {};
    it.advance(&mut sys, 2.0, Some(&mut obs)).unwrap();
    let s = it.stats();
    let mean_h = 2.0 / s.steps as f64;
    (s.stiff_steps as f64 / s.steps as f64, mean_h * lambda)
}

#[test]
fn stiffness_detection_flags_stability_bound_steps_only() {
    // lambda = 1e4 at a loose tolerance: after the transient the accuracy would allow steps of
    // ~0.1, so the step size is bounded by stability, h*lambda near the method's reach
    // (DOPRI5 ~3.3, DOP853 ~6): most steps must be flagged.
    for (m, reach) in [(Method::Dopri5, 3.3), (Method::Dop853, 6.0)] {
        let (share, h_lambda) = stiff_share(m, 1e4, 1e-3);
        assert!(share > 0.5, "{m}: only {share} of the steps flagged");
        // and the mean step is indeed at the stability limit (independent check)
        assert!(
            h_lambda > 0.5 * reach && h_lambda < 1.2 * reach,
            "{m}: mean h*lambda {h_lambda}"
        );
    }
    // lambda = 1: accuracy-bound steps, h*lambda far below the boundary: nothing flagged.
    for m in [Method::Dopri5, Method::Dop853] {
        let (share, h_lambda) = stiff_share(m, 1.0, 1e-8);
        assert!(h_lambda < 1.0, "{m}: {h_lambda}");
        assert_eq!(share, 0.0, "{m}");
    }
    // RKF45 has no detection.
    assert_eq!(stiff_share(Method::Rkf45, 1e4, 1e-3).0, 0.0);
}

#[test]
fn restart_after_discontinuity_takes_a_fresh_initial_step() {
    let run = |restart: bool| {
        let mut o = Options::new(Method::Dopri5, 1e-6, vec![1e-9]);
        o.restart_after_discontinuity = restart;
        let mut sys = Lin { lambda: 1.0 };
        let mut it = Integrator::new(o, 0.0, &[1.0]).unwrap();
        it.advance(&mut sys, 1.0, None).unwrap();
        let h_before = it.h_next();
        assert!(h_before > 0.0);
        it.discontinuity();
        let h_after = it.h_next();
        let evals = it.stats().rhs_evals;
        it.advance(&mut sys, 1.0 + 1e-3, None).unwrap();
        (h_before, h_after, it.stats().rhs_evals - evals)
    };
    let (hb, ha, _) = run(false);
    assert_eq!(ha, hb, "without restart the proposed step is kept");
    let (_, ha, evals) = run(true);
    assert_eq!(ha, 0.0, "with restart the proposal is dropped");
    // f(t, y) + the hinit probe + 6 stages of one landing step
    assert_eq!(evals, 8);
}

#[test]
fn set_step_control_validates() {
    let mut it =
        Integrator::new(Options::new(Method::Dop853, 1e-6, vec![1e-9]), 0.0, &[1.0]).unwrap();
    let mut c = Options::new(Method::Dop853, 1e-6, vec![1e-9]);
    c.pi_beta = 0.5;
    let e = it.set_step_control(&c).unwrap_err().to_string();
    assert!(e.contains("pi_beta"), "{e}");
    assert_eq!(
        it.options().pi_beta,
        0.0,
        "a rejected setting changes nothing"
    );
    c.pi_beta = 0.04;
    c.safety = 0.8;
    it.set_step_control(&c).unwrap();
    assert_eq!((it.options().pi_beta, it.options().safety), (0.04, 0.8));
}

#[test]
fn observed_order_sizes_the_retry_after_two_rejections() {
    use raceway::solver::controller::Controller;
    let tab = Method::Dop853.tableau();
    let mut o = Options::new(Method::Dop853, 1e-6, vec![1e-9]);
    o.observed_order_on_reject = true;
    let mut c = Controller::default();
    // First rejection: nominal exponent 1/8, limited by fac_min = 0.2.
    let h1 = c.reject(tab, &o, 1.0, 3.0);
    assert!((h1 - 0.9 * 3f64.powf(-1.0 / 8.0)).abs() < 1e-12, "{h1}");
    // The error fell only like h^2 (a kink): err2 = 3 h1^2. The retry must use p = 2:
    // h2 = h1 * (0.9 / err2)^(1/2), instead of the nominal h1 * 0.9 * err2^(-1/8).
    let e2 = 3.0 * h1 * h1;
    let h2 = c.reject(tab, &o, h1, e2);
    let want = h1 * 0.9 / e2.sqrt();
    assert!((h2 - want).abs() < 1e-12 * want, "{h2} vs {want}");
    // Acceptance clears the memory: the next rejection is nominal again.
    c.accept(tab, &o, h2, 0.5);
    let h3 = c.reject(tab, &o, 1.0, 3.0);
    assert!((h3 - h1).abs() < 1e-12);
    // Without the option the second retry is nominal.
    let mut c = Controller::default();
    o.observed_order_on_reject = false;
    c.reject(tab, &o, 1.0, 3.0);
    let h2n = c.reject(tab, &o, h1, e2);
    assert!((h2n - h1 * 0.9 * e2.powf(-1.0 / 8.0)).abs() < 1e-12);
}

/// The scene's `solver.pi_beta` reaches the integrator's controller (fewer rejections on the
/// spall scene at the lumped level, as `docs/research/step-control.md` measured for β = 0.08) and is
/// validated with the field named.
#[test]
fn scene_pi_beta_reaches_the_controller_and_is_validated() {
    use raceway::Simulation;
    use raceway::{Fidelity, Scene};
    let rejected = |beta: f64| {
        let mut s = Scene::default_scene();
        s.fidelity = Fidelity::Lumped;
        s.solver.pi_beta = beta;
        // the edge of the study that measured it (the blend; with the abrupt default, D2, PI
        // 0.08 rejects 469 steps against the I-controller's 797)
        s.bearing.defect.blend_length =
            raceway::BlendLength::Named(raceway::BlendName::SemiMinorAxis);
        let mut sim = Simulation::new(&s).unwrap();
        sim.advance(0.03).unwrap();
        let st = sim.solver_stats();
        (st.rejected, st.steps)
    };
    let (r0, n0) = rejected(0.0);
    let (r8, n8) = rejected(0.08);
    eprintln!("I: {r0} of {n0} rejected; PI 0.08: {r8} of {n8}");
    assert!(
        r0 > 100,
        "the I-controller rejects steps on this scene: {r0}"
    );
    assert!(2 * r8 < r0, "PI 0.08 rejects {r8}, the I-controller {r0}");
    for bad in [-0.01, 0.25, f64::NAN] {
        let mut s = Scene::default_scene();
        s.solver.pi_beta = bad;
        let e = Simulation::new(&s).err().expect("refused").to_string();
        assert!(e.contains("solver.pi_beta"), "{e}");
    }
}

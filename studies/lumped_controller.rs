//! The step-size controller on the lumped level's default scene (DOP853, 0.1 s, outer spall):
//! work (steps, rejected, RHS evaluations) and the error of the ring-on-pedestal displacement
//! (relative RMS against DOP853 at rtol 1e-12) for the I controller (β = 0) and PI controllers
//! (β = 0.04, 0.08), and smaller growth limits fac_max. Not a test: a measurement behind the
//! controller notes in docs/performance.md.
//!
//!     cargo run --release -p raceway-studies --bin lumped_controller

use raceway::models::{self, ModelSystem};
use raceway::solver::{AdvanceOutcome, Integrator, Method, Options};
use raceway::{Bearing, Scene};

fn run(rtol: f64, beta: f64, fac_max: f64, t_end: f64) -> (u64, u64, u64, Vec<f64>) {
    let scene = Scene::default_scene();
    let bearing = Bearing::new(&scene.bearing).unwrap();
    let inputs = scene.operating;
    let mut model = models::build(&scene, &bearing, &inputs).unwrap();
    let n = model.dim();
    let mut y0 = vec![0.0; n];
    model.initial_state(&mut y0);
    model.update_mode(0.0, &y0);
    let mut nom = vec![0.0; n];
    model.nominal(&mut nom);
    let mut o = Options::new(Method::Dop853, rtol, nom.iter().map(|v| v * rtol).collect());
    o.pi_beta = beta;
    o.fac_max = fac_max;
    let mut integ = Integrator::new(o, 0.0, &y0).unwrap();
    let mut samples = Vec::new();
    let dt = 1.0 / 51200.0;
    let mut k = 1;
    while integ.t() < t_end {
        let t = integ.t();
        let stop = model.next_stop(t, integ.y(), t_end);
        let target = stop.unwrap_or(t_end);
        let mut buf = vec![0.0; n];
        let mut obs = |v: &raceway::solver::StepView| {
            while (k as f64) * dt <= v.t_end() {
                v.interpolate(k as f64 * dt, &mut buf);
                samples.push(buf[2] - buf[4]);
                k += 1;
            }
        };
        let r = integ
            .advance_with_events(&mut ModelSystem(model.as_mut()), target, Some(&mut obs))
            .unwrap();
        if stop.is_some() || matches!(r, AdvanceOutcome::Stopped { .. }) {
            let tt = integ.t();
            let yy = integ.y().to_vec();
            model.update_mode(tt, &yy);
            integ.discontinuity();
        }
    }
    let s = integ.stats();
    (s.steps, s.rejected, s.rhs_evals, samples)
}

fn main() {
    let t_end = 0.1;
    let (_, _, _, reference) = run(1e-12, 0.0, 10.0, t_end);
    let skip = 1024;
    let rms = (reference[skip..].iter().map(|v| v * v).sum::<f64>()
        / (reference.len() - skip) as f64)
        .sqrt();
    for rtol in [1e-4, 1e-6] {
        for (beta, fac_max) in [
            (0.0, 10.0),
            (0.04, 10.0),
            (0.08, 10.0),
            (0.0, 5.0),
            (0.04, 5.0),
            (0.0, 3.0),
        ] {
            let (st, rj, ev, x) = run(rtol, beta, fac_max, t_end);
            let m = x.len().min(reference.len());
            let e = (x[skip..m]
                .iter()
                .zip(&reference[skip..m])
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                / (m - skip) as f64)
                .sqrt()
                / rms;
            eprintln!("rtol {rtol:e} beta {beta} fac_max {fac_max}: steps {st} rej {rj} rhs {ev} E(ring-ped z) {e:.2e}");
        }
    }
}

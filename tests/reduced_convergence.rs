//! The reduced model converges with the tolerance across spall passes: the pedestal acceleration
//! at rtol 1e-6 agrees with rtol 1e-9 to a fraction of a per cent (relative RMS), over ten
//! passes with the rattle of the balls after each (contacts opening and closing, the spall's
//! corner switch and blend boundary, all located as events with the full model's
//! `Switches`). Before, with only the spall edges and centre as events and the half re-derived
//! from the sign of θ_bd, DOP853 rtol 1e-6 was off by E1 = 0.48 here (79 % of its steps
//! rejected); now E1 ≈ 1e-4.

use raceway::scene::{Fidelity, MethodName, Scene};
use raceway::simulation::{out, Simulation};

fn run(method: MethodName, rtol: f64, duration: f64) -> (Vec<f64>, u64) {
    let mut s = Scene::default_scene();
    s.fidelity = Fidelity::Reduced;
    s.solver.method = method;
    s.solver.rtol = rtol;
    s.solver.max_steps = 5_000_000;
    let mut sim = Simulation::new(&s).expect("scene");
    let mut sig = Vec::new();
    sim.advance_sampled(duration, 1.0 / 51_200.0, &mut |_, o| {
        sig.push(o[out::PEDESTAL_A_Z])
    })
    .expect("advance");
    (sig, sim.stats().rhs_evals)
}

fn rel_rms(x: &[f64], r: &[f64], skip: usize) -> f64 {
    let n = x.len().min(r.len());
    let (mut d2, mut r2) = (0.0, 0.0);
    for i in skip..n {
        d2 += (x[i] - r[i]).powi(2);
        r2 += r[i].powi(2);
    }
    (d2 / r2).sqrt()
}

#[test]
fn spall_passes_converge_with_the_tolerance() {
    let duration = 0.011; // ten outer-race passes at BPFO ≈ 986 Hz
    let (reference, _) = run(MethodName::Dop853, 1e-9, duration);
    let skip = 51; // 1 ms
    for method in [MethodName::Dop853, MethodName::Dopri5] {
        let (x, rhs) = run(method, 1e-6, duration);
        let e1 = rel_rms(&x, &reference, skip);
        eprintln!("{method:?} rtol 1e-6: E1 {e1:.2e} against rtol 1e-9, {rhs} RHS");
        assert!(e1 < 1e-2, "{method:?}: E1 {e1:.3e} against rtol 1e-9");
    }
}

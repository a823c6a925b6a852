//! Where the reduced model stalls (diagnostics, not part of CI): integrates the default scene
//! (S2) with the reduced model as `studies/divergence.rs` does (events stop the advance, the mode
//! is updated, the integrator restarts) and, when a step-size underflow ends the run, prints
//! per ball the spall angle, the frozen modes and the contact functions at the last accepted
//! state, then the RHS along the ODE from that state on a fine grid, to show which derivative
//! jumps and where.
//!
//! `cargo run --release -p raceway-studies --bin stall_probe -- [rtol] [duration] [method]`

use raceway::models::internals::layout::REDUCED_PER_BALL as PER_BALL;
use raceway::models::Model;
use raceway::models::ReducedModel;
use raceway::solver::{AdvanceOutcome, Integrator, Method, Options};
use raceway::{Bearing, Scene};

use raceway::models::ModelSystem as Driver;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let rtol: f64 = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(1e-12);
    let duration: f64 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.02);
    let method = match a.get(3).map_or("dop853", |s| s.as_str()) {
        "dopri5" => Method::Dopri5,
        _ => Method::Dop853,
    };
    let scene = Scene::default_scene();
    let bearing = Bearing::new(&scene.bearing).expect("bearing");
    let inputs = scene.operating;
    let mut m = ReducedModel::new(&scene, &bearing, &inputs).expect("model");
    let n = m.dim();
    let z = bearing.z;
    let mut y0 = vec![0.0; n];
    m.initial_state(&mut y0);
    let mut nominal = vec![0.0; n];
    m.nominal(&mut nominal);
    m.update_mode(0.0, &y0);
    let atol = nominal.iter().map(|v| v * rtol).collect();
    let mut integ = Integrator::new(Options::new(method, rtol, atol), 0.0, &y0).expect("integ");
    let mut n_events = 0usize;
    let mut last_events: Vec<(f64, f64)> = Vec::new();
    let err = loop {
        if integ.t() >= duration {
            break None;
        }
        match integ.advance_with_events(&mut Driver(&mut m), duration, None) {
            Ok(AdvanceOutcome::Stopped { .. }) => {
                n_events += 1;
                last_events.push((integ.t(), 0.0));
                let t = integ.t();
                m.update_mode(t, integ.y());
                integ.discontinuity();
            }
            Ok(_) => {}
            Err(e) => break Some(e),
        }
    };
    let st = integ.stats();
    println!(
        "t = {:.15}  steps {} rejected {} rhs {} events {n_events}",
        integ.t(),
        st.steps,
        st.rejected,
        st.rhs_evals
    );
    let Some(e) = err else { return };
    println!("error: {e}");
    println!(
        "last events at: {:?}",
        &last_events[last_events.len().saturating_sub(8)..]
    );
    let t0 = integ.t();
    let y = integ.y().to_vec();
    let d = m.defect().expect("spall").clone();
    let mut g = vec![0.0; m.n_events()];
    m.events(t0, &y, &mut g);
    for j in 0..z {
        let (tbd, rate) = m.core().theta_bd(&d, &y, j);
        let sw = m.core().switches();
        println!(
            "ball {j:2}: tbd {:+.6e} (te {:.5e}) rate {:+.3e} side {:+} blend {:?} law ({:?},{:?}) g_in {:+.3e} g_out {:+.3e} zone {:+.3e} centre {:+.3e} blendm {:+.3e}",
            tbd,
            d.half_angle(),
            rate,
            sw.side(j),
            sw.blend(j),
            sw.law(j, 0),
            sw.law(j, 1),
            g[2 * j],
            g[2 * j + 1],
            g[2 * z + 2 * j],
            g[2 * z + 2 * j + 1],
            g[4 * z + j]
        );
    }
    // The RHS along an explicit Euler path from the stalled state: a jump of some derivative
    // inside a few 1e-14 s shows up as a large difference between neighbouring points.
    let mut f0 = vec![0.0; n];
    let mut f1 = vec![0.0; n];
    let mut yy = vec![0.0; n];
    m.rhs(t0, &y, &mut f0);
    for k in 1..=40 {
        let h = 1e-15 * 1.6f64.powi(k);
        for i in 0..n {
            yy[i] = y[i] + h * f0[i];
        }
        m.rhs(t0 + h, &yy, &mut f1);
        let (mut worst, mut wi) = (0.0, 0);
        for i in 0..n {
            let scale = nominal[i] * 1e6; // derivative scale ~ nominal / 1 µs
            let dlt = (f1[i] - f0[i]).abs() / scale;
            if dlt > worst {
                worst = dlt;
                wi = i;
            }
        }
        let (ball, st) = if wi < PER_BALL * z {
            (wi / PER_BALL, wi % PER_BALL)
        } else {
            (usize::MAX, wi)
        };
        println!("h {h:.3e}: largest relative change of f {worst:.3e} at state {wi} (ball {ball}, state {st})");
        if worst > 1e-4 && k < 100 {
            let b = (0..z)
                .min_by(|&p, &q| g[2 * z + 2 * p].abs().total_cmp(&g[2 * z + 2 * q].abs()))
                .unwrap_or(0);
            let jumps: Vec<String> = (0..PER_BALL)
                .map(|i| format!("{:+.3e}", f1[PER_BALL * b + i] - f0[PER_BALL * b + i]))
                .collect();
            println!("   jump of ball {b}'s derivatives: {}", jumps.join(" "));
            let jumps: Vec<String> = (n - 8..n - 2)
                .map(|i| format!("{:+.3e}", f1[i] - f0[i]))
                .collect();
            println!("   jump of pedestal derivatives: {}", jumps.join(" "));
            break;
        }
    }
}

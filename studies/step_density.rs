//! Where the full (or reduced, or lumped) model spends its steps on the default scene: advances
//! in 20 µs chunks (or `chunk` seconds) and prints, per chunk, the accepted and rejected steps
//! and the balls in the spall zone.
//! Usage: `cargo run --release -p raceway-studies --bin step_density --
//! [full|reduced|lumped] [S1|S2] [t0] [t1] [chunk]`.
use raceway::{Fidelity, Scene, Simulation};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let mut s = Scene::default_scene();
    s.fidelity = match a.get(1).map(String::as_str) {
        Some("reduced") => Fidelity::Reduced,
        Some("lumped") => Fidelity::Lumped,
        _ => Fidelity::Full,
    };
    if a.get(2).is_some_and(|v| v == "S1") {
        s.defect = None;
    }
    let t0: f64 = a.get(3).and_then(|v| v.parse().ok()).unwrap_or(0.02);
    let t1: f64 = a.get(4).and_then(|v| v.parse().ok()).unwrap_or(0.025);
    s.solver.max_steps = 50_000_000;
    let mut sim = Simulation::new(&s).expect("scene");
    sim.advance(t0).expect("advance");
    let dt: f64 = a.get(5).and_then(|v| v.parse().ok()).unwrap_or(20e-6);
    let mut t = t0;
    let mut last = sim.solver_stats();
    let (mut tot_s, mut tot_r) = (0, 0);
    while t < t1 - 1e-12 {
        t += dt;
        let mut zone = String::new();
        sim.advance_sampled_with_model(t, dt, &mut |_, _, m| {
            for j in 0..16 {
                if m.in_spall_zone(j) {
                    zone.push_str(&format!("{j} "));
                }
            }
        })
        .expect("advance");
        let st = sim.solver_stats();
        let (ds, dr) = (st.steps - last.steps, st.rejected - last.rejected);
        tot_s += ds;
        tot_r += dr;
        println!("{:.5} {:4} {:3} {}", t * 1e3, ds, dr, zone);
        last = st;
    }
    println!(
        "# steps {tot_s} rejected {tot_r} per ms {:.1}",
        tot_s as f64 / ((t1 - t0) * 1e3)
    );
}

//! The monolithic reference of docs/coupling.md part C run natively (a `Simulation`, no FMU):
//! default scene, healthy bearing, force mode, the rotor of mass M folded into the inner ring
//! (inner_ring.mass = M − z m_b / 2, so the lumped ring mass is M), loads Fa = 4000 N,
//! Fz = −1000 N − M g, unbalance 2e-4 kg·m at 9900 rpm as a rotating load sampled at each step's
//! midpoint, steps of h for 20 ms. Prints `t,ring.x,ring.y,ring.z` per step (CSV) for
//! studies/coupling_study.py, which compares it with the same run through the FMU.
//!
//!     cargo run --release -p raceway-studies --bin native_reference -- [h]

use raceway::{out, Bearing, Scene, Simulation};

fn main() {
    let h: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().expect("h [s]"))
        .unwrap_or(1e-6);
    let (m, g, rpm, unb, t_end) = (2.0, 9.81, 9900.0, 2e-4, 0.02);
    let mut scene = Scene::default_scene();
    scene.defect = None;
    let probe = Bearing::new(&scene.bearing).expect("bearing");
    scene.bearing.inner_ring.mass = m - 0.5 * probe.z as f64 * probe.ball_mass;
    scene.operating.shaft_speed = raceway::rpm_to_rad_s(rpm);
    scene.operating.fx = 4000.0;
    scene.operating.fy = 0.0;
    scene.operating.fz = -(1000.0 + m * g);
    let mut sim = Simulation::new(&scene).expect("simulation");
    let w = rpm * std::f64::consts::PI / 30.0;
    let mut o = vec![0.0; sim.output_table().len()];
    let n = (t_end / h).round() as usize;
    let mut print = |sim: &mut Simulation, t: f64| {
        sim.try_outputs(&mut o).expect("outputs");
        println!(
            "{t:e},{:e},{:e},{:e}",
            o[out::RING_X],
            o[out::RING_Y],
            o[out::RING_Z]
        );
    };
    println!("t,ring.x,ring.y,ring.z");
    print(&mut sim, 0.0);
    let base = sim.inputs();
    for k in 0..n {
        let t = k as f64 * h;
        let tm = t + 0.5 * h;
        let mut inp = base;
        inp.fy += unb * w * w * (w * tm).cos();
        inp.fz += unb * w * w * (w * tm).sin();
        sim.set_inputs(inp).expect("inputs");
        sim.advance((k + 1) as f64 * h).expect("advance");
        print(&mut sim, (k + 1) as f64 * h);
    }
}

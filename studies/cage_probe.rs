//! Cage speed under the strip traction against L1's outer-race control (diagnostic, not part
//! of CI), and the cost of the solve. `cargo run --release -p raceway-studies --bin cage_probe -- [SCENE]`
use raceway::models;
use raceway::{Bearing, Scene};
use std::time::Instant;

fn main() {
    let path = std::env::args()
        .nth(1)
        .unwrap_or("examples/scenes/sec3.5-outer.toml".into());
    let scene = Scene::load(std::path::Path::new(&path)).unwrap();
    let bearing = Bearing::new(&scene.bearing).unwrap();
    let inputs = scene.operating;
    let l1 = models::solve_l1(&bearing, &inputs, "probe").unwrap();
    let t0 = Instant::now();
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20);
    let mut w = f64::NAN;
    for _ in 0..reps {
        w = models::traction_cage_speed(&bearing, &inputs, Some(&l1), None).unwrap();
    }
    let dt = t0.elapsed().as_secs_f64() / reps as f64;
    let tau = std::f64::consts::TAU;
    let z = bearing.z as f64;
    println!(
        "L1 cage {:.4} Hz (BPFO {:.2}); traction cage {:.4} Hz (BPFO {:.2}); solve {:.3} ms",
        l1.cage_speed / tau,
        z * l1.cage_speed / tau,
        w / tau,
        z * w / tau,
        dt * 1e3
    );
}

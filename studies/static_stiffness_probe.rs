//! Quasi-static radial stiffness of L4 at speed (not part of CI): settle the healthy bearing at
//! (Fa, Fr) and at (Fa, Fr + dF), tilt held, and divide dF by the change of the mean ring-minus-
//! pedestal displacement. Compare with `raceway static --fa FA --fr FR --speed-rpm RPM`.
//!
//! `cargo run --release -p raceway-studies --bin static_stiffness_probe -- RPM FA FR DF`
use raceway::{out, Fidelity, Scene, Simulation};

fn mean_offset(rpm: f64, fa: f64, fr: f64) -> (f64, f64) {
    let mut s = Scene::default_scene();
    s.fidelity = Fidelity::Full;
    s.defect = None;
    s.full.lock_tilt = true;
    s.operating.shaft_speed = raceway::rpm_to_rad_s(rpm);
    s.operating.fx = fa;
    s.operating.fz = -fr;
    let mut sim = Simulation::new(&s).unwrap();
    let (mut sum, mut sum_x, mut n) = (0.0, 0.0, 0.0);
    sim.advance_sampled(0.06, 1.0 / 51_200.0, &mut |t, o| {
        if t > 0.04 {
            sum += o[out::RING_Z] - o[out::PEDESTAL_Z];
            sum_x += o[out::RING_X];
            n += 1.0;
        }
    })
    .unwrap();
    (sum / n, sum_x / n)
}

fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|v| v.parse().unwrap())
        .collect();
    let (rpm, fa, fr, df) = (a[0], a[1], a[2], a[3]);
    let (z0, x0) = mean_offset(rpm, fa, fr);
    let (z1, x1) = mean_offset(rpm, fa, fr + df);
    println!(
        "rpm {rpm}: ring z {z0:.6e} -> {z1:.6e} m, k_zz = {:.4e} N/m (x {x0:.4e} -> {x1:.4e})",
        df / (z0 - z1)
    );
}

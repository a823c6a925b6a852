//! The Table-2 impact test at L4 with knobs (not part of CI): fel and feh of the pedestal's
//! pulse response, measured as in `validate_full` (run minus the run without the pulse,
//! 20–100 ms, zero-padded to 1 s, rectangular window).
//!
//! `cargo run --release -p raceway-studies --bin feh_probe -- RPM FA [traction on|off] [tilt held|free] [cb N s/m]`
use raceway::signal::{self, Window};
use raceway::{out, Fidelity, Scene, Simulation};

fn record(s: &Scene, fs: f64) -> Vec<f64> {
    let mut sim = Simulation::new(s).unwrap();
    let mut a = Vec::new();
    sim.advance_sampled(0.1, 1.0 / fs, &mut |t, o| {
        if t >= 0.02 {
            a.push(o[out::PEDESTAL_A_Z]);
        }
    })
    .unwrap();
    a
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let rpm: f64 = a[0].parse().unwrap();
    let fa: f64 = a[1].parse().unwrap();
    let traction = a.get(2).is_none_or(|v| v == "on");
    let held = a.get(3).is_none_or(|v| v == "held");
    let mut s = Scene::load(std::path::Path::new(
        "examples/scenes/impact-test-fa4000.toml",
    ))
    .unwrap();
    s.fidelity = Fidelity::Full;
    s.operating.shaft_speed = raceway::rpm_to_rad_s(rpm);
    s.operating.fx = fa;
    s.full.traction = traction;
    s.full.lock_tilt = held;
    if let Some(cb) = a.get(4).and_then(|v| v.parse::<f64>().ok()) {
        s.bearing.contact.c_br = cb;
    }
    let fs = 102_400.0;
    let with = record(&s, fs);
    let mut quiet = s.clone();
    quiet.pulse = None;
    let without = record(&quiet, fs);
    let mut d: Vec<f64> = with.iter().zip(&without).map(|(x, y)| x - y).collect();
    d.resize(fs as usize, 0.0);
    let sp = signal::amplitude_spectrum(&d, fs, Window::Rectangular).unwrap();
    let pk = |lo: f64, hi: f64| signal::dominant_peak(&sp, lo, hi).map_or(f64::NAN, |p| p.freq);
    println!(
        "rpm {rpm} Fa {fa} traction {traction} tilt {}: fel {:.1} Hz, feh {:.0} Hz",
        if held { "held" } else { "free" },
        pk(400.0, 800.0),
        pk(3000.0, 9000.0)
    );
}

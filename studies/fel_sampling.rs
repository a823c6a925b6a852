//! How the impact test's fel reading depends on the output sample rate (not part of CI).
//!
//! `pedestal.a.z` holds the pulse force itself (−P(t)/m_p, a 100 µs triangle). Sampled, its
//! discrete transform equals the continuous one only when the triangle's corners fall on samples;
//! otherwise the sampled pulse has the wrong area, and the broad fel peak (ζ ≈ 0.21) moves. This
//! probe reads fel two ways at several sample rates and pulse start times:
//! - `sampled`: the peak of |DFT| of the sampled pulse response (what the tests do);
//! - `exact`: the pulse term taken out of the samples and added back as its analytic Fourier
//!   transform, so that only the smooth structural response is sampled.
//!
//! `cargo run --release -p raceway-studies --bin fel_sampling -- [fa=4000] [level=full]`

use std::f64::consts::TAU;

use raceway::{out, Fidelity, Scene, Simulation};

fn main() {
    let mut fa = 4000.0;
    let mut level = Fidelity::Full;
    for a in std::env::args().skip(1) {
        let (k, v) = a.split_once('=').expect("key=value");
        match k {
            "fa" => fa = v.parse().unwrap(),
            "level" => level = Fidelity::from_name(v).expect("level"),
            _ => panic!("unknown key {k}"),
        }
    }
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join(format!("examples/scenes/impact-test-fa{}.toml", fa as i32));
    let mut base = Scene::load(&path).unwrap();
    base.fidelity = level;
    base.full.lock_tilt = true;
    let m_p = base.bearing.pedestal.mass;
    let window = 0.06;
    println!(
        "level {}, Fa {fa} N, m_p {m_p} kg, window {window} s",
        level.name()
    );
    println!("| t0 [ms] | fs [kHz] | corners on samples | fel sampled [Hz] | fel exact [Hz] |");
    println!("|---|---|---|---|---|");
    for t0 in [20e-3, 2e-3, 20.0123e-3] {
        for fs in [51_200.0, 102_400.0, 200_000.0, 400_000.0, 800_000.0] {
            let mut sc = base.clone();
            sc.pulse.as_mut().unwrap().t0 = t0;
            let pulse = sc.pulse.clone().unwrap();
            let az = |sc: &Scene| {
                let mut sim = Simulation::new(sc).expect("simulation builds");
                let mut a = Vec::new();
                sim.advance_sampled(t0 + window, 1.0 / fs, &mut |t, o| {
                    if t >= t0 {
                        a.push((t, o[out::PEDESTAL_A_Z]));
                    }
                })
                .expect("simulation runs");
                a
            };
            let with = az(&sc);
            let mut quiet = sc.clone();
            quiet.pulse = None;
            let without = az(&quiet);
            let d: Vec<(f64, f64)> = with
                .iter()
                .zip(&without)
                .map(|(a, b)| (a.0, a.1 - b.1))
                .collect();
            // The structural part: a.z + P(t)/m_p (the pulse acts along −z).
            let r: Vec<(f64, f64)> = d
                .iter()
                .map(|&(t, v)| (t, v + pulse.force(t) / m_p))
                .collect();
            let dt = 1.0 / fs;
            let dft = |x: &[(f64, f64)], f: f64| {
                let (mut re, mut im) = (0.0, 0.0);
                for &(t, v) in x {
                    let (s, c) = (TAU * f * (t - t0)).sin_cos();
                    re += v * c * dt;
                    im -= v * s * dt;
                }
                (re, im)
            };
            // Analytic transform of the triangle (height F, base T, centre t0 + T/2) in the same
            // time origin: F (T/2) sinc²(f T/2) e^{−i 2π f T/2}.
            let tri = |f: f64| {
                let h = 0.5 * pulse.duration;
                let x = std::f64::consts::PI * f * h;
                let sinc = if x == 0.0 { 1.0 } else { x.sin() / x };
                let mag = pulse.peak * h * sinc * sinc;
                let ph = -TAU * f * h;
                (mag * ph.cos(), mag * ph.sin())
            };
            let (mut best_s, mut best_e) = ((0.0, 0.0), (0.0, 0.0));
            let mut f = 400.0;
            while f <= 800.0 {
                let (sr, si) = dft(&d, f);
                let ms = sr.hypot(si);
                if ms > best_s.1 {
                    best_s = (f, ms);
                }
                let (rr, ri) = dft(&r, f);
                let (pr, pi) = tri(f);
                let me = (rr - pr / m_p).hypot(ri - pi / m_p);
                if me > best_e.1 {
                    best_e = (f, me);
                }
                f += 0.5;
            }
            let on = |t: f64| ((t * fs) - (t * fs).round()).abs() < 1e-6;
            let corners = on(t0) && on(t0 + 0.5 * pulse.duration) && on(t0 + pulse.duration);
            println!(
                "| {:.4} | {:.1} | {} | {:.1} | {:.1} |",
                t0 * 1e3,
                fs / 1e3,
                if corners { "yes" } else { "no" },
                best_s.0,
                best_e.0
            );
        }
    }
}

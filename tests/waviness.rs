//! Distributed defects at the lumped, reduced and full levels (docs/model.md#distributed): race
//! waviness of order
//! n = kZ ± 1 gives the radial lines Wardle (1988) and Yhland (1992) predict, ball waviness the
//! lines of the balls' spin, roughness raises
//! the broadband floor as its RMS² and leaves a spall's lines where they were, the roughness
//! field has the statistics it was asked for, and the scene tables refuse bad values by name.

use raceway::signal::{self, Spectrum, Window};
use raceway::{
    out, Bearing, Fidelity, Harmonic, Race, RoughnessSpec, Scene, SimError, Simulation, TrackField,
    TrackRoughness, WavinessSpec,
};
use std::f64::consts::TAU;
use std::path::Path;

const FS: f64 = 51200.0;
const Z: f64 = 14.0;

fn scene(name: &str) -> Scene {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes")
        .join(name);
    Scene::load(&p).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The Sec. 3.5 bearing (Z = 14) at 9900 rpm without the spall, under the pure axial load of
/// 4000 N: every ball loaded alike, the setting of Wardle's and Yhland's formulas. With the cage
/// at the reduced and full levels (without it each ball orbits at its own rate and the lines
/// of a common cage speed smear).
fn healthy_axial() -> Scene {
    let mut s = scene("sec3.5-outer.toml");
    s.defect = None;
    s.operating.fz = 0.0;
    s.full.cage = true;
    s
}

/// The levels that carry race waviness and roughness.
const LEVELS: [Fidelity; 3] = [Fidelity::Lumped, Fidelity::Reduced, Fidelity::Full];

fn at(level: Fidelity, sc: &Scene) -> Scene {
    let mut s = sc.clone();
    s.fidelity = level;
    s
}

/// `column` of a run of `duration` s sampled at [`FS`], after 20 ms.
fn run(sc: &Scene, duration: f64, column: usize) -> Vec<f64> {
    let mut sim = Simulation::new(sc).expect("simulation builds");
    let mut v = Vec::new();
    sim.advance_sampled(duration, 1.0 / FS, &mut |t, o| {
        if t >= 0.02 {
            v.push(o[column]);
        }
    })
    .expect("simulation runs");
    v
}

/// Amplitude spectrum (Hann) of the pedestal's radial (z) acceleration over 0.3 s.
fn pedestal_spectrum(sc: &Scene) -> Spectrum {
    signal::amplitude_spectrum(&run(sc, 0.32, out::PEDESTAL_A_Z), FS, Window::Hann).unwrap()
}

/// The model's shaft and cage frequencies [Hz].
fn shaft_cage_hz(sc: &Scene) -> (f64, f64) {
    let sim = Simulation::new(sc).unwrap();
    (sc.operating.shaft_speed / TAU, sim.cage_speed() / TAU)
}

fn with_waviness(sc: &Scene, w: WavinessSpec) -> Scene {
    let mut s = sc.clone();
    s.waviness = Some(w);
    s
}

/// The strongest line of `wavy` in `band` is at `expected` (within a bin or 0.5 %), and at
/// least 40 dB above the healthy spectrum there; returns (line frequency, dB above healthy).
fn assert_line(wavy: &Spectrum, healthy: &Spectrum, band: (f64, f64), expected: f64) -> (f64, f64) {
    let p = signal::dominant_peak(wavy, band.0, band.1).expect("a line in the band");
    let tol = wavy.resolution().max(0.005 * expected);
    assert!(
        (p.freq - expected).abs() <= tol,
        "strongest line in {band:?} at {:.2} Hz, predicted {expected:.2} Hz",
        p.freq
    );
    let db = 20.0 * (wavy.value[p.bin] / healthy.value[p.bin]).log10();
    assert!(
        db > 40.0,
        "line at {:.1} Hz only {db:.1} dB above healthy",
        p.freq
    );
    println!(
        "line at {:.2} Hz, predicted {expected:.2} Hz, {db:.1} dB above healthy",
        p.freq
    );
    (p.freq, db)
}

#[test]
fn inner_race_waviness_of_order_kz_pm_1_gives_k_bpfi_pm_fs() {
    for level in LEVELS {
        inner_race_waviness_at(level);
    }
}

fn inner_race_waviness_at(level: Fidelity) {
    let healthy = at(level, &healthy_axial());
    let (f_s, f_c) = shaft_cage_hz(&healthy);
    let bpfi = Z * (f_s - f_c);
    let base = pedestal_spectrum(&healthy);
    println!(
        "{}: f_s {f_s:.3} Hz, f_c {f_c:.3} Hz, BPFI {bpfi:.2} Hz",
        level.name()
    );
    // n = Z + 1: the radial force turns at BPFI + f_s; n = 2Z − 1: at 2·BPFI − f_s.
    for (n, k, sign) in [(15.0, 1.0, 1.0), (27.0, 2.0, -1.0)] {
        let wavy = with_waviness(
            &healthy,
            WavinessSpec {
                inner: vec![Harmonic(n, 0.2e-6, 0.3)],
                ..Default::default()
            },
        );
        let s = pedestal_spectrum(&wavy);
        let band = (k * bpfi - 2.0 * f_s, k * bpfi + 2.0 * f_s);
        assert_line(&s, &base, band, k * bpfi + sign * f_s);
        // The other sideband is not excited: order Z + 1 gives no line at BPFI − f_s.
        let other = k * bpfi - sign * f_s;
        let b = s.bin_of(other).unwrap();
        let line = signal::dominant_peak(&s, band.0, band.1).unwrap().value;
        assert!(
            s.value[b] < 1e-2 * line,
            "line at {other:.1} Hz: {}",
            s.value[b]
        );
    }
}

#[test]
fn outer_race_waviness_of_order_kz_pm_1_gives_k_bpfo() {
    for level in LEVELS {
        outer_race_waviness_at(level);
    }
}

fn outer_race_waviness_at(level: Fidelity) {
    let healthy = at(level, &healthy_axial());
    let (_, f_c) = shaft_cage_hz(&healthy);
    let bpfo = Z * f_c;
    println!("{}: BPFO {bpfo:.2} Hz", level.name());
    let base = pedestal_spectrum(&healthy);
    for (n, k) in [(13.0, 1.0), (29.0, 2.0)] {
        let wavy = with_waviness(
            &healthy,
            WavinessSpec {
                outer: vec![Harmonic(n, 0.2e-6, 1.0)],
                ..Default::default()
            },
        );
        let s = pedestal_spectrum(&wavy);
        assert_line(&s, &base, (0.7 * k * bpfo, 1.3 * k * bpfo), k * bpfo);
    }
}

/// The balls' spin frequency relative to the cage f_b \[Hz\]: at the lumped level the
/// kinematic one, (dm/D)(1 + γ0) f_c; at the ball levels the mean over the balls and over
/// 0.02–0.07 s (states at 1 ms intervals) of each ball's simulated spin relative to its orbit,
/// |ω − θ̇ e_x| (the full level's ball block x, r, θ, ẋ, ṙ, θ̇, ω_x, ω_y, ω_z; the reduced
/// level's x, r, θ, ẋ, ṙ, θ̇, ω_s).
fn ball_spin_hz(sc: &Scene) -> f64 {
    let b = Bearing::new(&sc.bearing).unwrap();
    let mut sim = Simulation::new(sc).unwrap();
    if sc.fidelity == Fidelity::Lumped {
        return b.dm / b.d * (1.0 + b.gamma(b.alpha0)) * sim.cage_speed() / TAU;
    }
    let spin = |y: &[f64], j: usize| match sc.fidelity {
        Fidelity::Full => (y[9 * j + 6] - y[9 * j + 5])
            .hypot(y[9 * j + 7])
            .hypot(y[9 * j + 8]),
        _ => y[7 * j + 6].abs(),
    };
    let (mut sum, mut n) = (0.0, 0);
    for k in 0..=50 {
        sim.advance(0.02 + k as f64 * 1e-3).unwrap();
        for j in 0..b.z {
            sum += spin(sim.state(), j);
            n += 1;
        }
    }
    sum / n as f64 / TAU
}

#[test]
fn even_order_ball_waviness_gives_lines_at_its_order_times_the_ball_spin() {
    // A ball of order n touches both races at opposite points: even orders show at n·f_b
    // (f_b the ball spin relative to the cage: the kinematic one at the lumped level, the
    // simulated one at the ball levels), odd ones cancel. One wavy ball's approach modulates
    // at 2·f_b (n = 2), every ball alike here.
    for level in LEVELS {
        ball_waviness_lines(level);
    }
}

fn ball_waviness_lines(level: Fidelity) {
    let healthy = at(level, &healthy_axial());
    let (f_s, f_c) = shaft_cage_hz(&healthy);
    let b = Bearing::new(&healthy.bearing).unwrap();
    let f_b = ball_spin_hz(&healthy);
    // The textbook BSF at the free angle (fault_frequencies) is the same number at pure rolling.
    let bsf = raceway::fault_frequencies::fault_frequencies(&b, f_s, b.alpha0).bsf;
    println!(
        "{}: f_b {f_b:.3} Hz (f_c {f_c:.3} Hz), BSF {bsf:.2} Hz (pure rolling)",
        level.name()
    );
    let even = with_waviness(
        &healthy,
        WavinessSpec {
            ball: vec![Harmonic(2.0, 0.2e-6, 0.0)],
            ..Default::default()
        },
    );
    let odd = with_waviness(
        &healthy,
        WavinessSpec {
            ball: vec![Harmonic(3.0, 0.2e-6, 0.0)],
            ..Default::default()
        },
    );
    // All balls in phase: the axial force carries the line (radially the balls cancel).
    let fx = |sc: &Scene| {
        signal::amplitude_spectrum(&run(sc, 0.32, out::BEARING_F_X), FS, Window::Hann).unwrap()
    };
    let (s_even, s_odd, base) = (fx(&even), fx(&odd), fx(&healthy));
    assert_line(
        &s_even,
        &base,
        (0.6 * 2.0 * f_b, 1.4 * 2.0 * f_b),
        2.0 * f_b,
    );
    let odd_line = signal::dominant_peak(&s_odd, 0.6 * 3.0 * f_b, 1.4 * 3.0 * f_b).unwrap();
    let even_line = signal::dominant_peak(&s_even, 0.6 * 2.0 * f_b, 1.4 * 2.0 * f_b).unwrap();
    println!(
        "{}: odd order {:.3e} at {:.1} Hz against the even line {:.3e}",
        level.name(),
        odd_line.value,
        odd_line.freq,
        even_line.value
    );
    // At the lumped level the two contacts are exactly opposite and an odd order cancels to
    // round-off; at the ball levels they are not (the inner and outer contact angles differ
    // under the balls' centrifugal force), and it cancels to first order only.
    let cancel = if level == Fidelity::Lumped {
        1e-3
    } else {
        1e-2
    };
    assert!(
        odd_line.value < cancel * even_line.value,
        "{}: odd order: {:.3e} at {:.1} Hz",
        level.name(),
        odd_line.value,
        odd_line.freq
    );
}

#[test]
fn ball_waviness_with_random_phases_gives_radial_lines_at_2_fb_pm_fc() {
    // Balls of order 2 out of phase with one another (Wardle 1988): the radial force of ball j,
    // 2A cos(2 ψ_j + φ_j) e_r(θ_j), carries 2·f_b ± f_c; in phase (the previous test) the
    // balls' radial parts cancel.
    for level in LEVELS {
        random_phase_ball_waviness(level);
    }
}

fn random_phase_ball_waviness(level: Fidelity) {
    let healthy = at(level, &healthy_axial());
    let (_, f_c) = shaft_cage_hz(&healthy);
    let f_b = ball_spin_hz(&healthy);
    let wavy = with_waviness(
        &healthy,
        WavinessSpec {
            ball: vec![Harmonic(2.0, 0.2e-6, 0.0)],
            ball_phase_seed: Some(5),
            ..Default::default()
        },
    );
    let (s, base) = (pedestal_spectrum(&wavy), pedestal_spectrum(&healthy));
    for f in [2.0 * f_b - f_c, 2.0 * f_b + f_c] {
        assert_line(&s, &base, (f - 0.5 * f_c, f + 0.5 * f_c), f);
    }
    // Nothing radial at 2·f_b itself.
    let mid = s.value[s.bin_of(2.0 * f_b).unwrap()];
    let line = signal::peak_near(&s, 2.0 * f_b + f_c, 2.0).unwrap().value;
    assert!(mid < 1e-2 * line, "at 2 f_b: {mid:e} against {line:e}");
}

#[test]
fn an_off_size_ball_adds_its_deviation_to_its_contact_approach() {
    // A ball ΔD larger adds ΔD to its approach at a fixed ring; the ring then gives way. Under a
    // pure axial load every ball has the same contact stiffness k along its normal
    // n_j = (sin α, cos α e_r(θ_j)); the ring's displacement d balances the extra forces,
    // Σ k (ΔD_j + n_j·d) n_j = 0, so sin α d_x = −ΔD/Z (axially) and cos α d_r = −2ΔD/Z
    // (radially toward the big ball, Σ cos²θ_j = Z/2). The big ball's approach grows by
    // ΔD (1 − 3/Z), the opposite ball's by ΔD/Z.
    let healthy = healthy_axial();
    let dd = 1e-6;
    let mut s = healthy.clone();
    let mut dev = vec![0.0; 14];
    dev[0] = dd;
    s.waviness = Some(WavinessSpec {
        ball_diameter_deviation: dev,
        ..Default::default()
    });
    let q = |sc: &Scene| {
        let mut sim = Simulation::new(sc).unwrap();
        let mut o = vec![0.0; sim.output_table().len()];
        sim.outputs(&mut o);
        o[out::CONTACT_START..out::CONTACT_START + 14].to_vec()
    };
    let (q_off, q_nom) = (q(&s), q(&healthy));
    let k = Bearing::new(&healthy.bearing).unwrap().k_series();
    // Approach from the Hertz law of the two contacts in series, δ = (Q/K)^(2/3).
    let d = |q: f64| (q / k).powf(2.0 / 3.0);
    let (big, opposite) = (d(q_off[0]) - d(q_nom[0]), d(q_off[7]) - d(q_nom[7]));
    println!(
        "off-size ball: approach +{big:.4e} m (closed form {:.4e}), opposite +{opposite:.4e} m ({:.4e})",
        dd * (1.0 - 3.0 / Z),
        dd / Z
    );
    assert!((big - dd * (1.0 - 3.0 / Z)).abs() < 0.01 * dd, "{big:e}");
    assert!((opposite - dd / Z).abs() < 0.01 * dd, "{opposite:e}");
}

#[test]
fn roughness_field_has_the_rms_and_gaussian_correlation_it_was_given() {
    // Closed forms: mean square σ², autocorrelation σ² e^(−s²/ℓ²) at lags ℓ/2, ℓ, 2ℓ.
    let sigma = 0.1e-6;
    let ell = 0.5e-3;
    let radius = 0.04;
    let f = TrackField::new(
        &TrackRoughness {
            rms: sigma,
            correlation_length: ell,
            seed: 7,
        },
        radius,
        1,
        "roughness.outer",
    )
    .unwrap();
    let h = f.points();
    let n = h.len();
    let ms = h.iter().map(|v| v * v).sum::<f64>() / n as f64;
    assert!(
        (ms.sqrt() / sigma - 1.0).abs() < 1e-9,
        "rms {:e} vs {sigma:e}",
        ms.sqrt()
    );
    let mean = h.iter().sum::<f64>() / n as f64;
    assert!(mean.abs() < 1e-12 * sigma);
    let ds = TAU * radius / n as f64;
    for lag in [0.5 * ell, ell, 2.0 * ell] {
        let k = (lag / ds).round() as usize;
        let s = k as f64 * ds;
        let r = (0..n).map(|i| h[i] * h[(i + k) % n]).sum::<f64>() / n as f64 / ms;
        let expected = (-(s / ell).powi(2)).exp();
        assert!(
            (r - expected).abs() < 0.01,
            "correlation at {s:e} m: {r:.4}, Gaussian {expected:.4}"
        );
    }
    // Interpolation between table points: continuous, and the derivative is that of h.
    let x = 1.2345;
    let (h0, dh) = f.at(x);
    let e = 1e-7;
    let fd = (f.at(x + e).0 - f.at(x - e).0) / (2.0 * e);
    assert!((fd - dh).abs() < 1e-3 * dh.abs().max(sigma / (ell / radius)));
    assert!(h0.abs() < 6.0 * sigma);
    // Seeded: the same seed gives the same field, another seed another one.
    let again = TrackField::new(
        &TrackRoughness {
            rms: sigma,
            correlation_length: ell,
            seed: 7,
        },
        radius,
        1,
        "x",
    )
    .unwrap();
    assert_eq!(again.points(), h);
    let other = TrackField::new(
        &TrackRoughness {
            rms: sigma,
            correlation_length: ell,
            seed: 8,
        },
        radius,
        1,
        "x",
    )
    .unwrap();
    assert_ne!(other.points(), h);
}

fn rough(sc: &Scene, rms: f64) -> Scene {
    let mut s = sc.clone();
    let t = TrackRoughness {
        rms,
        correlation_length: 1e-3,
        seed: 3,
    };
    s.roughness = Some(RoughnessSpec {
        inner: Some(t),
        outer: Some(t),
    });
    s
}

/// Welch PSD of the pedestal's radial acceleration, 4096-sample Hann segments.
fn psd(sc: &Scene) -> Spectrum {
    signal::welch_psd(
        &run(sc, 0.42, out::PEDESTAL_A_Z),
        FS,
        &signal::WelchConfig::default(),
    )
    .unwrap()
}

#[test]
fn roughness_raises_the_floor_as_its_rms_squared() {
    for level in LEVELS {
        roughness_floor_at(level);
    }
}

fn roughness_floor_at(level: Fidelity) {
    let healthy = at(level, &healthy_axial());
    let (p0, p1, p2) = (
        psd(&healthy),
        psd(&rough(&healthy, 0.05e-6)),
        psd(&rough(&healthy, 0.1e-6)),
    );
    // Bands clear of the lines of a healthy or wavy bearing at this speed (BPFO 979, BPFI 1331).
    for (lo, hi) in [(2000.0, 4000.0), (4000.0, 8000.0)] {
        let (b0, b1, b2) = (
            p0.band_power(lo, hi),
            p1.band_power(lo, hi),
            p2.band_power(lo, hi),
        );
        println!(
            "{}: {lo}-{hi} Hz: healthy {b0:.3e}, rms 0.05 µm {b1:.3e}, rms 0.1 µm {b2:.3e}, ratio {:.3}",
            level.name(),
            b2 / b1
        );
        assert!(b1 > 100.0 * b0, "floor barely raised: {b1:e} over {b0:e}");
        assert!(
            (3.0..5.0).contains(&(b2 / b1)),
            "doubling the rms: ×{:.2} in power",
            b2 / b1
        );
    }
}

#[test]
fn roughness_leaves_a_spalls_bpfo_where_it_was() {
    let spalled = scene("sec3.5-outer.toml");
    let bpfo = Z * shaft_cage_hz(&spalled).1;
    let envelope_peak = |sc: &Scene| {
        let a = run(sc, 0.32, out::PEDESTAL_A_Z);
        let env = signal::envelope_spectrum(&a, FS, Some((2000.0, 12000.0)), Window::Hann).unwrap();
        signal::dominant_peak(&env, 50.0, 1500.0).unwrap()
    };
    let (p0, p1) = (
        envelope_peak(&spalled),
        envelope_peak(&rough(&spalled, 0.1e-6)),
    );
    println!(
        "BPFO {bpfo:.2} Hz: envelope line {:.2} Hz without, {:.2} Hz with roughness",
        p0.freq, p1.freq
    );
    assert!((p1.freq - bpfo).abs() < 0.005 * bpfo);
    assert!((p1.freq - p0.freq).abs() <= p0.freq.max(1.0) * 1e-9 + 1.0 / 0.3);
    assert!(p1.is_significant(3.0));
}

#[test]
fn features_off_change_nothing() {
    // An empty [waviness] table (zero deviations) and zero rms give the same samples, bit for
    // bit, at every level that carries them.
    for level in LEVELS {
        let mut sc = scene("sec3.5-outer.toml");
        sc.fidelity = level;
        let mut off = sc.clone();
        off.waviness = Some(WavinessSpec {
            ball_diameter_deviation: vec![0.0; 14],
            ..Default::default()
        });
        off.roughness = Some(RoughnessSpec {
            inner: Some(TrackRoughness {
                rms: 0.0,
                correlation_length: 1e-3,
                seed: 1,
            }),
            outer: None,
        });
        let duration = if level == Fidelity::Lumped {
            0.03
        } else {
            0.022
        };
        let a = run(&sc, duration, out::PEDESTAL_A_Z);
        let b = run(&off, duration, out::PEDESTAL_A_Z);
        assert!(!a.is_empty());
        assert_eq!(a, b, "{}", level.name());
    }
}

fn parse_err(extra: &str) -> raceway::ConfigError {
    let base = "bearing = \"niu2014-table1\"\n[operating]\nspeed_rpm = 9900.0\nfa = 4000.0\n";
    Scene::from_toml_str(&format!("{base}{extra}"), "test", None).unwrap_err()
}

#[test]
fn bad_values_name_their_field() {
    let cases = [
        (
            "[waviness]\ninner = [[0, 1e-7, 0.0]]",
            "waviness.inner[0]",
            "order",
        ),
        (
            "[waviness]\nouter = [[3, 1e-7, 0.0], [2.5, 1e-7, 0.0]]",
            "waviness.outer[1]",
            "integer",
        ),
        (
            "[waviness]\nball = [[2, 1.0, 0.0]]",
            "waviness.ball[0]",
            "amplitude",
        ),
        (
            "[waviness]\nball = [[2, 1e-7, nan]]",
            "waviness.ball[0]",
            "phase",
        ),
        (
            "[waviness]\nball_diameter_deviation = [0.0, inf]",
            "waviness.ball_diameter_deviation[1]",
            "finite",
        ),
        (
            "[roughness.outer]\nrms = -1e-7\ncorrelation_length = 1e-3",
            "roughness.outer.rms",
            "rms",
        ),
        (
            "[roughness.inner]\nrms = 1e-7\ncorrelation_length = 0.0",
            "roughness.inner.correlation_length",
            "> 0",
        ),
    ];
    for (toml, field, word) in cases {
        let e = parse_err(toml);
        assert_eq!(e.field, field, "{toml}: {e}");
        assert!(
            e.to_string().contains(word) || e.field.contains(word),
            "{toml}: {e}"
        );
    }
    // Unknown keys and malformed harmonics are refused by the parser, naming the key.
    let e = parse_err("[waviness]\ninner_race = [[15, 1e-7, 0.0]]");
    assert!(e.to_string().contains("inner_race"), "{e}");
    let e = parse_err("[roughness]\nrms = 1e-7");
    assert!(e.to_string().contains("rms"), "{e}");
    let e = parse_err("[waviness]\ninner = [[15, 1e-7]]");
    assert!(e.to_string().contains("inner"), "{e}");
    // Checked against the bearing when the model is built: one deviation per ball.
    let mut s = healthy_axial();
    s.waviness = Some(WavinessSpec {
        ball_diameter_deviation: vec![1e-7; 3],
        ..Default::default()
    });
    match Simulation::new(&s) {
        Err(SimError::Config(e)) => assert_eq!(e.field, "waviness.ball_diameter_deviation"),
        other => panic!("{:?}", other.err()),
    }
    // A correlation length too short for the track's table.
    let mut s = rough(&healthy_axial(), 1e-7);
    s.roughness
        .as_mut()
        .unwrap()
        .outer
        .as_mut()
        .unwrap()
        .correlation_length = 1e-8;
    match Simulation::new(&s) {
        Err(SimError::Config(e)) => assert_eq!(e.field, "roughness.outer.correlation_length"),
        other => panic!("{:?}", other.err()),
    }
}

#[test]
fn levels_without_distributed_defects_refuse_them() {
    for level in [Fidelity::Kinematic, Fidelity::QuasiStatic] {
        let s = at(level, &rough(&healthy_axial(), 1e-7));
        match Simulation::new(&s) {
            Err(SimError::Unsupported(m)) => assert!(
                m.contains("[roughness]") && m.contains("lumped, reduced, full"),
                "{m}"
            ),
            other => panic!("{}: {:?}", level.name(), other.err()),
        }
        // An empty table adds nothing and is no reason to refuse.
        let mut s = at(level, &healthy_axial());
        s.waviness = Some(WavinessSpec::default());
        assert!(Simulation::new(&s).is_ok(), "{}", level.name());
    }
}

#[test]
fn a_scene_file_with_waviness_and_roughness_parses() {
    let s = scene("waviness-roughness.toml");
    let w = s.waviness.as_ref().unwrap();
    assert_eq!(w.inner, vec![Harmonic(15.0, 0.2e-6, 0.0)]);
    assert_eq!(s.roughness.unwrap().outer.unwrap().seed, 2);
    let _ = Race::Inner;
}

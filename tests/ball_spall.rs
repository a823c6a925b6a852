//! A spall on a ball (docs/model.md#ball-spall): its envelope line at twice the ball spin
//! frequency with cage-rate sidebands, and the scene file's and levels' handling of it.

use raceway::signal::{self, Window};
use raceway::{out, Scene, Simulation, Site};
use std::f64::consts::TAU;
use std::path::Path;

fn scene_file(name: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn scene(text: &str) -> Result<Scene, String> {
    Scene::from_toml_str(text, "test", None).map_err(|e| e.to_string())
}

/// The pedestal's vertical acceleration of a scene, sampled at `fs` after `skip` s.
fn pedestal_acceleration(sc: &Scene, duration: f64, fs: f64, skip: f64) -> Vec<f64> {
    let mut sim = Simulation::new(sc).expect("simulation builds");
    let mut a = Vec::new();
    sim.advance_sampled(duration, 1.0 / fs, &mut |t, o| {
        if t >= skip {
            a.push(o[out::PEDESTAL_A_Z]);
        }
    })
    .expect("simulation runs");
    a
}

#[test]
fn a_ball_spall_strikes_at_twice_the_ball_spin_frequency_with_cage_sidebands() {
    let sc = scene(&scene_file("ball-spall.toml")).unwrap();
    assert_eq!(sc.defect.as_ref().unwrap().ring, Site::Ball(1));
    let b = Simulation::new(&sc).unwrap().bearing().clone();
    let f_cage = Simulation::new(&sc).unwrap().cage_speed() / TAU;
    let fs_shaft = sc.operating.speed_rpm() / 60.0;
    // The kinematic ball's spin in the cage frame: pure rolling on the fixed outer race at α0,
    // ω_s = ω_c (d_o/D) with d_o = dm + D cos α0, the contact circle's diameter. At the
    // textbook cage speed FTF = (fs/2)(1 − γ) it is the textbook BSF = (dm/2D) fs (1 − γ²).
    let gamma = b.d * b.alpha0.cos() / b.dm;
    let spin_per_cage = (b.dm + b.d * b.alpha0.cos()) / b.d;
    let textbook_bsf = b.dm / (2.0 * b.d) * fs_shaft * (1.0 - gamma * gamma);
    let textbook_ftf = 0.5 * fs_shaft * (1.0 - gamma);
    assert!((spin_per_cage * textbook_ftf - textbook_bsf).abs() < 1e-9 * textbook_bsf);
    let bsf = spin_per_cage * f_cage;
    let two_bsf = 2.0 * bsf;

    let fs = 51200.0;
    let a = pedestal_acceleration(&sc, 0.52, fs, 0.02);
    assert!(a.iter().all(|v| v.is_finite()));
    let env = signal::envelope_spectrum(&a, fs, Some((2000.0, 12000.0)), Window::Hann).unwrap();
    // The strongest line between BSF·1.5 and BSF·2.5 (above the cage-rate harmonics of the
    // spalled ball's trip through the load zone) is 2·BSF.
    let dom = signal::dominant_peak(&env, 1.5 * bsf, 2.5 * bsf).unwrap();
    assert!(
        dom.rel_error(two_bsf).abs() < 0.005,
        "strongest line {:.2} Hz, 2·BSF {two_bsf:.2} Hz",
        dom.freq
    );
    assert!(dom.is_significant(10.0), "prominence {}", dom.prominence);
    // Sidebands at the cage rate: the spall strikes hardest while its ball is in the load zone.
    for sb in signal::sidebands(&env, two_bsf, f_cage, 2, 3.0) {
        let p = sb.peak.expect("sideband inside the spectrum");
        assert!(
            (p.freq - sb.expected_hz).abs() < 3.0 && p.is_significant(10.0),
            "sideband {} at {:.1} Hz: {p:?}",
            sb.order,
            sb.expected_hz
        );
    }
    let cage = signal::peak_near(&env, f_cage, 3.0).unwrap();
    assert!(cage.rel_error(f_cage).abs() < 0.01 && cage.is_significant(10.0));

    // The healthy bearing has no such line: the spall makes it.
    let mut healthy = sc.clone();
    healthy.set_defects(Vec::new());
    let a0 = pedestal_acceleration(&healthy, 0.52, fs, 0.02);
    let env0 = signal::envelope_spectrum(&a0, fs, Some((2000.0, 12000.0)), Window::Hann).unwrap();
    let at = |s: &signal::Spectrum| s.value[s.bin_of(two_bsf).unwrap()];
    assert!(
        at(&env0) < 0.01 * dom.value,
        "healthy {:e} vs spalled {:e}",
        at(&env0),
        dom.value
    );
}

/// The scene file's ball-spall scene at another level.
fn at_level(level: &str) -> Scene {
    scene(
        &scene_file("ball-spall.toml")
            .replace("fidelity = \"lumped\"", &format!("fidelity = \"{level}\"")),
    )
    .unwrap()
}

/// The simulated spin of ball 1 relative to its orbit, |ω − θ̇ e_x| [rad/s], at the state of a
/// ball-level model (the full level's ball block: x, r, θ, ẋ, ṙ, θ̇, ω_x, ω_y, ω_z; the
/// reduced level's: x, r, θ, ẋ, ṙ, θ̇, ω_s about an axis turning with the orbit).
fn ball_1_spin(sc: &Scene, y: &[f64]) -> f64 {
    match sc.fidelity {
        raceway::Fidelity::Full => (y[6] - y[5]).hypot(y[7]).hypot(y[8]),
        raceway::Fidelity::Reduced => y[6].abs(),
        f => panic!("{f:?} has no ball states"),
    }
}

/// Ball 1's mean spin relative to its orbit over `duration` after `skip` [rad/s], from the
/// states at 1 ms intervals.
fn mean_ball_1_spin(sc: &Scene, skip: f64, duration: f64) -> f64 {
    let mut sim = Simulation::new(sc).unwrap();
    sim.advance(skip).unwrap();
    let n = (duration / 1e-3).round() as usize;
    let mut sum = 0.0;
    for k in 1..=n {
        sim.advance(skip + k as f64 * 1e-3).unwrap();
        sum += ball_1_spin(sc, sim.state());
    }
    // The spall's direction on the ball (the last three states) stays a unit vector: u̇ = ω × u
    // keeps |u| but for the integration error.
    let y = sim.state();
    let norm = y[y.len() - 3..].iter().map(|v| v * v).sum::<f64>().sqrt();
    assert!(
        (norm - 1.0).abs() < 1e-6,
        "|u| = {norm} after {} s",
        skip + duration
    );
    sum / n as f64
}

#[test]
fn the_kinematic_levels_impulse_train_of_a_ball_spall_is_at_twice_the_kinematic_ball_spin() {
    // L0 generates the spall's meetings with the races at the kinematic spin of its own cage
    // speed (L1's): 2·BSF with BSF = (dm + D cos α0)/D · f_c, the strikes' strength following
    // the spalled ball's load through the load zone (cage-rate sidebands).
    let sc = at_level("kinematic");
    let sim = Simulation::new(&sc).unwrap();
    let b = sim.bearing().clone();
    let f_cage = sim.cage_speed() / TAU;
    let bsf = (b.dm + b.d * b.alpha0.cos()) / b.d * f_cage;
    // (No resonator at L0: the band starts at 200 Hz.)
    assert_two_bsf_line(&sc, bsf, f_cage, 200.0);
    // Ball 1 loses its load where the spall meets a race: a quarter spin turn from θ0 = 0, then
    // every half turn.
    meets_the_races_in_turn(&sc);
}

#[test]
fn at_the_ball_levels_a_ball_spall_strikes_at_twice_the_simulated_ball_spin_with_cage_sidebands() {
    // The reduced and full levels turn the spall with the ball's own simulated spin: the
    // envelope line is at twice that spin frequency (measured from the states), with the
    // cage-rate sidebands of the spalled ball's trip through the load zone.
    for level in ["reduced", "full"] {
        let sc = at_level(level);
        let bsf = mean_ball_1_spin(&sc, 0.02, 0.1) / TAU;
        let f_cage = Simulation::new(&sc).unwrap().cage_speed() / TAU;
        assert_two_bsf_line(&sc, bsf, f_cage, 2000.0);
    }
}

/// The envelope spectrum (`low` Hz to 12 kHz) of a scene's pedestal acceleration over 0.5 s
/// after 20 ms: its strongest line between 1.5 and 2.5 × `bsf` is 2·BSF within 0.5 % with a
/// prominence of at least 10, and the first sidebands at ∓ `f_cage` are there (within 3 Hz,
/// prominence at least 5).
fn assert_two_bsf_line(sc: &Scene, bsf: f64, f_cage: f64, low: f64) {
    let level = sc.fidelity.name();
    let fs = 51200.0;
    let a = pedestal_acceleration(sc, 0.52, fs, 0.02);
    assert!(a.iter().all(|v| v.is_finite()));
    let env = signal::envelope_spectrum(&a, fs, Some((low, 12000.0)), Window::Hann).unwrap();
    let dom = signal::dominant_peak(&env, 1.5 * bsf, 2.5 * bsf).unwrap();
    eprintln!(
        "{level}: 2·BSF {:.3} Hz, line {:.3} Hz ({:+.3} %), prominence {:.1}",
        2.0 * bsf,
        dom.freq,
        100.0 * dom.rel_error(2.0 * bsf),
        dom.prominence
    );
    assert!(
        dom.rel_error(2.0 * bsf).abs() < 0.005 && dom.is_significant(10.0),
        "{level}: strongest line {:.2} Hz (prominence {:.1}), 2·BSF {:.2} Hz",
        dom.freq,
        dom.prominence,
        2.0 * bsf
    );
    for sb in signal::sidebands(&env, dom.freq, f_cage, 1, 3.0) {
        let p = sb.peak.expect("sideband inside the spectrum");
        eprintln!(
            "{level}: sideband {} at {:.1} Hz: {:.1} Hz, prominence {:.1}",
            sb.order, sb.expected_hz, p.freq, p.prominence
        );
        assert!(
            (p.freq - sb.expected_hz).abs() < 3.0 && p.is_significant(5.0),
            "{level}: sideband {} at {:.1} Hz: {p:?}",
            sb.order,
            sb.expected_hz
        );
    }
}

#[test]
fn a_ball_spall_meets_the_outer_and_the_inner_race_in_turn() {
    // Ball 1's contact force drops where its spall meets a race: the spin angle from the
    // scene's θ0 = 0 reaches π/2 (outer) after a quarter spin turn and 3π/2 (inner) after three
    // quarters, then every turn. The drops of the force of ball 1 come at those times (within a
    // contact's passage), and the other balls' forces show none. At the lumped level the spin
    // is the kinematic one; at the ball levels the ball's own (its start value).
    for level in ["lumped", "reduced", "full"] {
        meets_the_races_in_turn(&at_level(level));
    }
}

fn meets_the_races_in_turn(sc: &Scene) {
    let mut sim = Simulation::new(sc).unwrap();
    let b = sim.bearing().clone();
    let kinematic = [raceway::Fidelity::Lumped, raceway::Fidelity::Kinematic];
    let w_spin = if kinematic.contains(&sc.fidelity) {
        (b.dm + b.d * b.alpha0.cos()) / b.d * sim.cage_speed()
    } else {
        ball_1_spin(sc, sim.state())
    };
    let names: Vec<String> = sim.output_table().into_iter().map(|o| o.name).collect();
    let col = |n: &str| names.iter().position(|c| c == n).expect(n);
    // (At the lumped level a ball's two contact forces are one: its series contact.)
    let (q1, q2) = (col("contact.outer.Q[1]"), col("contact.outer.Q[2]"));
    let qi1 = col("contact.inner.Q[1]");
    let fs = 400_000.0;
    let (mut t, mut f1, mut f2, mut fi1) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let turn = TAU / w_spin;
    sim.advance_sampled(2.2 * turn, 1.0 / fs, &mut |ts, o| {
        t.push(ts);
        f1.push(o[q1]);
        f2.push(o[q2]);
        fi1.push(o[qi1]);
    })
    .unwrap();
    // Where a force drops to (nearly) nothing: the ball falls into the spall and leaves the
    // race (the rattle after it stays above 70 % of the mean). The middle of each such run.
    // (L0's load loss keeps the part of the static approach the spall's drop does not reach:
    // 6 % here.)
    let floor = if sc.fidelity == raceway::Fidelity::Kinematic {
        0.1
    } else {
        0.01
    };
    let dips = |f: &[f64]| -> Vec<f64> {
        let mean = f.iter().sum::<f64>() / f.len() as f64;
        let low: Vec<bool> = f.iter().map(|&q| q < floor * mean).collect();
        let mut out = Vec::new();
        let mut start = None;
        for (i, &l) in low.iter().enumerate() {
            match (l, start) {
                (true, None) => start = Some(i),
                (false, Some(s)) => {
                    out.push(0.5 * (t[s] + t[i - 1]));
                    start = None;
                }
                _ => {}
            }
        }
        out
    };
    let level = sc.fidelity;
    let expected: Vec<f64> = [0.25, 0.75, 1.25, 1.75].iter().map(|k| k * turn).collect();
    let first_dips = |f: &[f64]| {
        // At the ball levels the ball rattles after each strike: the first dip of each pass.
        let mut d = dips(f);
        d.dedup_by(|b, a| *b - *a < 0.35 * turn);
        d
    };
    let d1 = first_dips(&f1);
    assert_eq!(
        d1.len(),
        expected.len(),
        "{level:?}: dips of ball 1 at {d1:?}, expected {expected:?}"
    );
    for (got, want) in d1.iter().zip(&expected) {
        // The spall is 1 mm wide on a ball of 12.7 mm: it takes 1/40 turn to pass a contact.
        assert!(
            (got - want).abs() < 0.02 * turn,
            "{level:?}: dip at {got:e} s, expected {want:e} s (spin turn {turn:e} s)"
        );
    }
    if !kinematic.contains(&level) {
        // The ball levels have both contacts: each strike unloads both (the ball falls in).
        let di = first_dips(&fi1);
        assert_eq!(di.len(), expected.len(), "{level:?}: inner dips at {di:?}");
    }
    assert!(dips(&f2).is_empty(), "ball 2 dips at {:?}", dips(&f2));
}

#[test]
fn scene_files_name_the_ball_and_refuse_what_is_not_a_ball_spall() {
    let base = scene_file("ball-spall.toml");
    // No ball number.
    let e = scene(&base.replace("ball = 1\n", "")).unwrap_err();
    assert!(
        e.contains("defect.ball") && e.contains("needs the ball's number"),
        "{e}"
    );
    // Not a ball number.
    let e = scene(&base.replace("ball = 1\n", "ball = 0\n")).unwrap_err();
    assert!(
        e.contains("defect.ball") && e.contains("numbered from 1"),
        "{e}"
    );
    // A ball number with a raceway spall.
    let e = scene(&base.replace("ring = \"ball\"", "ring = \"outer\"")).unwrap_err();
    assert!(
        e.contains("defect.ball") && e.contains("ring = \"outer\""),
        "{e}"
    );
    // Beyond the bearing's 14 balls: refused when the model is built.
    let sc = scene(&base.replace("ball = 1\n", "ball = 15\n")).unwrap();
    let e = Simulation::new(&sc).err().unwrap().to_string();
    assert!(
        e.contains("defect.ball") && e.contains("balls 1 to 14"),
        "{e}"
    );
    let sc = scene(&base.replace("ball = 1\n", "ball = 14\n")).unwrap();
    assert!(Simulation::new(&sc).is_ok());
    // The level without it (the quasi-static one: no dynamics) refuses it, naming those that
    // have it.
    let sc = at_level("quasi_static");
    let e = Simulation::new(&sc).err().unwrap().to_string();
    assert!(
        e.contains("the quasi_static level")
            && e.contains("spall on a ball")
            && e.contains("levels that do: kinematic, lumped, reduced, full"),
        "{e}"
    );
}

const TWO: &str = r#"
name = "two"
bearing = "niu2014-table1"
fidelity = "lumped"
[operating]
speed_rpm = 9900.0
fa = 4000.0
fr = 1000.0
[[defect]]
ring = "outer"
width = 1.0e-3
depth = 0.2e-3
theta0 = 3.1416
[[defect]]
ring = "ball"
ball = 3
width = 1.0e-3
depth = 0.2e-3
theta0 = THETA
"#;

#[test]
fn spalls_on_balls_and_races_mix_in_one_scene_and_two_on_one_ball_must_not_overlap() {
    let sc = scene(&TWO.replace("THETA", "0.0")).unwrap();
    assert_eq!(sc.defects().nth(1).unwrap().ring, Site::Ball(3));
    let mut sim = Simulation::new(&sc).unwrap();
    // Ball 3 loses contact where its spall meets a race (a quarter spin turn in, then every
    // half turn); ball 1 only at the outer-race spall, which it does not reach in this time.
    let names: Vec<String> = sim.output_table().into_iter().map(|o| o.name).collect();
    let col = |n: &str| names.iter().position(|c| c == n).expect(n);
    let (q1, q3) = (col("contact.outer.Q[1]"), col("contact.outer.Q[3]"));
    let (mut zero1, mut zero3) = (0, 0);
    sim.advance_sampled(0.004, 2.5e-6, &mut |_, o| {
        zero1 += usize::from(o[q1] == 0.0);
        zero3 += usize::from(o[q3] == 0.0);
    })
    .unwrap();
    assert!(
        zero3 > 0 && zero1 == 0,
        "samples without contact: ball 1 {zero1}, ball 3 {zero3}"
    );
    // An error in the second entry names it, when the file is read and when the model is built.
    let second = |from: &str, to: &str| TWO.replace("THETA", "0.0").replace(from, to);
    let e = scene(&second("ball = 3\n", "ball = -2\n")).unwrap_err();
    assert!(e.contains("defect[1].ball"), "{e}");
    let beyond = scene(&second("ball = 3\n", "ball = 15\n")).unwrap();
    let e = Simulation::new(&beyond).err().unwrap().to_string();
    assert!(
        e.contains("defect[1].ball") && e.contains("balls 1 to 14"),
        "{e}"
    );
    // A second spall on ball 3 overlapping the first (1 mm wide on a 12.7 mm ball: half angle
    // 0.0787 rad each).
    let three = format!(
        "{}\n[[defect]]\nring = \"ball\"\nball = 3\nwidth = 1.0e-3\ndepth = 0.2e-3\ntheta0 = OTHER\n",
        TWO.replace("THETA", "0.5")
    );
    let e = Simulation::new(&scene(&three.replace("OTHER", "0.65")).unwrap())
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("defect[2]") && e.contains("defect[1]") && e.contains("ball 3"),
        "{e}"
    );
    assert!(Simulation::new(&scene(&three.replace("OTHER", "0.66")).unwrap()).is_ok());
}

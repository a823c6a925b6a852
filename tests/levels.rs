//! The cheap levels of the ladder through `Simulation`: kinematic (L0s) and quasi_static (L1),
//! checked against L1's own solve, the fault-frequency formulas and the load-zone closed form.

use raceway::load_distribution;
use raceway::models::KinematicModel;
use raceway::signal::{self, Window};
use raceway::{out, Bearing, CageSpeed, Fidelity, OperatingPoint, Race, Scene, Simulation};
use std::f64::consts::{PI, TAU};

/// The default scene with L1's cage speed (outer-race control): these tests check the levels
/// against L1; `kinematic_impulse_train_sits_at_the_paper_fault_frequencies_with_traction`
/// checks the default traction cage speed.
fn scene(level: Fidelity, ring: Option<Race>) -> Scene {
    let mut s = Scene::default_scene();
    s.fidelity = level;
    s.lumped.cage_speed = CageSpeed::OuterRaceControl;
    match ring {
        None => s.defect = None,
        Some(r) => {
            let d = s.defect.as_mut().unwrap();
            d.ring = r.into();
            if r == Race::Inner {
                d.theta0 = 0.0;
            }
        }
    }
    s
}

fn accel(s: &Scene, t_end: f64, fs: f64) -> Vec<f64> {
    let mut sim = Simulation::new(s).unwrap();
    let mut a = Vec::new();
    sim.advance_sampled(t_end, 1.0 / fs, &mut |t, o| {
        if t >= 0.01 {
            a.push(o[out::PEDESTAL_A_Z]);
        }
    })
    .unwrap();
    a
}

/// L1 cage speed of the default operating point [rad/s].
fn l1_cage() -> (f64, f64) {
    let s = Scene::default_scene();
    let b = Bearing::new(&s.bearing).unwrap();
    let qs =
        load_distribution::solve(&b, &OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0)).unwrap();
    (qs.cage_speed, 9900.0 * TAU / 60.0)
}

/// Envelope peaks of the kinematic level at the L1 fault frequency: BPFO = z ω_c/2π (outer),
/// BPFI = z(Ω − ω_c)/2π (inner), within 0.5 % and 10 dB over the floor; healthy: silent.
#[test]
fn kinematic_impulse_train_sits_at_the_l1_fault_frequencies() {
    let fs = 51_200.0;
    let (wc, omega) = l1_cage();
    for (ring, f) in [
        (Race::Outer, 14.0 * wc / TAU),
        (Race::Inner, 14.0 * (omega - wc) / TAU),
    ] {
        let a = accel(&scene(Fidelity::Kinematic, Some(ring)), 0.25, fs);
        let env = signal::envelope_spectrum(&a, fs, Some((1000.0, 20000.0)), Window::Hann).unwrap();
        let p = signal::peak_near(&env, f, 0.05 * f).expect("peak");
        assert!(p.rel_error(f).abs() < 0.005, "{ring:?}: {} vs {f}", p.freq);
        assert!(
            p.is_significant(3.0),
            "{ring:?}: prominence {}",
            p.prominence
        );
    }
    let a = accel(&scene(Fidelity::Kinematic, None), 0.05, fs);
    assert!(a.iter().all(|v| *v == 0.0));
}

/// With the default traction cage speed the kinematic impulse train sits at the paper's fault
/// frequencies (docs/model.md#ref-dynamic: BPFO 980.4 Hz, BPFI 1329 Hz, each ± 0.3 %), which L1's outer-race
/// control misses (985.9 / 1324.1 Hz).
#[test]
fn kinematic_impulse_train_sits_at_the_paper_fault_frequencies_with_traction() {
    let fs = 51_200.0;
    for (ring, f) in [(Race::Outer, 980.4), (Race::Inner, 1329.0)] {
        let mut s = scene(Fidelity::Kinematic, Some(ring));
        s.lumped.cage_speed = CageSpeed::Traction;
        let mut sim = Simulation::new(&s).unwrap();
        let wc = sim.cage_speed();
        let model = match ring {
            Race::Outer => 14.0 * wc / TAU,
            Race::Inner => 14.0 * (9900.0 / 60.0 - wc / TAU),
        };
        assert!(
            (model / f - 1.0).abs() < 3e-3,
            "{ring:?}: model {model} vs paper {f}"
        );
        let mut a = Vec::new();
        sim.advance_sampled(0.25, 1.0 / fs, &mut |t, o| {
            if t >= 0.01 {
                a.push(o[out::PEDESTAL_A_Z]);
            }
        })
        .unwrap();
        let env = signal::envelope_spectrum(&a, fs, Some((1000.0, 20000.0)), Window::Hann).unwrap();
        let p = signal::peak_near(&env, f, 0.05 * f).expect("peak");
        // 4 Hz bins over 0.24 s: the peak within half a percent.
        assert!(p.rel_error(f).abs() < 0.005, "{ring:?}: {} vs {f}", p.freq);
    }
}

/// q(θ) = q_max[1 − (1 − cos θ)/(2ε)]^1.5: q(0) = q_max; ε = 1 → q(π/2) = q_max/√8, q(π) = 0;
/// ε = ∞ (pure axial) → q_max everywhere; beyond the load zone 0.
#[test]
fn load_zone_closed_form() {
    assert_eq!(KinematicModel::load_zone(700.0, 0.5, 0.0), 700.0);
    let v = KinematicModel::load_zone(700.0, 1.0, PI / 2.0);
    assert!((v - 700.0 / 8f64.sqrt()).abs() < 1e-9, "{v}");
    assert_eq!(KinematicModel::load_zone(700.0, 1.0, PI), 0.0);
    assert_eq!(KinematicModel::load_zone(700.0, 0.5, 2.0), 0.0);
    assert_eq!(KinematicModel::load_zone(700.0, f64::INFINITY, 2.0), 700.0);
}

/// The quasi-static level at t = 0 reproduces L1's per-ball loads (balls at 2πj/z), the pedestal
/// sits at −Fr/k_p, accelerations are 0 and the cage speed is L1's; half a ball spacing later
/// the set of loads has moved with the cage (ball j between L1's j and j+1).
#[test]
fn quasi_static_level_outputs_are_the_l1_solution() {
    let s = scene(Fidelity::QuasiStatic, Some(Race::Outer));
    let b = Bearing::new(&s.bearing).unwrap();
    let qs =
        load_distribution::solve(&b, &OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0)).unwrap();
    let mut sim = Simulation::new(&s).unwrap();
    let mut o = vec![0.0; sim.output_table().len()];
    sim.outputs(&mut o);
    for (j, ball) in qs.balls.iter().enumerate() {
        assert!((o[out::CONTACT_START + j] - ball.q_inner).abs() < 1e-9 * ball.q_inner.max(1.0));
        assert!(
            (o[out::CONTACT_START + 14 + j] - ball.q_outer).abs() < 1e-9 * ball.q_outer.max(1.0)
        );
    }
    let zp = -1000.0 / s.bearing.pedestal.k_z;
    assert!((o[out::PEDESTAL_Z] - zp).abs() < 1e-15);
    assert_eq!(o[out::PEDESTAL_A_Z], 0.0);
    assert!((o[out::CAGE_SPEED] - qs.cage_speed).abs() < 1e-12 * qs.cage_speed);
    // Half a spacing later.
    sim.advance(PI / 14.0 / qs.cage_speed).unwrap();
    sim.outputs(&mut o);
    for j in 0..14 {
        let (lo, hi) = (qs.balls[j].q_inner, qs.balls[(j + 1) % 14].q_inner);
        let q = o[out::CONTACT_START + j];
        assert!(
            q >= lo.min(hi) - 1e-6 && q <= lo.max(hi) + 1e-6,
            "{j}: {q} not between {lo} and {hi}"
        );
    }
}

/// The reduced level is deprecated (docs/model.md#l3): a simulation of it starts with a warning
/// that says so, why, and which levels to use; no other level warns at the default scene.
#[test]
fn only_the_deprecated_reduced_level_starts_with_a_deprecation_warning() {
    for level in raceway::models::LEVELS.iter().map(|l| l.fidelity) {
        let mut s = Scene::default_scene();
        s.fidelity = level;
        let w = Simulation::new(&s).unwrap().take_warnings();
        let deprecation: Vec<&String> = w.iter().filter(|m| m.contains("deprecated")).collect();
        if level == Fidelity::Reduced {
            assert_eq!(deprecation.len(), 1, "{w:?}");
            let m = deprecation[0];
            for part in [
                "fidelity \"reduced\" (L3, FMU fidelity = 3) is deprecated",
                "full level's steps",
                "use \"full\" (4) or \"lumped\" (2) instead",
            ] {
                assert!(m.contains(part), "{part:?} not in {m:?}");
            }
        } else {
            assert!(deprecation.is_empty(), "{level:?}: {w:?}");
        }
    }
}

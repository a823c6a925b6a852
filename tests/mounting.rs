//! The axially located inner ring (issue 17 item 5): a single angular-contact bearing carries a
//! pure radial load when its inner ring is held axially, as it is when mounted. Checked against
//! the force-controlled solve (an independent problem with the same equilibrium), at every
//! level and through the scene file (the FMU's parameters: fmu/tests/mounting.rs; the CLI's
//! `static --axial-offset`: cli/tests/cli_static.rs).

use raceway::load_distribution::{solve, solve_located};
use raceway::{
    out, AxialMount, Bearing, CouplingMode, Fidelity, Mounting, OperatingPoint, Scene, Simulation,
};

fn table1() -> Bearing {
    Bearing::load("niu2014-table1").unwrap()
}

#[test]
fn the_location_reaction_is_the_axial_load_of_the_same_equilibrium() {
    // Held at δa under Fr alone, the location supplies an axial force R; loading the free ring
    // with Fa = R and the same Fr must find the ring at δa again, with the same ball loads.
    let b = table1();
    for (rpm, fr, held) in [
        (0.0, 2000.0, 0.0),
        (9900.0, 4000.0, 0.0),
        (9900.0, 4000.0, 5e-6),
    ] {
        let case = OperatingPoint::from_rpm(rpm, 0.0, fr);
        let located = solve_located(&b, &case, held).unwrap();
        let r = located.ring_force();
        assert!((located.delta_axial - held).abs() < 1e-15);
        assert!(r[0] > 0.1 * fr, "axial reaction {} N", r[0]);
        assert!((r[2] - case.fz).abs() < 1e-5, "radial balance {r:?}");
        let free = solve(&b, &OperatingPoint::from_rpm(rpm, r[0], fr)).unwrap();
        assert!(
            (free.delta_axial - held).abs() < 1e-10,
            "{rpm} rpm, Fr {fr}: free ring at {} m, located at {held} m",
            free.delta_axial
        );
        assert!((free.delta_z - located.delta_z).abs() < 1e-10);
        for (a, c) in free.balls.iter().zip(&located.balls) {
            assert!((a.q_inner - c.q_inner).abs() < 1e-5 * (1.0 + a.q_inner));
        }
    }
}

#[test]
fn a_pure_radial_load_is_refused_unless_the_ring_is_located() {
    let b = table1();
    let case = OperatingPoint::from_rpm(5000.0, 0.0, 3000.0);
    let e = solve(&b, &case).unwrap_err().to_string();
    assert!(e.contains("located"), "{e}");
    assert!(solve_located(&b, &case, 0.0).is_ok());
}

fn located_scene(level: Fidelity, fa: f64, fr: f64, offset: Option<f64>) -> Scene {
    let mut s = Scene::healthy(
        raceway::BearingFile::load("niu2014-table1").unwrap(),
        OperatingPoint::from_rpm(6000.0, fa, fr),
    );
    s.fidelity = level;
    s.mounting = Mounting {
        axial: AxialMount::Located,
        axial_offset: offset,
    };
    s
}

#[test]
fn every_level_runs_a_located_ring_under_a_pure_radial_load() {
    // The ring stays at its place and bearing.F.x is the location's reaction: exactly L1's at
    // the static levels; at the dynamic ones its mean over the run within 4 % (they ring after
    // the start, and the traction's axial components, which L1 has not, take 2–3 % at the
    // reduced and full levels over 20 ms), against L1 at rest for the lumped level (no
    // centrifugal ball forces at L2).
    let b = table1();
    let case = OperatingPoint::from_rpm(6000.0, 0.0, 3000.0);
    let at_speed = solve_located(&b, &case, 2e-6).unwrap().ring_force()[0];
    let rest = OperatingPoint {
        shaft_speed: 0.0,
        ..case
    };
    let at_rest = solve_located(&b, &rest, 2e-6).unwrap().ring_force()[0];
    for (level, t_end) in [
        (Fidelity::Kinematic, 0.02),
        (Fidelity::QuasiStatic, 0.02),
        (Fidelity::Lumped, 0.02),
        (Fidelity::Reduced, 4e-3),
        (Fidelity::Full, 4e-3),
    ] {
        let mut scene = located_scene(level, 0.0, 3000.0, Some(2e-6));
        // The tilt held (decision D1 (docs/model.md#d1); with the ring's own tilt inertia free, it rocks).
        scene.full.lock_tilt = true;
        // Without a cage, as L1: a cage starts the unloaded balls of this partial load zone at
        // the caged rate and its pockets push them, which moves the 4 ms mean by another 1–2 %.
        scene.full.cage = false;
        let mut sim = Simulation::new(&scene).unwrap();
        let (mut fx, mut n) = (0.0, 0);
        let mut x_range = (f64::MAX, f64::MIN);
        sim.advance_sampled(t_end, 2e-5, &mut |_, o| {
            fx += o[out::BEARING_F_X];
            n += 1;
            x_range = (x_range.0.min(o[out::RING_X]), x_range.1.max(o[out::RING_X]));
        })
        .unwrap();
        let mean = fx / n as f64;
        let reaction = if level == Fidelity::Lumped {
            at_rest
        } else {
            at_speed
        };
        eprintln!("{level:?}: bearing.F.x {mean:.1} N, L1 reaction {reaction:.1} N");
        let tol = match level {
            Fidelity::Kinematic | Fidelity::QuasiStatic => 1e-9,
            _ => 0.04,
        };
        assert!(
            (mean + reaction).abs() < tol * reaction,
            "{level:?}: {mean} vs {reaction}"
        );
        assert!(
            (x_range.0 - 2e-6).abs() < 1e-12 && (x_range.1 - 2e-6).abs() < 1e-12,
            "{level:?}: ring.x {x_range:?}"
        );
    }
}

#[test]
fn located_by_default_where_the_start_axial_load_puts_the_ring() {
    // ring.axial = 1: the start's Fa alone sets the place (a preload), then the ring is held
    // there while the radial load acts; the load input Fx cannot change afterwards.
    let b = table1();
    let preload = solve(&b, &OperatingPoint::from_rpm(6000.0, 1000.0, 0.0)).unwrap();
    let mut sim =
        Simulation::new(&located_scene(Fidelity::QuasiStatic, 1000.0, 4000.0, None)).unwrap();
    let mut o = vec![0.0; sim.output_table().len()];
    sim.outputs(&mut o);
    assert!((o[out::RING_X] - preload.delta_axial).abs() < 1e-15);
    // The radial load adds axial thrust the location takes: more than the preload.
    assert!(-o[out::BEARING_F_X] > 1000.0, "{}", o[out::BEARING_F_X]);
    let mut i = sim.inputs();
    i.fz = -3000.0;
    sim.set_inputs(i).unwrap();
    i.fx = 2000.0;
    let e = sim.set_inputs(i).unwrap_err().to_string();
    assert!(e.contains("load.Fx") && e.contains("located"), "{e}");
}

#[test]
fn scene_files_and_fmu_parameters_set_the_mounting() {
    let text = r#"
        bearing = "niu2014-table1"
        fidelity = "quasi_static"
        [operating]
        speed_rpm = 3000.0
        fr = 2000.0
        [mounting]
        axial = "located"
        axial_offset = 1e-6
    "#;
    let s = Scene::from_toml_str(text, "test", None).unwrap();
    assert_eq!(s.mounting.axial, AxialMount::Located);
    assert_eq!(s.mounting.axial_offset, Some(1e-6));
    // An offset without a located ring, a located ring in motion coupling: errors naming the key.
    let e = Scene::from_toml_str(&text.replace("\"located\"", "\"load\""), "test", None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("mounting.axial_offset"), "{e}");
    let mut m = s.clone();
    m.coupling = CouplingMode::Motion;
    assert!(m
        .validate()
        .unwrap_err()
        .to_string()
        .contains("mounting.axial"));
}

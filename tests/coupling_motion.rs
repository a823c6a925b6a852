//! Coupling mode "motion" (issue 6): the journal's motion in, the bearing's reaction out, at
//! every level; the reaction Jacobian against central finite differences of the reaction itself
//! (the journal moved through the public API, an independent path from the analytic formulas).
#![allow(clippy::needless_range_loop)] // 3×3 index arithmetic reads best with indices

use raceway::models::ReactionJacobian;
use raceway::{out, CouplingMode, Fidelity, Journal, OperatingPoint, Scene, Simulation};

fn scene(fidelity: Fidelity, spall: bool) -> Scene {
    let mut s = Scene::default_scene();
    s.fidelity = fidelity;
    // The full level's analytic Jacobian covers the normal forces (frictionless contacts).
    s.full.traction = false;
    s.coupling = CouplingMode::Motion;
    if !spall {
        s.defect = None;
    }
    s
}

fn outputs(sim: &mut Simulation) -> Vec<f64> {
    let mut o = vec![0.0; sim.output_table().len()];
    sim.try_outputs(&mut o).expect("outputs");
    o
}

fn force(sim: &mut Simulation) -> [f64; 3] {
    let o = outputs(sim);
    [
        o[out::BEARING_F_X],
        o[out::BEARING_F_Y],
        o[out::BEARING_F_Z],
    ]
}

/// Central differences of bearing.F in the journal's displacement (h_x) and velocity (h_v),
/// moving the journal at the current time (no integration).
fn fd_jacobian(sim: &mut Simulation, h_x: f64, h_v: f64) -> ReactionJacobian {
    let j0 = sim.journal();
    let mut jac = ReactionJacobian::default();
    for k in 0..3 {
        for (h, is_x) in [(h_x, true), (h_v, false)] {
            let mut f = [[0.0; 3]; 2];
            for (s, sign) in [1.0, -1.0].into_iter().enumerate() {
                let mut j = j0;
                if is_x {
                    j.x[k] += sign * h;
                } else {
                    j.v[k] += sign * h;
                }
                sim.set_journal(j).unwrap();
                f[s] = force(sim);
            }
            for i in 0..3 {
                let d = (f[0][i] - f[1][i]) / (2.0 * h);
                if is_x {
                    jac.dfdx[i][k] = d;
                } else {
                    jac.dfdv[i][k] = d;
                }
            }
        }
    }
    sim.set_journal(j0).unwrap();
    jac
}

fn max_abs(m: &[[f64; 3]; 3]) -> f64 {
    m.iter().flatten().fold(0.0_f64, |a, v| a.max(v.abs()))
}

/// Largest entry difference relative to the largest entry, for ∂F/∂x and ∂F/∂v.
fn rel_diff(a: &ReactionJacobian, b: &ReactionJacobian) -> (f64, f64) {
    let d = |p: &[[f64; 3]; 3], q: &[[f64; 3]; 3]| {
        let mut m = 0.0_f64;
        for i in 0..3 {
            for k in 0..3 {
                m = m.max((p[i][k] - q[i][k]).abs());
            }
        }
        m / max_abs(q).max(1e-300)
    };
    (d(&a.dfdx, &b.dfdx), d(&a.dfdv, &b.dfdv))
}

#[test]
fn lumped_motion_starts_in_equilibrium_and_follows_the_journal() {
    starts_in_equilibrium_and_follows_the_journal(Fidelity::Lumped, 1e-3);
}

#[test]
fn reduced_motion_starts_in_equilibrium_and_follows_the_journal() {
    // L1 (the start) has no traction; at 9900 rpm the rolling traction of the L3 (and L4) start
    // adds about 330 N across the load (bearing.F.y) at t = 0, so the balance is looser here.
    starts_in_equilibrium_and_follows_the_journal(Fidelity::Reduced, 0.1);
}

fn starts_in_equilibrium_and_follows_the_journal(fidelity: Fidelity, rel: f64) {
    let sc = scene(fidelity, true);
    let mut sim = Simulation::new(&sc).unwrap();
    let o = outputs(&mut sim);
    // The start: the ring at the static equilibrium under the scene's loads (L1 start), so the
    // reaction balances the load.
    let load = [sc.operating.fx, sc.operating.fy, sc.operating.fz];
    for k in 0..3 {
        assert!(
            (o[out::BEARING_F_X + k] + load[k]).abs() < rel * 4000.0,
            "F[{k}] = {} vs load {}",
            o[out::BEARING_F_X + k],
            load[k]
        );
    }
    let j0 = sim.journal();
    assert_eq!(
        [o[out::RING_X], o[out::RING_Y], o[out::RING_Z]],
        j0.x,
        "ring.* is the journal"
    );
    // A velocity over a step: the ring ends at x + v H exactly (linear motion integrated).
    let v = [1e-4, -2e-4, 3e-4];
    let h = 1e-4;
    sim.set_journal(Journal { x: j0.x, v }).unwrap();
    sim.advance(h).unwrap();
    let o = outputs(&mut sim);
    for k in 0..3 {
        let expect = j0.x[k] + v[k] * h;
        assert!(
            (o[out::RING_X + k] - expect).abs() < 1e-15,
            "ring[{k}] {} vs {expect}",
            o[out::RING_X + k]
        );
    }
    // Load inputs are ignored after the start: same reaction with a different load.
    let f1 = force(&mut sim);
    let mut inp = sim.inputs();
    inp.fz -= 500.0;
    sim.set_inputs(inp).unwrap();
    let f2 = force(&mut sim);
    assert_eq!(f1, f2);
}

/// Sets the journal where the ring is now (keeping its velocity), so that the linearization
/// point and the finite differences' centre coincide.
fn anchor(sim: &mut Simulation) {
    let o = outputs(sim);
    let mut j = sim.journal();
    j.x = [o[out::RING_X], o[out::RING_Y], o[out::RING_Z]];
    sim.set_journal(j).unwrap();
}

/// Checks the Jacobian against finite differences along a run with the journal moving; returns
/// the largest relative errors (∂F/∂x, ∂F/∂v) and how many checks had a ball in the spall.
fn check_along_run(fidelity: Fidelity, spall: bool, checks: usize) -> (f64, f64, usize) {
    let sc = scene(fidelity, spall);
    let mut sim = Simulation::new(&sc).unwrap();
    let mut healthy = Simulation::new(&scene(fidelity, false)).unwrap();
    let z = sim.bearing().z;
    let (mut ex_max, mut ev_max, mut in_spall) = (0.0_f64, 0.0_f64, 0);
    for step in 0..checks * 10 {
        let v = [
            2e-4 * (0.3 * step as f64).sin(),
            1e-4,
            -1e-4 * (0.2 * step as f64).cos(),
        ];
        for s in [&mut sim, &mut healthy] {
            let mut j = s.journal();
            let dt = s.time() - 0.0;
            let _ = dt;
            j.v = v;
            s.set_journal(j).unwrap();
            let t = s.time();
            s.advance(t + 2e-5).unwrap();
            anchor(s);
        }
        if step % 10 != 9 {
            continue;
        }
        let a = sim.reaction_jacobian().unwrap();
        let fd = fd_jacobian(&mut sim, 1e-9, 1e-4);
        let (ex, ev) = rel_diff(&a, &fd);
        assert!(
            ex < 1e-4 && ev < 1e-4,
            "{fidelity:?} spall {spall}, t = {}: ∂F/∂x rel. error {ex:e}, ∂F/∂v {ev:e}\nanalytic {a:?}\nfd {fd:?}",
            sim.time()
        );
        ex_max = ex_max.max(ex);
        ev_max = ev_max.max(ev);
        let o = outputs(&mut sim);
        let oh = outputs(&mut healthy);
        let q = &o[out::CONTACT_START..out::CONTACT_START + z];
        let qh = &oh[out::CONTACT_START..out::CONTACT_START + z];
        // A ball in the spall carries clearly less than the same ball without the spall (at
        // the full level it may lift off the spall floor); every other contact is closed.
        assert!(
            q.iter().zip(qh).all(|(a, b)| *a > 0.0 || *a < 0.8 * b),
            "every contact outside the spall closed at the checks: {q:?}"
        );
        if q.iter().zip(qh).any(|(a, b)| *a < 0.8 * b) {
            in_spall += 1;
        }
    }
    (ex_max, ev_max, in_spall)
}

#[test]
fn lumped_reaction_jacobian_matches_finite_differences() {
    // Along a run with the journal moving (so that the damping terms, ȧ ≠ 0, count), healthy
    // and with the spall (the spall's modified Hertz constant while a ball is in it).
    let (ex, ev, _) = check_along_run(Fidelity::Lumped, false, 10);
    eprintln!("lumped healthy: max rel. error dF/dx {ex:.1e}, dF/dv {ev:.1e}");
    let (ex, ev, in_spall) = check_along_run(Fidelity::Lumped, true, 90);
    eprintln!(
        "lumped spall: max rel. error dF/dx {ex:.1e}, dF/dv {ev:.1e}, {in_spall} checks with a ball in the spall"
    );
    assert!(
        in_spall >= 3,
        "only {in_spall} checks had a ball in the spall"
    );
}

#[test]
fn full_reaction_jacobian_matches_finite_differences_without_traction() {
    let (ex, ev, _) = check_along_run(Fidelity::Full, false, 4);
    eprintln!("full healthy: max rel. error dF/dx {ex:.1e}, dF/dv {ev:.1e}");
    let (ex, ev, in_spall) = check_along_run(Fidelity::Full, true, 50);
    eprintln!(
        "full spall: max rel. error dF/dx {ex:.1e}, dF/dv {ev:.1e}, {in_spall} checks with a ball in the spall"
    );
    assert!(
        in_spall >= 2,
        "only {in_spall} checks had a ball in the spall"
    );
}

#[test]
fn full_motion_prescribes_the_ring_translation() {
    let mut sim = Simulation::new(&scene(Fidelity::Full, true)).unwrap();
    let j0 = sim.journal();
    let v = [-1e-4, 2e-4, 1e-4];
    sim.set_journal(Journal { x: j0.x, v }).unwrap();
    sim.advance(3e-4).unwrap();
    let o = outputs(&mut sim);
    for k in 0..3 {
        let expect = j0.x[k] + v[k] * 3e-4;
        assert!((o[out::RING_X + k] - expect).abs() < 1e-15, "ring[{k}]");
    }
}

#[test]
fn quasi_static_levels_give_the_displacement_controlled_reaction() {
    for fidelity in [Fidelity::Kinematic, Fidelity::QuasiStatic] {
        let sc = scene(fidelity, false);
        let mut sim = Simulation::new(&sc).unwrap();
        // The start reproduces the load (the L1 equilibrium, displacement-controlled).
        let f = force(&mut sim);
        let load = [sc.operating.fx, sc.operating.fy, sc.operating.fz];
        for k in 0..3 {
            assert!(
                (f[k] + load[k]).abs() < 1e-3,
                "{fidelity:?} F[{k}] {}",
                f[k]
            );
        }
        // Push the journal 2 µm down: the reaction grows along +z by about k_zz · 2 µm.
        let a = sim.reaction_jacobian().unwrap();
        let fd = fd_jacobian(&mut sim, 1e-9, 1e-4);
        let (ex, ev) = rel_diff(&a, &fd);
        eprintln!("{fidelity:?}: ∂F/∂x rel. error {ex:.1e}");
        assert!(ex < 1e-4, "{fidelity:?}: {a:?} vs {fd:?}");
        assert_eq!(ev, 0.0);
        let mut j = sim.journal();
        j.x[2] -= 2e-6;
        sim.set_journal(j).unwrap();
        let f2 = force(&mut sim);
        let expect = -a.dfdx[2][2] * 2e-6;
        assert!(
            ((f2[2] - f[2]) - expect).abs() < 0.1 * expect.abs(),
            "{fidelity:?}: ΔF_z {} vs linear {expect}",
            f2[2] - f[2]
        );
        sim.advance(1e-3).unwrap();
        let o = outputs(&mut sim);
        assert_eq!(o[out::RING_Z], j.x[2]);
    }
}

#[test]
fn coupling_mode_in_scenes() {
    let base =
        "bearing = \"niu2014-table1\"\n[operating]\nspeed_rpm = 9900.0\nfa = 4000.0\nfr = 1000.0\n";
    let s = Scene::from_toml_str(base, "t", None).unwrap();
    assert_eq!(s.coupling, CouplingMode::Force);
    let s =
        Scene::from_toml_str(&format!("{base}[coupling]\nmode = \"motion\"\n"), "t", None).unwrap();
    assert_eq!(s.coupling, CouplingMode::Motion);
    let e = Scene::from_toml_str(&format!("{base}[coupling]\nmode = \"moton\"\n"), "t", None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("coupling.mode") && e.contains("moton"), "{e}");
    // Force mode refuses a journal and the Jacobian.
    let mut sim = Simulation::new(&Scene::from_toml_str(base, "t", None).unwrap()).unwrap();
    assert!(sim.set_journal(Journal::default()).is_err());
    assert!(sim.reaction_jacobian().is_err());
}

#[test]
/// Motion coupling, lumped level: when the speed moves, the cage speed moves to the traction's
/// caged balance at the new speed and the start's loads, whatever the journal's state then (the
/// reaction of a journal pressed 5 µm down would give another cage speed): it depends on the
/// inputs alone, so masters that hand the same inputs get the same cage speed (issue 19).
fn lumped_cage_speed_follows_the_speed_at_the_start_loads_not_the_journal() {
    use raceway::load_distribution::solve;
    let sc = scene(Fidelity::Lumped, false);
    let mut sim = Simulation::new(&sc).unwrap();
    // Press the journal 5 µm down (more radial load than the start's), then change the speed.
    let mut j = sim.journal();
    j.x[2] -= 5e-6;
    sim.set_journal(j).unwrap();
    let f = force(&mut sim);
    let mut inp = sim.inputs();
    let cage0 = sim.cage_speed();
    inp.shaft_speed *= 1.1;
    sim.set_inputs(inp).unwrap();
    // The L1 point moves at the start of the next step.
    assert!((sim.cage_speed() - 1.1 * cage0).abs() < 1e-12 * cage0);
    let t = sim.time();
    sim.advance(t + 1e-9).unwrap();
    // The traction solve at an L1 point (started
    // here from L1's outer-race control, in the simulation from the last ratio: both converge
    // to within 1e-9 of the shaft speed).
    let traction = |fx: f64, fy: f64, fz: f64| {
        let inputs = OperatingPoint { fx, fy, fz, ..inp };
        let l1 = solve(
            sim.bearing(),
            &OperatingPoint {
                shaft_speed: inp.shaft_speed,
                fx,
                fy,
                fz,
            },
        )
        .unwrap();
        raceway::models::traction_cage_speed(sim.bearing(), &inputs, Some(&l1), None).unwrap()
    };
    let expect = traction(-f[0], -f[1], -f[2]);
    let at_start_loads = traction(sc.operating.fx, sc.operating.fy, sc.operating.fz);
    assert!(f[2] > 1.5 * (-sc.operating.fz), "radial reaction {}", f[2]);
    assert!(
        (sim.cage_speed() - at_start_loads).abs() < 1e-8 * at_start_loads,
        "{} vs {at_start_loads}",
        sim.cage_speed()
    );
    assert!((expect - at_start_loads).abs() > 1e-6 * expect);
}

/// Lumped level, motion mode, speed ramp: the result does not depend on whether the master sets
/// the speed or the journal first within a communication point, and L1 is re-solved once per
/// 2 % of speed, not at every step (the cage speed stays ratio × speed between re-solves).
#[test]
fn lumped_speed_ramp_is_independent_of_the_input_order() {
    let sc = scene(Fidelity::Lumped, true);
    let mut a = Simulation::new(&sc).unwrap();
    let mut b = Simulation::new(&sc).unwrap();
    let j0 = a.journal();
    let s0 = a.inputs().shaft_speed;
    let h = 2e-5;
    let mut ratios = Vec::new();
    for k in 0..100 {
        let t = k as f64 * h;
        // A journal orbit and a 10 % speed ramp over the run.
        let mut j = j0;
        j.x[1] += 2e-6 * (3000.0 * t).sin();
        j.x[2] += 2e-6 * (3000.0 * t).cos() - 2e-6;
        j.v = [0.0, 6e-3 * (3000.0 * t).cos(), -6e-3 * (3000.0 * t).sin()];
        let mut inp = a.inputs();
        inp.shaft_speed = s0 * (1.0 + 0.1 * t / (100.0 * h));
        a.set_inputs(inp).unwrap();
        a.set_journal(j).unwrap();
        b.set_journal(j).unwrap();
        b.set_inputs(inp).unwrap();
        a.advance(t + h).unwrap();
        b.advance(t + h).unwrap();
        ratios.push(a.cage_speed() / inp.shaft_speed);
    }
    assert_eq!(outputs(&mut a), outputs(&mut b));
    // Piecewise-constant cage ratio: it changes 4 or 5 times over a 10 % ramp (2 % steps).
    let changes = ratios.windows(2).filter(|w| w[0] != w[1]).count();
    assert!((4..=5).contains(&changes), "{changes} L1 re-solves");
}

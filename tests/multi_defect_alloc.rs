//! With several spalls (two outer, one inner) the lumped and reduced models' right-hand side,
//! event functions and mode updates do not allocate (a counting global allocator watches
//! them), with balls inside the spall zones; the event count is 2z + 3z per spall. The ball
//! levels' event functions one at a time (what the root finder calls) are those of all at once,
//! bit for bit, and do not allocate either.

use raceway::models::{FullModel, LumpedModel, Model, ReducedModel};
use raceway::{Bearing, DefectSpec, Fidelity, OperatingPoint, Race, Scene, Site};
#[path = "common/alloc_counter.rs"]
mod alloc_counter;
use alloc_counter::allocations_during;

fn spall(ring: Race, theta0: f64) -> DefectSpec {
    DefectSpec {
        ring: ring.into(),
        width: 1.0e-3,
        depth: 0.2e-3,
        theta0,
    }
}

#[test]
fn rhs_and_events_do_not_allocate_with_three_spalls() {
    let file = raceway::BearingFile::load("niu2014-table1").unwrap();
    let mut scene = Scene::healthy(file, OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0));
    scene.set_defects(vec![
        spall(Race::Outer, 0.0),
        spall(Race::Outer, 0.1),
        spall(Race::Inner, 0.05),
    ]);
    assert_eq!(scene.n_defects(), 3);
    let bearing = Bearing::new(&scene.bearing).unwrap();
    let inputs = scene.operating;
    let z = bearing.z;
    for level in [Fidelity::Lumped, Fidelity::Reduced] {
        scene.fidelity = level;
        let mut m: Box<dyn Model> = match level {
            Fidelity::Lumped => Box::new(LumpedModel::new(&scene, &bearing, &inputs).unwrap()),
            _ => Box::new(ReducedModel::new(&scene, &bearing, &inputs).unwrap()),
        };
        let n = m.dim();
        let mut y = vec![0.0; n];
        m.initial_state(&mut y);
        if level == Fidelity::Reduced {
            assert_eq!(m.n_events(), 2 * z + 3 * z * 3);
        }
        let mut d = vec![0.0; n];
        let mut o = vec![0.0; raceway::output_table(z).len()];
        let mut g = vec![0.0; m.n_events()];
        // Move the balls over the spalls: sweep the cage angle (state 10 of the lumped level,
        // the reference cage angle ψ of the reduced level).
        let psi = match level {
            Fidelity::Reduced => Some(
                ReducedModel::new(&scene, &bearing, &inputs)
                    .unwrap()
                    .layout()
                    .psi(),
            ),
            _ => None,
        };
        let mut in_zone = 0;
        let (count, ()) = allocations_during(|| {
            for k in 0..16 {
                let s = -0.3 + 0.6 * k as f64 / 15.0;
                match psi {
                    Some(p) => y[p] = s,
                    None => y[10] = s,
                }
                m.update_mode(0.0, &y);
                m.rhs(0.0, &y, &mut d);
                m.events(0.0, &y, &mut g);
                m.outputs(0.0, &y, &mut o);
                // Balls whose outer contact force dropped to 0 are over a spall.
                in_zone += (0..z)
                    .filter(|&j| o[raceway::out::CONTACT_START + z + j] == 0.0)
                    .count();
            }
        });
        assert!(d.iter().all(|v| v.is_finite()), "{level:?}");
        assert_eq!(count, 0, "allocations in rhs/events/outputs ({level:?})");
        assert!(in_zone > 0, "{level:?}: no ball reached a spall");
    }
}

/// `Model::event(i)` is `Model::events()[i]` bit for bit, for every function of the reduced and
/// full levels (contacts and every spall slot's edge, centre and blend functions), over a sweep
/// of the cage angle that takes balls across the spalls, and it does not allocate. Two sets of
/// spalls: two raceway spalls and a spall on ball 3; one raceway spall and spalls on balls 3
/// and 8 (an odd number of raceway slots before the ball spalls' two slots each).
#[test]
fn one_event_function_is_that_of_all_bit_for_bit() {
    let file = raceway::BearingFile::load("niu2014-table1").unwrap();
    let on_ball = |j: usize, theta0: f64| {
        let mut d = spall(Race::Outer, theta0);
        d.ring = Site::Ball(j);
        d
    };
    for (spalls, slots) in [
        (
            vec![
                spall(Race::Outer, 0.0),
                spall(Race::Inner, 0.05),
                on_ball(2, 1.2),
            ],
            4,
        ),
        (
            vec![spall(Race::Outer, 0.0), on_ball(2, 1.2), on_ball(7, 0.3)],
            5,
        ),
    ] {
        let mut scene = Scene::healthy(
            file.clone(),
            OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0),
        );
        scene.set_defects(spalls);
        let bearing = Bearing::new(&scene.bearing).unwrap();
        let inputs = scene.operating;
        let z = bearing.z;
        for level in [Fidelity::Reduced, Fidelity::Full] {
            scene.fidelity = level;
            let (mut m, psi): (Box<dyn Model>, usize) = match level {
                Fidelity::Reduced => {
                    let m = ReducedModel::new(&scene, &bearing, &inputs).unwrap();
                    let psi = m.layout().psi();
                    (Box::new(m), psi)
                }
                _ => {
                    let m = FullModel::new(&scene, &bearing, &inputs).unwrap();
                    let psi = m.layout().psi();
                    (Box::new(m), psi)
                }
            };
            let ne = m.n_events();
            assert_eq!(ne, 2 * z + 3 * z * slots, "{level:?}: {slots} spall slots");
            let n = m.dim();
            let mut y = vec![0.0; n];
            m.initial_state(&mut y);
            let (mut all, mut one, mut scratch) = (vec![0.0; ne], vec![0.0; ne], vec![0.0; ne]);
            let mut differ = Vec::new();
            let (mut contact_sides, mut spall_negative) = ([0, 0], 0);
            for k in 0..24 {
                y[psi] = -0.3 + 0.6 * k as f64 / 23.0;
                m.update_mode(0.0, &y);
                m.events(0.0, &y, &mut all);
                let (count, ()) = allocations_during(|| {
                    for (i, g) in one.iter_mut().enumerate() {
                        scratch.fill(f64::NAN);
                        *g = m.event(i, 0.0, &y, &mut scratch);
                    }
                });
                assert_eq!(count, 0, "{level:?}: allocations in event");
                for i in 0..ne {
                    if all[i].to_bits() != one[i].to_bits() {
                        differ.push((k, i, all[i], one[i]));
                    }
                }
                for &g in &all[..2 * z] {
                    contact_sides[usize::from(g > 0.0)] += 1;
                }
                spall_negative += all[2 * z..].iter().filter(|&&g| g < 0.0).count();
            }
            assert!(
                differ.is_empty(),
                "{level:?}: (sweep, function, all, one) {differ:?}"
            );
            // The sweep reaches the functions' other sides: contacts lost over a spall, balls
            // in a spall's zone and past its centre.
            assert!(
                contact_sides[0] > 0 && contact_sides[1] > 0 && spall_negative > 0,
                "{level:?}: contact functions (≤ 0, > 0) {contact_sides:?}, negative spall \
                 functions {spall_negative}"
            );
        }
    }
}

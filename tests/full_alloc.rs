//! The full model's right-hand side and event functions do not allocate (a counting global
//! allocator watches them), with and without a spall, with balls inside the spall zone.

use raceway::models::FullModel;
use raceway::models::Model;
use raceway::{Bearing, DefectSpec, Fidelity, OperatingPoint, Race, Scene};
#[path = "common/alloc_counter.rs"]
mod alloc_counter;
use alloc_counter::allocations_during;

#[test]
fn rhs_and_events_do_not_allocate() {
    let file = raceway::BearingFile::load("niu2014-table1").unwrap();
    let mut scene = Scene::healthy(file, OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0));
    scene.fidelity = Fidelity::Full;
    for defect in [None, Some(Race::Outer), Some(Race::Inner)] {
        scene.defect = defect.map(|ring| DefectSpec {
            ring: ring.into(),
            width: 1.0e-3,
            depth: 0.2e-3,
            theta0: 0.0,
        });
        let bearing = Bearing::new(&scene.bearing).unwrap();
        let inputs = scene.operating;
        let mut m = FullModel::new(&scene, &bearing, &inputs).unwrap();
        let n = m.dim();
        let mut y = vec![0.0; n];
        m.initial_state(&mut y);
        // Move ball 0 onto the spall (θ_d0 = 0, ball 0 starts at a clear azimuth).
        let lay = m.layout();
        let psi = lay.psi();
        let mut d = vec![0.0; n];
        let mut g = vec![0.0; m.n_events()];
        let mut shifts = Vec::new();
        for k in 0..8 {
            shifts.push(-0.3 + 0.6 * k as f64 / 7.0);
        }
        let (n, ()) = allocations_during(|| {
            for &s in &shifts {
                y[psi] = s;
                m.update_mode(0.0, &y);
                m.rhs(0.0, &y, &mut d);
                m.events(0.0, &y, &mut g);
            }
        });
        assert!(d.iter().all(|v| v.is_finite()));
        assert_eq!(n, 0, "allocations in rhs/events/update_mode ({defect:?})");
    }
}

//! A step with waviness, off-size balls and roughness does not allocate, at every level that
//! carries them (their tables are built with the model). The counting allocator counts the
//! test's own thread.

use raceway::{Fidelity, Harmonic, RoughnessSpec, Scene, Simulation, TrackRoughness, WavinessSpec};
#[path = "common/alloc_counter.rs"]
mod alloc_counter;
use alloc_counter::allocations_during;

#[test]
fn distributed_defects_do_not_allocate_in_a_step() {
    for level in [Fidelity::Lumped, Fidelity::Reduced, Fidelity::Full] {
        let mut s = Scene::default_scene();
        s.fidelity = level;
        let t = TrackRoughness {
            rms: 0.1e-6,
            correlation_length: 1e-3,
            seed: 3,
        };
        s.roughness = Some(RoughnessSpec {
            inner: Some(t),
            outer: Some(t),
        });
        s.waviness = Some(WavinessSpec {
            inner: vec![Harmonic(15.0, 0.1e-6, 0.0)],
            outer: vec![Harmonic(13.0, 0.1e-6, 0.0)],
            // (At the reduced and full levels ball waviness adds each ball's reference
            // direction to the states.)
            ball: vec![Harmonic(2.0, 0.1e-6, 0.0)],
            ball_phase_seed: Some(1),
            ball_diameter_deviation: vec![0.1e-6; 14],
        });
        let mut sim = Simulation::new(&s).unwrap();
        let mut o = vec![0.0; sim.output_table().len()];
        let h = 1e-4;
        sim.advance(h).unwrap();
        sim.outputs(&mut o);
        let (n, ()) = allocations_during(|| {
            for k in 2..=20 {
                sim.advance(k as f64 * h).unwrap();
                sim.outputs(&mut o);
            }
        });
        assert_eq!(n, 0, "{}: {n} allocations in 19 advances", level.name());
    }
}

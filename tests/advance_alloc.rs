//! A communication step does not allocate in the steady state, at every level: the checkpoint
//! an advance takes (so that a failure leaves no trace) reuses its buffers, and so does reading
//! the outputs. A counting global allocator watches 0.1 ms advances after a first one.

use raceway::{Fidelity, Scene, Simulation};
#[path = "common/alloc_counter.rs"]
mod alloc_counter;
use alloc_counter::allocations_during;

#[test]
fn advances_and_outputs_do_not_allocate() {
    for level in (0..=4).filter_map(Fidelity::from_code) {
        let mut s = Scene::default_scene();
        s.fidelity = level;
        no_allocation_in_advances(&s);
    }
}

#[test]
fn a_spall_on_a_ball_adds_no_allocation() {
    // Its direction states and switch slots at the ball levels, its passes at L0 (ball
    // waviness: tests/waviness_alloc.rs).
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/ball-spall.toml");
    for level in [
        Fidelity::Kinematic,
        Fidelity::Lumped,
        Fidelity::Reduced,
        Fidelity::Full,
    ] {
        let mut s = Scene::load(&path).unwrap();
        s.fidelity = level;
        no_allocation_in_advances(&s);
    }
}

#[test]
fn the_counter_sees_the_allocations_of_its_thread() {
    // The tests above can fail: a vector made inside is counted.
    let (n, v) = allocations_during(|| vec![0u8; 64]);
    assert!(n >= 1 && v.len() == 64, "{n}");
}

/// 19 advances of 0.1 ms and their outputs after a first one allocate nothing.
fn no_allocation_in_advances(s: &Scene) {
    let mut sim = Simulation::new(s).unwrap();
    let mut o = vec![0.0; sim.output_table().len()];
    let h = 1e-4;
    sim.advance(h).unwrap();
    sim.outputs(&mut o);
    // 2 ms: spall passes, stops and events on the way at the dynamic levels.
    let (n, ()) = allocations_during(|| {
        for k in 2..=20 {
            sim.advance(k as f64 * h).unwrap();
            sim.outputs(&mut o);
        }
    });
    assert_eq!(
        n,
        0,
        "{}: {n} allocations in 19 advances",
        s.fidelity.name()
    );
}

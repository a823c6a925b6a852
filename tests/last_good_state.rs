//! The last good state after a failure: an advance that fails (here: its step budget,
//! `solver.max_steps`, is too small for its length) leaves the simulation exactly where it
//! started, at every level — state, modes, registered spall passes, output memory, work
//! counters — and says where the integrator stopped. The continuation is then the one of a
//! simulation that was never asked, bit for bit.

use raceway::{Fidelity, Scene, SimError, Simulation};

/// Communication step of the good advances [s].
const H: f64 = 1e-4;

/// The default scene (outer-race spall in the load zone) with a partial load zone at `level`,
/// with a budget that the
/// 0.1 ms advances stay within and a long one exceeds (kinematic: spall passes; quasi-static:
/// the few steps of its two angles).
fn scene(level: Fidelity) -> (Scene, f64) {
    let mut s = Scene::default_scene();
    s.fidelity = level;
    // A partial load zone: balls leave and regain contact, so contact modes switch too.
    s.operating.fx = 2000.0;
    s.operating.fz = -4000.0;
    let (budget, long) = match level {
        Fidelity::Kinematic => (50, 10.0),
        Fidelity::QuasiStatic => (2, 1e9),
        Fidelity::Lumped => (400, 1.0),
        Fidelity::Reduced | Fidelity::Full => (400, 1.0),
    };
    s.solver.max_steps = budget;
    (s, long)
}

fn outputs(sim: &mut Simulation) -> Vec<u64> {
    let mut o = vec![0.0; sim.output_table().len()];
    sim.outputs(&mut o);
    o.iter().map(|v| v.to_bits()).collect()
}

/// Advances in steps of [`H`] from the current time, `n` times, reading every output after
/// each step (as an FMU master does); returns the outputs of each step.
fn steps(sim: &mut Simulation, n: usize) -> Vec<Vec<u64>> {
    let t0 = sim.time();
    (1..=n)
        .map(|k| {
            sim.advance(t0 + k as f64 * H)
                .unwrap_or_else(|e| panic!("step {k}: {e}"));
            outputs(sim)
        })
        .collect()
}

/// At every level: a failed advance (plain, or sampled) puts everything back, and the run goes
/// on as if it had not been asked.
#[test]
fn a_failed_advance_leaves_every_level_where_it_started() {
    for level in (0..=4).filter_map(Fidelity::from_code) {
        let (sc, long) = scene(level);
        let n = if matches!(level, Fidelity::Reduced | Fidelity::Full) {
            5
        } else {
            20
        };
        let mut reference = Simulation::new(&sc).unwrap();
        let mut sim = Simulation::new(&sc).unwrap();
        steps(&mut reference, n);
        steps(&mut sim, n);
        let t1 = sim.time();
        let before = outputs(&mut sim);
        let (snapshot, stats) = (sim.save_state(), sim.stats());
        for sampled in [false, true] {
            let target = t1 + long;
            let r = if sampled {
                sim.advance_sampled(target, 1e-5, &mut |_, _| {})
            } else {
                sim.advance(target)
            };
            let name = format!("{} (sampled: {sampled})", level.name());
            match &r {
                Err(SimError::Solver { t, message }) => {
                    assert!(*t > t1 && *t <= target, "{name}: stopped at {t}");
                    assert!(message.contains("work discarded"), "{name}: {message}");
                }
                other => panic!("{name}: expected a solver error, got {other:?}"),
            }
            assert_eq!(sim.time(), t1, "{name}");
            assert_eq!(sim.stats(), stats, "{name}");
            assert!(sim.save_state() == snapshot, "{name}: the state differs");
            assert_eq!(outputs(&mut sim), before, "{name}: the outputs differ");
        }
        // A successful advance undone is the same.
        sim.advance(t1 + H).unwrap();
        sim.undo_advance().unwrap();
        assert!(sim.save_state() == snapshot, "{}: undo", level.name());
        assert!(
            sim.undo_advance().is_err(),
            "{}: undone twice",
            level.name()
        );
        let (a, b) = (steps(&mut sim, n), steps(&mut reference, n));
        let first = a.iter().zip(&b).enumerate().find_map(|(k, (x, y))| {
            let i = x.iter().zip(y).position(|(p, q)| p != q)?;
            Some((k, i, f64::from_bits(x[i]), f64::from_bits(y[i])))
        });
        assert_eq!(
            first,
            None,
            "{}: the continuation differs (step, output, value, reference)",
            level.name()
        );
    }
}

/// The kinematic level's catch-up (the spall passes it registers lazily) counts against the
/// step budget, sampled or not: an advance of 1e6 s (about 1e9 passes) with the default budget
/// of 2 000 000 fails at once, naming the passes and the budget, and leaves the simulation where
/// it was; so does a sampled one whose samples lie 1e5 s apart (1e8 passes each).
#[test]
fn the_kinematic_catch_up_is_bounded_by_the_step_budget() {
    let mut sc = Scene::default_scene();
    sc.fidelity = Fidelity::Kinematic;
    let mut sim = Simulation::new(&sc).unwrap();
    sim.advance(0.01).unwrap();
    let snapshot = sim.save_state();
    for sampled in [false, true] {
        let started = std::time::Instant::now();
        let r = if sampled {
            sim.advance_sampled(1e6, 1e5, &mut |_, _| {})
        } else {
            sim.advance(1e6)
        };
        assert!(started.elapsed().as_secs_f64() < 1.0, "sampled: {sampled}");
        let e = r.expect_err("an advance over 1e9 spall passes");
        let text = e.to_string();
        assert!(
            matches!(e, SimError::Solver { .. })
                && text.contains("spall passes")
                && text.contains("2000000"),
            "sampled: {sampled}: {text}"
        );
        assert_eq!(sim.time(), 0.01);
        assert!(sim.save_state() == snapshot, "sampled: {sampled}");
    }
}

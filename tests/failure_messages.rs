//! A failed advance says why in facts the code knows, not a guess: which state limited the
//! collapsed step (named by the level: "resonator velocity along z", "ball 3 orbital rate θ̇"),
//! whether the right-hand side gave non-finite values, and, where the level can tell, that
//! contact is lost at every ball.

use raceway::models::Model;
use raceway::{Bearing, CouplingMode, Fidelity, Journal, Resonator, Scene, SimError, Simulation};

/// A resonator at 100 THz on the lumped level's pedestal: an explicit method would need steps
/// of about 1e-15 s, below the minimum step (1e-14 s), so the step collapses at the start, and
/// the message names the resonator's velocity as the state whose error limits it, with its
/// index, and no longer guesses ("stiff or discontinuous right-hand side?").
#[test]
fn a_collapsed_step_names_the_state_that_limits_it() {
    let mut s = Scene::default_scene();
    s.lumped.resonator = Some(Resonator {
        frequency: 1e14,
        damping_ratio: 0.05,
        mass: 1e-3,
    });
    let mut sim = Simulation::new(&s).unwrap();
    let e = sim.advance(1e-3).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, SimError::Solver { .. }), "{text}");
    for needle in [
        "fell below the minimum 1.0e-14 s",
        "the error estimate of resonator velocity along z (state 13)",
        "times its tolerance",
    ] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
    assert!(!text.contains("stiff or discontinuous"), "{text}");
    assert_eq!(sim.time(), 0.0);
}

/// Coupling mode "motion" at the reduced and full levels: the journal pulled 50 µm against the
/// axial load opens every contact; a step budget of 200 then runs out on the free pedestal, and
/// the message adds that contact is lost at every ball there.
#[test]
fn a_failure_with_every_contact_open_says_so() {
    for level in [Fidelity::Reduced, Fidelity::Full] {
        let mut s = Scene::default_scene();
        s.fidelity = level;
        s.coupling = CouplingMode::Motion;
        s.solver.max_steps = 200;
        let mut sim = Simulation::new(&s).unwrap();
        let j = sim.journal();
        sim.set_journal(Journal {
            x: [j.x[0] - 5e-5, j.x[1], j.x[2]],
            v: [0.0; 3],
        })
        .unwrap();
        let text = sim.advance(1.0).unwrap_err().to_string();
        for needle in [
            "step budget exhausted",
            "contact is lost at every ball (none of the 14 balls presses on both races)",
        ] {
            assert!(text.contains(needle), "{}: {needle}: {text}", level.name());
        }
    }
}

/// Every level names each of its states (balls counted from 1, as in the outputs).
#[test]
fn every_level_names_its_states() {
    let s = Scene::default_scene();
    let bearing = Bearing::new(&s.bearing).unwrap();
    let inputs = s.operating;
    let expect: [(Fidelity, &[(usize, &str)]); 5] = [
        (
            Fidelity::Kinematic,
            &[(0, "cage angle θ_c"), (1, "shaft angle φ")],
        ),
        (
            Fidelity::QuasiStatic,
            &[(0, "cage angle θ_c"), (1, "shaft angle φ")],
        ),
        (
            Fidelity::Lumped,
            &[
                (2, "inner-ring displacement along z"),
                (9, "pedestal velocity along z"),
                (10, "cage angle θ_c"),
            ],
        ),
        (
            Fidelity::Reduced,
            // 7 states per ball: x, r, θ, ẋ, ṙ, θ̇, ω_s.
            &[
                (2 * 7 + 5, "ball 3 orbital rate θ̇"),
                (2 * 7 + 6, "ball 3 spin rate ω_s"),
                (14 * 7 + 4, "inner-ring velocity along y"),
                (14 * 7 + 6 + 3, "pedestal velocity along z"),
            ],
        ),
        (
            Fidelity::Full,
            // 9 states per ball, then the ring (10), the pedestal (4), ψ and φ.
            &[
                (2 * 9 + 5, "ball 3 orbital rate θ̇"),
                (13 * 9 + 8, "ball 14 ω_z"),
                (14 * 9 + 9, "inner-ring tilt rate β̇_z"),
                (14 * 9 + 10 + 1, "pedestal displacement along z"),
                (14 * 9 + 14, "reference cage angle ψ"),
                (14 * 9 + 15, "shaft angle φ"),
            ],
        ),
    ];
    for (level, names) in expect {
        let mut sc = s.clone();
        sc.fidelity = level;
        let model: Box<dyn Model> = raceway::models::build(&sc, &bearing, &inputs).unwrap();
        for &(i, name) in names {
            assert_eq!(model.state_name(i), name, "{} state {i}", level.name());
        }
        for i in 0..model.dim() {
            let n = model.state_name(i);
            assert!(
                !n.starts_with("state component"),
                "{}: {i} unnamed",
                level.name()
            );
        }
    }
}

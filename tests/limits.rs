//! Plausibility limits (issue 17 item 4): the ISO 76 static load rating computed from the
//! geometry, against the published catalogue ratings of the bearings the presets describe.

use raceway::{
    peak_contact, Bearing, CouplingMode, Fidelity, Race, Scene, SimError, Simulation, StaticRating,
};

#[test]
fn static_rating_matches_the_catalogue_of_the_preset_bearings() {
    // SKF 6205 and 6203 (the CWRU data set's bearings): C0 = 7.8 kN and 4.75 kN.
    for (preset, catalogue) in [("cwru-6205-de", 7800.0), ("cwru-6203-fe", 4750.0)] {
        let r = StaticRating::of(&Bearing::load(preset).unwrap());
        assert!(
            (r.c0 / catalogue - 1.0).abs() < 0.03,
            "{preset}: {} N",
            r.c0
        );
        assert_eq!((r.x0, r.y0), (0.6, 0.5));
    }
}

#[test]
fn peak_contact_finds_the_most_stressed_contact() {
    let b = Bearing::load("niu2014-table1").unwrap();
    let qi = [100.0, 2000.0, 50.0];
    let qo = [120.0, 1900.0, 3000.0];
    let (p, j, race, q) = peak_contact(&b, &qi, &qo);
    let pi = b.hertz(Race::Inner).peak_pressure(2000.0);
    let po = b.hertz(Race::Outer).peak_pressure(3000.0);
    assert_eq!(p, pi.max(po));
    assert_eq!(
        (j, race, q),
        if pi > po {
            (1, Race::Inner, 2000.0)
        } else {
            (2, Race::Outer, 3000.0)
        }
    );
}

fn scene(level: Fidelity, fa: f64, fr: f64) -> Scene {
    let mut s = Scene::default_scene();
    s.fidelity = level;
    s.operating.fx = fa;
    s.operating.fz = -fr;
    s
}

#[test]
fn a_load_beyond_the_rating_warns_once_and_runs() {
    // Table-1 bearing: C0 = 29.3 kN; Fa 4000 N, Fr 30 kN gives P0 = 30 kN and a peak pressure
    // just above 4.2 GPa: both warnings once, the run goes on.
    for level in [Fidelity::Kinematic, Fidelity::Lumped] {
        let mut sim = Simulation::new(&scene(level, 4000.0, 30000.0)).unwrap();
        let w = sim.take_warnings();
        assert!(
            w.iter().any(|m| m.contains("static load rating C0")),
            "{level:?}: {w:?}"
        );
        sim.advance(0.005).unwrap();
        sim.advance(0.01).unwrap();
        let later = sim.take_warnings();
        assert!(
            later.iter().all(|m| !m.contains("static equivalent load")),
            "{level:?}: the rating warning came again: {later:?}"
        );
        assert!(sim.take_warnings().is_empty());
    }
    // Within the rating: nothing.
    let mut sim = Simulation::new(&scene(Fidelity::Lumped, 4000.0, 1000.0)).unwrap();
    sim.advance(0.01).unwrap();
    assert!(sim.take_warnings().is_empty());
}

#[test]
fn an_absurd_load_is_refused_naming_it_and_the_simulation_stays() {
    // 1e9 N, at the start or set during a run, at every level: refused with the load named
    // (its static equivalent load against the rating), the simulation where it was.
    for level in [
        Fidelity::Kinematic,
        Fidelity::QuasiStatic,
        Fidelity::Lumped,
        Fidelity::Reduced,
        Fidelity::Full,
    ] {
        let e = Simulation::new(&scene(level, 4000.0, 1e9))
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("1000000000") && e.contains("C0"),
            "{level:?}: {e}"
        );
        let mut sim = Simulation::new(&scene(level, 4000.0, 1000.0)).unwrap();
        sim.advance(5e-4).unwrap();
        let mut before = vec![0.0; sim.output_table().len()];
        sim.outputs(&mut before);
        let mut i = sim.inputs();
        i.fz = -1e9;
        let e = sim.set_inputs(i).unwrap_err().to_string();
        assert!(
            e.contains("-1000000000") && e.contains("C0"),
            "{level:?}: {e}"
        );
        assert_eq!(sim.inputs().fz, -1000.0);
        sim.advance(1e-3).unwrap();
        let mut after = vec![0.0; before.len()];
        sim.outputs(&mut after);
        assert!(after.iter().all(|v| v.is_finite()), "{level:?}");
    }
}

#[test]
fn a_contact_beyond_the_pressure_limit_stops_the_advance_and_the_state_stays() {
    // A 2 MN hammer blow (the impact test's pulse) on the pedestal during a lumped run: the
    // loads are fine, the contacts are not. The advance that reaches the blow stops with an
    // error naming the contact and its pressure, and the simulation stays at its start.
    let mut s = scene(Fidelity::Lumped, 4000.0, 1000.0);
    s.pulse = Some(raceway::Pulse {
        peak: 2e6,
        duration: 2e-4,
        t0: 1e-3,
    });
    let mut sim = Simulation::new(&s).unwrap();
    sim.advance(5e-4).unwrap();
    let e = sim.advance(1.1e-3).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, SimError::Input(_)), "{text}");
    assert!(text.contains("GPa") && text.contains("contact"), "{text}");
    assert_eq!(sim.time(), 5e-4);
}

#[test]
fn a_journal_pushed_far_into_the_balls_is_refused_naming_it() {
    // Motion coupling: journal displacements of 20 mm and 1 m put the contacts far beyond the
    // pressure limit (1 mm is only 15 kN into the 15e6 N/m pedestal). The setter refuses them
    // naming the journal, and the simulation keeps the journal it had.
    for level in [Fidelity::QuasiStatic, Fidelity::Lumped, Fidelity::Full] {
        let mut s = scene(level, 4000.0, 1000.0);
        s.coupling = CouplingMode::Motion;
        s.defect = None;
        let mut sim = Simulation::new(&s).unwrap();
        let j0 = sim.journal();
        for push in [20e-3, 1.0] {
            let mut j = j0;
            j.x[2] -= push;
            let e = sim.set_journal(j).unwrap_err().to_string();
            assert!(e.contains("journal"), "{level:?}, {push} m: {e}");
            assert_eq!(sim.journal(), j0, "{level:?}");
        }
        sim.advance(1e-4).unwrap();
    }
}

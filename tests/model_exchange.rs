//! The Model Exchange API of [`Simulation`]: an importer's loop written here (the solver
//! crate's DOP853 integrating the states the simulation hands out, locating the sign changes of
//! its event functions and landing on its time events) against [`Simulation::advance`].

use raceway::solver::{
    AdvanceOutcome, EventAction, EventSystem, Integrator, Method, Options, System,
};
use raceway::{model_exchange_capacity, Fidelity, Scene, Simulation};

/// The importer's view of a simulation: derivatives and event functions at (t, y).
struct Host<'a>(&'a mut Simulation);

impl System for Host<'_> {
    fn dim(&self) -> usize {
        self.0.state_dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        self.0.set_state(t, y).expect("finite state");
        self.0.derivatives(dydt);
    }
}

impl EventSystem for Host<'_> {
    fn n_events(&self) -> usize {
        self.0.n_event_functions()
    }
    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        self.0.set_state(t, y).expect("finite state");
        self.0.event_functions(g);
    }
    fn handle_event(&mut self, _index: usize, _t: f64, _y: &mut [f64]) -> EventAction {
        EventAction::Stop
    }
}

/// Runs `sim` from its current state to `t_end` as an importer does: integrate with the frozen
/// mode to the next time event or state event, hand the state back, event update, repeat.
/// Returns the number of state and time events.
fn importer_run(sim: &mut Simulation, t_end: f64, rtol: f64) -> (usize, usize) {
    sim.begin_model_exchange().unwrap();
    let n = sim.state_dim();
    let mut nominal = vec![0.0; n];
    sim.nominals(&mut nominal);
    let atol = nominal.iter().map(|v| v * rtol).collect();
    let mut opts = Options::new(Method::Dop853, rtol, atol);
    opts.max_steps = 10_000_000;
    let mut integ = Integrator::new(opts, sim.time(), sim.state()).unwrap();
    let (mut state_events, mut time_events) = (0, 0);
    sim.event_update().unwrap();
    while integ.t() < t_end {
        let stop = sim.next_time_event().filter(|&s| s < t_end);
        let target = stop.unwrap_or(t_end);
        let outcome = integ
            .advance_with_events(&mut Host(sim), target, None)
            .unwrap();
        sim.set_state(integ.t(), integ.y()).unwrap();
        let stopped = matches!(outcome, AdvanceOutcome::Stopped { .. });
        if std::env::var("ME_DEBUG").is_ok() {
            if let AdvanceOutcome::Stopped { t, index } = outcome {
                let mut g = vec![0.0; sim.n_event_functions()];
                sim.event_functions(&mut g);
                eprintln!("state event {index} at {t:e}: g = {:e}", g[index]);
            }
        }
        if sim.step_completed() || stopped || stop.is_some() {
            if stopped {
                state_events += 1;
            } else if stop.is_some() {
                time_events += 1;
            }
            let fired = sim.event_update().unwrap();
            if std::env::var("ME_DEBUG").is_ok() && !fired.is_empty() {
                eprintln!("fired {fired:?} at {:e}", integ.t());
            }
            integ.discontinuity();
        }
    }
    (state_events, time_events)
}

fn scene(fidelity: Fidelity) -> Scene {
    let mut s = Scene::default_scene();
    s.fidelity = fidelity;
    s
}

fn outputs(sim: &mut Simulation) -> Vec<f64> {
    let mut o = vec![0.0; sim.output_table().len()];
    sim.try_outputs(&mut o).unwrap();
    o
}

#[test]
fn an_importer_loop_reproduces_the_advance_of_the_default_scene() {
    let t_end: f64 = std::env::var("ME_T").map_or(0.006, |v| v.parse().unwrap());
    let mut s = scene(Fidelity::Lumped);
    if let Ok(r) = std::env::var("ME_RTOL") {
        s.solver.rtol = r.parse().unwrap();
    }
    let mut cs = Simulation::new(&s).unwrap();
    cs.advance(t_end).unwrap();
    if std::env::var("ME_DEBUG").is_ok() {
        eprintln!("advance: {:?}", cs.solver_stats());
    }
    let mut me = Simulation::new(&s).unwrap();
    let (state_events, time_events) = importer_run(&mut me, t_end, s.solver.rtol);
    assert!(
        time_events > 10,
        "spall edges are time events: {time_events}"
    );
    let (a, b) = (outputs(&mut cs), outputs(&mut me));
    let table = cs.output_table();
    if std::env::var("ME_DEBUG").is_ok() {
        for (k, info) in table.iter().enumerate().take(20) {
            eprintln!("{:24} {:>14.6e} {:>14.6e}", info.name, a[k], b[k]);
        }
    }
    for (k, info) in table.iter().enumerate() {
        let scale = a[k].abs().max(1e-3 * table.len() as f64);
        assert!(
            (a[k] - b[k]).abs() <= 1e-9 * scale.max(1.0),
            "{}: advance {} importer {} ({state_events} state events)",
            info.name,
            a[k],
            b[k]
        );
    }
}

#[test]
fn the_capacity_holds_every_level() {
    let (nx, ne) = model_exchange_capacity(14);
    // The full model with its cage (6 states) has the most states.
    assert_eq!((nx, ne), (9 * 14 + 16 + 6, 70));
    for f in [
        Fidelity::Kinematic,
        Fidelity::QuasiStatic,
        Fidelity::Lumped,
        Fidelity::Reduced,
        Fidelity::Full,
    ] {
        let sim = Simulation::new(&scene(f)).unwrap();
        assert!(sim.state_dim() <= nx, "{f:?}");
        assert!(sim.n_event_functions() <= ne, "{f:?}");
    }
    let full = Simulation::new(&scene(Fidelity::Full)).unwrap();
    assert_eq!((full.state_dim(), full.n_event_functions()), (nx, ne));
}

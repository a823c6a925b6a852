//! The BallBearing's Model Exchange through the generic shell (the code the C entry points
//! run): the padded state vector round trip, finite derivatives, the refused configurations,
//! and an importer loop written here that locates a spall edge as an event indicator crossing
//! (the reduced level, where the edges are state events) and ends where the Co-Simulation does.

use ballbearing_fmu::ballbearing::BallBearing;
use fmi2::bindings::*;
use fmi2::capture::LogCapture;
use fmi2::functions as sh;
use raceway::solver::{
    AdvanceOutcome, EventAction, EventSystem, Integrator, Method, Options, System,
};
use raceway::BearingFile;
use std::ffi::CString;

type M = BallBearing;
struct H {
    log: LogCapture,
    b: BearingFile,
}

impl H {
    fn new() -> Self {
        Self {
            log: LogCapture::new(),
            b: BearingFile::default_preset(),
        }
    }
    fn inst(&self, kind: Fmi2Type) -> Fmi2Component {
        let g = CString::new(ballbearing_fmu::guid(&self.b)).unwrap();
        // SAFETY: test importer: the strings and callbacks outlive the call.
        let c = unsafe {
            sh::instantiate::<M>(
                c"bb".as_ptr(),
                kind,
                g.as_ptr(),
                std::ptr::null(),
                self.log.callbacks(),
                0,
                1,
            )
        };
        assert!(!c.is_null(), "{}", self.last());
        c
    }
    fn last(&self) -> String {
        self.log.last()
    }
    fn messages(&self) -> Vec<String> {
        self.log.messages()
    }
    fn vr(&self, name: &str) -> u32 {
        ballbearing_fmu::variables::table(&self.b)
            .into_iter()
            .find(|e| e.var.name == name)
            .unwrap_or_else(|| panic!("{name}"))
            .var
            .vr
    }
    /// An instance of `kind` at `fidelity` after fmi2ExitInitializationMode (Model Exchange:
    /// also the initial event update and continuous-time mode); None if the exit is refused.
    fn ready(&self, kind: Fmi2Type, fidelity: i32, coupling: i32) -> Option<Fmi2Component> {
        self.ready_with(kind, fidelity, coupling, &[])
    }
    /// [`H::ready`] with Real start values.
    fn ready_with(
        &self,
        kind: Fmi2Type,
        fidelity: i32,
        coupling: i32,
        start: &[(&str, f64)],
    ) -> Option<Fmi2Component> {
        let c = self.inst(kind);
        // SAFETY: test importer: live component, the values outlive the calls.
        unsafe {
            assert_eq!(
                sh::setup_experiment::<M>(c, 0, 0.0, 0.0, 0, 0.0),
                Fmi2Status::Ok
            );
            for (name, v) in [("fidelity", fidelity), ("coupling", coupling)] {
                assert_eq!(
                    sh::set_integer::<M>(c, &self.vr(name), 1, &v),
                    Fmi2Status::Ok
                );
            }
            for (name, v) in start {
                assert_eq!(sh::set_real::<M>(c, &self.vr(name), 1, v), Fmi2Status::Ok);
            }
            assert_eq!(sh::enter_initialization_mode::<M>(c), Fmi2Status::Ok);
            if sh::exit_initialization_mode::<M>(c) != Fmi2Status::Ok {
                sh::free_instance::<M>(c);
                return None;
            }
            if kind == FMI2_MODEL_EXCHANGE {
                let mut info = Fmi2EventInfo::default();
                assert_eq!(sh::new_discrete_states::<M>(c, &mut info), Fmi2Status::Ok);
                assert_eq!(info.new_discrete_states_needed, 0);
                assert_eq!(sh::enter_continuous_time_mode::<M>(c), Fmi2Status::Ok);
            }
        }
        Some(c)
    }
}

const NX: usize = 148; // the full level's states with its cage on the 14-ball default bearing
const NZ: usize = 70;

fn vector(
    c: Fmi2Component,
    f: unsafe fn(Fmi2Component, *mut f64, usize) -> Fmi2Status,
    n: usize,
) -> Vec<f64> {
    let mut v = vec![f64::NAN; n];
    // SAFETY: test importer: live component, v holds n values.
    assert_eq!(unsafe { f(c, v.as_mut_ptr(), n) }, Fmi2Status::Ok);
    v
}

fn states(c: Fmi2Component) -> Vec<f64> {
    vector(c, sh::get_continuous_states::<M>, NX)
}
fn derivatives(c: Fmi2Component) -> Vec<f64> {
    vector(c, sh::get_derivatives::<M>, NX)
}
fn indicators(c: Fmi2Component) -> Vec<f64> {
    vector(c, sh::get_event_indicators::<M>, NZ)
}

fn set_point(c: Fmi2Component, t: f64, x: &[f64]) {
    // SAFETY: test importer: live component, x holds NX values.
    unsafe {
        assert_eq!(sh::set_time::<M>(c, t), Fmi2Status::Ok);
        assert_eq!(
            sh::set_continuous_states::<M>(c, x.as_ptr(), NX),
            Fmi2Status::Ok
        );
    }
}

fn reals(c: Fmi2Component, vrs: &[u32]) -> Vec<f64> {
    let mut v = vec![0.0; vrs.len()];
    // SAFETY: test importer: live component, the arrays hold vrs.len() values.
    let status = unsafe { sh::get_real::<M>(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()) };
    assert_eq!(status, Fmi2Status::Ok);
    v
}

#[test]
fn states_round_trip_with_padding_and_derivatives_are_finite_at_every_dynamic_level() {
    let h = H::new();
    // the level's number of states and event functions on the default bearing (the reduced and
    // full levels with their cage's 6)
    for (fidelity, dim, ne) in [
        (1, 2, 0),
        (2, 12, 14),
        (3, 7 * 14 + 12 + 6, 70),
        (4, NX, 70),
    ] {
        let c = h
            .ready(FMI2_MODEL_EXCHANGE, fidelity, 0)
            .expect("a dynamic level");
        let x = states(c);
        assert!(x[..dim].iter().all(|v| v.is_finite()));
        assert!(x[dim..].iter().all(|&v| v == 0.0), "padding states are 0");
        let n = vector(c, sh::get_nominals_of_continuous_states::<M>, NX);
        assert!(n.iter().all(|&v| v > 0.0));
        assert!(n[dim..].iter().all(|&v| v == 1.0));
        let d = derivatives(c);
        assert!(d.iter().all(|v| v.is_finite()), "level {fidelity}");
        assert!(
            d[dim..].iter().all(|&v| v == 0.0),
            "padding derivatives are 0"
        );
        let g = indicators(c);
        assert!(g.iter().all(|v| v.is_finite()));
        assert!(
            g[ne..].iter().all(|&v| v == 1.0),
            "padding indicators are 1"
        );
        // the state and derivative variables read the same vectors
        let vrs: Vec<u32> = (0..NX as u32).map(|i| 2000 + i).collect();
        assert_eq!(reals(c, &vrs), x);
        let dvrs: Vec<u32> = (0..NX as u32).map(|i| 3000 + i).collect();
        assert_eq!(reals(c, &dvrs), d);
        // round trip: a perturbed state comes back bit for bit, the padding is ignored
        let mut y = x.clone();
        for v in y.iter_mut().take(dim) {
            *v += 1e-9;
        }
        y[NX - 1] = 5.0;
        set_point(c, 1e-5, &y);
        let back = states(c);
        assert_eq!(&back[..dim], &y[..dim]);
        assert!(back[dim..].iter().all(|&v| v == 0.0));
        assert!(derivatives(c).iter().all(|v| v.is_finite()));
        // outputs at the state set
        let out = reals(c, &[h.vr("pedestal.a.z"), h.vr("bearing.F.z")]);
        assert!(out.iter().all(|v| v.is_finite()));
        // SAFETY: test importer: live component.
        unsafe { sh::free_instance::<M>(c) };
    }
}

fn set_reals(c: Fmi2Component, vrs: &[u32], v: &[f64]) {
    // SAFETY: test importer: live component, the arrays hold vrs.len() values.
    let status = unsafe { sh::set_real::<M>(c, vrs.as_ptr(), vrs.len(), v.as_ptr()) };
    assert_eq!(status, Fmi2Status::Ok);
}

#[test]
fn in_motion_coupling_the_journal_inputs_take_the_ring_states_at_every_ring_level() {
    // The journal inputs are the ring's six states: they follow the inputs, ignore the
    // importer's writes, have derivative 0, and the reaction's change for a small journal move
    // is the Co-Simulation instance's directional derivative dF_z/dz (its reaction Jacobian).
    let h = H::new();
    let (jz, jvz, fz) = (h.vr("journal.z"), h.vr("journal.v.z"), h.vr("bearing.F.z"));
    for fidelity in [2, 3, 4] {
        let cs = h.ready(FMI2_CO_SIMULATION, fidelity, 1).expect("CS motion");
        let mut k = [0.0];
        // SAFETY: test importer: live component, the arrays hold one value each.
        let status = unsafe {
            sh::get_directional_derivative::<M>(cs, &fz, 1, &jz, 1, &1.0, k.as_mut_ptr())
        };
        assert_eq!(status, Fmi2Status::Ok);
        // SAFETY: test importer: live component.
        unsafe { sh::free_instance::<M>(cs) };

        let c = h
            .ready(FMI2_MODEL_EXCHANGE, fidelity, 1)
            .unwrap_or_else(|| panic!("ME motion at level {fidelity}: {}", h.last()));
        let [z0, f0] = reals(c, &[jz, fz])[..] else {
            unreachable!()
        };
        let x0 = states(c);
        let dz = 1e-9;
        set_reals(c, &[jz, jvz], &[z0 + dz, 0.01]);
        let x1 = states(c);
        let moved: Vec<usize> = (0..NX).filter(|&i| x1[i] != x0[i]).collect();
        assert_eq!(
            moved.len(),
            2,
            "level {fidelity}: the ring's z and v_z slots"
        );
        let (iz, iv) = (moved[0], moved[1]);
        assert_eq!((x1[iz], x1[iv]), (z0 + dz, 0.01));
        // the importer's writes to the ring slots are ignored
        let mut y = x1.clone();
        y[iz] += 1e-6;
        y[iv] = -3.0;
        set_point(c, 0.0, &y);
        let back = states(c);
        assert_eq!((back[iz], back[iv]), (z0 + dz, 0.01));
        let d = derivatives(c);
        assert_eq!((d[iz], d[iv]), (0.0, 0.0));
        assert!(d.iter().all(|v| v.is_finite()));
        // the reaction's response against the reaction Jacobian of Co-Simulation (the velocity
        // term adds c v_z, c ~ 100 N s/m: 1 N; measure it with the velocity back at 0)
        set_reals(c, &[jvz], &[0.0]);
        let f1 = reals(c, &[fz])[0];
        let slope = (f1 - f0) / dz;
        assert!(k[0] < -1e7, "level {fidelity}: dF_z/dz = {}", k[0]);
        assert!(
            (slope / k[0] - 1.0).abs() < 0.02,
            "level {fidelity}: dF_z/dz {slope:e} (ME) against {:e} (CS)",
            k[0]
        );
        // SAFETY: test importer: live component.
        unsafe { sh::free_instance::<M>(c) };
    }
}

#[test]
fn the_kinematic_level_and_the_co_simulation_couplings_are_refused_with_reasons() {
    let h = H::new();
    let said = |what: &str| h.messages().iter().any(|m| m.contains(what));
    assert!(h.ready(FMI2_MODEL_EXCHANGE, 0, 0).is_none());
    assert!(said("the kinematic level (L0) has no continuous dynamics"));
    assert!(h.ready(FMI2_MODEL_EXCHANGE, 1, 1).is_none());
    assert!(said(
        "coupling mode motion in Model Exchange needs a level whose inner ring is a dynamic body"
    ));
    assert!(h.ready(FMI2_MODEL_EXCHANGE, 2, 2).is_none());
    assert!(said("coupling = 2 (tlm) is refused"));
    // More states or indicators than the FMU declares (a spall on a ball at the full level, a
    // second raceway spall at the reduced level): refused at the exit, naming Co-Simulation;
    // the same scenes run in Co-Simulation.
    for (fidelity, ints) in [
        (4, [("defect.ring", 3), ("defect.ball", 2)]),
        (3, [("defect2.ring", 1), ("defect2.ball", 1)]),
    ] {
        let refused = |kind| {
            let c = h.inst(kind);
            // SAFETY: test importer: live component, the values outlive the calls.
            unsafe {
                assert_eq!(
                    sh::setup_experiment::<M>(c, 0, 0.0, 0.0, 0, 0.0),
                    Fmi2Status::Ok
                );
                for (name, v) in [("fidelity", fidelity)].into_iter().chain(ints) {
                    assert_eq!(sh::set_integer::<M>(c, &h.vr(name), 1, &v), Fmi2Status::Ok);
                }
                if ints[0].0 == "defect2.ring" {
                    // 90° from spall 1 (at π).
                    assert_eq!(
                        sh::set_real::<M>(
                            c,
                            &h.vr("defect2.theta0"),
                            1,
                            &std::f64::consts::FRAC_PI_2
                        ),
                        Fmi2Status::Ok
                    );
                }
                assert_eq!(sh::enter_initialization_mode::<M>(c), Fmi2Status::Ok);
                let st = sh::exit_initialization_mode::<M>(c);
                sh::free_instance::<M>(c);
                st != Fmi2Status::Ok
            }
        };
        assert!(refused(FMI2_MODEL_EXCHANGE), "fidelity {fidelity} {ints:?}");
        assert!(said("a Model Exchange FMU of this bearing declares") && said("use Co-Simulation"));
        assert!(!refused(FMI2_CO_SIMULATION), "{}", h.last());
    }
    // and the kinematic level still runs in Co-Simulation
    let c = h
        .ready(FMI2_CO_SIMULATION, 0, 0)
        .expect("L0 in Co-Simulation");
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(sh::do_step::<M>(c, 0.0, 1e-4, 1), Fmi2Status::Ok);
        sh::free_instance::<M>(c);
    }
}

/// The importer's view through the shell.
struct Host(Fmi2Component);

impl System for Host {
    fn dim(&self) -> usize {
        NX
    }
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        set_point(self.0, t, y);
        // SAFETY: test importer: live component, dydt holds NX values.
        let status = unsafe { sh::get_derivatives::<M>(self.0, dydt.as_mut_ptr(), NX) };
        assert_eq!(status, Fmi2Status::Ok);
    }
}

impl EventSystem for Host {
    fn n_events(&self) -> usize {
        NZ
    }
    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        set_point(self.0, t, y);
        // SAFETY: test importer: live component, g holds NZ values.
        let status = unsafe { sh::get_event_indicators::<M>(self.0, g.as_mut_ptr(), NZ) };
        assert_eq!(status, Fmi2Status::Ok);
    }
    fn handle_event(&mut self, _index: usize, _t: f64, _y: &mut [f64]) -> EventAction {
        EventAction::Stop
    }
}

/// The event update through the shell: (next time event, the indices the FMU logged as fired).
fn event_update(h: &H, c: Fmi2Component) -> (Option<f64>, String) {
    let mut info = Fmi2EventInfo::default();
    // SAFETY: test importer: live component, info outlives the calls.
    unsafe {
        assert_eq!(sh::enter_event_mode::<M>(c), Fmi2Status::Ok);
        let s = sh::new_discrete_states::<M>(c, &mut info);
        assert!(
            s == Fmi2Status::Ok || s == Fmi2Status::Warning,
            "{}",
            h.last()
        );
        assert_eq!(info.new_discrete_states_needed, 0);
        assert_eq!(sh::enter_continuous_time_mode::<M>(c), Fmi2Status::Ok);
    }
    let fired = h
        .messages()
        .into_iter()
        .rev()
        .find(|m| m.starts_with("event update at"))
        .unwrap_or_default();
    (
        (info.next_event_time_defined != 0).then_some(info.next_event_time),
        fired,
    )
}

#[test]
fn an_importer_locates_a_spall_edge_crossing_and_ends_where_the_co_simulation_does() {
    let h = H::new();
    // The importer at rtol 1e-8: its error norm also counts the padding states, so at the
    // Co-Simulation's 1e-6 its steps are longer, and after the abrupt spall edge (D2) the ball
    // rattles: a contact open for less than a step between two step ends is missed, as by any
    // importer that tests signs at step ends (at 1e-6 one was, and the end state was 0.5 % off).
    let (fidelity, t_end, rtol) = (3, 1.2e-3, 1e-8);
    let c = h.ready(FMI2_MODEL_EXCHANGE, fidelity, 0).unwrap();
    // SAFETY: test importer: live component, the categories outlive the call.
    unsafe {
        let cat = [c"logEvents".as_ptr()];
        assert_eq!(
            sh::set_debug_logging::<M>(c, 1, 1, cat.as_ptr()),
            Fmi2Status::Ok
        );
    }
    let nominal = vector(c, sh::get_nominals_of_continuous_states::<M>, NX);
    let mut opts = Options::new(
        Method::Dop853,
        rtol,
        nominal.iter().map(|n| n * rtol).collect(),
    );
    opts.max_steps = 1_000_000;
    let mut integ = Integrator::new(opts, 0.0, &states(c)).unwrap();
    let (mut next, _) = event_update(&h, c);
    let z = 14;
    let mut edges = Vec::new();
    let mut prev: Option<(f64, Vec<usize>)> = None;
    while integ.t() < t_end {
        let target = next.filter(|&s| s < t_end).unwrap_or(t_end);
        let outcome = integ
            .advance_with_events(&mut Host(c), target, None)
            .unwrap();
        set_point(c, integ.t(), integ.y());
        let (mut enter, mut stop) = (0, 0);
        // SAFETY: test importer: live component.
        unsafe {
            assert_eq!(
                sh::completed_integrator_step::<M>(c, 1, &mut enter, &mut stop),
                Fmi2Status::Ok
            );
        }
        assert_eq!(stop, 0);
        let located = match outcome {
            AdvanceOutcome::Stopped { index, .. } => Some(index),
            AdvanceOutcome::Reached => None,
        };
        if located.is_some() || next.is_some_and(|s| s <= integ.t()) || enter != 0 {
            let g_before = indicators(c);
            let (n, fired) = event_update(&h, c);
            let list: Vec<usize> = fired
                .split_once('[')
                .and_then(|(_, r)| r.split_once(']'))
                .map(|(l, _)| l.split(',').filter_map(|p| p.trim().parse().ok()).collect())
                .unwrap_or_default();
            if let Some(k) = located {
                // A located root fires an indicator, or it is the same crossing found again
                // right after the restart of the event just before (the FMU fired it there,
                // a hair ahead of a root located on the old side).
                let again = prev
                    .as_ref()
                    .is_some_and(|p: &(f64, Vec<usize>)| p.1.contains(&k));
                assert!(
                    !list.is_empty() || again,
                    "indicator {k} located at {}, FMU says {fired}",
                    integ.t()
                );
            }
            // the spall-edge indicators: θ_e − |θ_bd| of ball j at 2z + 2j
            for &k in &list {
                if (2 * z..4 * z).contains(&k) && (k - 2 * z) % 2 == 0 {
                    edges.push((integ.t(), k, g_before[k]));
                }
            }
            prev = Some((integ.t(), list));
            next = n;
            // a restart, as CVODE's after an event (no memory of the event just handled)
            let y = integ.y().to_vec();
            integ.set_state(integ.t(), &y);
            integ.discontinuity();
        }
    }
    assert!(
        !edges.is_empty(),
        "a ball reaches the spall edge within {t_end} s"
    );
    for &(t, k, g) in &edges {
        assert!(
            g.abs() < 1e-9,
            "edge indicator {k} at t = {t}: {g} (located)"
        );
    }
    // The Co-Simulation of the same level and tolerance ends at the same point.
    let cs = h.ready(FMI2_CO_SIMULATION, fidelity, 0).unwrap();
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(
            sh::set_real::<M>(cs, &h.vr("solver.rtol"), 1, &rtol),
            Fmi2Status::Error,
            "fixed after init"
        );
        assert_eq!(
            sh::do_step::<M>(cs, 0.0, t_end, 1),
            Fmi2Status::Ok,
            "{}",
            h.last()
        );
    }
    let names = ["pedestal.z", "ring.z", "bearing.F.z", "cage.speed"];
    let vrs: Vec<u32> = names.iter().map(|n| h.vr(n)).collect();
    let (a, b) = (reals(cs, &vrs), reals(c, &vrs));
    for (k, name) in names.iter().enumerate() {
        assert!(
            (a[k] - b[k]).abs() <= 1e-3 * a[k].abs(),
            "{name}: Co-Simulation {} importer {}",
            a[k],
            b[k]
        );
    }
    // SAFETY: test importer: live components.
    unsafe {
        sh::free_instance::<M>(cs);
        sh::free_instance::<M>(c);
    }
}

#[test]
fn an_input_set_in_continuous_time_asks_for_an_event_when_the_speed_moves() {
    let h = H::new();
    let c = h.ready(FMI2_MODEL_EXCHANGE, 2, 0).unwrap();
    let complete = || {
        let (mut e, mut t) = (0, 0);
        // SAFETY: test importer: live component.
        let status = unsafe { sh::completed_integrator_step::<M>(c, 1, &mut e, &mut t) };
        assert_eq!(status, Fmi2Status::Ok);
        e != 0
    };
    assert!(!complete());
    let set = |name: &str, v: f64| {
        // SAFETY: test importer: live component.
        unsafe { sh::set_real::<M>(c, &h.vr(name), 1, &v) }
    };
    // a load change within the level's re-solve threshold (2 %) acts at once, no event
    let d0 = derivatives(c);
    assert_eq!(set("load.Fz", -1010.0), Fmi2Status::Ok);
    assert_ne!(
        derivatives(c),
        d0,
        "the load reaches the derivatives at once"
    );
    assert!(!complete());
    // a speed change asks for one (the time events were predicted at the old speed)
    assert_eq!(set("shaft.speed", 1000.0), Fmi2Status::Ok);
    assert!(complete());
    let (next, _) = event_update(&h, c);
    assert!(next.is_some());
    assert!(!complete(), "answered by the event update");
    // parameters cannot be set in continuous time
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(
            sh::set_integer::<M>(c, &h.vr("fidelity"), 1, &3),
            Fmi2Status::Error
        );
        sh::free_instance::<M>(c);
    }
}

#[test]
fn in_motion_coupling_a_speed_change_is_an_event_that_moves_the_cage_speed_and_loads_are_ignored() {
    let h = H::new();
    let c = h.ready(FMI2_MODEL_EXCHANGE, 2, 1).unwrap();
    let complete = || {
        let (mut e, mut t) = (0, 0);
        // SAFETY: test importer: live component.
        let status = unsafe { sh::completed_integrator_step::<M>(c, 1, &mut e, &mut t) };
        assert_eq!(status, Fmi2Status::Ok);
        e != 0
    };
    let (w, cage) = (h.vr("shaft.speed"), h.vr("cage.speed"));
    let [w0, cage0] = reals(c, &[w, cage])[..] else {
        unreachable!()
    };
    // loads act only at the start in motion coupling: the derivatives do not move
    let d0 = derivatives(c);
    set_reals(c, &[h.vr("load.Fz")], &[-3000.0]);
    assert_eq!(derivatives(c), d0);
    assert!(!complete());
    // a speed 5 % up (beyond the 2 % of the L1 point's update) asks for an event, at which the
    // cage-to-shaft ratio becomes that of a start at the new speed
    set_reals(c, &[w], &[1.05 * w0]);
    assert!(complete());
    event_update(&h, c);
    let ratio = reals(c, &[cage])[0] / (1.05 * w0);
    let fresh = h
        .ready_with(FMI2_MODEL_EXCHANGE, 2, 1, &[("shaft.speed", 1.05 * w0)])
        .unwrap();
    let fresh_ratio = reals(fresh, &[cage])[0] / (1.05 * w0);
    assert!(
        (ratio / fresh_ratio - 1.0).abs() < 1e-9,
        "{ratio} against {fresh_ratio} (at the start speed {})",
        cage0 / w0
    );
    assert!(
        (cage0 / w0 / fresh_ratio - 1.0).abs() > 1e-7,
        "the ratio moves with the speed"
    );
    assert!(
        h.messages().iter().any(|m| m.contains("load.F")),
        "the ignored loads are reported: {:?}",
        h.messages()
    );
    // SAFETY: test importer: live components.
    unsafe {
        sh::free_instance::<M>(c);
        sh::free_instance::<M>(fresh);
    }
}

//! The JeffcottRotor's Model Exchange through the generic shell (the code the C entry points
//! run): its 10 states round trip, the derivatives are the right-hand side, an importer loop
//! written here (the solver crate's DOP853 on the FMU's derivatives, landing on the ramp's end
//! as a time event) ends where the Co-Simulation does, and coupling mode tlm is refused.

use fmi2::bindings::*;
use fmi2::capture::LogCapture;
use fmi2::functions as sh;
use raceway_rotor::fmu::{guid, table, JeffcottRotor};
use raceway_solver::{Integrator, Method, Options, System};
use std::ffi::CString;

type M = JeffcottRotor;
const NX: usize = 10;
/// A speed ramp from 500 to 1000 rad/s over 10 ms (its end is a time event).
const RAMP: [(&str, f64); 3] = [
    ("speed.initial", 500.0),
    ("speed.final", 1000.0),
    ("speed.rate", 5e4),
];

struct H {
    log: LogCapture,
}

fn vr(name: &str) -> u32 {
    table()
        .into_iter()
        .find(|(v, _)| v.name == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .0
        .vr
}

impl H {
    fn new() -> Self {
        Self {
            log: LogCapture::new(),
        }
    }

    /// An initialized instance of `kind` with `coupling` and tolerance 1e-12 (Co-Simulation:
    /// its DOPRI5's; Model Exchange: unused) (Model Exchange: after the initial
    /// event update, in continuous-time mode, and the next time event); None if refused.
    fn ready(&self, kind: Fmi2Type, coupling: i32) -> Option<(Fmi2Component, Option<f64>)> {
        self.ready_with(kind, coupling, &RAMP)
    }

    fn ready_with(
        &self,
        kind: Fmi2Type,
        coupling: i32,
        params: &[(&str, f64)],
    ) -> Option<(Fmi2Component, Option<f64>)> {
        let g = CString::new(guid()).unwrap();
        // SAFETY: test importer: the strings and callbacks outlive the instance.
        unsafe {
            let c = sh::instantiate::<M>(
                c"rotor".as_ptr(),
                kind,
                g.as_ptr(),
                std::ptr::null(),
                self.log.callbacks(),
                0,
                0,
            );
            assert!(!c.is_null());
            assert_eq!(
                sh::setup_experiment::<M>(c, 1, 1e-12, 0.0, 0, 0.0),
                Fmi2Status::Ok
            );
            assert_eq!(
                sh::set_integer::<M>(c, &vr("coupling"), 1, &coupling),
                Fmi2Status::Ok
            );
            for (name, v) in params {
                assert_eq!(
                    sh::set_real::<M>(c, &vr(name), 1, v),
                    Fmi2Status::Ok,
                    "{name}"
                );
            }
            assert_eq!(sh::enter_initialization_mode::<M>(c), Fmi2Status::Ok);
            if sh::exit_initialization_mode::<M>(c) != Fmi2Status::Ok {
                sh::free_instance::<M>(c);
                return None;
            }
            let mut next = None;
            if kind == FMI2_MODEL_EXCHANGE {
                let mut info = Fmi2EventInfo::default();
                assert_eq!(sh::new_discrete_states::<M>(c, &mut info), Fmi2Status::Ok);
                next = (info.next_event_time_defined != 0).then_some(info.next_event_time);
                assert_eq!(sh::enter_continuous_time_mode::<M>(c), Fmi2Status::Ok);
            }
            Some((c, next))
        }
    }
}

fn get(c: Fmi2Component, f: unsafe fn(Fmi2Component, *mut f64, usize) -> Fmi2Status) -> Vec<f64> {
    let mut v = vec![f64::NAN; NX];
    // SAFETY: test importer: live component, v holds NX values.
    assert_eq!(unsafe { f(c, v.as_mut_ptr(), NX) }, Fmi2Status::Ok);
    v
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

fn reals(c: Fmi2Component, names: &[&str]) -> Vec<f64> {
    let vrs: Vec<u32> = names.iter().map(|n| vr(n)).collect();
    let mut v = vec![0.0; vrs.len()];
    // SAFETY: test importer: live component, the arrays hold vrs.len() values.
    let status = unsafe { sh::get_real::<M>(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()) };
    assert_eq!(status, Fmi2Status::Ok);
    v
}

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

#[test]
fn states_round_trip_and_the_derivatives_are_the_state_variables() {
    let h = H::new();
    let (c, next) = h.ready(FMI2_MODEL_EXCHANGE, 0).unwrap();
    let x = get(c, sh::get_continuous_states::<M>);
    assert_eq!(
        &x[..3],
        &reals(c, &["journal.x", "journal.y", "journal.z"])[..]
    );
    assert_eq!(x[6], reals(c, &["disk.y"])[0]);
    let d = get(c, sh::get_derivatives::<M>);
    assert!(d.iter().all(|v| v.is_finite()));
    // der(journal displacement) = journal velocity; der(velocity) = journal.a
    assert_eq!(&d[..3], &x[3..6]);
    assert_eq!(
        &d[3..6],
        &reals(c, &["journal.a.x", "journal.a.y", "journal.a.z"])[..]
    );
    let vrs: Vec<u32> = (0..NX as u32).map(|i| 3000 + i).collect();
    let mut dv = vec![0.0; NX];
    // SAFETY: test importer: live component.
    let status = unsafe { sh::get_real::<M>(c, vrs.as_ptr(), NX, dv.as_mut_ptr()) };
    assert_eq!(status, Fmi2Status::Ok);
    assert_eq!(dv, d);
    let y: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, v)| v + 1e-7 * i as f64)
        .collect();
    set_point(c, 0.01, &y);
    assert_eq!(get(c, sh::get_continuous_states::<M>), y);
    assert_eq!(reals(c, &["disk.v.z"])[0], y[9]);
    let n = get(c, sh::get_nominals_of_continuous_states::<M>);
    assert!(n.iter().all(|&v| v > 0.0));
    // the default rotor ramps its speed: the ramp's end is the time event
    assert!(next.is_some_and(|t| t > 0.0), "{next:?}");
    // no event indicators
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(
            sh::get_event_indicators::<M>(c, std::ptr::null_mut(), 0),
            Fmi2Status::Ok
        );
        sh::free_instance::<M>(c);
    }
}

#[test]
fn an_importer_loop_ends_where_the_co_simulation_does_and_tlm_is_refused() {
    let h = H::new();
    let t_end = 0.02;
    let (c, next) = h.ready(FMI2_MODEL_EXCHANGE, 0).unwrap();
    let rtol = 1e-10;
    let n = get(c, sh::get_nominals_of_continuous_states::<M>);
    let opts = Options::new(Method::Dop853, rtol, n.iter().map(|v| v * rtol).collect());
    let mut integ = Integrator::new(opts, 0.0, &get(c, sh::get_continuous_states::<M>)).unwrap();
    let mut next = next;
    while integ.t() < t_end {
        let target = next.filter(|&s| s < t_end).unwrap_or(t_end);
        integ.advance(&mut Host(c), target, None).unwrap();
        set_point(c, integ.t(), integ.y());
        let (mut e, mut s) = (0, 0);
        // SAFETY: test importer: live component.
        unsafe {
            assert_eq!(
                sh::completed_integrator_step::<M>(c, 1, &mut e, &mut s),
                Fmi2Status::Ok
            );
            assert_eq!((e, s), (0, 0));
            if next.is_some_and(|s| s <= integ.t()) {
                let mut info = Fmi2EventInfo::default();
                assert_eq!(sh::enter_event_mode::<M>(c), Fmi2Status::Ok);
                assert_eq!(sh::new_discrete_states::<M>(c, &mut info), Fmi2Status::Ok);
                next = (info.next_event_time_defined != 0).then_some(info.next_event_time);
                assert_eq!(sh::enter_continuous_time_mode::<M>(c), Fmi2Status::Ok);
                integ.discontinuity();
            }
        }
    }
    assert_eq!(next, None, "past the ramp's end, no more time events");
    assert_eq!(reals(c, &["shaft.speed"])[0], 1000.0);
    let (cs, _) = h.ready(FMI2_CO_SIMULATION, 0).unwrap();
    let mut t = 0.0;
    for _ in 0..200 {
        // SAFETY: test importer: live component.
        assert_eq!(unsafe { sh::do_step::<M>(cs, t, 1e-4, 1) }, Fmi2Status::Ok);
        t += 1e-4;
    }
    let names = ["journal.y", "journal.z", "disk.y", "disk.z", "shaft.speed"];
    let (a, b) = (reals(cs, &names), reals(c, &names));
    // to 1e-8 m (the Co-Simulation's DOPRI5 runs with its fixed absolute tolerance of 1e-12 m
    // per step, the importer's DOP853 with 1e-15 m: their difference is the former's)
    for (k, name) in names.iter().enumerate() {
        assert!(
            (a[k] - b[k]).abs() <= 1e-5 * a[k].abs().max(1e-3),
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
    assert!(h.ready(FMI2_MODEL_EXCHANGE, 1).is_none());
    assert!(h.log.any("coupling = 1 (tlm) is refused"));
}

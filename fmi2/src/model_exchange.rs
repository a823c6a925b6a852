//! The FMI 2.0 Model Exchange functions, generic over the model: `fmi2SetTime`,
//! `fmi2SetContinuousStates`, `fmi2GetContinuousStates`, `fmi2GetDerivatives`,
//! `fmi2GetEventIndicators`, `fmi2GetNominalsOfContinuousStates`, `fmi2EnterEventMode`,
//! `fmi2NewDiscreteStates`, `fmi2EnterContinuousTimeMode` and `fmi2CompletedIntegratorStep`.
//!
//! Each checks, in this order and with no effect when a check fails (fmi2Error and a message):
//! the call state ([`crate::instance`]'s masks), that the instance is a Model Exchange one,
//! the array arguments (non-NULL, the length the model description declares) and that reals
//! passed in are finite. Then it asks the model ([`FmuModel`]'s Model Exchange methods). What
//! the model returns is checked too: non-finite states, derivatives, indicators or nominals are
//! an error naming the index, never handed to the importer with fmi2OK.
//!
//! A model failure in `fmi2NewDiscreteStates` or `fmi2CompletedIntegratorStep` moves the
//! instance to the Error state (as `fmi2DoStep` does in Co-Simulation); a failure of an
//! evaluation (`fmi2GetDerivatives`, …) is an fmi2Error with the instance left where it was, so
//! that an importer may retry at other states.

use crate::bindings::*;
use crate::ffi::{slice_in, slice_out, with_instance};
use crate::instance::{mask, CallState, Instance};
use crate::logging::LOG_STATUS_WARNING;
use crate::model::{FmuModel, Interface};

/// The checks every Model Exchange function starts with: the call state and the interface.
fn check_me<M: FmuModel>(me: &Instance<M>, fname: &str, allowed: u16) -> Result<(), Fmi2Status> {
    me.check_state(fname, allowed)?;
    me.check_interface(fname, Interface::ModelExchange)
}

/// The length check of a state or indicator array: `n` must be the declared number `want`.
fn check_len<M: FmuModel>(
    me: &Instance<M>,
    fname: &str,
    what: &str,
    n: usize,
    want: usize,
) -> Result<(), Fmi2Status> {
    if n == want {
        Ok(())
    } else {
        Err(me.error(
            fname,
            format!(
                "{what} = {n}, but the model description declares {want} (numberOf{})",
                if what == "ni" {
                    "EventIndicators"
                } else {
                    " continuous states: the Derivatives of ModelStructure"
                }
            ),
        ))
    }
}

/// Logs the model's warnings at status fmi2Warning; the status the call returns.
fn warn<M: FmuModel>(me: &Instance<M>, fname: &str, warnings: &[String]) -> Fmi2Status {
    for w in warnings {
        me.logger.log(
            Fmi2Status::Warning,
            LOG_STATUS_WARNING,
            &format!("{fname} at t = {}: {w}", me.time),
        );
    }
    if warnings.is_empty() {
        Fmi2Status::Ok
    } else {
        Fmi2Status::Warning
    }
}

/// The common body of the four getters of a vector of `n` reals: state, interface, length and
/// pointer checks, the model's `get`, then every value finite. `out` is the importer's array
/// (`None`: NULL).
fn get_vector<M: FmuModel>(
    me: &mut Instance<M>,
    fname: &'static str,
    allowed: u16,
    out: Option<&mut [f64]>,
    n: usize,
    indicators: bool,
    get: impl FnOnce(&mut M, &mut [f64]) -> Result<(), String>,
) -> Fmi2Status {
    if let Err(s) = check_me(me, fname, allowed) {
        return s;
    }
    let (what, want) = if indicators {
        ("ni", me.model.number_of_event_indicators())
    } else {
        ("nx", me.model.number_of_continuous_states())
    };
    if let Err(s) = check_len(me, fname, what, n, want) {
        return s;
    }
    let Some(out) = out else {
        return me.error(fname, format!("the array is NULL with {what} = {n}"));
    };
    // Into a scratch vector first: on a failure the importer's array is left as it was.
    let mut v = vec![0.0; n];
    if let Err(e) = get(&mut me.model, &mut v) {
        return me.error(fname, e);
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return me.error(
            fname,
            format!(
                "element {i} is {} at t = {} (no valid value at this time and state)",
                v[i], me.time
            ),
        );
    }
    out.copy_from_slice(&v);
    Fmi2Status::Ok
}

/// `fmi2SetTime`: the time of the next evaluations (event or continuous-time mode).
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_time<M: FmuModel>(c: Fmi2Component, time: Fmi2Real) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, which is what with_instance needs.
    unsafe { with_instance::<M>(c, "fmi2SetTime", |me| set_time_in(me, time)) }
}

fn set_time_in<M: FmuModel>(me: &mut Instance<M>, time: f64) -> Fmi2Status {
    const F: &str = "fmi2SetTime";
    if let Err(s) = check_me(me, F, mask::SET_TIME) {
        return s;
    }
    if !time.is_finite() {
        return me.error(F, format!("time = {time} is not finite"));
    }
    if time < me.start_time {
        return me.error(
            F,
            format!(
                "time = {time} is before the start time {} of fmi2SetupExperiment",
                me.start_time
            ),
        );
    }
    if let Err(e) = me.model.set_time(time) {
        return me.error(F, e);
    }
    me.time = time;
    Fmi2Status::Ok
}

/// `fmi2SetContinuousStates` (continuous-time mode).
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_continuous_states<M: FmuModel>(
    c: Fmi2Component,
    x: *const Fmi2Real,
    nx: usize,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and `x` is NULL or valid for `nx` reads, which is what
    // with_instance and slice_in need.
    unsafe {
        with_instance::<M>(c, "fmi2SetContinuousStates", |me| {
            set_continuous_states_in(me, slice_in(x, nx), nx)
        })
    }
}

fn set_continuous_states_in<M: FmuModel>(
    me: &mut Instance<M>,
    x: Option<&[f64]>,
    nx: usize,
) -> Fmi2Status {
    const F: &str = "fmi2SetContinuousStates";
    if let Err(s) = check_me(me, F, mask::SET_CONTINUOUS_STATES) {
        return s;
    }
    if let Err(s) = check_len(me, F, "nx", nx, me.model.number_of_continuous_states()) {
        return s;
    }
    let Some(x) = x else {
        return me.error(F, format!("x is NULL with nx = {nx}"));
    };
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return me.error(
            F,
            format!("x[{i}] = {} is not finite; states rejected", x[i]),
        );
    }
    match me.model.set_continuous_states(x) {
        Ok(()) => Fmi2Status::Ok,
        Err(e) => me.error(F, e),
    }
}

/// `fmi2GetContinuousStates`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_continuous_states<M: FmuModel>(
    c: Fmi2Component,
    x: *mut Fmi2Real,
    nx: usize,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and the array is NULL or valid for nx writes, which is
    // what with_instance and slice_out need.
    unsafe {
        with_instance::<M>(c, "fmi2GetContinuousStates", |me| {
            get_vector(
                me,
                "fmi2GetContinuousStates",
                mask::GET_CONTINUOUS_STATES,
                slice_out(x, nx),
                nx,
                false,
                |m, v| m.get_continuous_states(v),
            )
        })
    }
}

/// `fmi2GetDerivatives`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_derivatives<M: FmuModel>(
    c: Fmi2Component,
    derivatives: *mut Fmi2Real,
    nx: usize,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and the array is NULL or valid for nx writes, which is
    // what with_instance and slice_out need.
    unsafe {
        with_instance::<M>(c, "fmi2GetDerivatives", |me| {
            get_vector(
                me,
                "fmi2GetDerivatives",
                mask::GET_DERIVATIVES,
                slice_out(derivatives, nx),
                nx,
                false,
                |m, v| m.get_derivatives(v),
            )
        })
    }
}

/// `fmi2GetEventIndicators`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_event_indicators<M: FmuModel>(
    c: Fmi2Component,
    indicators: *mut Fmi2Real,
    ni: usize,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and the array is NULL or valid for ni writes, which is
    // what with_instance and slice_out need.
    unsafe {
        with_instance::<M>(c, "fmi2GetEventIndicators", |me| {
            get_vector(
                me,
                "fmi2GetEventIndicators",
                mask::GET_EVENT_INDICATORS,
                slice_out(indicators, ni),
                ni,
                true,
                |m, v| m.get_event_indicators(v),
            )
        })
    }
}

/// `fmi2GetNominalsOfContinuousStates`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_nominals_of_continuous_states<M: FmuModel>(
    c: Fmi2Component,
    x_nominal: *mut Fmi2Real,
    nx: usize,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and the array is NULL or valid for nx writes, which is
    // what with_instance and slice_out need.
    unsafe {
        with_instance::<M>(c, "fmi2GetNominalsOfContinuousStates", |me| {
            get_vector(
                me,
                "fmi2GetNominalsOfContinuousStates",
                mask::GET_NOMINALS,
                slice_out(x_nominal, nx),
                nx,
                false,
                |m, v| m.get_nominals(v),
            )
        })
    }
}

/// `fmi2EnterEventMode`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn enter_event_mode<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, which is what with_instance needs.
    unsafe { with_instance::<M>(c, "fmi2EnterEventMode", enter_event_mode_in) }
}

fn enter_event_mode_in<M: FmuModel>(me: &mut Instance<M>) -> Fmi2Status {
    const F: &str = "fmi2EnterEventMode";
    if let Err(s) = check_me(me, F, mask::ENTER_EVENT_MODE) {
        return s;
    }
    if let Err(e) = me.model.enter_event_mode() {
        return me.error(F, e);
    }
    me.state = CallState::EventMode;
    me.event(|| format!("{F} at t = {}", me.time));
    Fmi2Status::Ok
}

/// `fmi2NewDiscreteStates`: the model's event update, reported in `*event_info`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn new_discrete_states<M: FmuModel>(
    c: Fmi2Component,
    event_info: *mut Fmi2EventInfo,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and `event_info` is NULL or valid for a write, which is
    // what with_instance and `as_mut` need.
    unsafe {
        with_instance::<M>(c, "fmi2NewDiscreteStates", |me| {
            new_discrete_states_in(me, event_info.as_mut())
        })
    }
}

fn new_discrete_states_in<M: FmuModel>(
    me: &mut Instance<M>,
    event_info: Option<&mut Fmi2EventInfo>,
) -> Fmi2Status {
    const F: &str = "fmi2NewDiscreteStates";
    if let Err(s) = check_me(me, F, mask::NEW_DISCRETE_STATES) {
        return s;
    }
    let Some(event_info) = event_info else {
        return me.error(F, "fmi2EventInfo is NULL");
    };
    let u = match me.model.new_discrete_states(&me.logger) {
        Ok(u) => u,
        Err(e) => {
            me.state = CallState::Error;
            return me.error(F, format!("{e} (the instance is now in the Error state)"));
        }
    };
    let next = u.next_event_time.filter(|t| t.is_finite());
    *event_info = Fmi2EventInfo {
        new_discrete_states_needed: u.new_discrete_states_needed.into(),
        terminate_simulation: u.terminate_simulation.into(),
        nominals_of_continuous_states_changed: u.nominals_changed.into(),
        values_of_continuous_states_changed: u.states_changed.into(),
        next_event_time_defined: next.is_some().into(),
        next_event_time: next.unwrap_or(0.0),
    };
    me.event(|| format!("{F} at t = {}: {u:?}", me.time));
    warn(me, F, &u.warnings)
}

/// `fmi2EnterContinuousTimeMode`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn enter_continuous_time_mode<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, which is what with_instance needs.
    unsafe {
        with_instance::<M>(
            c,
            "fmi2EnterContinuousTimeMode",
            enter_continuous_time_mode_in,
        )
    }
}

fn enter_continuous_time_mode_in<M: FmuModel>(me: &mut Instance<M>) -> Fmi2Status {
    const F: &str = "fmi2EnterContinuousTimeMode";
    if let Err(s) = check_me(me, F, mask::ENTER_CONTINUOUS_TIME_MODE) {
        return s;
    }
    if let Err(e) = me.model.enter_continuous_time_mode() {
        return me.error(F, e);
    }
    me.state = CallState::ContinuousTimeMode;
    me.inputs_changed = false;
    me.event(|| format!("{F} at t = {}", me.time));
    Fmi2Status::Ok
}

/// `fmi2CompletedIntegratorStep`: tells the model the importer accepted a step; the model may
/// ask for an event (`*enter_event_mode`) or to stop (`*terminate_simulation`).
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn completed_integrator_step<M: FmuModel>(
    c: Fmi2Component,
    _no_set_fmu_state_prior: Fmi2Boolean,
    enter_event_mode: *mut Fmi2Boolean,
    terminate_simulation: *mut Fmi2Boolean,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and both out-pointers are NULL or valid for a write,
    // which is what with_instance and `as_mut` need.
    unsafe {
        with_instance::<M>(c, "fmi2CompletedIntegratorStep", |me| {
            completed_integrator_step_in(
                me,
                enter_event_mode.as_mut(),
                terminate_simulation.as_mut(),
            )
        })
    }
}

fn completed_integrator_step_in<M: FmuModel>(
    me: &mut Instance<M>,
    enter_event_mode: Option<&mut Fmi2Boolean>,
    terminate_simulation: Option<&mut Fmi2Boolean>,
) -> Fmi2Status {
    const F: &str = "fmi2CompletedIntegratorStep";
    if let Err(s) = check_me(me, F, mask::COMPLETED_INTEGRATOR_STEP) {
        return s;
    }
    let (Some(enter_event_mode), Some(terminate_simulation)) =
        (enter_event_mode, terminate_simulation)
    else {
        return me.error(F, "enterEventMode or terminateSimulation is NULL");
    };
    let r = match me
        .model
        .completed_integrator_step(me.inputs_changed, &me.logger)
    {
        Ok(r) => r,
        Err(e) => {
            me.state = CallState::Error;
            return me.error(F, format!("{e} (the instance is now in the Error state)"));
        }
    };
    me.inputs_changed = false;
    *enter_event_mode = r.enter_event_mode.into();
    *terminate_simulation = r.terminate_simulation.into();
    if r.enter_event_mode {
        me.event(|| format!("{F} at t = {}: the model asks for an event", me.time));
    }
    warn(me, F, &r.warnings)
}

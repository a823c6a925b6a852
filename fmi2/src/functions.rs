//! The FMI 2.0 functions, generic over the model: what the `#[no_mangle]` entry points of
//! [`export_fmi2!`](crate::export_fmi2) forward to (tests may call them directly).
//! This file holds the life cycle (instantiate, experiment, initialization, step, terminate,
//! reset, status queries, directional derivatives); [`crate::values`] the getters and setters,
//! [`crate::fmu_state`] the FMU-state functions.

use crate::bindings::*;
use crate::ffi::{opt_str, panic_text, slice_in, slice_out, with_instance};
use crate::instance::{mask, CallState, Instance, INSTANCE_MAGIC, STOP_EPS, TIME_EPS};
use crate::logging::{
    Logger, LOG_CATEGORIES, LOG_STATUS_DISCARD, LOG_STATUS_ERROR, LOG_STATUS_FATAL,
    LOG_STATUS_WARNING,
};
use crate::model::{FmuModel, InstantiateArgs, Interface, StepResult};
use crate::variable::{Causality, VarType};
use std::collections::HashMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

pub use crate::fmu_state::{
    deserialize_fmu_state, free_fmu_state, get_fmu_state, serialize_fmu_state,
    serialized_fmu_state_size, set_fmu_state,
};
pub use crate::model_exchange::{
    completed_integrator_step, enter_continuous_time_mode, enter_event_mode, get_continuous_states,
    get_derivatives, get_event_indicators, get_nominals_of_continuous_states, new_discrete_states,
    set_continuous_states, set_time,
};
pub use crate::values::{
    get_boolean, get_integer, get_real, get_string, set_boolean, set_integer, set_real, set_string,
};

/// `fmi2Instantiate`.
///
/// # Safety
/// Pointer arguments must be NULL or valid as the FMI 2.0 standard requires.
pub unsafe fn instantiate<M: FmuModel>(
    instance_name: Fmi2String,
    fmu_type: Fmi2Type,
    fmu_guid: Fmi2String,
    resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    // SAFETY: the arguments are passed on unchanged under this function's contract.
    let r = catch_unwind(AssertUnwindSafe(|| unsafe {
        instantiate_inner::<M>(
            instance_name,
            fmu_type,
            fmu_guid,
            resource_location,
            functions,
            logging_on,
        )
    }));
    match r {
        Ok(Ok(c)) => c,
        Ok(Err(())) => std::ptr::null_mut(),
        Err(payload) => {
            // SAFETY: same checks as in instantiate_inner.
            if let Some(cb) = unsafe { functions.as_ref() } {
                if cb.logger.is_some() {
                    // SAFETY: instanceName is NULL or a C string (this function's contract).
                    let name = unsafe { opt_str(instance_name) }.unwrap_or("?");
                    Logger::new(*cb, name, true).emit(
                        Fmi2Status::Fatal,
                        LOG_STATUS_FATAL,
                        &format!(
                            "fmi2Instantiate: internal error (Rust panic: {})",
                            panic_text(payload.as_ref())
                        ),
                    );
                }
            }
            std::ptr::null_mut()
        }
    }
}

unsafe fn instantiate_inner<M: FmuModel>(
    instance_name: Fmi2String,
    fmu_type: Fmi2Type,
    fmu_guid: Fmi2String,
    resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    logging_on: Fmi2Boolean,
) -> Result<Fmi2Component, ()> {
    // SAFETY: NULL or a valid struct.
    let Some(cb) = (unsafe { functions.as_ref() }).copied() else {
        eprintln!(
            "{}: fmi2Instantiate: the callback functions pointer is NULL; instance not created",
            M::MODEL_IDENTIFIER
        );
        return Err(());
    };
    if cb.logger.is_none() {
        eprintln!(
            "{}: fmi2Instantiate: the callback functions have no logger (NULL); instance not created",
            M::MODEL_IDENTIFIER
        );
        return Err(());
    }
    // SAFETY: instanceName is NULL or a C string (this function's contract).
    let raw_name = unsafe { opt_str(instance_name) };
    let fail = |name: &str, msg: String| {
        Logger::new(cb, name, true).emit(
            Fmi2Status::Error,
            LOG_STATUS_ERROR,
            &format!("fmi2Instantiate: {msg}"),
        );
        Err(())
    };
    let name = match raw_name {
        Some(n) if !n.trim().is_empty() => n.to_string(),
        Some(_) => return fail("", "the instance name is empty".into()),
        None if instance_name.is_null() => {
            return fail("", "the instance name is NULL".into());
        }
        None => return fail("", "the instance name is not valid UTF-8".into()),
    };
    let interface = match fmu_type {
        FMI2_CO_SIMULATION => Interface::CoSimulation,
        FMI2_MODEL_EXCHANGE if M::MODEL_EXCHANGE => Interface::ModelExchange,
        _ => {
            return fail(
                &name,
                format!(
                    "fmuType = {fmu_type} ({}): {} supports {}",
                    if fmu_type == FMI2_MODEL_EXCHANGE {
                        "fmi2ModelExchange"
                    } else {
                        "unknown"
                    },
                    M::MODEL_IDENTIFIER,
                    if M::MODEL_EXCHANGE {
                        "Model Exchange (fmi2ModelExchange = 0) and Co-Simulation \
                         (fmi2CoSimulation = 1)"
                    } else {
                        "Co-Simulation (fmi2CoSimulation = 1) only"
                    }
                ),
            )
        }
    };
    // SAFETY: fmuGUID is NULL or a C string (this function's contract).
    let Some(guid) = (unsafe { opt_str(fmu_guid) }) else {
        return fail(&name, "the GUID is NULL or not valid UTF-8".into());
    };
    // SAFETY: fmuResourceLocation is NULL or a C string (this function's contract).
    let resource_dir = match unsafe { opt_str(resource_location) } {
        None if resource_location.is_null() => None,
        None => return fail(&name, "fmuResourceLocation is not valid UTF-8".into()),
        Some("") => None,
        Some(s) => match crate::uri::file_uri_to_path(s) {
            Ok(p) => Some(p),
            Err(e) => return fail(&name, e),
        },
    };
    let args = InstantiateArgs {
        instance_name: name.clone(),
        resource_dir,
        logging_on: logging_on != 0,
        interface,
    };
    let logger = Logger::new(cb, &name, logging_on != 0);
    let model = match M::instantiate(&args, &logger) {
        Ok(m) => m,
        Err(e) => return fail(&name, e),
    };
    if model.guid() != guid {
        return fail(
            &name,
            format!(
                "GUID {guid} does not match this FMU ({}: GUID {} for the bearing it loaded); \
                 use the modelDescription.xml shipped in the same FMU",
                M::MODEL_IDENTIFIER,
                model.guid()
            ),
        );
    }
    let mut vr_index = HashMap::new();
    for (i, v) in model.variables().iter().enumerate() {
        if vr_index.insert(v.vr, i).is_some() {
            return fail(
                &name,
                format!("internal error: duplicate value reference {}", v.vr),
            );
        }
    }
    let inst = Box::new(Instance {
        magic: INSTANCE_MAGIC,
        interface,
        logger,
        initial_logging: logging_on != 0,
        state: CallState::Instantiated,
        model,
        vr_index,
        time: 0.0,
        start_time: 0.0,
        stop_time: None,
        tolerance: None,
        last_successful_time: 0.0,
        terminated: false,
        strings: Vec::new(),
        refused: Vec::new(),
        inputs_changed: false,
    });
    inst.event(|| {
        format!(
            "fmi2Instantiate: {} instance '{name}' of {} created (GUID {guid})",
            interface.name(),
            M::MODEL_IDENTIFIER
        )
    });
    Ok(Box::into_raw(inst) as Fmi2Component)
}

/// `fmi2FreeInstance`.
///
/// # Safety
/// `c` must be NULL or an instance of this model not yet freed.
pub unsafe fn free_instance<M: FmuModel>(c: Fmi2Component) {
    if c.is_null() {
        return;
    }
    let inst = c as *mut Instance<M>;
    // SAFETY: see with_instance.
    if unsafe { (*inst).magic } != INSTANCE_MAGIC {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: ownership returns to us; the magic is cleared so a double free is caught
        // as long as the memory has not been reused.
        let mut b = unsafe { Box::from_raw(inst) };
        b.magic = 0;
        b.event(|| "fmi2FreeInstance".to_string());
        drop(b);
    }));
}

/// `fmi2SetDebugLogging`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_debug_logging<M: FmuModel>(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n: usize,
    categories: *const Fmi2String,
) -> Fmi2Status {
    const F: &str = "fmi2SetDebugLogging";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::SET_DEBUG_LOGGING) {
                return s;
            }
            let Some(cats) = slice_in(categories, n) else {
                return me.error(F, format!("categories is NULL but nCategories = {n}"));
            };
            let valid = || {
                LOG_CATEGORIES
                    .iter()
                    .map(|(n, _)| *n)
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let mut idx = Vec::with_capacity(n);
            for &p in cats {
                let Some(s) = opt_str(p) else {
                    return me.error(F, format!("NULL or non-UTF-8 category; valid: {}", valid()));
                };
                match Logger::index(s) {
                    Some(i) => idx.push(i),
                    None => {
                        return me.error(
                            F,
                            format!("unknown log category '{s}'; valid categories: {}", valid()),
                        )
                    }
                }
            }
            let on = logging_on != 0;
            if idx.is_empty() {
                me.logger.enabled.iter_mut().for_each(|e| *e = on);
            } else {
                if on {
                    me.logger.enabled.iter_mut().for_each(|e| *e = false);
                }
                for i in idx {
                    me.logger.enabled[i] = on;
                }
            }
            Fmi2Status::Ok
        })
    }
}

/// `fmi2SetupExperiment`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn setup_experiment<M: FmuModel>(
    c: Fmi2Component,
    tolerance_defined: Fmi2Boolean,
    tolerance: Fmi2Real,
    start_time: Fmi2Real,
    stop_time_defined: Fmi2Boolean,
    stop_time: Fmi2Real,
) -> Fmi2Status {
    const F: &str = "fmi2SetupExperiment";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::SETUP_EXPERIMENT) {
                return s;
            }
            let tol = (tolerance_defined != 0).then_some(tolerance);
            if let Some(t) = tol {
                if !(t.is_finite() && t > 0.0) {
                    return me.error(F, format!("tolerance = {t} must be a finite number > 0"));
                }
            }
            if !start_time.is_finite() {
                return me.error(F, format!("startTime = {start_time} is not finite"));
            }
            let stop = (stop_time_defined != 0).then_some(stop_time);
            if let Some(s) = stop {
                if !(s.is_finite() && s >= start_time) {
                    return me.error(
                        F,
                        format!("stopTime = {s} must be finite and ≥ startTime = {start_time}"),
                    );
                }
            }
            if let Err(e) = me.model.setup_experiment(tol, start_time, stop) {
                return me.error(F, e);
            }
            me.tolerance = tol;
            me.start_time = start_time;
            me.time = start_time;
            me.last_successful_time = start_time;
            me.stop_time = stop;
            me.event(|| {
                format!("{F}: tolerance {tol:?}, startTime {start_time}, stopTime {stop:?}")
            });
            Fmi2Status::Ok
        })
    }
}

/// `fmi2EnterInitializationMode`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn enter_initialization_mode<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    const F: &str = "fmi2EnterInitializationMode";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::ENTER_INIT) {
                return s;
            }
            if let Err(e) = me.model.enter_initialization(&me.logger) {
                me.state = CallState::Error;
                return me.error(F, e);
            }
            me.state = CallState::InitializationMode;
            me.event(|| F.to_string());
            Fmi2Status::Ok
        })
    }
}

/// `fmi2ExitInitializationMode`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn exit_initialization_mode<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    const F: &str = "fmi2ExitInitializationMode";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::EXIT_INIT) {
                return s;
            }
            if let Err(s) = me.check_refused(F) {
                return s;
            }
            if let Err(e) = me.model.exit_initialization(&me.logger) {
                me.state = CallState::Error;
                return me.error(
                    F,
                    format!("{e} (the instance is now in the Error state; fmi2Reset to retry)"),
                );
            }
            me.state = match me.interface {
                Interface::CoSimulation => CallState::StepComplete,
                // Model Exchange: the event mode of the initial event iteration.
                Interface::ModelExchange => CallState::EventMode,
            };
            me.time = me.start_time;
            me.last_successful_time = me.start_time;
            me.terminated = false;
            me.inputs_changed = false;
            me.event(|| format!("{F}: ready at t = {} ({:?})", me.time, me.state));
            Fmi2Status::Ok
        })
    }
}

/// `fmi2Terminate`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn terminate<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    const F: &str = "fmi2Terminate";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::TERMINATE) {
                return s;
            }
            if let Err(e) = me.model.terminate() {
                me.state = CallState::Error;
                return me.error(F, e);
            }
            me.state = CallState::Terminated;
            me.event(|| format!("{F} at t = {}", me.time));
            Fmi2Status::Ok
        })
    }
}

/// `fmi2Reset`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn reset<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    const F: &str = "fmi2Reset";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::RESET) {
                return s;
            }
            if let Err(e) = me.model.reset() {
                me.state = CallState::Error;
                return me.error(F, e);
            }
            me.reset_shell();
            let on = me.initial_logging;
            me.logger.enabled.iter_mut().for_each(|e| *e = on);
            me.event(|| format!("{F}: back to the just-instantiated state"));
            Fmi2Status::Ok
        })
    }
}

/// `fmi2GetDirectionalDerivative`: checks the call state, the arrays and that the unknowns are
/// Real outputs and the knowns Real inputs, then asks [`FmuModel::directional_derivative`].
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_directional_derivative<M: FmuModel>(
    c: Fmi2Component,
    unknown: *const Fmi2ValueReference,
    n_unknown: usize,
    known: *const Fmi2ValueReference,
    n_known: usize,
    dv_known: *const Fmi2Real,
    dv_unknown: *mut Fmi2Real,
) -> Fmi2Status {
    const F: &str = "fmi2GetDirectionalDerivative";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::DIRECTIONAL) {
                return s;
            }
            // Model Exchange declares providesDirectionalDerivative="false".
            if let Err(s) = me.check_interface(F, Interface::CoSimulation) {
                return s;
            }
            let (Some(vu), Some(vk), Some(dk), Some(du)) = (
                slice_in(unknown, n_unknown),
                slice_in(known, n_known),
                slice_in(dv_known, n_known),
                slice_out(dv_unknown, n_unknown),
            ) else {
                return me.error(
                    F,
                    format!(
                        "vUnknown_ref, vKnown_ref, dvKnown or dvUnknown is NULL (nUnknown = {n_unknown}, nKnown = {n_known})"
                    ),
                );
            };
            let mut iu = Vec::with_capacity(n_unknown);
            for &r in vu {
                let i = match me.lookup(F, r, VarType::Real) {
                    Ok(i) => i,
                    Err(s) => return s,
                };
                let v = &me.model.variables()[i];
                if v.causality != Causality::Output {
                    return me.error(
                        F,
                        format!(
                            "unknown '{}' (value reference {r}) is not an output",
                            v.name
                        ),
                    );
                }
                iu.push(i);
            }
            let mut ik = Vec::with_capacity(n_known);
            for (&r, &d) in vk.iter().zip(dk) {
                let i = match me.lookup(F, r, VarType::Real) {
                    Ok(i) => i,
                    Err(s) => return s,
                };
                let v = &me.model.variables()[i];
                if v.causality != Causality::Input {
                    return me.error(
                        F,
                        format!("known '{}' (value reference {r}) is not an input", v.name),
                    );
                }
                if !d.is_finite() {
                    return me.error(F, format!("dvKnown for '{}' is {d}", v.name));
                }
                ik.push(i);
            }
            match me.model.directional_derivative(&iu, &ik, dk, du) {
                Ok(()) => {
                    if let Some(k) = du.iter().position(|v| !v.is_finite()) {
                        let name = me.model.variables()[iu[k]].name.clone();
                        return me.error(F, format!("the derivative of '{name}' is not finite"));
                    }
                    Fmi2Status::Ok
                }
                Err(e) => me.error(F, e),
            }
        })
    }
}

/// `fmi2SetRealInputDerivatives`: not supported.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_real_input_derivatives<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        unsupported::<M>(
            c,
            "fmi2SetRealInputDerivatives",
            mask::SET_INPUT_DERIVATIVES,
            "not supported: inputs are held constant over a step (canInterpolateInputs=\"false\")",
        )
    }
}

/// `fmi2GetRealOutputDerivatives`: not supported.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_real_output_derivatives<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        unsupported::<M>(
            c,
            "fmi2GetRealOutputDerivatives",
            mask::GET_OUTPUT_DERIVATIVES,
            "not supported (maxOutputDerivativeOrder=\"0\")",
        )
    }
}

/// `fmi2DoStep`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn do_step<M: FmuModel>(
    c: Fmi2Component,
    t: Fmi2Real,
    h: Fmi2Real,
    _no_set_prior: Fmi2Boolean,
) -> Fmi2Status {
    const F: &str = "fmi2DoStep";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::DO_STEP) {
                return s;
            }
            if let Err(s) = me.check_refused(F) {
                return s;
            }
            if !(h.is_finite() && h > 0.0) {
                return me.error(
                    F,
                    format!("communicationStepSize = {h} must be a finite number > 0"),
                );
            }
            let eps = TIME_EPS * me.time.abs().max(1.0);
            if !t.is_finite() || (t - me.time).abs() > eps {
                return me.error(
                    F,
                    format!(
                        "currentCommunicationPoint = {t} does not match the FMU's time {} \
                         (difference {:e} > {eps:e})",
                        me.time,
                        t - me.time
                    ),
                );
            }
            let t_end = t + h;
            if let Some(stop) = me.stop_time {
                if t_end > stop + STOP_EPS * stop.abs().max(1.0) {
                    return me.error(
                        F,
                        format!(
                            "currentCommunicationPoint + communicationStepSize = {t_end} is past \
                             the stop time {stop} set by fmi2SetupExperiment"
                        ),
                    );
                }
            }
            match me.model.do_step(me.time, t_end, &me.logger) {
                StepResult::Ok => {
                    me.time = t_end;
                    me.last_successful_time = t_end;
                    Fmi2Status::Ok
                }
                StepResult::Warning(messages) => {
                    me.time = t_end;
                    me.last_successful_time = t_end;
                    for m in messages {
                        me.logger.log(
                            Fmi2Status::Warning,
                            LOG_STATUS_WARNING,
                            &format!("{F}: step from {t} to {t_end}: {m}"),
                        );
                    }
                    Fmi2Status::Warning
                }
                StepResult::Discard {
                    message,
                    last_good_time,
                } => {
                    me.state = CallState::StepFailed;
                    me.terminated = true;
                    me.time = last_good_time;
                    me.last_successful_time = last_good_time;
                    me.logger.log(
                        Fmi2Status::Discard,
                        LOG_STATUS_DISCARD,
                        &format!(
                            "{F}: step from {t} to {t_end} discarded: {message}; the FMU stays \
                             at t = {last_good_time} with the outputs of that point \
                             (fmi2LastSuccessfulTime = {last_good_time}, fmi2Terminated = true)"
                        ),
                    );
                    Fmi2Status::Discard
                }
                StepResult::Error(message) => {
                    me.state = CallState::Error;
                    me.error(
                        F,
                        format!(
                            "step from {t} to {t_end} failed: {message}; the outputs are those \
                             of t = {t}"
                        ),
                    )
                }
            }
        })
    }
}

/// `fmi2CancelStep`: no step is ever in progress.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn cancel_step<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        unsupported::<M>(
            c,
            "fmi2CancelStep",
            mask::CANCEL_STEP,
            "not supported (canRunAsynchronuously=\"false\")",
        )
    }
}

/// Body of the optional functions this FMU does not provide: state check, then fmi2Error with
/// a message saying why.
///
/// # Safety
/// FMI 2.0 pointer rules.
unsafe fn unsupported<M: FmuModel>(
    c: Fmi2Component,
    function: &'static str,
    allowed: u16,
    why: &'static str,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, function, |me| {
            if let Err(s) = me.check_state(function, allowed) {
                return s;
            }
            me.error(function, why)
        })
    }
}

fn status_kind_name(k: Fmi2StatusKind) -> String {
    match k {
        FMI2_DO_STEP_STATUS => "fmi2DoStepStatus".into(),
        FMI2_PENDING_STATUS => "fmi2PendingStatus".into(),
        FMI2_LAST_SUCCESSFUL_TIME => "fmi2LastSuccessfulTime".into(),
        FMI2_TERMINATED => "fmi2Terminated".into(),
        k => format!("unknown status kind {k}"),
    }
}

unsafe fn status_query<M: FmuModel, T>(
    c: Fmi2Component,
    fname: &'static str,
    kind: Fmi2StatusKind,
    value: *mut T,
    get: impl FnOnce(&Instance<M>, Fmi2StatusKind) -> Option<T>,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, fname, |me| {
            if let Err(s) = me.check_state(fname, mask::STATUS) {
                return s;
            }
            if let Err(s) = me.check_interface(fname, Interface::CoSimulation) {
                return s;
            }
            if value.is_null() {
                return me.error(fname, "value is NULL");
            }
            match get(me, kind) {
                Some(v) => {
                    *value = v;
                    Fmi2Status::Ok
                }
                None => {
                    me.logger.log(
                        Fmi2Status::Discard,
                        LOG_STATUS_DISCARD,
                        &format!(
                            "{fname}: {} gives no value of this type (this FMU never returns fmi2Pending)",
                            status_kind_name(kind)
                        ),
                    );
                    Fmi2Status::Discard
                }
            }
        })
    }
}

/// `fmi2GetStatus`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_status<M: FmuModel>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Status,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract).
    unsafe { status_query::<M, Fmi2Status>(c, "fmi2GetStatus", kind, value, |_, _| None) }
}

/// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_real_status<M: FmuModel>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        status_query::<M, Fmi2Real>(c, "fmi2GetRealStatus", kind, value, |me, k| {
            (k == FMI2_LAST_SUCCESSFUL_TIME).then_some(me.last_successful_time)
        })
    }
}

/// `fmi2GetIntegerStatus`: no integer status exists.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_integer_status<M: FmuModel>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Integer,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract).
    unsafe { status_query::<M, Fmi2Integer>(c, "fmi2GetIntegerStatus", kind, value, |_, _| None) }
}

/// `fmi2GetBooleanStatus`: `fmi2Terminated`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_boolean_status<M: FmuModel>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        status_query::<M, Fmi2Boolean>(c, "fmi2GetBooleanStatus", kind, value, |me, k| {
            (k == FMI2_TERMINATED).then_some(me.terminated as Fmi2Boolean)
        })
    }
}

/// `fmi2GetStringStatus`: nothing is ever pending.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_string_status<M: FmuModel>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2String,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract).
    unsafe { status_query::<M, Fmi2String>(c, "fmi2GetStringStatus", kind, value, |_, _| None) }
}

//! The C entry points. [`export_fmi2!`](crate::export_fmi2) expands to one `#[no_mangle]`
//! function per FMI 2.0 function (the common, Co-Simulation and Model Exchange ones: 44), each
//! forwarding to the generic shell for one model type. A cdylib can export them for one model
//! only. A model without Model Exchange still exports its functions (they refuse: no instance
//! of it is ever a Model Exchange one).

/// The names of the functions [`export_fmi2!`](crate::export_fmi2) exports: the full FMI 2.0 set.
pub const EXPORTED_FUNCTIONS: [&str; 44] = [
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
    "fmi2EnterEventMode",
    "fmi2NewDiscreteStates",
    "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep",
    "fmi2SetTime",
    "fmi2SetContinuousStates",
    "fmi2GetDerivatives",
    "fmi2GetEventIndicators",
    "fmi2GetContinuousStates",
    "fmi2GetNominalsOfContinuousStates",
];

/// Exports the FMI 2.0 functions (Co-Simulation and Model Exchange) for `$model` (an
/// [`FmuModel`](crate::FmuModel)).
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        const _: () = {
            use std::os::raw::c_char;
            use $crate::bindings::*;
            use $crate::functions as sh;
            type M = $model;

            #[no_mangle]
            pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
                TYPES_PLATFORM.as_ptr() as *const c_char
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetVersion() -> *const c_char {
                VERSION.as_ptr() as *const c_char
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: Fmi2Component,
                logging_on: Fmi2Boolean,
                n: usize,
                categories: *const Fmi2String,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_debug_logging::<M>(c, logging_on, n, categories) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Instantiate(
                instance_name: Fmi2String,
                fmu_type: Fmi2Type,
                guid: Fmi2String,
                resource_location: Fmi2String,
                functions: *const Fmi2CallbackFunctions,
                visible: Fmi2Boolean,
                logging_on: Fmi2Boolean,
            ) -> Fmi2Component {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe {
                    sh::instantiate::<M>(
                        instance_name,
                        fmu_type,
                        guid,
                        resource_location,
                        functions,
                        visible,
                        logging_on,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::free_instance::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: Fmi2Component,
                tolerance_defined: Fmi2Boolean,
                tolerance: Fmi2Real,
                start_time: Fmi2Real,
                stop_time_defined: Fmi2Boolean,
                stop_time: Fmi2Real,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe {
                    sh::setup_experiment::<M>(
                        c,
                        tolerance_defined,
                        tolerance,
                        start_time,
                        stop_time_defined,
                        stop_time,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::enter_initialization_mode::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::exit_initialization_mode::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::terminate::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::reset::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetReal(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                value: *mut Fmi2Real,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_real::<M>(c, vr, n, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                value: *mut Fmi2Integer,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_integer::<M>(c, vr, n, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                value: *mut Fmi2Boolean,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_boolean::<M>(c, vr, n, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetString(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                value: *mut Fmi2String,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_string::<M>(c, vr, n, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetReal(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                value: *const Fmi2Real,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_real::<M>(c, vr, n, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                value: *const Fmi2Integer,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_integer::<M>(c, vr, n, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                value: *const Fmi2Boolean,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_boolean::<M>(c, vr, n, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetString(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                value: *const Fmi2String,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_string::<M>(c, vr, n, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetFMUstate(
                c: Fmi2Component,
                state: *mut Fmi2FmuState,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_fmu_state::<M>(c, state) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetFMUstate(
                c: Fmi2Component,
                state: Fmi2FmuState,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_fmu_state::<M>(c, state) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeFMUstate(
                c: Fmi2Component,
                state: *mut Fmi2FmuState,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::free_fmu_state::<M>(c, state) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: Fmi2Component,
                state: Fmi2FmuState,
                size: *mut usize,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::serialized_fmu_state_size::<M>(c, state, size) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: Fmi2Component,
                state: Fmi2FmuState,
                bytes: *mut Fmi2Byte,
                size: usize,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::serialize_fmu_state::<M>(c, state, bytes, size) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: Fmi2Component,
                bytes: *const Fmi2Byte,
                size: usize,
                state: *mut Fmi2FmuState,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::deserialize_fmu_state::<M>(c, bytes, size, state) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: Fmi2Component,
                unknown: *const Fmi2ValueReference,
                n_unknown: usize,
                known: *const Fmi2ValueReference,
                n_known: usize,
                dv_known: *const Fmi2Real,
                dv_unknown: *mut Fmi2Real,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe {
                    sh::get_directional_derivative::<M>(
                        c, unknown, n_unknown, known, n_known, dv_known, dv_unknown,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Fmi2Component,
                _vr: *const Fmi2ValueReference,
                _n: usize,
                _order: *const Fmi2Integer,
                _value: *const Fmi2Real,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_real_input_derivatives::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Fmi2Component,
                _vr: *const Fmi2ValueReference,
                _n: usize,
                _order: *const Fmi2Integer,
                _value: *mut Fmi2Real,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_real_output_derivatives::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DoStep(
                c: Fmi2Component,
                t: Fmi2Real,
                h: Fmi2Real,
                no_set_prior: Fmi2Boolean,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::do_step::<M>(c, t, h, no_set_prior) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::cancel_step::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStatus(
                c: Fmi2Component,
                kind: Fmi2StatusKind,
                value: *mut Fmi2Status,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_status::<M>(c, kind, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealStatus(
                c: Fmi2Component,
                kind: Fmi2StatusKind,
                value: *mut Fmi2Real,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_real_status::<M>(c, kind, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: Fmi2Component,
                kind: Fmi2StatusKind,
                value: *mut Fmi2Integer,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_integer_status::<M>(c, kind, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: Fmi2Component,
                kind: Fmi2StatusKind,
                value: *mut Fmi2Boolean,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_boolean_status::<M>(c, kind, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: Fmi2Component,
                kind: Fmi2StatusKind,
                value: *mut Fmi2String,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_string_status::<M>(c, kind, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterEventMode(c: Fmi2Component) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::enter_event_mode::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2NewDiscreteStates(
                c: Fmi2Component,
                event_info: *mut Fmi2EventInfo,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::new_discrete_states::<M>(c, event_info) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: Fmi2Component) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::enter_continuous_time_mode::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
                c: Fmi2Component,
                no_set_fmu_state_prior: Fmi2Boolean,
                enter_event_mode: *mut Fmi2Boolean,
                terminate_simulation: *mut Fmi2Boolean,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe {
                    sh::completed_integrator_step::<M>(
                        c,
                        no_set_fmu_state_prior,
                        enter_event_mode,
                        terminate_simulation,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetTime(c: Fmi2Component, time: Fmi2Real) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_time::<M>(c, time) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetContinuousStates(
                c: Fmi2Component,
                x: *const Fmi2Real,
                nx: usize,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::set_continuous_states::<M>(c, x, nx) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetDerivatives(
                c: Fmi2Component,
                derivatives: *mut Fmi2Real,
                nx: usize,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_derivatives::<M>(c, derivatives, nx) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetEventIndicators(
                c: Fmi2Component,
                indicators: *mut Fmi2Real,
                ni: usize,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_event_indicators::<M>(c, indicators, ni) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetContinuousStates(
                c: Fmi2Component,
                x: *mut Fmi2Real,
                nx: usize,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_continuous_states::<M>(c, x, nx) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
                c: Fmi2Component,
                x_nominal: *mut Fmi2Real,
                nx: usize,
            ) -> Fmi2Status {
                // SAFETY: the importer keeps the FMI 2.0 pointer rules, the contract of this entry
                // point and of the shell function it forwards to.
                unsafe { sh::get_nominals_of_continuous_states::<M>(c, x_nominal, nx) }
            }
        };
    };
}

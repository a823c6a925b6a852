//! FMI 2.0 C types (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`), written for raceway.
//!
//! What a Co-Simulation and Model Exchange FMU needs. Layouts follow the standard headers for the
//! "default" platform: `fmi2Boolean` is `int`, `fmi2ValueReference` is `unsigned int`.

use std::os::raw::{c_char, c_int, c_uint, c_void};

/// `fmi2TypesPlatform` of the standard headers.
pub const TYPES_PLATFORM: &[u8] = b"default\0";
/// `fmi2Version`.
pub const VERSION: &[u8] = b"2.0\0";

/// An instance handle (`fmi2Component`).
pub type Fmi2Component = *mut c_void;
/// The importer's opaque pointer handed back to its callbacks.
pub type Fmi2ComponentEnvironment = *mut c_void;
/// A saved FMU state handle (`fmi2FMUstate`).
pub type Fmi2FmuState = *mut c_void;
/// `fmi2ValueReference`.
pub type Fmi2ValueReference = c_uint;
/// `fmi2Real`.
pub type Fmi2Real = f64;
/// `fmi2Integer`.
pub type Fmi2Integer = c_int;
/// `fmi2Boolean` (0 false, anything else true).
pub type Fmi2Boolean = c_int;
/// `fmi2Char`.
pub type Fmi2Char = c_char;
/// `fmi2String`: a NUL-terminated C string.
pub type Fmi2String = *const c_char;
/// `fmi2Byte`.
pub type Fmi2Byte = c_char;

/// `fmi2True`.
pub const FMI2_TRUE: Fmi2Boolean = 1;
/// `fmi2False`.
pub const FMI2_FALSE: Fmi2Boolean = 0;

/// `fmi2Status`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Fmi2Status {
    /// `fmi2OK`.
    Ok = 0,
    /// `fmi2Warning`.
    Warning = 1,
    /// `fmi2Discard`.
    Discard = 2,
    /// `fmi2Error`.
    Error = 3,
    /// `fmi2Fatal`.
    Fatal = 4,
    /// `fmi2Pending`.
    Pending = 5,
}

impl Fmi2Status {
    /// The status name used in log messages.
    pub fn name(self) -> &'static str {
        match self {
            Fmi2Status::Ok => "fmi2OK",
            Fmi2Status::Warning => "fmi2Warning",
            Fmi2Status::Discard => "fmi2Discard",
            Fmi2Status::Error => "fmi2Error",
            Fmi2Status::Fatal => "fmi2Fatal",
            Fmi2Status::Pending => "fmi2Pending",
        }
    }
}

/// `fmi2Type` (passed as a C enum, i.e. an `int`).
pub type Fmi2Type = c_int;
/// `fmi2ModelExchange`.
pub const FMI2_MODEL_EXCHANGE: Fmi2Type = 0;
/// `fmi2CoSimulation`.
pub const FMI2_CO_SIMULATION: Fmi2Type = 1;

/// `fmi2StatusKind` (a C enum).
pub type Fmi2StatusKind = c_int;
/// `fmi2DoStepStatus`.
pub const FMI2_DO_STEP_STATUS: Fmi2StatusKind = 0;
/// `fmi2PendingStatus`.
pub const FMI2_PENDING_STATUS: Fmi2StatusKind = 1;
/// `fmi2LastSuccessfulTime`.
pub const FMI2_LAST_SUCCESSFUL_TIME: Fmi2StatusKind = 2;
/// `fmi2Terminated`.
pub const FMI2_TERMINATED: Fmi2StatusKind = 3;

/// `fmi2EventInfo`, filled by `fmi2NewDiscreteStates`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Fmi2EventInfo {
    /// `newDiscreteStatesNeeded`.
    pub new_discrete_states_needed: Fmi2Boolean,
    /// `terminateSimulation`.
    pub terminate_simulation: Fmi2Boolean,
    /// `nominalsOfContinuousStatesChanged`.
    pub nominals_of_continuous_states_changed: Fmi2Boolean,
    /// `valuesOfContinuousStatesChanged`.
    pub values_of_continuous_states_changed: Fmi2Boolean,
    /// `nextEventTimeDefined`.
    pub next_event_time_defined: Fmi2Boolean,
    /// `nextEventTime`.
    pub next_event_time: Fmi2Real,
}

/// `fmi2CallbackLogger`: C-variadic. raceway always calls it with the format `"%s"` and one
/// string argument, so no importer-side formatting of our text can go wrong.
pub type Fmi2CallbackLogger = unsafe extern "C" fn(
    component_environment: Fmi2ComponentEnvironment,
    instance_name: Fmi2String,
    status: Fmi2Status,
    category: Fmi2String,
    message: Fmi2String,
    ...
);
/// A logger with the message as a sixth fixed argument: what a Rust-side importer (tests,
/// fmu-build's reference run) can define, since stable Rust cannot define a C-variadic function.
pub type FixedArgsLogger = unsafe extern "C" fn(
    Fmi2ComponentEnvironment,
    Fmi2String,
    Fmi2Status,
    Fmi2String,
    Fmi2String,
    *const c_char,
);

/// Passes a [`FixedArgsLogger`] where an `fmi2CallbackLogger` is expected.
///
/// # Safety
/// Sound only because raceway always calls the logger with the format `"%s"` and exactly one
/// string argument, which the x86-64 and aarch64 System V C ABIs (linux64) pass exactly like a
/// sixth fixed argument. Not for other targets or other callers.
pub unsafe fn fixed_args_logger(f: FixedArgsLogger) -> Fmi2CallbackLogger {
    // SAFETY: both are `unsafe extern "C"` function pointers of the same size; the call
    // convention argument is this function's contract.
    unsafe { std::mem::transmute::<FixedArgsLogger, Fmi2CallbackLogger>(f) }
}

/// `fmi2CallbackAllocateMemory`.
pub type Fmi2CallbackAllocateMemory = unsafe extern "C" fn(nobj: usize, size: usize) -> *mut c_void;
/// `fmi2CallbackFreeMemory`.
pub type Fmi2CallbackFreeMemory = unsafe extern "C" fn(obj: *mut c_void);
/// `fmi2StepFinished`.
pub type Fmi2StepFinished =
    unsafe extern "C" fn(component_environment: Fmi2ComponentEnvironment, status: Fmi2Status);

/// `fmi2CallbackFunctions`. Function pointers are `Option` so that NULL is representable.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Fmi2CallbackFunctions {
    /// The importer's logger (required by this shell).
    pub logger: Option<Fmi2CallbackLogger>,
    /// Memory allocation callback (unused: the shell allocates with Rust's allocator).
    pub allocate_memory: Option<Fmi2CallbackAllocateMemory>,
    /// Memory release callback (unused).
    pub free_memory: Option<Fmi2CallbackFreeMemory>,
    /// Asynchronous step-finished callback (unused: steps are synchronous).
    pub step_finished: Option<Fmi2StepFinished>,
    /// Passed back as the first argument of every callback.
    pub component_environment: Fmi2ComponentEnvironment,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_match_the_c_headers() {
        assert_eq!(std::mem::size_of::<Fmi2Status>(), 4);
        assert_eq!(
            std::mem::size_of::<Fmi2CallbackFunctions>(),
            5 * std::mem::size_of::<*const ()>()
        );
        assert_eq!(std::mem::size_of::<Option<Fmi2CallbackLogger>>(), 8);
        assert_eq!(std::mem::size_of::<Fmi2Boolean>(), 4);
        // five ints, then a double at offset 24 (8-byte aligned)
        assert_eq!(std::mem::size_of::<Fmi2EventInfo>(), 32);
        assert_eq!(std::mem::offset_of!(Fmi2EventInfo, next_event_time), 24);
    }
}

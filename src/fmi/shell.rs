//! The generic FMI 2.0 Co-Simulation shell: one heap instance per `fmi2Instantiate`, the FMI 2.0
//! call-state machine, argument checks, logging, panic containment and the FMU-state format.
//!
//! The shell knows no physics. A model implements [`FmuModel`]; [`crate::export_fmi2!`] (in
//! `exports.rs`) generates the `#[no_mangle]` C entry points that forward to the generic
//! functions of this module (`do_step::<M>` etc.), which tests may also call directly.
//!
//! Conventions (documented in the FMU's index.html too):
//! - A call rejected by an argument or call-sequence check returns `fmi2Error`, logs why, and
//!   has no effect (the instance stays in its state). A failure of the model itself during
//!   `fmi2ExitInitializationMode` or `fmi2DoStep` moves the instance to the Error state, from
//!   which `fmi2Reset`, `fmi2SetFMUstate` and `fmi2FreeInstance` lead out.
//! - Messages with status Warning, Discard, Error or Fatal are always passed to the logger; all
//!   others only when `loggingOn` and their category are enabled.
//! - A panic inside any entry point becomes `fmi2Fatal` (the instance is then only freeable).

use super::bindings::*;
use super::codec::{fnv1a64, ByteReader, ByteWriter};
use std::collections::HashMap;
use std::ffi::{CStr, CString};
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

// ---------------------------------------------------------------------------------------------
// Variables
// ---------------------------------------------------------------------------------------------

/// FMI base type of a variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VarType {
    Real,
    Integer,
    Boolean,
    String,
}

impl VarType {
    pub fn name(self) -> &'static str {
        match self {
            VarType::Real => "Real",
            VarType::Integer => "Integer",
            VarType::Boolean => "Boolean",
            VarType::String => "String",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
    Independent,
}

impl Causality {
    pub fn name(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
            Causality::Independent => "independent",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

impl Variability {
    pub fn name(self) -> &'static str {
        match self {
            Variability::Constant => "constant",
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

impl Initial {
    pub fn name(self) -> &'static str {
        match self {
            Initial::Exact => "exact",
            Initial::Approx => "approx",
            Initial::Calculated => "calculated",
        }
    }
}

/// Start value of a variable (its type must match the variable's).
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    None,
    Real(f64),
    Integer(i32),
    Boolean(bool),
    String(String),
}

/// One model variable: what the shell checks calls against, and what the XML generator writes.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    pub vr: u32,
    pub name: String,
    pub ty: VarType,
    pub causality: Causality,
    pub variability: Variability,
    /// `None`: the attribute is omitted (FMI default for the causality/variability).
    pub initial: Option<Initial>,
    pub description: String,
    /// Real only: unit name (must be defined in the model's unit definitions).
    pub unit: Option<String>,
    /// Real only: the `SimpleType` name, if any.
    pub declared_type: Option<String>,
    pub display_unit: Option<String>,
    pub start: Start,
    /// Inclusive bounds (Real and Integer); the shell enforces them on every set.
    pub min: Option<f64>,
    pub max: Option<f64>,
}

impl Variable {
    /// Whether `fmi2Set*` may write the variable at all (ignoring the call state).
    pub fn is_settable(&self) -> bool {
        self.variability != Variability::Constant
            && matches!(self.causality, Causality::Parameter | Causality::Input)
    }
}

// ---------------------------------------------------------------------------------------------
// Logging
// ---------------------------------------------------------------------------------------------

pub const LOG_EVENTS: &str = "logEvents";
pub const LOG_SOLVER: &str = "logSolver";
pub const LOG_STATUS_WARNING: &str = "logStatusWarning";
pub const LOG_STATUS_DISCARD: &str = "logStatusDiscard";
pub const LOG_STATUS_ERROR: &str = "logStatusError";
pub const LOG_STATUS_FATAL: &str = "logStatusFatal";
pub const LOG_ALL: &str = "logAll";

/// The log categories of every raceway FMU (name, description), in `LogCategories` order.
pub const LOG_CATEGORIES: &[(&str, &str)] = &[
    (
        LOG_EVENTS,
        "Call-sequence events: instantiation, initialization, parameter changes, reset, state save/restore",
    ),
    (
        LOG_SOLVER,
        "Integrator work per communication step (steps, rejected steps, right-hand-side evaluations)",
    ),
    (
        LOG_STATUS_WARNING,
        "Calls that return fmi2Warning (always logged)",
    ),
    (
        LOG_STATUS_DISCARD,
        "Calls that return fmi2Discard (always logged)",
    ),
    (LOG_STATUS_ERROR, "Calls that return fmi2Error (always logged)"),
    (LOG_STATUS_FATAL, "Calls that return fmi2Fatal (always logged)"),
    (LOG_ALL, "Every message"),
];

/// The importer's logger, bound to one instance.
pub struct Logger {
    callbacks: Fmi2CallbackFunctions,
    instance_name: CString,
    /// One flag per entry of [`LOG_CATEGORIES`].
    enabled: Vec<bool>,
}

// SAFETY: the component environment is an opaque pointer we only hand back to the importer's
// logger; FMI allows an instance to be used from any thread as long as calls are not concurrent.
unsafe impl Send for Logger {}

impl Logger {
    fn new(callbacks: Fmi2CallbackFunctions, instance_name: &str, logging_on: bool) -> Self {
        Self {
            callbacks,
            instance_name: to_cstring(instance_name),
            enabled: vec![logging_on; LOG_CATEGORIES.len()],
        }
    }

    fn index(category: &str) -> Option<usize> {
        LOG_CATEGORIES.iter().position(|(n, _)| *n == category)
    }

    /// Whether a debug message of this category would reach the importer.
    pub fn enabled(&self, category: &str) -> bool {
        let all = self.enabled[LOG_CATEGORIES.len() - 1];
        all || Self::index(category).is_some_and(|i| self.enabled[i])
    }

    /// Logs `message`. Warning, Discard, Error and Fatal always reach the logger; others only
    /// if their category is enabled.
    pub fn log(&self, status: Fmi2Status, category: &str, message: &str) {
        if status < Fmi2Status::Warning && !self.enabled(category) {
            return;
        }
        self.emit(status, category, message);
    }

    fn emit(&self, status: Fmi2Status, category: &str, message: &str) {
        let Some(logger) = self.callbacks.logger else {
            return;
        };
        let cat = to_cstring(category);
        let msg = to_cstring(message);
        // SAFETY: the importer promised a valid logger; we pass "%s" and one C string.
        unsafe {
            logger(
                self.callbacks.component_environment,
                self.instance_name.as_ptr(),
                status,
                cat.as_ptr(),
                c"%s".as_ptr(),
                msg.as_ptr(),
            );
        }
    }
}

fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).expect("NULs were replaced")
}

// ---------------------------------------------------------------------------------------------
// The model trait
// ---------------------------------------------------------------------------------------------

/// What `fmi2Instantiate` hands to [`FmuModel::instantiate`].
#[derive(Debug, Clone)]
pub struct InstantiateArgs {
    pub instance_name: String,
    /// The decoded `fmuResourceLocation`, if one was given.
    pub resource_dir: Option<PathBuf>,
    pub logging_on: bool,
}

/// Outcome of one communication step.
#[derive(Debug, Clone, PartialEq)]
pub enum StepResult {
    /// The model is now exactly at the requested end time.
    Ok,
    /// As `Ok`, with warnings the model raised in the step (each logged with status
    /// fmi2Warning; the call returns fmi2Warning).
    Warning(Vec<String>),
    /// The model cannot complete the step (integrator failure); it is valid at
    /// `last_good_time`, whose outputs are what the master reads from now on.
    Discard {
        message: String,
        last_good_time: f64,
    },
    /// Something else went wrong; the instance goes to the Error state. The model should stay
    /// at the step's start, whose outputs remain readable.
    Error(String),
}

/// A model behind the shell. Indices are positions in [`FmuModel::variables`]; the shell has
/// already checked the value reference, the type, the causality and the call state, that reals
/// are finite, and the declared min/max.
pub trait FmuModel: Send + Sized + 'static {
    /// `modelIdentifier`.
    const MODEL_IDENTIFIER: &'static str;

    /// Builds the model for a new instance (reads resources); an `Err` makes `fmi2Instantiate`
    /// return NULL with that message.
    fn instantiate(args: &InstantiateArgs, log: &Logger) -> Result<Self, String>;
    /// The GUID of the model description this instance implements.
    fn guid(&self) -> &str;
    /// The variable table; value references must be unique.
    fn variables(&self) -> &[Variable];

    fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<(), String>;
    fn enter_initialization(&mut self, _log: &Logger) -> Result<(), String> {
        Ok(())
    }
    /// Validates the parameters and builds the runnable model.
    fn exit_initialization(&mut self, log: &Logger) -> Result<(), String>;
    /// Advances from `t` to exactly `t_end` (absolute times).
    fn do_step(&mut self, t: f64, t_end: f64, log: &Logger) -> StepResult;
    fn terminate(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// Back to the just-instantiated state.
    fn reset(&mut self) -> Result<(), String>;

    fn get_real(&mut self, index: usize) -> Result<f64, String>;
    fn set_real(&mut self, index: usize, value: f64) -> Result<(), String>;
    fn get_integer(&mut self, index: usize) -> Result<i32, String> {
        Err(format!("variable #{index} is not an Integer of this model"))
    }
    fn set_integer(&mut self, index: usize, _value: i32) -> Result<(), String> {
        Err(format!("variable #{index} is not an Integer of this model"))
    }
    fn get_boolean(&mut self, index: usize) -> Result<bool, String> {
        Err(format!("variable #{index} is not a Boolean of this model"))
    }
    fn set_boolean(&mut self, index: usize, _value: bool) -> Result<(), String> {
        Err(format!("variable #{index} is not a Boolean of this model"))
    }
    fn get_string(&mut self, index: usize) -> Result<String, String> {
        Err(format!("variable #{index} is not a String of this model"))
    }
    fn set_string(&mut self, index: usize, _value: &str) -> Result<(), String> {
        Err(format!("variable #{index} is not a String of this model"))
    }

    /// `fmi2GetDirectionalDerivative`: `dv_unknown = ∂unknowns/∂knowns · dv_known` at the
    /// current point (CS: the direct dependence of outputs on inputs). `unknowns` are indices
    /// of Real outputs, `knowns` of Real inputs (the shell has checked both, and the lengths).
    /// The default says the FMU does not provide it (`providesDirectionalDerivative="false"`).
    fn directional_derivative(
        &mut self,
        _unknowns: &[usize],
        _knowns: &[usize],
        _dv_known: &[f64],
        _dv_unknown: &mut [f64],
    ) -> Result<(), String> {
        Err("not provided by this FMU (providesDirectionalDerivative=\"false\")".into())
    }

    /// The model's own part of an FMU state (pointer-free bytes).
    fn save_state(&self) -> Vec<u8>;
    /// Restores [`FmuModel::save_state`] bytes; must leave the model unchanged on `Err`.
    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String>;
}

// ---------------------------------------------------------------------------------------------
// The instance and its state machine
// ---------------------------------------------------------------------------------------------

/// FMI 2.0 Co-Simulation call states (bit flags so allowed sets are masks).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum CallState {
    Instantiated = 1,
    InitializationMode = 2,
    StepComplete = 4,
    StepFailed = 8,
    StepCanceled = 16,
    Terminated = 32,
    Error = 64,
    Fatal = 128,
}

impl CallState {
    fn from_u8(b: u8) -> Option<Self> {
        Some(match b {
            1 => CallState::Instantiated,
            2 => CallState::InitializationMode,
            4 => CallState::StepComplete,
            8 => CallState::StepFailed,
            16 => CallState::StepCanceled,
            32 => CallState::Terminated,
            64 => CallState::Error,
            128 => CallState::Fatal,
            _ => return None,
        })
    }
}

const INSTANTIATED: u8 = CallState::Instantiated as u8;
const INIT_MODE: u8 = CallState::InitializationMode as u8;
const STEP_COMPLETE: u8 = CallState::StepComplete as u8;
const STEP_FAILED: u8 = CallState::StepFailed as u8;
const STEP_CANCELED: u8 = CallState::StepCanceled as u8;
const TERMINATED: u8 = CallState::Terminated as u8;
const ERROR: u8 = CallState::Error as u8;

mod mask {
    use super::*;
    pub const SET_DEBUG_LOGGING: u8 =
        INSTANTIATED | INIT_MODE | STEP_COMPLETE | STEP_FAILED | STEP_CANCELED | TERMINATED | ERROR;
    pub const SETUP_EXPERIMENT: u8 = INSTANTIATED;
    pub const ENTER_INIT: u8 = INSTANTIATED;
    pub const EXIT_INIT: u8 = INIT_MODE;
    pub const TERMINATE: u8 = STEP_COMPLETE | STEP_FAILED | STEP_CANCELED;
    pub const RESET: u8 = SET_DEBUG_LOGGING;
    pub const GET: u8 =
        INIT_MODE | STEP_COMPLETE | STEP_FAILED | STEP_CANCELED | TERMINATED | ERROR;
    pub const SET: u8 = INSTANTIATED | INIT_MODE | STEP_COMPLETE;
    pub const FMU_STATE: u8 = SET_DEBUG_LOGGING;
    pub const DIRECTIONAL: u8 = GET;
    pub const SET_INPUT_DERIVATIVES: u8 = INSTANTIATED | INIT_MODE | STEP_COMPLETE;
    pub const GET_OUTPUT_DERIVATIVES: u8 =
        STEP_COMPLETE | STEP_FAILED | STEP_CANCELED | TERMINATED | ERROR;
    pub const DO_STEP: u8 = STEP_COMPLETE;
    pub const CANCEL_STEP: u8 = 0; // no step is ever in progress (synchronous FMU)
    pub const STATUS: u8 = STEP_COMPLETE | STEP_FAILED | STEP_CANCELED | TERMINATED;
}

fn mask_names(mask: u8) -> String {
    let all = [
        CallState::Instantiated,
        CallState::InitializationMode,
        CallState::StepComplete,
        CallState::StepFailed,
        CallState::StepCanceled,
        CallState::Terminated,
        CallState::Error,
    ];
    let v: Vec<String> = all
        .iter()
        .filter(|s| mask & (**s as u8) != 0)
        .map(|s| format!("{s:?}"))
        .collect();
    if v.is_empty() {
        "no state (the FMU never has a step in progress)".into()
    } else {
        v.join(", ")
    }
}

const INSTANCE_MAGIC: u64 = 0x5241_4345_5741_5949; // "RACEWAYI"
const FMU_STATE_MAGIC: u64 = 0x5241_4345_5741_5953; // "RACEWAYS"

/// Magic bytes and version of the serialized FMU state.
pub const STATE_MAGIC: &[u8; 8] = b"RWYFMUST";
pub const STATE_FORMAT_VERSION: u32 = 1;

/// Relative tolerance on `currentCommunicationPoint` (× max(1, |t|)).
pub const TIME_EPS: f64 = 1e-12;
/// Relative tolerance on the stop time (× max(1, |stopTime|)).
pub const STOP_EPS: f64 = 1e-9;

/// One FMU instance (owned by the importer through an opaque pointer).
pub struct Instance<M: FmuModel> {
    magic: u64,
    logger: Logger,
    initial_logging: bool,
    state: CallState,
    model: M,
    vr_index: HashMap<u32, usize>,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    tolerance: Option<f64>,
    last_successful_time: f64,
    terminated: bool,
    /// Storage of the strings returned by `fmi2GetString` (valid until the next call).
    strings: Vec<CString>,
}

/// A saved FMU state (what `fmi2FMUstate` points to): the serialized bytes.
struct SavedState {
    magic: u64,
    bytes: Vec<u8>,
}

impl<M: FmuModel> Instance<M> {
    /// The model, for tests and tools.
    pub fn model(&self) -> &M {
        &self.model
    }
    pub fn call_state(&self) -> CallState {
        self.state
    }
    pub fn time(&self) -> f64 {
        self.time
    }

    fn error(&self, fname: &str, message: impl AsRef<str>) -> Fmi2Status {
        self.logger.log(
            Fmi2Status::Error,
            LOG_STATUS_ERROR,
            &format!("{fname}: {}", message.as_ref()),
        );
        Fmi2Status::Error
    }

    fn event(&self, message: impl FnOnce() -> String) {
        if self.logger.enabled(LOG_EVENTS) {
            self.logger.log(Fmi2Status::Ok, LOG_EVENTS, &message());
        }
    }

    fn check_state(&self, fname: &str, allowed: u8) -> Result<(), Fmi2Status> {
        if self.state as u8 & allowed != 0 {
            Ok(())
        } else {
            Err(self.error(
                fname,
                format!(
                    "illegal call sequence: the instance is in state {:?}; allowed in: {}",
                    self.state,
                    mask_names(allowed)
                ),
            ))
        }
    }

    fn lookup(&self, fname: &str, vr: u32, ty: VarType) -> Result<usize, Fmi2Status> {
        let Some(&i) = self.vr_index.get(&vr) else {
            return Err(self.error(fname, format!("unknown value reference {vr}")));
        };
        let v = &self.model.variables()[i];
        if v.ty != ty {
            return Err(self.error(
                fname,
                format!(
                    "value reference {vr} is '{}', a {} variable, not a {}",
                    v.name,
                    v.ty.name(),
                    ty.name()
                ),
            ));
        }
        Ok(i)
    }

    fn check_settable(&self, fname: &str, i: usize) -> Result<(), Fmi2Status> {
        let v = &self.model.variables()[i];
        if !v.is_settable() {
            let what = match v.causality {
                Causality::Output => "a calculated output".to_string(),
                c => format!("a {} variable ({})", c.name(), v.variability.name()),
            };
            return Err(self.error(
                fname,
                format!(
                    "'{}' (value reference {}) is {what} and cannot be set",
                    v.name, v.vr
                ),
            ));
        }
        if self.state == CallState::StepComplete
            && v.causality == Causality::Parameter
            && v.variability != Variability::Tunable
        {
            return Err(self.error(
                fname,
                format!(
                    "'{}' is a {} parameter: it can only be set before fmi2ExitInitializationMode \
                     (use fmi2Reset to change it)",
                    v.name,
                    v.variability.name()
                ),
            ));
        }
        Ok(())
    }

    fn check_bounds(&self, fname: &str, i: usize, value: f64) -> Result<(), Fmi2Status> {
        let v = &self.model.variables()[i];
        if !value.is_finite() {
            return Err(self.error(
                fname,
                format!(
                    "'{}' = {value} is not a finite number; value rejected",
                    v.name
                ),
            ));
        }
        let below = v.min.is_some_and(|m| value < m);
        let above = v.max.is_some_and(|m| value > m);
        if below || above {
            let lo = v.min.map_or("-inf".to_string(), |m| m.to_string());
            let hi = v.max.map_or("+inf".to_string(), |m| m.to_string());
            return Err(self.error(
                fname,
                format!(
                    "'{}' = {value} is outside its range [{lo}, {hi}]; value rejected",
                    v.name
                ),
            ));
        }
        Ok(())
    }

    fn reset_shell(&mut self) {
        self.state = CallState::Instantiated;
        self.time = 0.0;
        self.start_time = 0.0;
        self.stop_time = None;
        self.tolerance = None;
        self.last_successful_time = 0.0;
        self.terminated = false;
        self.strings.clear();
    }

    /// The full serialized FMU state (header + shell + model + checksum).
    fn serialize(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.raw(STATE_MAGIC)
            .u32(STATE_FORMAT_VERSION)
            .str(M::MODEL_IDENTIFIER)
            .str(self.model.guid())
            .u8(self.state as u8)
            .f64(self.time)
            .f64(self.start_time)
            .opt_f64(self.stop_time)
            .opt_f64(self.tolerance)
            .f64(self.last_successful_time)
            .bool(self.terminated)
            .bytes(&self.model.save_state());
        let sum = fnv1a64(&w.buf);
        w.u64(sum);
        w.into_bytes()
    }

    /// Checks a serialized state without applying it.
    fn check_blob<'a>(&self, bytes: &'a [u8]) -> Result<ShellSnapshot<'a>, String> {
        if bytes.len() < STATE_MAGIC.len() + 4 + 8 || &bytes[..8] != STATE_MAGIC {
            return Err(format!(
                "not a serialized {} FMU state (bad magic or {} bytes only)",
                M::MODEL_IDENTIFIER,
                bytes.len()
            ));
        }
        let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
        if version != STATE_FORMAT_VERSION {
            return Err(format!(
                "state format version {version} is not supported (this FMU reads version {STATE_FORMAT_VERSION})"
            ));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        if fnv1a64(body) != u64::from_le_bytes(sum.try_into().expect("8 bytes")) {
            return Err(format!(
                "truncated or corrupt FMU state ({} bytes, checksum mismatch)",
                bytes.len()
            ));
        }
        let mut r = ByteReader::new(&body[12..]);
        let ident = r.str("model identifier")?;
        if ident != M::MODEL_IDENTIFIER {
            return Err(format!(
                "the state belongs to FMU '{ident}', not '{}'",
                M::MODEL_IDENTIFIER
            ));
        }
        let guid = r.str("GUID")?;
        if guid != self.model.guid() {
            return Err(format!(
                "the state was saved by an FMU with GUID {guid}; this instance is {}",
                self.model.guid()
            ));
        }
        let state_byte = r.u8("call state")?;
        let state = CallState::from_u8(state_byte)
            .filter(|s| *s != CallState::Fatal)
            .ok_or_else(|| format!("corrupt state: call state {state_byte}"))?;
        let snap = ShellSnapshot {
            state,
            time: r.f64("time")?,
            start_time: r.f64("start time")?,
            stop_time: r.opt_f64("stop time")?,
            tolerance: r.opt_f64("tolerance")?,
            last_successful_time: r.f64("last successful time")?,
            terminated: r.bool("terminated flag")?,
            model: r.bytes("model state")?,
        };
        r.finish("the model state")?;
        Ok(snap)
    }
}

struct ShellSnapshot<'a> {
    state: CallState,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    tolerance: Option<f64>,
    last_successful_time: f64,
    terminated: bool,
    model: &'a [u8],
}

// ---------------------------------------------------------------------------------------------
// Entry-point helpers
// ---------------------------------------------------------------------------------------------

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_string()
    }
}

/// Runs `f` on the instance behind `c`: NULL and foreign pointers are rejected, a Fatal
/// instance refuses everything, and a panic becomes `fmi2Fatal`.
unsafe fn with_instance<M: FmuModel>(
    c: Fmi2Component,
    fname: &str,
    f: impl FnOnce(&mut Instance<M>) -> Fmi2Status,
) -> Fmi2Status {
    if c.is_null() {
        return Fmi2Status::Error;
    }
    let inst = c as *mut Instance<M>;
    // SAFETY: the importer passes back what fmi2Instantiate returned; the magic catches some
    // (not all) foreign pointers.
    if unsafe { (*inst).magic } != INSTANCE_MAGIC {
        return Fmi2Status::Error;
    }
    let result = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: valid instance, and FMI forbids concurrent calls on one instance.
        let me = unsafe { &mut *inst };
        if me.state == CallState::Fatal {
            me.logger.log(
                Fmi2Status::Error,
                LOG_STATUS_ERROR,
                &format!("{fname}: the instance is in the Fatal state; only fmi2FreeInstance is possible"),
            );
            return Fmi2Status::Error;
        }
        f(me)
    }));
    match result {
        Ok(s) => s,
        Err(payload) => {
            let text = panic_text(payload.as_ref());
            let _ = catch_unwind(AssertUnwindSafe(|| {
                // SAFETY: as above; the panicking borrow has ended.
                let me = unsafe { &mut *inst };
                me.state = CallState::Fatal;
                me.logger.log(
                    Fmi2Status::Fatal,
                    LOG_STATUS_FATAL,
                    &format!("{fname}: internal error (Rust panic: {text}); the instance is unusable, free it"),
                );
            }));
            Fmi2Status::Fatal
        }
    }
}

/// Checks an array argument: NULL is only allowed when `n == 0`.
fn slice_in<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        // SAFETY: the importer passes n valid elements.
        Some(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

fn slice_out<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        // SAFETY: the importer passes room for n elements.
        Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

unsafe fn opt_str<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        None
    } else {
        // SAFETY: NUL-terminated string from the importer.
        unsafe { CStr::from_ptr(p) }.to_str().ok()
    }
}

// ---------------------------------------------------------------------------------------------
// The FMI functions, generic over the model
// ---------------------------------------------------------------------------------------------

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
    if fmu_type != FMI2_CO_SIMULATION {
        return fail(
            &name,
            format!(
                "fmuType = {fmu_type} ({}): {} supports Co-Simulation (fmi2CoSimulation = 1) only",
                if fmu_type == FMI2_MODEL_EXCHANGE {
                    "fmi2ModelExchange"
                } else {
                    "unknown"
                },
                M::MODEL_IDENTIFIER
            ),
        );
    }
    let Some(guid) = (unsafe { opt_str(fmu_guid) }) else {
        return fail(&name, "the GUID is NULL or not valid UTF-8".into());
    };
    let resource_dir = match unsafe { opt_str(resource_location) } {
        None if resource_location.is_null() => None,
        None => return fail(&name, "fmuResourceLocation is not valid UTF-8".into()),
        Some("") => None,
        Some(s) => match super::uri::file_uri_to_path(s) {
            Ok(p) => Some(p),
            Err(e) => return fail(&name, e),
        },
    };
    let args = InstantiateArgs {
        instance_name: name.clone(),
        resource_dir,
        logging_on: logging_on != 0,
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
    });
    inst.event(|| {
        format!(
            "fmi2Instantiate: instance '{name}' of {} created (GUID {guid})",
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
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::EXIT_INIT) {
                return s;
            }
            if let Err(e) = me.model.exit_initialization(&me.logger) {
                me.state = CallState::Error;
                return me.error(
                    F,
                    format!("{e} (the instance is now in the Error state; fmi2Reset to retry)"),
                );
            }
            me.state = CallState::StepComplete;
            me.time = me.start_time;
            me.last_successful_time = me.start_time;
            me.terminated = false;
            me.event(|| format!("{F}: ready at t = {}", me.time));
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

macro_rules! getter {
    ($fname:ident, $F:literal, $ty:ty, $vt:expr, $get:ident, $conv:expr) => {
        /// `fmi2Get*`.
        ///
        /// # Safety
        /// FMI 2.0 pointer rules.
        pub unsafe fn $fname<M: FmuModel>(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            value: *mut $ty,
        ) -> Fmi2Status {
            const F: &str = $F;
            unsafe {
                with_instance::<M>(c, F, |me| {
                    if let Err(s) = me.check_state(F, mask::GET) {
                        return s;
                    }
                    let (Some(vrs), Some(out)) = (slice_in(vr, n), slice_out(value, n)) else {
                        return me.error(F, format!("vr or value is NULL with nvr = {n}"));
                    };
                    for (k, &r) in vrs.iter().enumerate() {
                        let i = match me.lookup(F, r, $vt) {
                            Ok(i) => i,
                            Err(s) => return s,
                        };
                        match me.model.$get(i) {
                            Ok(v) =>
                            {
                                #[allow(clippy::redundant_closure_call)]
                                match ($conv)(me, i, v) {
                                    Ok(x) => out[k] = x,
                                    Err(s) => return s,
                                }
                            }
                            Err(e) => return me.error(F, e),
                        }
                    }
                    Fmi2Status::Ok
                })
            }
        }
    };
}

fn real_out<M: FmuModel>(me: &mut Instance<M>, i: usize, v: f64) -> Result<f64, Fmi2Status> {
    if v.is_finite() {
        Ok(v)
    } else {
        let name = me.model.variables()[i].name.clone();
        Err(me.error(
            "fmi2GetReal",
            format!(
                "'{name}' is {v} at t = {} (the integration failed; no valid value)",
                me.time
            ),
        ))
    }
}

getter!(
    get_real,
    "fmi2GetReal",
    Fmi2Real,
    VarType::Real,
    get_real,
    real_out::<M>
);
getter!(
    get_integer,
    "fmi2GetInteger",
    Fmi2Integer,
    VarType::Integer,
    get_integer,
    |_: &mut Instance<M>, _: usize, v: i32| -> Result<i32, Fmi2Status> { Ok(v) }
);
getter!(
    get_boolean,
    "fmi2GetBoolean",
    Fmi2Boolean,
    VarType::Boolean,
    get_boolean,
    |_: &mut Instance<M>, _: usize, v: bool| -> Result<Fmi2Boolean, Fmi2Status> {
        Ok(v as Fmi2Boolean)
    }
);

/// `fmi2GetString`: the returned pointers stay valid until the next call on this instance's
/// `fmi2GetString`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_string<M: FmuModel>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *mut Fmi2String,
) -> Fmi2Status {
    const F: &str = "fmi2GetString";
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::GET) {
                return s;
            }
            let (Some(vrs), Some(out)) = (slice_in(vr, n), slice_out(value, n)) else {
                return me.error(F, format!("vr or value is NULL with nvr = {n}"));
            };
            let mut strings = Vec::with_capacity(n);
            for &r in vrs {
                let i = match me.lookup(F, r, VarType::String) {
                    Ok(i) => i,
                    Err(s) => return s,
                };
                match me.model.get_string(i) {
                    Ok(v) => strings.push(to_cstring(&v)),
                    Err(e) => return me.error(F, e),
                }
            }
            me.strings = strings;
            for (k, s) in me.strings.iter().enumerate() {
                out[k] = s.as_ptr();
            }
            Fmi2Status::Ok
        })
    }
}

/// Common part of the setters: state, array and per-variable checks for all values first,
/// then the model's setter for each.
#[allow(clippy::too_many_arguments)]
unsafe fn set_values<M: FmuModel, T: Copy>(
    c: Fmi2Component,
    fname: &'static str,
    vt: VarType,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const T,
    as_f64: impl Fn(T) -> Option<f64>,
    apply: impl Fn(&mut M, usize, T) -> Result<(), String>,
) -> Fmi2Status {
    unsafe {
        with_instance::<M>(c, fname, |me| {
            if let Err(s) = me.check_state(fname, mask::SET) {
                return s;
            }
            let (Some(vrs), Some(vals)) = (slice_in(vr, n), slice_in(value, n)) else {
                return me.error(fname, format!("vr or value is NULL with nvr = {n}"));
            };
            let mut idx = Vec::with_capacity(n);
            for (k, &r) in vrs.iter().enumerate() {
                let i = match me.lookup(fname, r, vt) {
                    Ok(i) => i,
                    Err(s) => return s,
                };
                if let Err(s) = me.check_settable(fname, i) {
                    return s;
                }
                if let Some(x) = as_f64(vals[k]) {
                    if let Err(s) = me.check_bounds(fname, i, x) {
                        return s;
                    }
                }
                idx.push(i);
            }
            for (k, i) in idx.into_iter().enumerate() {
                if let Err(e) = apply(&mut me.model, i, vals[k]) {
                    return me.error(fname, e);
                }
            }
            Fmi2Status::Ok
        })
    }
}

/// `fmi2SetReal`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_real<M: FmuModel>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const Fmi2Real,
) -> Fmi2Status {
    unsafe {
        set_values::<M, f64>(
            c,
            "fmi2SetReal",
            VarType::Real,
            vr,
            n,
            value,
            Some,
            |m, i, v| m.set_real(i, v),
        )
    }
}

/// `fmi2SetInteger`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_integer<M: FmuModel>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const Fmi2Integer,
) -> Fmi2Status {
    unsafe {
        set_values::<M, i32>(
            c,
            "fmi2SetInteger",
            VarType::Integer,
            vr,
            n,
            value,
            |v| Some(v as f64),
            |m, i, v| m.set_integer(i, v),
        )
    }
}

/// `fmi2SetBoolean`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_boolean<M: FmuModel>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    unsafe {
        set_values::<M, Fmi2Boolean>(
            c,
            "fmi2SetBoolean",
            VarType::Boolean,
            vr,
            n,
            value,
            |_| None,
            |m, i, v| m.set_boolean(i, v != 0),
        )
    }
}

/// `fmi2SetString`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_string<M: FmuModel>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const Fmi2String,
) -> Fmi2Status {
    unsafe {
        set_values::<M, Fmi2String>(
            c,
            "fmi2SetString",
            VarType::String,
            vr,
            n,
            value,
            |_| None,
            |m, i, v| match opt_str(v) {
                Some(s) => m.set_string(i, s),
                None => Err("NULL or non-UTF-8 string value".into()),
            },
        )
    }
}

/// `fmi2GetFMUstate`: a heap copy of the state (reusing `*state` if it is one of ours).
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_fmu_state<M: FmuModel>(c: Fmi2Component, state: *mut Fmi2FmuState) -> Fmi2Status {
    const F: &str = "fmi2GetFMUstate";
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::FMU_STATE) {
                return s;
            }
            if state.is_null() {
                return me.error(F, "FMUstate is NULL");
            }
            let bytes = me.serialize();
            let existing = *state as *mut SavedState;
            if !existing.is_null() && (*existing).magic == FMU_STATE_MAGIC {
                (*existing).bytes = bytes;
            } else {
                *state = Box::into_raw(Box::new(SavedState {
                    magic: FMU_STATE_MAGIC,
                    bytes,
                })) as Fmi2FmuState;
            }
            me.event(|| format!("{F} at t = {}", me.time));
            Fmi2Status::Ok
        })
    }
}

unsafe fn saved<'a>(p: Fmi2FmuState) -> Option<&'a SavedState> {
    let s = p as *const SavedState;
    // SAFETY: NULL or a pointer from get/deserialize (magic checked).
    if s.is_null() || unsafe { (*s).magic } != FMU_STATE_MAGIC {
        None
    } else {
        Some(unsafe { &*s })
    }
}

/// Applies serialized bytes to the instance (all-or-nothing).
fn apply_blob<M: FmuModel>(me: &mut Instance<M>, fname: &str, bytes: &[u8]) -> Fmi2Status {
    let snap = match me.check_blob(bytes) {
        Ok(s) => s,
        Err(e) => return me.error(fname, e),
    };
    if let Err(e) = me.model.restore_state(snap.model) {
        return me.error(fname, e);
    }
    me.state = snap.state;
    me.time = snap.time;
    me.start_time = snap.start_time;
    me.stop_time = snap.stop_time;
    me.tolerance = snap.tolerance;
    me.last_successful_time = snap.last_successful_time;
    me.terminated = snap.terminated;
    me.event(|| {
        format!(
            "{fname}: restored state at t = {} ({:?})",
            me.time, me.state
        )
    });
    Fmi2Status::Ok
}

/// `fmi2SetFMUstate`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn set_fmu_state<M: FmuModel>(c: Fmi2Component, state: Fmi2FmuState) -> Fmi2Status {
    const F: &str = "fmi2SetFMUstate";
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::FMU_STATE) {
                return s;
            }
            let Some(s) = saved(state) else {
                return me.error(F, "FMUstate is NULL or not a state of this FMU");
            };
            let bytes = s.bytes.clone();
            apply_blob(me, F, &bytes)
        })
    }
}

/// `fmi2FreeFMUstate`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn free_fmu_state<M: FmuModel>(
    c: Fmi2Component,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    const F: &str = "fmi2FreeFMUstate";
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::FMU_STATE) {
                return s;
            }
            if state.is_null() {
                return me.error(F, "FMUstate is NULL");
            }
            if (*state).is_null() {
                return Fmi2Status::Ok;
            }
            if saved(*state).is_none() {
                return me.error(F, "*FMUstate is not a state of this FMU");
            }
            let mut b = Box::from_raw(*state as *mut SavedState);
            b.magic = 0;
            drop(b);
            *state = std::ptr::null_mut();
            Fmi2Status::Ok
        })
    }
}

/// `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn serialized_fmu_state_size<M: FmuModel>(
    c: Fmi2Component,
    state: Fmi2FmuState,
    size: *mut usize,
) -> Fmi2Status {
    const F: &str = "fmi2SerializedFMUstateSize";
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::FMU_STATE) {
                return s;
            }
            let Some(s) = saved(state) else {
                return me.error(F, "FMUstate is NULL or not a state of this FMU");
            };
            if size.is_null() {
                return me.error(F, "size is NULL");
            }
            *size = s.bytes.len();
            Fmi2Status::Ok
        })
    }
}

/// `fmi2SerializeFMUstate`.
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn serialize_fmu_state<M: FmuModel>(
    c: Fmi2Component,
    state: Fmi2FmuState,
    bytes: *mut Fmi2Byte,
    size: usize,
) -> Fmi2Status {
    const F: &str = "fmi2SerializeFMUstate";
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::FMU_STATE) {
                return s;
            }
            let Some(s) = saved(state) else {
                return me.error(F, "FMUstate is NULL or not a state of this FMU");
            };
            if size < s.bytes.len() {
                return me.error(
                    F,
                    format!(
                        "size = {size} is smaller than fmi2SerializedFMUstateSize = {}",
                        s.bytes.len()
                    ),
                );
            }
            let Some(out) = slice_out(bytes as *mut u8, s.bytes.len()) else {
                return me.error(F, "serializedState is NULL");
            };
            out.copy_from_slice(&s.bytes);
            Fmi2Status::Ok
        })
    }
}

/// `fmi2DeSerializeFMUstate`: checks the bytes (magic, version, GUID, checksum) and makes a
/// new heap state (or overwrites `*state` if it is one of ours).
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn deserialize_fmu_state<M: FmuModel>(
    c: Fmi2Component,
    bytes: *const Fmi2Byte,
    size: usize,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    const F: &str = "fmi2DeSerializeFMUstate";
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::FMU_STATE) {
                return s;
            }
            if state.is_null() {
                return me.error(F, "FMUstate is NULL");
            }
            let Some(data) = slice_in(bytes as *const u8, size) else {
                return me.error(F, format!("serializedState is NULL with size = {size}"));
            };
            if let Err(e) = me.check_blob(data) {
                return me.error(F, e);
            }
            let existing = *state as *mut SavedState;
            if !existing.is_null() && (*existing).magic == FMU_STATE_MAGIC {
                (*existing).bytes = data.to_vec();
            } else {
                *state = Box::into_raw(Box::new(SavedState {
                    magic: FMU_STATE_MAGIC,
                    bytes: data.to_vec(),
                })) as Fmi2FmuState;
            }
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
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::DIRECTIONAL) {
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
    unsafe {
        with_instance::<M>(c, F, |me| {
            if let Err(s) = me.check_state(F, mask::DO_STEP) {
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
    allowed: u8,
    why: &'static str,
) -> Fmi2Status {
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
    unsafe {
        with_instance::<M>(c, fname, |me| {
            if let Err(s) = me.check_state(fname, mask::STATUS) {
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
    unsafe { status_query::<M, Fmi2String>(c, "fmi2GetStringStatus", kind, value, |_, _| None) }
}

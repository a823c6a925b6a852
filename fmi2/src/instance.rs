//! The instance and its FMI 2.0 call-state machine, Co-Simulation and Model Exchange: one
//! call-state mask per function (as in the Modelica Reference-FMUs' `fmi2Functions.c`), and the
//! argument checks every function shares.

use crate::bindings::Fmi2Status;
use crate::logging::{Logger, LOG_EVENTS, LOG_STATUS_ERROR};
use crate::model::{FmuModel, Interface};
use crate::variable::{Causality, VarType, Variability};
use std::collections::HashMap;
use std::ffi::CString;

/// FMI 2.0 call states of both interfaces (bit flags so allowed sets are masks). The states
/// of one interface are never reached by an instance of the other (`StepComplete` … only in
/// Co-Simulation, `EventMode` and `ContinuousTimeMode` only in Model Exchange), so one mask per
/// function serves both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u16)]
pub enum CallState {
    /// After `fmi2Instantiate` (and `fmi2Reset`).
    Instantiated = 1,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    InitializationMode = 2,
    /// Ready for `fmi2DoStep`.
    StepComplete = 4,
    /// A step returned `fmi2Discard`; the outputs are those of the last good time.
    StepFailed = 8,
    /// A step was canceled (never happens: steps are synchronous).
    StepCanceled = 16,
    /// After `fmi2Terminate`.
    Terminated = 32,
    /// A model failure; `fmi2Reset`, `fmi2SetFMUstate` or `fmi2FreeInstance` lead out.
    Error = 64,
    /// A panic was caught; only `fmi2FreeInstance` is possible.
    Fatal = 128,
    /// Model Exchange: after `fmi2ExitInitializationMode` and `fmi2EnterEventMode` (discrete
    /// changes are made here, by `fmi2NewDiscreteStates`).
    EventMode = 256,
    /// Model Exchange: after `fmi2EnterContinuousTimeMode`, where the importer integrates the
    /// continuous states.
    ContinuousTimeMode = 512,
}

impl CallState {
    pub(crate) fn from_u16(b: u16) -> Option<Self> {
        Some(match b {
            1 => CallState::Instantiated,
            2 => CallState::InitializationMode,
            4 => CallState::StepComplete,
            8 => CallState::StepFailed,
            16 => CallState::StepCanceled,
            32 => CallState::Terminated,
            64 => CallState::Error,
            128 => CallState::Fatal,
            256 => CallState::EventMode,
            512 => CallState::ContinuousTimeMode,
            _ => return None,
        })
    }

    /// Whether an instance of `interface` can be in this state.
    pub fn belongs_to(self, interface: Interface) -> bool {
        let only_cs = STEP_COMPLETE | STEP_FAILED | STEP_CANCELED;
        let only_me = EVENT_MODE | CONTINUOUS_TIME_MODE;
        match interface {
            Interface::CoSimulation => self as u16 & only_me == 0,
            Interface::ModelExchange => self as u16 & only_cs == 0,
        }
    }
}

const INSTANTIATED: u16 = CallState::Instantiated as u16;
const INIT_MODE: u16 = CallState::InitializationMode as u16;
const STEP_COMPLETE: u16 = CallState::StepComplete as u16;
const STEP_FAILED: u16 = CallState::StepFailed as u16;
const STEP_CANCELED: u16 = CallState::StepCanceled as u16;
const TERMINATED: u16 = CallState::Terminated as u16;
const ERROR: u16 = CallState::Error as u16;
const EVENT_MODE: u16 = CallState::EventMode as u16;
const CONTINUOUS_TIME_MODE: u16 = CallState::ContinuousTimeMode as u16;

/// The call states in which each FMI function is allowed, as masks of [`CallState`] bits.
pub(crate) mod mask {
    use super::*;
    pub const SET_DEBUG_LOGGING: u16 = INSTANTIATED
        | INIT_MODE
        | STEP_COMPLETE
        | STEP_FAILED
        | STEP_CANCELED
        | TERMINATED
        | ERROR
        | EVENT_MODE
        | CONTINUOUS_TIME_MODE;
    pub const SETUP_EXPERIMENT: u16 = INSTANTIATED;
    pub const ENTER_INIT: u16 = INSTANTIATED;
    pub const EXIT_INIT: u16 = INIT_MODE;
    pub const TERMINATE: u16 =
        STEP_COMPLETE | STEP_FAILED | STEP_CANCELED | EVENT_MODE | CONTINUOUS_TIME_MODE;
    pub const RESET: u16 = SET_DEBUG_LOGGING;
    pub const GET: u16 = INIT_MODE
        | STEP_COMPLETE
        | STEP_FAILED
        | STEP_CANCELED
        | TERMINATED
        | ERROR
        | EVENT_MODE
        | CONTINUOUS_TIME_MODE;
    /// `fmi2SetReal`: in continuous-time mode only continuous inputs ([`Instance::check_settable`]).
    pub const SET_REAL: u16 =
        INSTANTIATED | INIT_MODE | STEP_COMPLETE | EVENT_MODE | CONTINUOUS_TIME_MODE;
    /// `fmi2SetInteger`, `fmi2SetBoolean`, `fmi2SetString`: not in continuous-time mode.
    pub const SET: u16 = INSTANTIATED | INIT_MODE | STEP_COMPLETE | EVENT_MODE;
    pub const FMU_STATE: u16 = SET_DEBUG_LOGGING;
    pub const DIRECTIONAL: u16 = GET;
    pub const SET_INPUT_DERIVATIVES: u16 = INSTANTIATED | INIT_MODE | STEP_COMPLETE;
    pub const GET_OUTPUT_DERIVATIVES: u16 =
        STEP_COMPLETE | STEP_FAILED | STEP_CANCELED | TERMINATED | ERROR;
    pub const DO_STEP: u16 = STEP_COMPLETE;
    pub const CANCEL_STEP: u16 = 0; // no step is ever in progress (synchronous FMU)
    pub const STATUS: u16 = STEP_COMPLETE | STEP_FAILED | STEP_CANCELED | TERMINATED;

    // Model Exchange.
    pub const SET_TIME: u16 = EVENT_MODE | CONTINUOUS_TIME_MODE;
    pub const SET_CONTINUOUS_STATES: u16 = CONTINUOUS_TIME_MODE;
    pub const ENTER_EVENT_MODE: u16 = EVENT_MODE | CONTINUOUS_TIME_MODE;
    pub const NEW_DISCRETE_STATES: u16 = EVENT_MODE;
    pub const ENTER_CONTINUOUS_TIME_MODE: u16 = EVENT_MODE;
    pub const COMPLETED_INTEGRATOR_STEP: u16 = CONTINUOUS_TIME_MODE;
    pub const GET_EVENT_INDICATORS: u16 =
        INIT_MODE | EVENT_MODE | CONTINUOUS_TIME_MODE | TERMINATED | ERROR;
    pub const GET_CONTINUOUS_STATES: u16 = GET_EVENT_INDICATORS;
    pub const GET_DERIVATIVES: u16 = EVENT_MODE | CONTINUOUS_TIME_MODE | TERMINATED | ERROR;
    pub const GET_NOMINALS: u16 =
        INSTANTIATED | EVENT_MODE | CONTINUOUS_TIME_MODE | TERMINATED | ERROR;
}

/// The states of `mask`, for messages.
pub(crate) fn mask_names(mask: u16) -> String {
    let all = [
        CallState::Instantiated,
        CallState::InitializationMode,
        CallState::StepComplete,
        CallState::StepFailed,
        CallState::StepCanceled,
        CallState::EventMode,
        CallState::ContinuousTimeMode,
        CallState::Terminated,
        CallState::Error,
    ];
    let v: Vec<String> = all
        .iter()
        .filter(|s| mask & (**s as u16) != 0)
        .map(|s| format!("{s:?}"))
        .collect();
    if v.is_empty() {
        "no state (the FMU never has a step in progress)".into()
    } else {
        v.join(", ")
    }
}

pub(crate) const INSTANCE_MAGIC: u64 = 0x5241_4345_5741_5949; // "RACEWAYI"

/// Relative tolerance on `currentCommunicationPoint` (× max(1, |t|)).
pub const TIME_EPS: f64 = 1e-12;
/// Relative tolerance on the stop time (× max(1, |stopTime|)).
pub const STOP_EPS: f64 = 1e-9;

/// One FMU instance (owned by the importer through an opaque pointer).
pub struct Instance<M: FmuModel> {
    pub(crate) magic: u64,
    /// The interface the instance was created for (`fmuType`).
    pub(crate) interface: Interface,
    pub(crate) logger: Logger,
    pub(crate) initial_logging: bool,
    pub(crate) state: CallState,
    pub(crate) model: M,
    pub(crate) vr_index: HashMap<u32, usize>,
    pub(crate) time: f64,
    pub(crate) start_time: f64,
    pub(crate) stop_time: Option<f64>,
    pub(crate) tolerance: Option<f64>,
    pub(crate) last_successful_time: f64,
    pub(crate) terminated: bool,
    /// Storage of the strings returned by `fmi2GetString` (valid until the next call).
    pub(crate) strings: Vec<CString>,
    /// Variables (table indices) whose last `fmi2Set*` call was refused, each with why: they
    /// keep their previous values, so `fmi2ExitInitializationMode` and `fmi2DoStep` refuse to
    /// run on them until they are set again (a master that ignores a setter's status learns
    /// it there).
    pub(crate) refused: Vec<(usize, String)>,
    /// Model Exchange: an input was set in continuous-time mode since the last completed
    /// integrator step (the model decides whether that needs an event).
    pub(crate) inputs_changed: bool,
}

impl<M: FmuModel> Instance<M> {
    /// The model, for tests and tools.
    pub fn model(&self) -> &M {
        &self.model
    }
    /// The current call state.
    pub fn call_state(&self) -> CallState {
        self.state
    }
    /// The current communication point (Co-Simulation) or the time last set (Model Exchange).
    pub fn time(&self) -> f64 {
        self.time
    }
    /// The interface the instance was created for.
    pub fn interface(&self) -> Interface {
        self.interface
    }

    pub(crate) fn error(&self, fname: &str, message: impl AsRef<str>) -> Fmi2Status {
        self.logger.log(
            Fmi2Status::Error,
            LOG_STATUS_ERROR,
            &format!("{fname}: {}", message.as_ref()),
        );
        Fmi2Status::Error
    }

    pub(crate) fn event(&self, message: impl FnOnce() -> String) {
        if self.logger.enabled(LOG_EVENTS) {
            self.logger.log(Fmi2Status::Ok, LOG_EVENTS, &message());
        }
    }

    pub(crate) fn check_state(&self, fname: &str, allowed: u16) -> Result<(), Fmi2Status> {
        if self.state as u16 & allowed != 0 {
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

    pub(crate) fn lookup(&self, fname: &str, vr: u32, ty: VarType) -> Result<usize, Fmi2Status> {
        let Some(&i) = self.vr_index.get(&vr) else {
            return Err(self.error(fname, format!("unknown value reference {vr}")));
        };
        let v = &self.model.variables()[i];
        if v.ty.access_type() != ty {
            let what = match v.ty {
                VarType::Enumeration => {
                    "an Enumeration variable (read and written as an Integer)".to_string()
                }
                t => format!("a {} variable", t.name()),
            };
            return Err(self.error(
                fname,
                format!(
                    "value reference {vr} is '{}', {what}, not a {}",
                    v.name,
                    ty.name()
                ),
            ));
        }
        Ok(i)
    }

    pub(crate) fn check_settable(&self, fname: &str, i: usize) -> Result<(), Fmi2Status> {
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
        if self.state == CallState::ContinuousTimeMode
            && !(v.causality == Causality::Input && v.variability == Variability::Continuous)
        {
            return Err(self.error(
                fname,
                format!(
                    "'{}' is a {} {}: in continuous-time mode only continuous inputs can be set \
                     (set it in event mode)",
                    v.name,
                    v.variability.name(),
                    v.causality.name()
                ),
            ));
        }
        if matches!(self.state, CallState::StepComplete | CallState::EventMode)
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

    pub(crate) fn check_bounds(&self, fname: &str, i: usize, value: f64) -> Result<(), Fmi2Status> {
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

    pub(crate) fn reset_shell(&mut self) {
        self.state = CallState::Instantiated;
        self.time = 0.0;
        self.start_time = 0.0;
        self.stop_time = None;
        self.tolerance = None;
        self.last_successful_time = 0.0;
        self.terminated = false;
        self.strings.clear();
        self.refused.clear();
        self.inputs_changed = false;
    }

    /// Refuses a function of the other interface (`fname` belongs to `interface` only).
    pub(crate) fn check_interface(
        &self,
        fname: &str,
        interface: Interface,
    ) -> Result<(), Fmi2Status> {
        if self.interface == interface {
            Ok(())
        } else {
            Err(self.error(
                fname,
                format!(
                    "illegal call: {fname} is a {} function, and this instance was instantiated \
                     for {}",
                    interface.name(),
                    self.interface.name()
                ),
            ))
        }
    }

    /// Records that a `fmi2Set*` call refused the values of `indices` (all of its values are
    /// then refused), replacing earlier reasons for them.
    pub(crate) fn note_refused(&mut self, indices: &[usize], why: String) {
        self.refused.retain(|(i, _)| !indices.contains(i));
        self.refused
            .extend(indices.iter().map(|&i| (i, why.clone())));
    }

    /// Refuses `fname` while a variable holds a value older than a refused `fmi2Set*`.
    pub(crate) fn check_refused(&self, fname: &str) -> Result<(), Fmi2Status> {
        let Some((i, why)) = self.refused.first() else {
            return Ok(());
        };
        let name = &self.model.variables()[*i].name;
        let more = match self.refused.len() {
            1 => String::new(),
            n => format!(" (and {} more variables)", n - 1),
        };
        Err(self.error(
            fname,
            format!(
                "'{name}'{more} still holds its value from before a refused set ({why}); set it \
                 again, or restore a state, before the model runs on it"
            ),
        ))
    }
}

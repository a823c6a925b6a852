//! The model trait: what a model implements to become an FMU behind the shell.

use crate::logging::Logger;
use crate::variable::Variable;
use std::path::PathBuf;

/// The FMI 2.0 interface an instance runs (`fmuType` of `fmi2Instantiate`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interface {
    /// `fmi2ModelExchange`: the importer integrates the continuous states.
    ModelExchange,
    /// `fmi2CoSimulation`: the FMU integrates itself in `fmi2DoStep`.
    CoSimulation,
}

impl Interface {
    /// The interface's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Interface::ModelExchange => "Model Exchange",
            Interface::CoSimulation => "Co-Simulation",
        }
    }
    /// The other interface.
    pub fn other(self) -> Self {
        match self {
            Interface::ModelExchange => Interface::CoSimulation,
            Interface::CoSimulation => Interface::ModelExchange,
        }
    }
}

/// What `fmi2Instantiate` hands to [`FmuModel::instantiate`].
#[derive(Debug, Clone)]
pub struct InstantiateArgs {
    /// The `instanceName` of `fmi2Instantiate`.
    pub instance_name: String,
    /// The decoded `fmuResourceLocation`, if one was given.
    pub resource_dir: Option<PathBuf>,
    /// The `loggingOn` of `fmi2Instantiate`.
    pub logging_on: bool,
    /// The interface the instance is for (Model Exchange only if
    /// [`FmuModel::MODEL_EXCHANGE`]).
    pub interface: Interface,
}

/// What [`FmuModel::new_discrete_states`] reports: the `fmi2EventInfo` of
/// `fmi2NewDiscreteStates`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EventUpdate {
    /// Another `fmi2NewDiscreteStates` is needed (the event iteration has not converged).
    pub new_discrete_states_needed: bool,
    /// The model asks the importer to stop.
    pub terminate_simulation: bool,
    /// The nominals of the continuous states changed.
    pub nominals_changed: bool,
    /// The values of the continuous states changed (the importer reads them again).
    pub states_changed: bool,
    /// The next time event, absolute time (`None`: none known).
    pub next_event_time: Option<f64>,
    /// Warnings the model raised (logged with status fmi2Warning; the call returns fmi2Warning).
    pub warnings: Vec<String>,
}

/// What [`FmuModel::completed_integrator_step`] reports.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepEnd {
    /// The model asks for an event (e.g. an input changed in continuous-time mode in a way
    /// that needs a discrete change).
    pub enter_event_mode: bool,
    /// The model asks the importer to stop.
    pub terminate_simulation: bool,
    /// Warnings the model raised (logged with status fmi2Warning; the call returns fmi2Warning).
    pub warnings: Vec<String>,
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
        /// Why the step could not be completed.
        message: String,
        /// The time the model is valid at (the step's start).
        last_good_time: f64,
    },
    /// Something else went wrong; the instance goes to the Error state. The model should stay
    /// at the step's start, whose outputs remain readable.
    Error(String),
}

/// A model behind the shell. Indices are positions in [`FmuModel::variables`]; the shell has
/// already checked the value reference, the type, the causality and the call state, that reals
/// are finite, and the declared min/max.
///
/// Model Exchange is optional: a model that sets [`FmuModel::MODEL_EXCHANGE`] provides the
/// functions from [`FmuModel::number_of_continuous_states`] on (their defaults refuse); the
/// others are refused at `fmi2Instantiate` with `fmuType = fmi2ModelExchange`. The shell checks
/// the call state, the interface, the array lengths (equal to the declared numbers) and that
/// states and times are finite before it calls them. Times are absolute.
pub trait FmuModel: Send + Sized + 'static {
    /// `modelIdentifier`.
    const MODEL_IDENTIFIER: &'static str;
    /// Whether the model provides Model Exchange (the `<ModelExchange>` element).
    const MODEL_EXCHANGE: bool = false;

    /// Builds the model for a new instance (reads resources); an `Err` makes `fmi2Instantiate`
    /// return NULL with that message.
    fn instantiate(args: &InstantiateArgs, log: &Logger) -> Result<Self, String>;
    /// The GUID of the model description this instance implements.
    fn guid(&self) -> &str;
    /// The variable table; value references must be unique.
    fn variables(&self) -> &[Variable];

    /// `fmi2SetupExperiment` (the shell has checked the times and the tolerance's sign).
    fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<(), String>;
    /// `fmi2EnterInitializationMode`.
    fn enter_initialization(&mut self, _log: &Logger) -> Result<(), String> {
        Ok(())
    }
    /// Validates the parameters and builds the runnable model.
    fn exit_initialization(&mut self, log: &Logger) -> Result<(), String>;
    /// Advances from `t` to exactly `t_end` (absolute times).
    fn do_step(&mut self, t: f64, t_end: f64, log: &Logger) -> StepResult;
    /// `fmi2Terminate`.
    fn terminate(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// Back to the just-instantiated state.
    fn reset(&mut self) -> Result<(), String>;

    /// What [`FmuModel::begin_set`] records to take back a partly applied `fmi2Set*` call.
    type Undo;
    /// Called before the values of an `fmi2Set*` call with more than one value are applied
    /// (in call order, one `set_*` each): records what [`FmuModel::rollback_set`] needs to put
    /// the model back if a later value of the call is refused. `indices` are the variables the
    /// call sets.
    fn begin_set(&self, indices: &[usize]) -> Self::Undo;
    /// Puts the model back as it was at the matching [`FmuModel::begin_set`] (the values of
    /// the call applied so far are taken back).
    fn rollback_set(&mut self, undo: Self::Undo) -> Result<(), String>;

    /// The value of the Real variable at `index`.
    fn get_real(&mut self, index: usize) -> Result<f64, String>;
    /// Sets the Real variable at `index` (one value of an `fmi2SetReal` call: see
    /// [`FmuModel::begin_set`] for the call as a whole).
    fn set_real(&mut self, index: usize, value: f64) -> Result<(), String>;
    /// The value of the Integer variable at `index`.
    fn get_integer(&mut self, index: usize) -> Result<i32, String> {
        Err(format!("variable #{index} is not an Integer of this model"))
    }
    /// Sets the Integer variable at `index` (as [`FmuModel::set_real`]).
    fn set_integer(&mut self, index: usize, _value: i32) -> Result<(), String> {
        Err(format!("variable #{index} is not an Integer of this model"))
    }
    /// The value of the Boolean variable at `index`.
    fn get_boolean(&mut self, index: usize) -> Result<bool, String> {
        Err(format!("variable #{index} is not a Boolean of this model"))
    }
    /// Sets the Boolean variable at `index` (as [`FmuModel::set_real`]).
    fn set_boolean(&mut self, index: usize, _value: bool) -> Result<(), String> {
        Err(format!("variable #{index} is not a Boolean of this model"))
    }
    /// The value of the String variable at `index`.
    fn get_string(&mut self, index: usize) -> Result<String, String> {
        Err(format!("variable #{index} is not a String of this model"))
    }
    /// Sets the String variable at `index` (as [`FmuModel::set_real`]).
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

    /// Model Exchange: the number of continuous states of the model description (fixed for the
    /// FMU; a model with fewer states in some configuration pads).
    fn number_of_continuous_states(&self) -> usize {
        0
    }
    /// Model Exchange: `numberOfEventIndicators` of the model description (fixed likewise).
    fn number_of_event_indicators(&self) -> usize {
        0
    }
    /// `fmi2SetTime` (event or continuous-time mode).
    fn set_time(&mut self, _t: f64) -> Result<(), String> {
        Err("Model Exchange is not provided by this FMU".into())
    }
    /// `fmi2SetContinuousStates` (continuous-time mode; finite values, the declared number).
    fn set_continuous_states(&mut self, _x: &[f64]) -> Result<(), String> {
        Err("Model Exchange is not provided by this FMU".into())
    }
    /// `fmi2GetContinuousStates` (from initialization mode on).
    fn get_continuous_states(&mut self, _x: &mut [f64]) -> Result<(), String> {
        Err("Model Exchange is not provided by this FMU".into())
    }
    /// `fmi2GetDerivatives` at the current time, states and inputs.
    fn get_derivatives(&mut self, _dx: &mut [f64]) -> Result<(), String> {
        Err("Model Exchange is not provided by this FMU".into())
    }
    /// `fmi2GetEventIndicators` at the current time, states and inputs (from initialization
    /// mode on).
    fn get_event_indicators(&mut self, _g: &mut [f64]) -> Result<(), String> {
        Err("Model Exchange is not provided by this FMU".into())
    }
    /// `fmi2GetNominalsOfContinuousStates` (also in the instantiated state).
    fn get_nominals(&mut self, _n: &mut [f64]) -> Result<(), String> {
        Err("Model Exchange is not provided by this FMU".into())
    }
    /// `fmi2EnterEventMode` (from continuous-time mode, or again in event mode).
    fn enter_event_mode(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// `fmi2NewDiscreteStates`: the event update at the current time and states (after
    /// `fmi2ExitInitializationMode` and every `fmi2EnterEventMode`).
    fn new_discrete_states(&mut self, _log: &Logger) -> Result<EventUpdate, String> {
        Err("Model Exchange is not provided by this FMU".into())
    }
    /// `fmi2EnterContinuousTimeMode`.
    fn enter_continuous_time_mode(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// `fmi2CompletedIntegratorStep`: the importer accepted a step at the current time and
    /// states; `inputs_changed` says whether an input was set in continuous-time mode since
    /// the last call (or since continuous-time mode was entered).
    fn completed_integrator_step(
        &mut self,
        _inputs_changed: bool,
        _log: &Logger,
    ) -> Result<StepEnd, String> {
        Err("Model Exchange is not provided by this FMU".into())
    }

    /// The model's own part of an FMU state (pointer-free bytes).
    fn save_state(&self) -> Vec<u8>;
    /// Restores [`FmuModel::save_state`] bytes; must leave the model unchanged on `Err`.
    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String>;
}

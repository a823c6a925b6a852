//! A generic FMI 2.0 shell, Co-Simulation and Model Exchange: everything an FMU needs around a
//! model, and no physics.
//!
//! A model implements [`FmuModel`] (its variable table, its step, its own part of the FMU
//! state); [`export_fmi2!`] generates the `#[no_mangle] fmi2*` C entry points of a cdylib, which
//! forward to the generic functions of [`functions`], [`values`] and [`fmu_state`].
//!
//! - [`bindings`]: the FMI 2.0 C types, written locally;
//! - [`variable`] and [`table`]: variable metadata and the declarative variable-table rows;
//! - [`logging`]: log categories and the importer's logger;
//! - [`model`]: the [`FmuModel`] trait;
//! - [`instance`]: the instance and its call-state machine (one mask per function);
//! - [`functions`], [`values`], [`fmu_state`]: the FMI functions, generic over the model;
//!   [`model_exchange`]: the Model Exchange functions (`fmi2SetTime` … `fmi2CompletedIntegratorStep`);
//! - [`state_format`]: the serialized FMU-state format (header, shell part, model part,
//!   checksum);
//! - [`exports`]: the [`export_fmi2!`] macro;
//! - [`xml`]: `modelDescription.xml` and its GUID; [`codec`], [`sha256`], [`uri`]: byte format,
//!   hash, resource-location parsing.
//!
//! Conventions (an FMU's documentation should repeat them):
//! - A call rejected by an argument or call-sequence check returns `fmi2Error`, logs why, and
//!   has no effect (the instance stays in its state); a `fmi2Set*` call applies all its values
//!   or none. The variables of a refused `fmi2Set*` call keep their earlier values, and
//!   `fmi2ExitInitializationMode` and `fmi2DoStep` are refused (no effect) until they are set
//!   again or a state is restored: a master that ignores a setter's status learns it at the
//!   next step instead of running on stale values. A failure of the model itself during `fmi2ExitInitializationMode` or `fmi2DoStep`
//!   moves the instance to the Error state, from which `fmi2Reset`, `fmi2SetFMUstate` and
//!   `fmi2FreeInstance` lead out.
//! - Messages with status Warning, Discard, Error or Fatal are always passed to the logger; all
//!   others only when `loggingOn` and their category are enabled.
//! - A panic inside any entry point becomes `fmi2Fatal` (the instance is then only freeable).
//!
//! `unsafe` code lives here only: the FMI functions take the importer's raw pointers, and every
//! `unsafe` block says why it is sound.

#![deny(clippy::undocumented_unsafe_blocks)]
#![warn(missing_docs)]

pub mod bindings;
pub mod capture;
pub mod codec;
pub mod exports;
mod ffi;
pub mod fmu_state;
pub mod functions;
pub mod instance;
pub mod logging;
pub mod model;
pub mod model_exchange;
pub mod sha256;
pub mod state_format;
pub mod table;
pub mod uri;
pub mod values;
pub mod variable;
pub mod xml;

pub use instance::{CallState, Instance};
pub use logging::{
    Logger, LOG_ALL, LOG_CATEGORIES, LOG_EVENTS, LOG_SOLVER, LOG_STATUS_DISCARD, LOG_STATUS_ERROR,
    LOG_STATUS_FATAL, LOG_STATUS_WARNING,
};
pub use model::{EventUpdate, FmuModel, InstantiateArgs, Interface, StepEnd, StepResult};
pub use variable::{
    Causality, EnumerationItem, EnumerationType, Initial, Start, VarType, Variability, Variable,
};

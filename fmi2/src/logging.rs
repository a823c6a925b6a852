//! Logging through the importer's `fmi2CallbackLogger`: the log categories and the per-instance
//! [`Logger`].

use crate::bindings::{Fmi2CallbackFunctions, Fmi2Status};
use std::ffi::CString;

/// Call-sequence events.
pub const LOG_EVENTS: &str = "logEvents";
/// Integrator work per communication step.
pub const LOG_SOLVER: &str = "logSolver";
/// Calls that return `fmi2Warning`.
pub const LOG_STATUS_WARNING: &str = "logStatusWarning";
/// Calls that return `fmi2Discard`.
pub const LOG_STATUS_DISCARD: &str = "logStatusDiscard";
/// Calls that return `fmi2Error`.
pub const LOG_STATUS_ERROR: &str = "logStatusError";
/// Calls that return `fmi2Fatal`.
pub const LOG_STATUS_FATAL: &str = "logStatusFatal";
/// Every message.
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
    pub(crate) enabled: Vec<bool>,
}

// SAFETY: the component environment is an opaque pointer we only hand back to the importer's
// logger; FMI allows an instance to be used from any thread as long as calls are not concurrent.
unsafe impl Send for Logger {}

impl Logger {
    pub(crate) fn new(
        callbacks: Fmi2CallbackFunctions,
        instance_name: &str,
        logging_on: bool,
    ) -> Self {
        Self {
            callbacks,
            instance_name: to_cstring(instance_name),
            enabled: vec![logging_on; LOG_CATEGORIES.len()],
        }
    }

    pub(crate) fn index(category: &str) -> Option<usize> {
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

    pub(crate) fn emit(&self, status: Fmi2Status, category: &str, message: &str) {
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

pub(crate) fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).expect("NULs were replaced")
}

//! A logger that records what an FMU says, for importers written in Rust (the FMUs' tests):
//! [`LogCapture::callbacks`] is the `fmi2CallbackFunctions` to instantiate with, and the
//! capture dereferences to the recorded `(status, category, message)` list.

use crate::bindings::{
    fixed_args_logger, Fmi2CallbackFunctions, Fmi2CallbackLogger, Fmi2ComponentEnvironment,
    Fmi2Status, Fmi2String,
};
use std::ffi::CStr;
use std::os::raw::{c_char, c_void};
use std::sync::Mutex;

/// The recorded messages, in order, with their status and category.
pub type Messages = Mutex<Vec<(Fmi2Status, String, String)>>;

/// Records every message an instance logs; keep it alive as long as the instances made with
/// its [`LogCapture::callbacks`].
pub struct LogCapture {
    messages: Box<Messages>,
    callbacks: Box<Fmi2CallbackFunctions>,
}

/// The shell calls the logger with the format "%s" and the message as the sixth argument,
/// passed like a fixed argument by the x86-64 and aarch64 C ABIs.
unsafe extern "C" fn record(
    env: Fmi2ComponentEnvironment,
    _name: Fmi2String,
    status: Fmi2Status,
    category: Fmi2String,
    _fmt: Fmi2String,
    msg: *const c_char,
) {
    // SAFETY: env is the Box<Messages> of the LogCapture whose callbacks the instance got,
    // alive as long as the capture (its contract).
    let messages = unsafe { &*(env as *const Messages) };
    // SAFETY: the shell passes the category and the message as NUL-terminated strings valid
    // during the call.
    let (c, m) = unsafe {
        (
            CStr::from_ptr(category).to_string_lossy().into_owned(),
            CStr::from_ptr(msg).to_string_lossy().into_owned(),
        )
    };
    if let Ok(mut v) = messages.lock() {
        v.push((status, c, m));
    }
}

impl LogCapture {
    /// An empty capture.
    pub fn new() -> Self {
        let messages: Box<Messages> = Box::default();
        // SAFETY: the shell always calls the logger with "%s" and one string
        // (fixed_args_logger's contract).
        let logger: Fmi2CallbackLogger = unsafe { fixed_args_logger(record) };
        let callbacks = Box::new(Fmi2CallbackFunctions {
            logger: Some(logger),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: &*messages as *const Messages as *mut c_void,
        });
        Self {
            messages,
            callbacks,
        }
    }

    /// The callbacks to pass to fmi2Instantiate.
    pub fn callbacks(&self) -> &Fmi2CallbackFunctions {
        &self.callbacks
    }

    /// The last message and its status (OK and empty if there is none).
    pub fn last_entry(&self) -> (Fmi2Status, String) {
        self.messages
            .lock()
            .ok()
            .and_then(|v| v.last().map(|(s, _, m)| (*s, m.clone())))
            .unwrap_or((Fmi2Status::Ok, String::new()))
    }

    /// Every message, in order.
    pub fn messages(&self) -> Vec<String> {
        self.messages.lock().map_or(Vec::new(), |v| {
            v.iter().map(|(_, _, m)| m.clone()).collect()
        })
    }

    /// Whether some message contains `needle`.
    pub fn any(&self, needle: &str) -> bool {
        self.messages
            .lock()
            .is_ok_and(|v| v.iter().any(|(_, _, m)| m.contains(needle)))
    }

    /// The last message (empty if there is none).
    pub fn last(&self) -> String {
        self.last_entry().1
    }

    /// How many messages with `status` contain `needle`.
    pub fn count(&self, status: Fmi2Status, needle: &str) -> usize {
        self.messages.lock().map_or(0, |v| {
            v.iter()
                .filter(|(s, _, m)| *s == status && m.contains(needle))
                .count()
        })
    }
}

impl Default for LogCapture {
    fn default() -> Self {
        Self::new()
    }
}

impl std::ops::Deref for LogCapture {
    type Target = Messages;
    fn deref(&self) -> &Messages {
        &self.messages
    }
}

//! Entry-point helpers: instance lookup with panic containment, and the checked conversions
//! of the importer's pointers.

use crate::bindings::{Fmi2Component, Fmi2Status};
use crate::instance::{CallState, Instance, INSTANCE_MAGIC};
use crate::logging::{LOG_STATUS_ERROR, LOG_STATUS_FATAL};
use crate::model::FmuModel;
use std::ffi::CStr;
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};

pub(crate) fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
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
pub(crate) unsafe fn with_instance<M: FmuModel>(
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
///
/// # Safety
/// `p` must be NULL or point to `n` initialized, properly aligned elements of `T` that stay
/// valid and unmodified for `'a` (the FMI 2.0 rule for an input array of a call).
pub(crate) unsafe fn slice_in<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        // SAFETY: p is non-NULL and, by this function's contract, points to n valid elements.
        Some(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

/// Checks an output-array argument: NULL is only allowed when `n == 0`.
///
/// # Safety
/// `p` must be NULL or point to room for `n` properly aligned elements of `T`, writable and
/// not otherwise accessed for `'a` (the FMI 2.0 rule for an output array of a call).
pub(crate) unsafe fn slice_out<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        // SAFETY: p is non-NULL and, by this function's contract, exclusively ours for n
        // elements. The FMI types written through it (numbers, pointers) have no invalid bit
        // patterns, so treating the caller's memory as initialized is sound.
        Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

/// A C string argument as UTF-8 (`None`: NULL or not UTF-8).
///
/// # Safety
/// `p` must be NULL or a NUL-terminated string valid for `'a`.
pub(crate) unsafe fn opt_str<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        None
    } else {
        // SAFETY: non-NULL, and NUL-terminated and valid for 'a by the contract.
        unsafe { CStr::from_ptr(p) }.to_str().ok()
    }
}

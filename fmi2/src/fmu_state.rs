//! `fmi2GetFMUstate` and the other FMU-state functions (the byte format is in
//! [`crate::state_format`]).

use crate::bindings::*;
use crate::ffi::{slice_in, slice_out, with_instance};
use crate::instance::{mask, Instance};
use crate::model::FmuModel;
use crate::state_format::{SavedState, FMU_STATE_MAGIC};

/// `fmi2GetFMUstate`: a heap copy of the state (reusing `*state` if it is one of ours).
///
/// # Safety
/// FMI 2.0 pointer rules.
pub unsafe fn get_fmu_state<M: FmuModel>(c: Fmi2Component, state: *mut Fmi2FmuState) -> Fmi2Status {
    const F: &str = "fmi2GetFMUstate";
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
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
        // SAFETY: non-NULL and carrying our magic, so it came from Box::into_raw of a SavedState
        // that has not been freed.
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
    me.refused.clear();
    me.inputs_changed = false;
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
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

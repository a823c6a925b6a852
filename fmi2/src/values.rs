//! `fmi2Get*` and `fmi2Set*`: value references checked against the variable table; a set
//! applies every value of the call or none.

use crate::bindings::*;
use crate::ffi::{opt_str, slice_in, slice_out, with_instance};
use crate::instance::{mask, CallState, Instance};
use crate::logging::to_cstring;
use crate::model::FmuModel;
use crate::variable::VarType;

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
            // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract):
            // `c` is NULL or a live instance, `vr` and `value` hold `n` elements.
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
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
/// then the model's setter for each, in call order; if the model refuses one, the values
/// applied before it are taken back ([`FmuModel::begin_set`], [`FmuModel::rollback_set`]), so
/// a call applies all its values or none.
///
/// # Safety
/// `vr` and `value` must be NULL or point to `n` elements (FMI 2.0 pointer rules).
#[allow(clippy::too_many_arguments)]
unsafe fn set_values<M: FmuModel, T: Copy>(
    c: Fmi2Component,
    fname: &'static str,
    allowed: u16,
    vt: VarType,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const T,
    as_f64: impl Fn(T) -> Option<f64>,
    apply: impl Fn(&mut M, usize, T) -> Result<(), String>,
) -> Fmi2Status {
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        with_instance::<M>(c, fname, |me| {
            if let Err(s) = me.check_state(fname, allowed) {
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
                idx.push(i);
                if let Some(x) = as_f64(vals[k]) {
                    if let Err(s) = me.check_bounds(fname, i, x) {
                        let name = me.model.variables()[i].name.clone();
                        me.note_refused(&idx, format!("{fname} refused '{name}' = {x}"));
                        return s;
                    }
                }
            }
            // All or nothing: a value the model refuses takes back the ones applied before it.
            let undo = (idx.len() > 1).then(|| me.model.begin_set(&idx));
            for (k, &i) in idx.iter().enumerate() {
                if let Err(e) = apply(&mut me.model, i, vals[k]) {
                    if let Some(Err(e2)) = undo.map(|u| me.model.rollback_set(u)) {
                        me.state = CallState::Error;
                        return me.error(
                            fname,
                            format!(
                                "{e}; the values set before it could not be taken back ({e2}): \
                                 the instance is now in the Error state"
                            ),
                        );
                    }
                    let name = me.model.variables()[i].name.clone();
                    me.note_refused(&idx, format!("{fname} refused '{name}': {e}"));
                    return me.error(fname, e);
                }
            }
            me.refused.retain(|(i, _)| !idx.contains(i));
            if me.state == CallState::ContinuousTimeMode && !idx.is_empty() {
                me.inputs_changed = true;
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        set_values::<M, f64>(
            c,
            "fmi2SetReal",
            mask::SET_REAL,
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        set_values::<M, i32>(
            c,
            "fmi2SetInteger",
            mask::SET,
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        set_values::<M, Fmi2Boolean>(
            c,
            "fmi2SetBoolean",
            mask::SET,
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
    // SAFETY: the caller keeps the FMI 2.0 pointer rules (this function's contract): `c` is
    // NULL or a live instance of `M`, and every array or out-pointer argument is NULL or valid
    // for its length, which is what with_instance, slice_in/slice_out and the writes need.
    unsafe {
        set_values::<M, Fmi2String>(
            c,
            "fmi2SetString",
            mask::SET,
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

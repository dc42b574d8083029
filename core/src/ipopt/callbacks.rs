//! The C callbacks IPOPT calls while it solves: each finds the problem through IPOPT's user-data
//! pointer, is timed, and turns an error or a panic into a stored [`Error`] instead of letting it
//! unwind into C.

use super::{Error, EvalError, Nlp};
use ipopt_sys as sys;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

/// Everything the C callbacks need, reached through IPOPT's user-data pointer.
pub(super) struct Context<'a, P: Nlp> {
    pub(super) problem: &'a mut P,
    pub(super) jacobian: Vec<(sys::Index, sys::Index)>,
    pub(super) hessian: Vec<(sys::Index, sys::Index)>,
    pub(super) callback_time: Duration,
    pub(super) iterations: sys::Index,
    pub(super) error: Option<Error>,
    /// Whether the intermediate callback stopped IPOPT because its work was asked to stop.
    pub(super) stopped: bool,
    /// The last point outside the problem's domain, with why (see [`EvalError`]).
    pub(super) outside_domain: Option<String>,
}

/// Runs one callback body with the problem: times it, and turns an `Err` or a panic into a stored
/// error and `FALSE`, so that nothing unwinds into C; a point outside the domain only returns
/// `FALSE`, remembered. Once an error is stored every later callback
/// returns `FALSE` at once and the intermediate callback stops IPOPT.
///
/// # Safety
/// `user_data` must be the `Context<P>` passed to `IpoptSolve`.
unsafe fn guarded<P: Nlp>(
    user_data: sys::UserDataPtr,
    callback: &'static str,
    body: impl FnOnce(&mut P) -> Result<(), EvalError>,
) -> sys::Bool {
    let context = &mut *user_data.cast::<Context<P>>();
    if context.error.is_some() {
        return 0;
    }
    let start = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| body(context.problem)));
    context.callback_time += start.elapsed();
    let message = match outcome {
        Ok(Ok(())) => return 1,
        // IPOPT cuts its step back from a point it cannot evaluate.
        Ok(Err(error)) if error.outside_domain => {
            context.outside_domain = Some(error.message);
            return 0;
        }
        Ok(Err(error)) => error.message,
        Err(payload) => {
            let text = payload
                .downcast_ref::<&str>()
                .map(|text| (*text).to_owned())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(non-text panic payload)".to_owned());
            format!("panicked: {text}")
        }
    };
    context.error = Some(Error::Callback { callback, message });
    0
}

/// # Safety
/// IPOPT passes a pointer to `len` valid numbers (or null when `len` is 0).
unsafe fn slice<'a>(ptr: *const sys::Number, len: sys::Index) -> &'a [f64] {
    match usize::try_from(len) {
        Ok(len) if len > 0 && !ptr.is_null() => std::slice::from_raw_parts(ptr, len),
        _ => &[],
    }
}

/// # Safety
/// IPOPT passes a pointer to `len` writable numbers (or null when `len` is 0).
unsafe fn slice_mut<'a>(ptr: *mut sys::Number, len: sys::Index) -> &'a mut [f64] {
    match usize::try_from(len) {
        Ok(len) if len > 0 && !ptr.is_null() => std::slice::from_raw_parts_mut(ptr, len),
        _ => &mut [],
    }
}

pub(super) unsafe extern "C" fn eval_f<P: Nlp>(
    n: sys::Index,
    x: *mut sys::Number,
    new_x: sys::Bool,
    obj_value: *mut sys::Number,
    user_data: sys::UserDataPtr,
) -> sys::Bool {
    let x = slice(x, n);
    guarded::<P>(user_data, "objective", |problem| {
        *obj_value = problem.objective(x, new_x != 0)?;
        Ok(())
    })
}

pub(super) unsafe extern "C" fn eval_grad_f<P: Nlp>(
    n: sys::Index,
    x: *mut sys::Number,
    new_x: sys::Bool,
    grad_f: *mut sys::Number,
    user_data: sys::UserDataPtr,
) -> sys::Bool {
    let (x, gradient) = (slice(x, n), slice_mut(grad_f, n));
    guarded::<P>(user_data, "gradient", |problem| {
        problem.gradient(x, new_x != 0, gradient)
    })
}

pub(super) unsafe extern "C" fn eval_g<P: Nlp>(
    n: sys::Index,
    x: *mut sys::Number,
    new_x: sys::Bool,
    m: sys::Index,
    g: *mut sys::Number,
    user_data: sys::UserDataPtr,
) -> sys::Bool {
    let (x, g) = (slice(x, n), slice_mut(g, m));
    guarded::<P>(user_data, "constraints", |problem| {
        problem.constraints(x, new_x != 0, g)
    })
}

/// Writes a stored sparsity structure into IPOPT's index arrays.
///
/// # Safety
/// `rows` and `cols` point to `structure.len()` writable indices.
unsafe fn write_structure(
    structure: &[(sys::Index, sys::Index)],
    rows: *mut sys::Index,
    cols: *mut sys::Index,
) {
    for (k, &(row, col)) in structure.iter().enumerate() {
        *rows.add(k) = row;
        *cols.add(k) = col;
    }
}

pub(super) unsafe extern "C" fn eval_jac_g<P: Nlp>(
    n: sys::Index,
    x: *mut sys::Number,
    new_x: sys::Bool,
    _m: sys::Index,
    nele_jac: sys::Index,
    i_row: *mut sys::Index,
    j_col: *mut sys::Index,
    values: *mut sys::Number,
    user_data: sys::UserDataPtr,
) -> sys::Bool {
    if values.is_null() {
        let context = &*user_data.cast::<Context<P>>();
        write_structure(&context.jacobian, i_row, j_col);
        return 1;
    }
    let (x, values) = (slice(x, n), slice_mut(values, nele_jac));
    guarded::<P>(user_data, "jacobian", |problem| {
        problem.jacobian_values(x, new_x != 0, values)
    })
}

pub(super) unsafe extern "C" fn eval_h<P: Nlp>(
    n: sys::Index,
    x: *mut sys::Number,
    new_x: sys::Bool,
    obj_factor: sys::Number,
    m: sys::Index,
    lambda: *mut sys::Number,
    _new_lambda: sys::Bool,
    nele_hess: sys::Index,
    i_row: *mut sys::Index,
    j_col: *mut sys::Index,
    values: *mut sys::Number,
    user_data: sys::UserDataPtr,
) -> sys::Bool {
    if values.is_null() {
        let context = &*user_data.cast::<Context<P>>();
        write_structure(&context.hessian, i_row, j_col);
        return 1;
    }
    let (x, lambda, values) = (slice(x, n), slice(lambda, m), slice_mut(values, nele_hess));
    guarded::<P>(user_data, "hessian", |problem| {
        problem.hessian_values(x, new_x != 0, obj_factor, lambda, values)
    })
}

pub(super) unsafe extern "C" fn intermediate<P: Nlp>(
    _alg_mod: sys::Index,
    iter_count: sys::Index,
    _obj_value: sys::Number,
    _inf_pr: sys::Number,
    _inf_du: sys::Number,
    _mu: sys::Number,
    _d_norm: sys::Number,
    _regularization_size: sys::Number,
    _alpha_du: sys::Number,
    _alpha_pr: sys::Number,
    _ls_trials: sys::Index,
    user_data: sys::UserDataPtr,
) -> sys::Bool {
    let context = &mut *user_data.cast::<Context<P>>();
    context.iterations = iter_count;
    context.stopped = crate::signals::stop_requested();
    sys::Bool::from(context.error.is_none() && !context.stopped)
}

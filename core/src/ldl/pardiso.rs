//! The Pardiso 4 calling convention (`pardisoinit`, `pardiso`) over [`Symbolic`] and [`Numeric`],
//! as IPOPT's Pardiso interface uses it: matrix type -2 (real symmetric indefinite), upper
//! triangle in 1-based compressed rows; phase 11 analyses, 22 factorises, 33 solves with the
//! solution written over the right-hand sides, -1 releases; the inertia comes back in
//! `iparm[21]` (positive) and `iparm[22]` (negative), 0-based.
//!
//! IPOPT's 64-slot handle `pt` holds, in `pt[0]`, the one [`Handle`] of its solver object. Nothing
//! is shared between handles. No panic crosses into C: each call runs under `catch_unwind` and a
//! failure becomes a Pardiso error code.

use super::{AnalysisCache, LdlError, Numeric, Symbolic, UpperCsr};
use std::ffi::c_void;
use std::os::raw::c_int;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;

/// The only matrix type this solver factorises: real symmetric indefinite.
const REAL_SYMMETRIC_INDEFINITE: c_int = -2;
/// Pardiso's error codes that IPOPT tells apart.
const INPUT_INCONSISTENT: c_int = -1;
const ZERO_PIVOT: c_int = -4;
/// Indices into `iparm` (0-based) that this solver reads or writes.
const IPARM_OVERWRITE_RHS: usize = 5;
const IPARM_REFINEMENT_STEPS: usize = 6;
const IPARM_PERTURBED_PIVOTS: usize = 13;
const IPARM_FACTOR_ENTRIES: usize = 17;
const IPARM_POSITIVE: usize = 21;
const IPARM_NEGATIVE: usize = 22;

/// The state behind one Pardiso handle: the analysis, shared through
/// [`AnalysisCache::shared`], and this handle's own factors.
struct Handle {
    symbolic: Arc<Symbolic>,
    numeric: Numeric,
}

/// `pardisoinit`: clears the handle and the parameter arrays.
///
/// # Safety
/// `pt` points to 64 pointers, `iparm` to 64 integers and `dparm` to 64 doubles, as the
/// Pardiso 4 interface requires; `mtype` and `error` are valid.
pub(super) unsafe extern "C" fn pardisoinit(
    pt: *mut *mut c_void,
    mtype: *const c_int,
    _solver: *const c_int,
    iparm: *mut c_int,
    dparm: *mut f64,
    error: *mut c_int,
) {
    // SAFETY: the caller passes arrays of 64 entries each (Pardiso's documented sizes).
    unsafe {
        std::slice::from_raw_parts_mut(pt, 64).fill(std::ptr::null_mut());
        std::slice::from_raw_parts_mut(iparm, 64).fill(0);
        std::slice::from_raw_parts_mut(dparm, 64).fill(0.0);
        *error = if *mtype == REAL_SYMMETRIC_INDEFINITE {
            0
        } else {
            INPUT_INCONSISTENT
        };
    }
}

/// `pardiso`: one phase of the solver on the handle in `pt[0]`.
///
/// # Safety
/// The arguments follow the Pardiso 4 convention: `pt` was initialised by [`pardisoinit`];
/// `ia` has `n + 1` entries and `ja`, `a` have `ia[n] - 1`; `b` and `x` hold `n * nrhs` values in
/// the solve phases; `iparm` has 64 entries.
#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "C" fn pardiso(
    pt: *mut *mut c_void,
    _maxfct: *const c_int,
    _mnum: *const c_int,
    mtype: *const c_int,
    phase: *const c_int,
    n: *const c_int,
    a: *const f64,
    ia: *const c_int,
    ja: *const c_int,
    _perm: *const c_int,
    nrhs: *const c_int,
    iparm: *mut c_int,
    msglvl: *const c_int,
    b: *mut f64,
    x: *mut f64,
    error: *mut c_int,
    _dparm: *mut f64,
) {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: forwarded from this function's contract.
        unsafe {
            let call = Call {
                n: usize::try_from(*n).map_err(|_| INPUT_INCONSISTENT)?,
                a,
                ia,
                ja,
                nrhs: usize::try_from(*nrhs).unwrap_or(0),
                iparm: std::slice::from_raw_parts_mut(iparm, 64),
                verbose: *msglvl > 0,
                b,
                x,
            };
            if *mtype != REAL_SYMMETRIC_INDEFINITE {
                return Err(INPUT_INCONSISTENT);
            }
            run_phase(&mut *pt.cast::<*mut Handle>(), *phase, call)
        }
    }));
    // SAFETY: `error` is valid by contract.
    unsafe {
        *error = outcome
            .unwrap_or(Err(INPUT_INCONSISTENT))
            .err()
            .unwrap_or(0)
    };
}

/// The arguments of one call, checked for sign.
struct Call<'a> {
    n: usize,
    a: *const f64,
    ia: *const c_int,
    ja: *const c_int,
    nrhs: usize,
    iparm: &'a mut [c_int],
    verbose: bool,
    b: *mut f64,
    x: *mut f64,
}

/// Runs `phase` (11, 12, 13, 22, 23, 33, 0 or -1) on the handle slot.
///
/// # Safety
/// The pointers of `call` satisfy [`pardiso`]'s contract for this phase.
unsafe fn run_phase(slot: &mut *mut Handle, phase: c_int, mut call: Call<'_>) -> Result<(), c_int> {
    if phase <= 0 {
        release(slot);
        return Ok(());
    }
    let (analyse, factorise, solve) = match phase {
        11 => (true, false, false),
        12 => (true, true, false),
        13 => (true, true, true),
        22 => (false, true, false),
        23 => (false, true, true),
        33 => (false, false, true),
        _ => return Err(INPUT_INCONSISTENT),
    };
    // SAFETY: `ia` has n + 1 entries and `ja` ia[n] - 1 (contract).
    let (ia, ja) = unsafe {
        let ia = std::slice::from_raw_parts(call.ia, call.n + 1);
        let entries = usize::try_from(ia[call.n] - 1).map_err(|_| INPUT_INCONSISTENT)?;
        (ia, std::slice::from_raw_parts(call.ja, entries))
    };
    let matrix = UpperCsr { ia, ja };
    // SAFETY: `a` has one value per entry of the structure in every phase that analyses or
    // factorises (contract).
    let values =
        (analyse || factorise).then(|| unsafe { std::slice::from_raw_parts(call.a, ja.len()) });
    if analyse {
        let symbolic = AnalysisCache::shared()
            .analyse(call.n, matrix, values.unwrap_or_default())
            .map_err(code)?;
        let numeric = Numeric::new(&symbolic);
        if call.verbose {
            note!(
                "codesign LDL: n = {}, {} entries, {} in L",
                call.n,
                symbolic.entries(),
                symbolic.factor_entries()
            );
        }
        release(slot);
        *slot = Box::into_raw(Box::new(Handle { symbolic, numeric }));
    }
    if slot.is_null() {
        return Err(INPUT_INCONSISTENT);
    }
    // SAFETY: a non-null slot holds this module's Handle, used by one IPOPT solver at a time.
    let handle = unsafe { &mut **slot };
    if handle.symbolic.n() != call.n || handle.symbolic.entries() != ja.len() {
        return Err(INPUT_INCONSISTENT);
    }
    if let (true, Some(values)) = (factorise, values) {
        if handle.symbolic.needs_reanalysis(values) {
            // A diagonal the order took for non-zero is zero in this matrix: order again with
            // it among the zero rows (this happens a few times per solve at most).
            handle.symbolic = AnalysisCache::shared()
                .reanalyse(&handle.symbolic, matrix, values)
                .map_err(code)?;
            handle.numeric = Numeric::new(&handle.symbolic);
            if call.verbose {
                note!("codesign LDL: new zero diagonals, order analysed again");
            }
        }
        #[cfg(test)]
        capture::keep(call.n, ia, ja, values);
        factorise_into(handle, values, &mut call)?;
    }
    if solve {
        // SAFETY: forwarded from this function's contract.
        unsafe { solve_into(handle, &mut call) };
    }
    Ok(())
}

/// Drops the handle in `slot`, if any.
fn release(slot: &mut *mut Handle) {
    if !slot.is_null() {
        // SAFETY: a non-null slot holds the Box leaked by `run_phase`'s analysis, released once.
        drop(unsafe { Box::from_raw(*slot) });
        *slot = std::ptr::null_mut();
    }
}

/// Factorises `values` and reports the inertia in `iparm`.
fn factorise_into(handle: &mut Handle, values: &[f64], call: &mut Call<'_>) -> Result<(), c_int> {
    let outcome = handle.numeric.factorise(&handle.symbolic, values);
    if call.verbose {
        note!("codesign LDL: factorisation: {outcome:?}");
    }
    let inertia = outcome.map_err(code)?;
    let count = |value: usize| c_int::try_from(value).unwrap_or(c_int::MAX);
    call.iparm[IPARM_POSITIVE] = count(inertia.positive);
    call.iparm[IPARM_NEGATIVE] = count(inertia.negative);
    // Pivots lost to cancellation are not reported as perturbed: IPOPT would answer with a new
    // analysis of the same structure, which gives the same order. Its iterative refinement sees
    // their (rounding-level) effect on the solution.
    call.iparm[IPARM_PERTURBED_PIVOTS] = 0;
    if call.verbose && handle.numeric.regularised_pivots() > 0 {
        note!(
            "codesign LDL: {} pivots lost to cancellation, set to the rounding bound",
            handle.numeric.regularised_pivots()
        );
    }
    call.iparm[IPARM_FACTOR_ENTRIES] = count(handle.symbolic.factor_entries());
    Ok(())
}

/// Solves for the `nrhs` right-hand sides in `b`, into `b` (`iparm[5] = 1`) or into `x`.
///
/// # Safety
/// `call.b` and `call.x` hold `n * nrhs` values each and do not overlap ([`pardiso`]'s contract).
unsafe fn solve_into(handle: &mut Handle, call: &mut Call<'_>) {
    let len = call.n * call.nrhs;
    // SAFETY: `b` and `x` hold n * nrhs values each (contract), and do not overlap.
    let target = unsafe {
        if call.iparm[IPARM_OVERWRITE_RHS] == 1 {
            std::slice::from_raw_parts_mut(call.b, len)
        } else {
            let x = std::slice::from_raw_parts_mut(call.x, len);
            x.copy_from_slice(std::slice::from_raw_parts(call.b, len));
            x
        }
    };
    handle.numeric.solve_in_place(&handle.symbolic, target);
    call.iparm[IPARM_REFINEMENT_STEPS] = 0;
}

/// The Pardiso error code of an [`LdlError`]: IPOPT treats a zero pivot as a singular matrix and
/// perturbs it; an inconsistent input is fatal.
fn code(error: LdlError) -> c_int {
    match error {
        LdlError::Structure(_) => INPUT_INCONSISTENT,
        LdlError::Singular { .. } | LdlError::NotFinite { .. } => ZERO_PIVOT,
    }
}

/// Matrices handed to [`pardiso`] on this thread, kept while a test asks for them.
#[cfg(test)]
pub(super) mod capture {
    use std::cell::RefCell;

    /// One matrix as IPOPT handed it over: n, row starts, columns, values (upper, 1-based).
    pub type Matrix = (usize, Vec<i32>, Vec<i32>, Vec<f64>);

    thread_local! {
        static MATRICES: RefCell<Option<Vec<Matrix>>> = const { RefCell::new(None) };
    }

    /// Starts keeping the matrices this thread factorises.
    pub fn start() {
        MATRICES.with(|m| *m.borrow_mut() = Some(Vec::new()));
    }

    /// Stops keeping them and returns those kept.
    pub fn take() -> Vec<Matrix> {
        MATRICES.with(|m| m.borrow_mut().take().unwrap_or_default())
    }

    pub(super) fn keep(n: usize, ia: &[i32], ja: &[i32], values: &[f64]) {
        MATRICES.with(|m| {
            if let Some(kept) = m.borrow_mut().as_mut() {
                kept.push((n, ia.to_vec(), ja.to_vec(), values.to_vec()));
            }
        });
    }
}

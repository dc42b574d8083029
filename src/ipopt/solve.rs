//! One solve: the problem handed to IPOPT through its C interface, callbacks guarded.

use super::{EvalError, LinearSolver, Nlp, OptionValue, Options, Status};
use ipopt_sys as sys;
use std::ffi::{c_void, CString};
use std::fmt;
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// MUMPS keeps global state and is not thread-safe: every solve with it in this process holds
/// this lock from the creation of its IPOPT problem to its release. Solves with
/// [`LinearSolver::Ldl`] keep all their state in their own IPOPT objects and do not take it.
static MUMPS_LOCK: Mutex<()> = Mutex::new(());

/// Why a solve could not produce a [`Solution`]. (A solve that ran and failed to converge is not
/// an error: it is a `Solution` with a non-success [`Status`].)
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// IPOPT rejected an option: unknown name, wrong type or value out of range.
    InvalidOption {
        /// The option's name.
        name: String,
        /// The value given, as text.
        value: String,
    },
    /// The problem's description is inconsistent (sizes, sparsity indices, bounds).
    InvalidProblem(String),
    /// A callback returned an error or panicked; IPOPT was stopped.
    Callback {
        /// Which callback: `objective`, `gradient`, `constraints`, `jacobian` or `hessian`.
        callback: &'static str,
        /// The error's or the panic's message.
        message: String,
    },
    /// IPOPT could not open the requested log file.
    OutputFile(String),
    /// The linear solver could not be used; names it and says why.
    LinearSolver {
        /// The solver asked for.
        solver: LinearSolver,
        /// What went wrong.
        message: String,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidOption { name, value } => {
                write!(f, "IPOPT rejected option `{name}` = {value}")
            }
            Error::InvalidProblem(message) => write!(f, "invalid NLP: {message}"),
            Error::Callback { callback, message } => {
                write!(f, "the {callback} callback failed: {message}")
            }
            Error::OutputFile(path) => write!(f, "IPOPT could not open its log file {path}"),
            Error::LinearSolver { solver, message } => {
                write!(f, "linear solver `{solver}` cannot be used: {message}")
            }
        }
    }
}

impl std::error::Error for Error {}

/// Wall-clock time of a solve, split into time spent in the problem's callbacks and the rest
/// (IPOPT itself: linear algebra, line search, bookkeeping).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// From the creation of the IPOPT problem to its release.
    pub total: Duration,
    /// Summed time inside the evaluation callbacks.
    pub callbacks: Duration,
    /// `total - callbacks`.
    pub ipopt: Duration,
}

/// The result of a solve that ran.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// IPOPT's return status.
    pub status: Status,
    /// The final primal point (length n).
    pub x: Vec<f64>,
    /// The constraint values g(x) at the final point (length m).
    pub g: Vec<f64>,
    /// Multipliers of the constraints (length m), in IPOPT's sign convention.
    pub lambda: Vec<f64>,
    /// Multipliers of the lower variable bounds (length n, >= 0).
    pub z_lower: Vec<f64>,
    /// Multipliers of the upper variable bounds (length n, >= 0).
    pub z_upper: Vec<f64>,
    /// f(x) at the final point.
    pub objective: f64,
    /// Iterations taken (the last iteration index IPOPT reported).
    pub iterations: usize,
    /// Where the time went.
    pub timing: Timing,
}

/// Everything the C callbacks need, reached through IPOPT's user-data pointer.
struct Context<'a, P: Nlp> {
    problem: &'a mut P,
    jacobian: Vec<(sys::Index, sys::Index)>,
    hessian: Vec<(sys::Index, sys::Index)>,
    callback_time: Duration,
    iterations: sys::Index,
    error: Option<Error>,
}

/// Owns an `IpoptProblem` and frees it exactly once.
struct Handle(sys::IpoptProblem);

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: the pointer came from CreateIpoptProblem, is non-null, and is freed only here.
        unsafe { sys::FreeIpoptProblem(self.0) }
    }
}

/// Solves `problem` with `options`, starting from [`Nlp::initial_point`].
///
/// Solves with MUMPS are serialised process-wide (MUMPS is not thread-safe): a second thread
/// calling this with MUMPS waits until the first has finished. Solves with the LDLᵀ run at once.
pub fn solve<P: Nlp>(problem: &mut P, options: &Options) -> Result<Solution, Error> {
    solve_from(problem, options, None)
}

/// Solves `problem` warm-started from an earlier solution of a problem of the same shape: its
/// primal point replaces [`Nlp::initial_point`] and its multipliers seed IPOPT's
/// (`warm_start_init_point = yes`). Without `start`, the same as [`solve`].
pub fn solve_from<P: Nlp>(
    problem: &mut P,
    options: &Options,
    warm: Option<&Solution>,
) -> Result<Solution, Error> {
    let _guard = linear_solver_ready(options.linear_solver)?;
    let start = Instant::now();
    let shape = Shape::of(problem)?;
    let mut point = Point::start(problem, warm, &shape)?;
    let mut options = options.clone();
    if warm.is_some() {
        options = options.str("warm_start_init_point", "yes");
    }
    let handle = shape.create::<P>()?;
    apply_options(&handle, &options)?;
    // SAFETY: the handle is valid; the callback has the signature IPOPT expects.
    unsafe { sys::SetIntermediateCallback(handle.0, Some(intermediate::<P>)) };

    let mut context = Context {
        problem,
        jacobian: shape.jacobian,
        hessian: shape.hessian,
        callback_time: Duration::ZERO,
        iterations: 0,
        error: None,
    };
    let mut g = vec![0.0; shape.m];
    let mut objective = f64::NAN;
    // SAFETY: all output arrays have the sizes IPOPT was given; the context outlives the call and
    // is only touched through the user-data pointer while IPOPT runs.
    let code = unsafe {
        sys::IpoptSolve(
            handle.0,
            point.x.as_mut_ptr(),
            g.as_mut_ptr(),
            &mut objective,
            point.lambda.as_mut_ptr(),
            point.z_lower.as_mut_ptr(),
            point.z_upper.as_mut_ptr(),
            (&mut context as *mut Context<P>).cast::<c_void>(),
        )
    };
    drop(handle);
    let total = start.elapsed();

    if let Some(error) = context.error {
        return Err(error);
    }
    let status = Status::from_code(code);
    if status == Status::InvalidOption {
        // Options whose values are checked only when the solve starts.
        return Err(Error::InvalidOption {
            name: "(checked at solve start)".to_owned(),
            value: "see IPOPT's log with --verbose".to_owned(),
        });
    }
    Ok(Solution {
        status,
        x: point.x,
        g,
        lambda: point.lambda,
        z_lower: point.z_lower,
        z_upper: point.z_upper,
        objective,
        iterations: usize::try_from(context.iterations).unwrap_or(0),
        timing: Timing {
            total,
            callbacks: context.callback_time,
            ipopt: total.saturating_sub(context.callback_time),
        },
    })
}

/// Makes the linear solver ready: takes the process-wide lock for MUMPS (held by the returned
/// guard until the solve ends), installs the LDLᵀ into IPOPT once per process.
fn linear_solver_ready(solver: LinearSolver) -> Result<Option<MutexGuard<'static, ()>>, Error> {
    match solver {
        LinearSolver::Mumps => Ok(Some(
            MUMPS_LOCK
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner()),
        )),
        LinearSolver::Ldl => {
            crate::ldl::install().map_err(|message| Error::LinearSolver { solver, message })?;
            Ok(None)
        }
    }
}

/// The problem as IPOPT is told about it: sizes, bounds and sparsity, checked.
struct Shape {
    n: usize,
    m: usize,
    x_bounds: (Vec<f64>, Vec<f64>),
    g_bounds: (Vec<f64>, Vec<f64>),
    jacobian: Vec<(sys::Index, sys::Index)>,
    hessian: Vec<(sys::Index, sys::Index)>,
}

impl Shape {
    fn of<P: Nlp>(problem: &P) -> Result<Shape, Error> {
        let (n, m) = (problem.num_variables(), problem.num_constraints());
        let (mut x_l, mut x_u) = (vec![0.0; n], vec![0.0; n]);
        let (mut g_l, mut g_u) = (vec![0.0; m], vec![0.0; m]);
        problem.variable_bounds(&mut x_l, &mut x_u);
        problem.constraint_bounds(&mut g_l, &mut g_u);
        check_bounds("variable", &x_l, &x_u)?;
        check_bounds("constraint", &g_l, &g_u)?;
        Ok(Shape {
            n,
            m,
            x_bounds: (x_l, x_u),
            g_bounds: (g_l, g_u),
            jacobian: checked_structure("Jacobian", problem.jacobian_structure(), m, n, false)?,
            hessian: checked_structure("Hessian", problem.hessian_structure(), n, n, true)?,
        })
    }

    /// A new IPOPT problem of this shape with `P`'s callbacks.
    fn create<P: Nlp>(&self) -> Result<Handle, Error> {
        let (mut x_l, mut x_u) = self.x_bounds.clone();
        let (mut g_l, mut g_u) = self.g_bounds.clone();
        // SAFETY: the bound arrays have lengths n and m and are copied by IPOPT; the callbacks
        // are instantiated for P and receive a Context<P> as their user data.
        let raw = unsafe {
            sys::CreateIpoptProblem(
                to_index(self.n, "variables")?,
                x_l.as_mut_ptr(),
                x_u.as_mut_ptr(),
                to_index(self.m, "constraints")?,
                g_l.as_mut_ptr(),
                g_u.as_mut_ptr(),
                to_index(self.jacobian.len(), "Jacobian")?,
                to_index(self.hessian.len(), "Hessian")?,
                0,
                Some(eval_f::<P>),
                Some(eval_g::<P>),
                Some(eval_grad_f::<P>),
                Some(eval_jac_g::<P>),
                Some(eval_h::<P>),
            )
        };
        if raw.is_null() {
            return Err(Error::InvalidProblem(
                "IPOPT refused to create the problem".to_owned(),
            ));
        }
        Ok(Handle(raw))
    }
}

/// The primal-dual point a solve starts from and IPOPT overwrites with its result.
struct Point {
    x: Vec<f64>,
    lambda: Vec<f64>,
    z_lower: Vec<f64>,
    z_upper: Vec<f64>,
}

impl Point {
    /// The warm start's point and multipliers, or the problem's initial point with zero
    /// multipliers; checked for size and finiteness.
    fn start<P: Nlp>(problem: &P, warm: Option<&Solution>, shape: &Shape) -> Result<Point, Error> {
        let (n, m) = (shape.n, shape.m);
        let point = match warm {
            Some(start) => {
                let sizes = [start.x.len(), start.z_lower.len(), start.z_upper.len()];
                if sizes != [n; 3] || start.lambda.len() != m {
                    return Err(Error::InvalidProblem(format!(
                        "warm start has {} variables and {} constraints, the problem {n} and {m}",
                        start.x.len(),
                        start.lambda.len()
                    )));
                }
                Point {
                    x: start.x.clone(),
                    lambda: start.lambda.clone(),
                    z_lower: start.z_lower.clone(),
                    z_upper: start.z_upper.clone(),
                }
            }
            None => {
                let mut x = vec![0.0; n];
                problem.initial_point(&mut x);
                Point {
                    x,
                    lambda: vec![0.0; m],
                    z_lower: vec![0.0; n],
                    z_upper: vec![0.0; n],
                }
            }
        };
        if let Some(i) = point.x.iter().position(|value| !value.is_finite()) {
            return Err(Error::InvalidProblem(format!(
                "initial point x[{i}] = {} is not finite",
                point.x[i]
            )));
        }
        Ok(point)
    }
}

fn to_index(count: usize, what: &str) -> Result<sys::Index, Error> {
    sys::Index::try_from(count)
        .map_err(|_| Error::InvalidProblem(format!("too many {what} entries for IPOPT: {count}")))
}

fn check_bounds(kind: &str, lower: &[f64], upper: &[f64]) -> Result<(), Error> {
    for (i, (&lo, &up)) in lower.iter().zip(upper).enumerate() {
        if lo.is_nan() || up.is_nan() || lo > up {
            return Err(Error::InvalidProblem(format!(
                "{kind} {i} has bounds [{lo}, {up}]"
            )));
        }
    }
    Ok(())
}

fn checked_structure(
    name: &str,
    entries: Vec<(usize, usize)>,
    rows: usize,
    cols: usize,
    lower_triangle: bool,
) -> Result<Vec<(sys::Index, sys::Index)>, Error> {
    entries
        .into_iter()
        .enumerate()
        .map(|(k, (row, col))| {
            if row >= rows || col >= cols {
                return Err(Error::InvalidProblem(format!(
                    "{name} entry {k} at ({row}, {col}) lies outside {rows} x {cols}"
                )));
            }
            if lower_triangle && col > row {
                return Err(Error::InvalidProblem(format!(
                    "{name} entry {k} at ({row}, {col}) is above the diagonal"
                )));
            }
            Ok((to_index(row, name)?, to_index(col, name)?))
        })
        .collect()
}

fn apply_options(handle: &Handle, options: &Options) -> Result<(), Error> {
    if options.get("linear_solver").is_some() {
        return Err(Error::InvalidOption {
            name: "linear_solver".to_owned(),
            value: "(choose the linear solver with Options::linear_solver: ldl or mumps)"
                .to_owned(),
        });
    }
    let print_level = if options.verbose { 5 } else { 0 };
    let solver = options.linear_solver.ipopt_name().to_owned();
    let mut entries = vec![
        ("print_level".to_owned(), OptionValue::Int(print_level)),
        ("linear_solver".to_owned(), OptionValue::Str(solver)),
    ];
    if !options.verbose {
        // IPOPT 3.11 prints its banner at any print level unless this undocumented option is set.
        entries.push(("sb".to_owned(), OptionValue::Str("yes".to_owned())));
    }
    entries.extend(options.entries.iter().cloned());
    for (name, value) in &entries {
        let key = c_string(name)?;
        // SAFETY: the handle is valid and the strings are NUL-terminated; IPOPT copies them.
        let accepted = unsafe {
            match value {
                OptionValue::Str(text) => sys::AddIpoptStrOption(
                    handle.0,
                    key.as_ptr() as *mut c_char,
                    c_string(text)?.as_ptr() as *mut c_char,
                ),
                OptionValue::Int(number) => {
                    sys::AddIpoptIntOption(handle.0, key.as_ptr() as *mut c_char, *number)
                }
                OptionValue::Num(number) => {
                    sys::AddIpoptNumOption(handle.0, key.as_ptr() as *mut c_char, *number)
                }
            }
        };
        if accepted == 0 {
            return Err(Error::InvalidOption {
                name: name.clone(),
                value: match value {
                    OptionValue::Str(text) => format!("\"{text}\""),
                    OptionValue::Int(number) => number.to_string(),
                    OptionValue::Num(number) => number.to_string(),
                },
            });
        }
    }
    if let Some((path, level)) = &options.output_file {
        let file = c_string(&path.to_string_lossy())?;
        // SAFETY: valid handle, NUL-terminated path.
        let opened =
            unsafe { sys::OpenIpoptOutputFile(handle.0, file.as_ptr() as *mut c_char, *level) };
        if opened == 0 {
            return Err(Error::OutputFile(path.display().to_string()));
        }
    }
    Ok(())
}

fn c_string(text: &str) -> Result<CString, Error> {
    CString::new(text).map_err(|_| Error::InvalidOption {
        name: text.to_owned(),
        value: "(contains a NUL byte)".to_owned(),
    })
}

/// Runs one callback body with the problem: times it, and turns an `Err` or a panic into a stored
/// error and `FALSE`, so that nothing unwinds into C. Once an error is stored every later callback
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
        Ok(Err(error)) => error.0,
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

unsafe extern "C" fn eval_f<P: Nlp>(
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

unsafe extern "C" fn eval_grad_f<P: Nlp>(
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

unsafe extern "C" fn eval_g<P: Nlp>(
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

unsafe extern "C" fn eval_jac_g<P: Nlp>(
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

unsafe extern "C" fn eval_h<P: Nlp>(
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

unsafe extern "C" fn intermediate<P: Nlp>(
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
    sys::Bool::from(context.error.is_none())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipopt::{check_derivatives, DerivativeOrder, Hs071};
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    /// HS071 with something wrong in one callback.
    struct Faulty {
        fault: Fault,
        active: Option<Arc<AtomicUsize>>,
        max_active: Option<Arc<AtomicUsize>>,
        /// Whether callbacks wait for a second solve to be inside one too.
        meet: bool,
    }

    enum Fault {
        None,
        PanicInHessian,
        ErrorInConstraints,
        WrongGradient,
    }

    impl Faulty {
        fn new(fault: Fault) -> Faulty {
            Faulty {
                fault,
                active: None,
                max_active: None,
                meet: false,
            }
        }

        /// Counts how many solves are inside a callback at the same moment. With `meet`, until two
        /// have met there, a callback waits up to a second for another solve to come in.
        fn enter(&self) {
            if let (Some(active), Some(max)) = (&self.active, &self.max_active) {
                let now = active.fetch_add(1, Ordering::SeqCst) + 1;
                max.fetch_max(now, Ordering::SeqCst);
                let waited = Instant::now();
                while self.meet
                    && max.load(Ordering::SeqCst) < 2
                    && waited.elapsed() < Duration::from_secs(1)
                {
                    std::thread::sleep(Duration::from_micros(50));
                }
                std::thread::sleep(Duration::from_micros(50));
                active.fetch_sub(1, Ordering::SeqCst);
            }
        }
    }

    impl Nlp for Faulty {
        fn num_variables(&self) -> usize {
            4
        }
        fn num_constraints(&self) -> usize {
            2
        }
        fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
            Hs071.variable_bounds(lower, upper)
        }
        fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
            Hs071.constraint_bounds(lower, upper)
        }
        fn initial_point(&self, x: &mut [f64]) {
            Hs071.initial_point(x)
        }
        fn objective(&mut self, x: &[f64], new_x: bool) -> Result<f64, EvalError> {
            self.enter();
            Hs071.objective(x, new_x)
        }
        fn gradient(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) -> Result<(), EvalError> {
            Hs071.gradient(x, new_x, g)?;
            if let Fault::WrongGradient = self.fault {
                g[2] += 0.5;
            }
            Ok(())
        }
        fn constraints(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) -> Result<(), EvalError> {
            if let Fault::ErrorInConstraints = self.fault {
                return Err(EvalError::from("constraint evaluation refused"));
            }
            Hs071.constraints(x, new_x, g)
        }
        fn jacobian_structure(&self) -> Vec<(usize, usize)> {
            Hs071.jacobian_structure()
        }
        fn jacobian_values(
            &mut self,
            x: &[f64],
            new_x: bool,
            v: &mut [f64],
        ) -> Result<(), EvalError> {
            Hs071.jacobian_values(x, new_x, v)
        }
        fn hessian_structure(&self) -> Vec<(usize, usize)> {
            Hs071.hessian_structure()
        }
        fn hessian_values(
            &mut self,
            x: &[f64],
            new_x: bool,
            obj_factor: f64,
            lambda: &[f64],
            values: &mut [f64],
        ) -> Result<(), EvalError> {
            if let Fault::PanicInHessian = self.fault {
                panic!("hessian exploded");
            }
            Hs071.hessian_values(x, new_x, obj_factor, lambda, values)
        }
    }

    /// min x0 + x1 with x0 + x1 >= 3 inside the box [0, 1]^2: no feasible point.
    struct Infeasible;

    impl Nlp for Infeasible {
        fn num_variables(&self) -> usize {
            2
        }
        fn num_constraints(&self) -> usize {
            1
        }
        fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
            lower.fill(0.0);
            upper.fill(1.0);
        }
        fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
            lower[0] = 3.0;
            upper[0] = f64::INFINITY;
        }
        fn initial_point(&self, x: &mut [f64]) {
            x.fill(0.5);
        }
        fn objective(&mut self, x: &[f64], _: bool) -> Result<f64, EvalError> {
            Ok(x[0] + x[1])
        }
        fn gradient(&mut self, _: &[f64], _: bool, g: &mut [f64]) -> Result<(), EvalError> {
            g.fill(1.0);
            Ok(())
        }
        fn constraints(&mut self, x: &[f64], _: bool, g: &mut [f64]) -> Result<(), EvalError> {
            g[0] = x[0] * x[0] + x[1];
            Ok(())
        }
        fn jacobian_structure(&self) -> Vec<(usize, usize)> {
            vec![(0, 0), (0, 1)]
        }
        fn jacobian_values(&mut self, x: &[f64], _: bool, v: &mut [f64]) -> Result<(), EvalError> {
            v[0] = 2.0 * x[0];
            v[1] = 1.0;
            Ok(())
        }
        fn hessian_structure(&self) -> Vec<(usize, usize)> {
            vec![(0, 0)]
        }
        fn hessian_values(
            &mut self,
            _: &[f64],
            _: bool,
            _: f64,
            lambda: &[f64],
            values: &mut [f64],
        ) -> Result<(), EvalError> {
            values[0] = 2.0 * lambda[0];
            Ok(())
        }
    }

    #[test]
    fn a_warm_start_from_the_optimum_converges_at_once() {
        let cold = solve(&mut Hs071, &Options::new()).unwrap();
        let warm = solve_from(
            &mut Hs071,
            &Options::new()
                .num("mu_init", 1e-9)
                .num("warm_start_bound_push", 1e-9),
            Some(&cold),
        )
        .unwrap();
        assert_eq!(warm.status, Status::SolveSucceeded);
        assert!((warm.objective - cold.objective).abs() < 1e-6);
        assert!(
            warm.iterations < cold.iterations,
            "{} vs {}",
            warm.iterations,
            cold.iterations
        );
        let mut other = Infeasible;
        assert!(matches!(
            solve_from(&mut other, &Options::new(), Some(&cold)),
            Err(Error::InvalidProblem(_))
        ));
    }

    #[test]
    fn infeasible_problem_is_reported_as_infeasible() {
        let solution = solve(&mut Infeasible, &Options::new()).unwrap();
        assert_eq!(solution.status, Status::InfeasibleProblemDetected);
        assert!(!solution.status.is_success());
    }

    #[test]
    fn panic_in_a_callback_becomes_an_error() {
        let error = solve(&mut Faulty::new(Fault::PanicInHessian), &Options::new()).unwrap_err();
        match error {
            Error::Callback { callback, message } => {
                assert_eq!(callback, "hessian");
                assert!(message.contains("hessian exploded"), "{message}");
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn error_in_a_callback_stops_the_solve() {
        let error =
            solve(&mut Faulty::new(Fault::ErrorInConstraints), &Options::new()).unwrap_err();
        assert_eq!(
            error,
            Error::Callback {
                callback: "constraints",
                message: "constraint evaluation refused".to_owned()
            }
        );
    }

    #[test]
    fn bad_options_are_rejected_by_name() {
        let unknown = solve(&mut Hs071, &Options::new().num("tolerance_of_doom", 1.0));
        assert!(
            matches!(&unknown, Err(Error::InvalidOption { name, .. }) if name == "tolerance_of_doom"),
            "{unknown:?}"
        );
        let wrong_value = solve(&mut Hs071, &Options::new().str("mu_strategy", "sideways"));
        assert!(
            matches!(&wrong_value, Err(Error::InvalidOption { name, .. }) if name == "mu_strategy"),
            "{wrong_value:?}"
        );
        let wrong_type = solve(&mut Hs071, &Options::new().str("tol", "small"));
        assert!(
            matches!(wrong_type, Err(Error::InvalidOption { .. })),
            "{wrong_type:?}"
        );
    }

    #[test]
    fn derivative_checker_catches_a_wrong_gradient() {
        let mut problem = Faulty::new(Fault::WrongGradient);
        let report =
            check_derivatives(&mut problem, &Options::new(), DerivativeOrder::First).unwrap();
        assert!(report.errors >= 1, "{report:?}");
        assert!(
            report.flagged.iter().any(|line| line.contains("grad_f")),
            "{report:?}"
        );
    }

    #[test]
    fn concurrent_mumps_solves_are_serialised() {
        let active = Arc::new(AtomicUsize::new(0));
        let max_active = Arc::new(AtomicUsize::new(0));
        let threads: Vec<_> = (0..4)
            .map(|_| {
                let (active, max_active) = (Arc::clone(&active), Arc::clone(&max_active));
                std::thread::spawn(move || {
                    let mut problem = Faulty {
                        fault: Fault::None,
                        active: Some(active),
                        max_active: Some(max_active),
                        meet: false,
                    };
                    (0..5)
                        .map(|_| {
                            solve(
                                &mut problem,
                                &Options::new().linear_solver(LinearSolver::Mumps),
                            )
                            .unwrap()
                            .objective
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for thread in threads {
            for objective in thread.join().unwrap() {
                assert!((objective - crate::ipopt::HS071_OPTIMUM).abs() < 1e-6);
            }
        }
        assert_eq!(max_active.load(Ordering::SeqCst), 1);
    }

    #[test]
    fn ldl_solves_on_two_threads_run_at_once_and_match_one_after_the_other() {
        let options = Options::new().linear_solver(LinearSolver::Ldl);
        let sequential: Vec<Solution> = (0..2)
            .map(|_| solve(&mut Faulty::new(Fault::None), &options).unwrap())
            .collect();
        let active = Arc::new(AtomicUsize::new(0));
        let max_active = Arc::new(AtomicUsize::new(0));
        let threads: Vec<_> = (0..2)
            .map(|_| {
                let (active, max_active) = (Arc::clone(&active), Arc::clone(&max_active));
                let options = options.clone();
                std::thread::spawn(move || {
                    let mut problem = Faulty {
                        fault: Fault::None,
                        active: Some(active),
                        max_active: Some(max_active),
                        meet: true,
                    };
                    solve(&mut problem, &options).unwrap()
                })
            })
            .collect();
        for (thread, alone) in threads.into_iter().zip(&sequential) {
            let together = thread.join().unwrap();
            assert_eq!(together.x, alone.x);
            assert_eq!(together.lambda, alone.lambda);
            assert_eq!(together.iterations, alone.iterations);
        }
        // Each callback waits up to a second for the other thread to be inside one too.
        assert_eq!(max_active.load(Ordering::SeqCst), 2);
    }
}

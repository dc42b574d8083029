//! The problem as IPOPT holds it: its checked shape (sizes, bounds, sparsity), the handle that
//! owns IPOPT's copy, the options applied to it, and the primal-dual point a solve starts from.

use super::callbacks::{eval_f, eval_g, eval_grad_f, eval_h, eval_jac_g};
use super::{Error, Nlp, OptionValue, Options, Solution};
use ipopt_sys as sys;
use std::ffi::CString;
use std::os::raw::c_char;

/// Owns an `IpoptProblem` and frees it exactly once.
pub(super) struct Handle(pub(super) sys::IpoptProblem);

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: the pointer came from CreateIpoptProblem, is non-null, and is freed only here.
        unsafe { sys::FreeIpoptProblem(self.0) }
    }
}

/// The problem as IPOPT is told about it: sizes, bounds and sparsity, checked.
pub(super) struct Shape {
    pub(super) n: usize,
    pub(super) m: usize,
    pub(super) x_bounds: (Vec<f64>, Vec<f64>),
    pub(super) g_bounds: (Vec<f64>, Vec<f64>),
    pub(super) jacobian: Vec<(sys::Index, sys::Index)>,
    pub(super) hessian: Vec<(sys::Index, sys::Index)>,
}

impl Shape {
    pub(super) fn of<P: Nlp>(problem: &P) -> Result<Shape, Error> {
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
    pub(super) fn create<P: Nlp>(&self) -> Result<Handle, Error> {
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

/// Fails on an option set in `options` that codesign sets itself: `linear_solver` (chosen by
/// [`Options::linear_solver`]) and `option_file_name` (no options file is ever read).
fn refuse_reserved(options: &Options) -> Result<(), Error> {
    for (name, why) in [
        (
            "linear_solver",
            "(choose the linear solver with Options::linear_solver: ldl or mumps)",
        ),
        (
            "option_file_name",
            "(every option is set in code: no options file is read)",
        ),
    ] {
        if options.get(name).is_some() {
            return Err(Error::InvalidOption {
                name: name.to_owned(),
                value: why.to_owned(),
            });
        }
    }
    Ok(())
}

/// The primal-dual point a solve starts from and IPOPT overwrites with its result.
pub(super) struct Point {
    pub(super) x: Vec<f64>,
    pub(super) lambda: Vec<f64>,
    pub(super) z_lower: Vec<f64>,
    pub(super) z_upper: Vec<f64>,
}

impl Point {
    /// The warm start's point and multipliers, or the problem's initial point with zero
    /// multipliers; checked for size and finiteness.
    pub(super) fn start<P: Nlp>(
        problem: &P,
        warm: Option<&Solution>,
        shape: &Shape,
    ) -> Result<Point, Error> {
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

pub(super) fn apply_options(handle: &Handle, options: &Options) -> Result<(), Error> {
    refuse_reserved(options)?;
    let print_level = if options.verbose { 5 } else { 0 };
    let solver = options.linear_solver.ipopt_name().to_owned();
    let mut entries = vec![
        // IPOPT reads `ipopt.opt` from the working folder unless told no file: its options
        // would change every solve unrecorded, and its `output_file` write over any file.
        (
            "option_file_name".to_owned(),
            OptionValue::Str(String::new()),
        ),
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
                OptionValue::Str(text) => {
                    sys::AddIpoptStrOption(
                        handle.0,
                        key.as_ptr() as *mut c_char,
                        c_string(text)?.as_ptr() as *mut c_char,
                    ) != 0
                }
                // An integer is also a number: IPOPT takes it as the type it declared.
                OptionValue::Int(number) => {
                    sys::AddIpoptIntOption(handle.0, key.as_ptr() as *mut c_char, *number) != 0
                        || sys::AddIpoptNumOption(
                            handle.0,
                            key.as_ptr() as *mut c_char,
                            f64::from(*number),
                        ) != 0
                }
                OptionValue::Num(number) => {
                    sys::AddIpoptNumOption(handle.0, key.as_ptr() as *mut c_char, *number) != 0
                }
            }
        };
        if !accepted {
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

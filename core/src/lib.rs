//! The engine of codesign: everything needed to pose and solve the trajectory problem of one
//! design of a robot with parallel transmissions, and to differentiate its optimum in the design.
//!
//! The data flow one way, each module using only those listed before it:
//! - [`model`]: the robot (URDF) and the task as data: motion, weights, box, motors,
//!   transmission, limit modes;
//! - [`jet`] and [`dynamics`]: truncated Taylor arithmetic, and the rigid-body dynamics (RNEA,
//!   mass matrix, kinematics) with their exact first and second derivatives;
//! - [`transmission`]: the coupling q_u = γ(q), G(q) of constant and pose-dependent (linkage)
//!   transmissions, and what it does to limits, losses and motors;
//! - [`problem`]: the trajectory problem, its variables, constraint families and cost, with
//!   sparse Jacobians and Hessians;
//! - [`ipopt`] and [`ldl`]: the safe adapter to IPOPT's C interface and the sparse LDLᵀ it
//!   factorises its KKT systems with;
//! - [`solve`]: the solve of one design under the one rule of feasibility, its result, and the
//!   sensitivity dJ*/dr.
//!
//! Beneath them: [`text`] (how numbers and names are written in messages), [`json_keys`] (strict
//! JSON), [`input`] (bounded file reading), [`hash`], [`rng`] (a seeded random stream, the same
//! on every machine) and [`signals`] (stop requests and the process's signal handling).
//!
//! It knows nothing of a command line, a result store, an experiment or worker processes: those
//! stand above it, in the `codesign` crate.

#![warn(missing_docs)]

/// Writes a line on stderr like `eprintln!`, but a failed write (stderr on a full disk, a closed
/// stderr) is ignored instead of panicking: a note is never worth a crash.
#[macro_export]
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::write_note(format_args!($($arg)*))
    };
}

/// The writer behind `note!`: one line on stderr, write errors ignored.
#[doc(hidden)]
pub fn write_note(text: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}

pub mod choice;
pub mod dynamics;
pub mod hash;
pub mod input;
pub mod ipopt;
pub mod jet;
pub mod json_keys;
pub mod ldl;
pub mod model;
pub mod problem;
pub mod rng;
pub mod signals;
pub mod solve;
#[cfg(any(test, feature = "testing"))]
pub mod testing;
pub mod text;
pub mod transmission;

/// The Rust example of the user guide (docs/guide/rust.md), compiled and run with the doctests.
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/rust.md")]
pub struct GuideRustExample;

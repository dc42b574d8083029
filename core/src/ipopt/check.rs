//! IPOPT's own derivative checker, run on any [`Nlp`] and read back as a report.

use super::{solve, Error, Nlp, Options};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Which derivatives IPOPT's checker compares with its finite differences.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DerivativeOrder {
    /// Gradient of the objective and Jacobian of the constraints.
    First,
    /// The first-order terms and the Hessian of the Lagrangian.
    Second,
}

/// What IPOPT's derivative checker reported.
#[derive(Clone, Debug, PartialEq)]
pub struct DerivativeReport {
    /// The number of errors IPOPT counted (0 when it printed "No errors detected").
    pub errors: usize,
    /// The entries IPOPT flagged, as it printed them (lines marked with `*`).
    pub flagged: Vec<String>,
}

/// Runs IPOPT's derivative checker at the problem's initial point, perturbed by the caller's
/// `point_perturbation_radius` (pass 0 in `options` to check at the initial point itself).
///
/// The check uses `options` plus `derivative_test`, `max_iter = 0` and a temporary log file that
/// is parsed and removed. Fails with [`Error::InvalidProblem`] if IPOPT printed no verdict.
pub fn check_derivatives<P: Nlp>(
    problem: &mut P,
    options: &Options,
    order: DerivativeOrder,
) -> Result<DerivativeReport, Error> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let log = std::env::temp_dir().join(format!(
        "codesign-derivative-check-{}-{}.log",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let test = match order {
        DerivativeOrder::First => "first-order",
        DerivativeOrder::Second => "second-order",
    };
    let options = options
        .clone()
        .str("derivative_test", test)
        .int("max_iter", 0)
        .output_file(&log, 5);
    let outcome = solve(problem, &options);
    let text = std::fs::read_to_string(&log);
    let _ = std::fs::remove_file(&log);
    outcome?;
    let text = text.map_err(|error| Error::OutputFile(format!("{}: {error}", log.display())))?;
    parse_report(&text, &log)
}

fn parse_report(text: &str, log: &Path) -> Result<DerivativeReport, Error> {
    let flagged: Vec<String> = text
        .lines()
        .filter(|line| line.starts_with('*'))
        .map(str::to_owned)
        .collect();
    let detected = text.lines().find_map(|line| {
        line.trim()
            .strip_prefix("Derivative checker detected ")
            .and_then(|rest| rest.split_whitespace().next())
            .and_then(|count| count.parse::<usize>().ok())
    });
    let errors = match detected {
        Some(count) => count,
        None if text.contains("No errors detected by derivative checker") => 0,
        None => {
            return Err(Error::InvalidProblem(format!(
                "IPOPT's derivative checker printed no verdict in {}",
                log.display()
            )))
        }
    };
    Ok(DerivativeReport { errors, flagged })
}

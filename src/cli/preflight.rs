//! Checks of a co-design run made before its first evaluation (flags, the task's solver
//! options) and after its last (whether any design was judged at all).

use super::optimize::{Args, ObjectiveKind};
use crate::design::evaluate::Evaluation;
use crate::model::task::{LimitModes, Task};
use crate::model::Robot;
use crate::problem::Formulation;
use crate::report::codesign::Method;
use crate::solver::{solve_design, SolveError, SolveSettings};

/// Most designs per CMA-ES generation: 100 times the paper's 100 (each is a solve, or about 10
/// with `--objective capacity`).
const MAX_POPULATION: usize = 10_000;

/// Most CMA-ES generations: 1000 times the paper's 30 would take months at the paper's
/// population; this bound only keeps sizes and the log's indices sane.
const MAX_GENERATIONS: usize = 30_000;

/// Checks `--population`: the limit and its reason in the message.
pub fn check_population(population: usize) -> Result<(), String> {
    if (5..=MAX_POPULATION).contains(&population) {
        Ok(())
    } else {
        Err(format!(
            "--population {population}: must be 5 to {MAX_POPULATION} (CMA-ES ranks at least 5 \
             designs per generation; {MAX_POPULATION} is 100 times the paper's 100)"
        ))
    }
}

/// Checks `--generations`: the limit and its reason in the message.
pub fn check_generations(generations: usize) -> Result<(), String> {
    if generations <= MAX_GENERATIONS {
        Ok(())
    } else {
        Err(format!(
            "--generations {generations}: must be at most {MAX_GENERATIONS} (1000 times the \
             paper's 30)"
        ))
    }
}

/// Checks the flags that need no task: every error names its flag, the limit and its reason.
pub fn check_flags(args: &Args) -> Result<(), String> {
    if args.method == Method::Cmaes {
        // The gradient method has no population or generations (reproduce passes 0 for both).
        check_population(args.population)?;
        check_generations(args.generations)?;
    }
    if !(args.sigma.is_finite() && args.sigma > 0.0) {
        return Err(format!("--sigma {}: must be a positive number", args.sigma));
    }
    if !args.penalty.is_finite() {
        return Err(format!("--penalty {}: must be finite", args.penalty));
    }
    if !(args.solve_timeout.is_finite() && args.solve_timeout > 0.0) {
        return Err(format!(
            "--solve-timeout {}: must be a positive number of seconds",
            args.solve_timeout
        ));
    }
    if args.workers == Some(0) {
        return Err("--workers 0: must be at least 1".to_owned());
    }
    match (args.method, args.objective) {
        (Method::Gradient, ObjectiveKind::Capacity) => Err(
            "--objective capacity: the capacity is not differentiable in r; use --method cmaes"
                .to_owned(),
        ),
        (Method::Gradient, _) if args.resume => Err(
            "--resume continues CMA-ES runs; a gradient run is short, start it again".to_owned(),
        ),
        (_, ObjectiveKind::Capacity)
            if !(args.capacity_resolution.is_finite() && args.capacity_resolution > 0.0) =>
        {
            Err(format!(
                "--capacity-resolution {}: must be a positive mass",
                args.capacity_resolution
            ))
        }
        _ => Ok(()),
    }
}

/// Solves the original design once on a 2-interval copy of the problem, so that a solver
/// option IPOPT rejects (the task file's `solver`) fails the run before its first generation,
/// with IPOPT's complaint, instead of penalising every design.
pub fn probe_solver(
    task: &Task,
    robot: &Robot,
    args: &Args,
    modes: LimitModes,
) -> Result<(), String> {
    let mut small = task.clone();
    small.motion.steps = 2;
    let formulation = Formulation::new(&small, robot.clone(), args.problem.space, modes)
        .map_err(|e| e.to_string())?;
    match solve_design(
        &formulation,
        &small.transmission.original,
        &SolveSettings::default(),
    ) {
        Err(SolveError::Ipopt(error)) => Err(format!(
            "{} solver: {error} (checked by a solve of the original design before the run)",
            args.model.source()
        )),
        _ => Ok(()),
    }
}

/// Fails when no evaluation judged a design: every one failed for the same reason that is not
/// the design's (a solver error, a crashed worker), so the run's result would mean nothing.
pub fn check_evaluations(evaluations: &[Evaluation]) -> Result<(), String> {
    let not_judged =
        |e: &Evaluation| !e.feasible && (e.status == "Solver_Error" || e.status == "Worker_Failed");
    match evaluations.first() {
        Some(first)
            if evaluations
                .iter()
                .all(|e| not_judged(e) && e.reason == first.reason) =>
        {
            Err(format!(
                "every one of the {} evaluations failed alike ({}: {}); no design was judged, \
                 so no result is written (fix the cause, then start afresh with --overwrite)",
                evaluations.len(),
                first.status,
                first.reason.as_deref().unwrap_or("no reason given")
            ))
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::{check_evaluations, check_flags, Args};
    use crate::design::evaluate::Evaluation;

    #[test]
    fn population_and_generations_are_checked_for_cma_es_only() {
        #[derive(clap::Parser)]
        struct Command {
            #[command(flatten)]
            args: Args,
        }
        let parse = |flags: &[&str]| {
            let line = ["optimize", "--population", "0", "--generations", "0"];
            <Command as clap::Parser>::parse_from(line.iter().chain(flags)).args
        };
        let error = check_flags(&parse(&[])).unwrap_err();
        assert!(error.contains("--population 0"), "{error}");
        check_flags(&parse(&["--method", "gradient"])).unwrap();
    }

    #[test]
    fn a_run_fails_when_its_evaluations_all_failed_alike() {
        let failed =
            |reason: &str| Evaluation::penalised(&[6.0], 1e6, "Solver_Error", reason.to_owned());
        let alike = vec![failed("IPOPT rejected option `x` = 3"); 3];
        let error = check_evaluations(&alike).unwrap_err();
        assert!(error.contains("every one of the 3 evaluations"), "{error}");
        assert!(error.contains("IPOPT rejected option"), "{error}");
        let differing = vec![failed("a"), failed("b")];
        assert!(check_evaluations(&differing).is_ok());
        let invalid = vec![Evaluation::penalised(&[6.0], 1e6, "Invalid_Design", "r".into()); 2];
        assert!(
            check_evaluations(&invalid).is_ok(),
            "the designs were judged"
        );
    }
}

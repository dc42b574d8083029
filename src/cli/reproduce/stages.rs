//! The stages of the experiment run in this process: the original designs, the co-design runs
//! and the capacities, each written to its file in the output folder as it finishes.

use super::{ExperimentTask, Outcomes};
use crate::cli::optimize::progress_bar;
use crate::cli::store_hints::run_error;
use crate::design::capacity::{payload_capacity, CapacitySettings};
use crate::design::run::{run_case, task_source, OptimizeDocument, RecordedHash};
use crate::design::score::Objective;
use crate::experiment::CapacityOf;
use crate::experiment::{Plan, PlannedRun, SPACES};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::report::codesign::{CapacityDocument, CapacityInputs};
use crate::report::table::ResultFile;
use crate::report::trajectory::{write_plots, SolveDocument};
use crate::solve::ToolInfo;
use crate::solve::{solve_design, SolveError};
use crate::store::document::write_document;

/// Runs every independent stage of `plan`: what its printed commands do elsewhere.
pub fn run_all(plan: &Plan, task: &ExperimentTask) -> Result<Outcomes, String> {
    Ok(Outcomes {
        originals: solve_originals(plan, task)?,
        runs: cost_runs(plan)?,
        gradient_runs: gradient_runs(plan),
        beyond_runs: beyond_runs(plan)?,
        original_capacities: SPACES
            .iter()
            .map(|&space| {
                let ratios = task.task.transmission.original.clone();
                capacity_document(plan, task, space, ratios, CapacityOf::Original(space))
            })
            .collect::<Result<_, _>>()?,
    })
}

/// The formulation of `task` with `payload_kg` in `space`, with the task's limit modes.
pub fn formulation_at(
    task: &ExperimentTask,
    payload_kg: f64,
    space: Space,
) -> Result<Formulation, String> {
    let robot = Robot::load(&task.task).map_err(|e| e.to_string())?;
    Formulation::new(&task.task, robot, space, task.task.limit_modes)
        .and_then(|formulation| {
            formulation
                .with_hold_tolerance(task.solver.constraint_tolerance())
                .with_payload(payload_kg)
        })
        .map_err(|e| e.to_string())
}

/// Solves the original design at every payload in both spaces; writes each result and its
/// plots.
fn solve_originals(plan: &Plan, task: &ExperimentTask) -> Result<Vec<ResultFile>, String> {
    let source = task_source(plan.task.as_ref());
    let mut files = Vec::new();
    for &payload in &plan.experiment.original_payloads_kg {
        for space in SPACES {
            let formulation = formulation_at(task, payload, space)?;
            let ratios = task.task.transmission.original.clone();
            let result =
                solve_design(&formulation, &ratios, &task.solver).map_err(|e| match e {
                    SolveError::Design(_) => format!("{source} transmission.original: {e}"),
                    SolveError::Ipopt(_) => format!("{source} solver: {e}"),
                    SolveError::Formulation(_) => format!("{source}: {e}"),
                })?;
            let verdict = match (&result.reason, result.feasible) {
                (Some(reason), false) => format!("; infeasible: {reason}"),
                _ => String::new(),
            };
            say!(
                "original design, {space} space, {payload} kg: {} J = {:.4} ({} iterations){verdict}",
                result.status,
                result.cost,
                result.iterations
            );
            write_plots(
                &plan.layout.original_plots(space, payload),
                &formulation,
                &result,
            )?;
            let document = SolveDocument::new(
                &source.label(),
                &task.hash,
                &formulation,
                &task.solver,
                result,
            );
            write_document(&plan.layout.original(space, payload), &document)
                .map_err(|e| e.to_string())?;
            files.push(ResultFile::Solve(Box::new(document)));
        }
    }
    Ok(files)
}

/// Runs one planned co-design run.
fn run(plan: &Plan, run: &PlannedRun) -> Result<OptimizeDocument, String> {
    run_case(&run.case, &plan.layout.run(&run.name), &progress_bar).map_err(run_error)
}

/// The paper's co-design runs (CMA-ES on the cost), in order.
fn cost_runs(plan: &Plan) -> Result<Vec<OptimizeDocument>, String> {
    let mut documents = Vec::new();
    for planned in plan.cost_runs() {
        let document = run(plan, &planned)?;
        say!(
            "co-design, {} space, {} kg, seed {}: {} ({} evaluations)",
            planned.case.problem.space,
            document.inputs.payload_kg,
            planned.case.settings.cmaes.seed,
            best_text(&document),
            document.evaluations
        );
        documents.push(document);
    }
    Ok(documents)
}

/// A CMA-ES run's best design and cost, or that it found no feasible design (and the best
/// penalised fitness, which grades the designs it tried under the graded penalty).
fn best_text(document: &OptimizeDocument) -> String {
    if document.best_ratios.is_empty() {
        format!("no feasible design, best fitness {:.4}", document.best_cost)
    } else {
        format!(
            "best r = {:?}, J = {:.4}",
            document.best_ratios, document.best_cost
        )
    }
}

/// Co-design by the gradient method for every co-designed case, and with the graded penalty at
/// the edge of feasibility; a case where it finds no feasible start is reported and left out.
fn gradient_runs(plan: &Plan) -> Vec<OptimizeDocument> {
    let mut documents = Vec::new();
    for planned in plan.gradient_runs() {
        let space = planned.case.problem.space;
        let payload = planned.case.model.payload.unwrap_or_default();
        let penalty = planned.case.settings.penalty();
        let label = format!("gradient co-design, {space} space, {payload} kg, {penalty} penalty");
        match run(plan, &planned) {
            Ok(document) if document.best_ratios.is_empty() => {
                say!(
                    "{label}: no feasible design found ({} solves)",
                    document.evaluations
                );
                documents.push(document);
            }
            Ok(document) => {
                say!(
                    "{label}: best r = {:?}, J = {:.4} ({} solves)",
                    document.best_ratios,
                    document.best_cost,
                    document.evaluations
                );
                documents.push(document);
            }
            Err(error) => say!("{label}: {error}"),
        }
    }
    documents
}

/// The CMA-ES runs beyond the paper: the design of largest payload capacity per space, and one
/// design for the payload range.
fn beyond_runs(plan: &Plan) -> Result<Vec<OptimizeDocument>, String> {
    let mut documents = Vec::new();
    for planned in plan.beyond_runs() {
        let document = run(plan, &planned)?;
        let space = planned.case.problem.space;
        match &planned.case.settings.objective {
            Objective::Range(range) => say!(
                "range co-design, {space} space, {:?} kg: {} ({} evaluations)",
                range.payloads_kg,
                best_text(&document),
                document.evaluations
            ),
            Objective::Capacity(_) if document.best_ratios.is_empty() => say!(
                "capacity co-design, {space} space: no design lifts any payload ({} evaluations)",
                document.evaluations
            ),
            Objective::Capacity(_) => say!(
                "capacity co-design, {space} space: r = {:?} lifts {:.3} kg ({} evaluations)",
                document.best_ratios,
                -document.best_cost,
                document.evaluations
            ),
            // The experiment plans no energy run.
            Objective::Cost | Objective::Energy => say!(
                "co-design, {space} space, {} kg, seed {}, penalty {}: {} ({} evaluations)",
                document.inputs.payload_kg,
                planned.case.settings.cmaes.seed,
                planned.case.settings.penalty(),
                best_text(&document),
                document.evaluations
            ),
        }
        documents.push(document);
    }
    Ok(documents)
}

/// Searches the payload capacity of `ratios` in `space` and writes it as `capacity/NAME.json`.
pub fn capacity_document(
    plan: &Plan,
    task: &ExperimentTask,
    space: Space,
    ratios: Vec<f64>,
    of: CapacityOf,
) -> Result<CapacityDocument, String> {
    let settings = CapacitySettings::default();
    let formulation = formulation_at(task, task.task.payload.mass_kg, space)?;
    let capacity = payload_capacity(&formulation, &task.solver, &ratios, &settings)
        .map_err(|e| e.to_string())?;
    match capacity.capacity_kg {
        Some(kg) => say!("payload capacity, {of}: {kg} kg"),
        None => say!("payload capacity, {of}: infeasible even without payload"),
    }
    let document = CapacityDocument {
        tool: ToolInfo::current(task.solver.linear_solver()),
        inputs: CapacityInputs {
            task_file: task_source(plan.task.as_ref()).label(),
            task_hash: RecordedHash(Some(task.hash.clone())),
            space,
            ratios,
            limit_modes: task.task.limit_modes,
            ends: task.task.motion.ends,
            settings,
        },
        capacity,
    };
    write_document(&plan.layout.capacity(of), &document).map_err(|e| e.to_string())?;
    Ok(document)
}

//! The table's rows from result files: the original design's solves ("before"), the co-design
//! runs ("after", the gradient method, the largest capacity), the capacities and the totals.

use super::check::motion;
use super::{
    AfterCell, DesignCell, PaperTable, PaperValues, RangeRow, ResultFile, TableRow, PAPER,
};
use crate::design::penalty::Grading;
use crate::design::run::{Method, OptimizeDocument};
use crate::design::score::Objective;
use crate::stats::median;
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::identity::built_in_task_hash;
use codesign_core::model::task::{Motors, PerMotor, Task};
use codesign_core::problem::Space;
use codesign_core::solve::ToolInfo;
use codesign_core::solve::{envelope_margins, TrajectoryResult};
use codesign_core::transmission::Envelope;

/// Builds the table from result files: solves of the original design give "before"; co-design
/// runs give "after" (the best over their seeds) and, if no solve did, "before" too. The
/// paper's values stand beside ours only when every file is of the paper's task.
pub fn build_table(files: &[ResultFile], notes: Vec<String>) -> PaperTable {
    let task = TableTask::of(files);
    let paper = task.paper;
    let mut rows: Vec<TableRow> = Vec::new();
    for file in files {
        if let ResultFile::Solve(doc) = file {
            let original = &doc.inputs.task.task.transmission.original;
            if doc.result.ratios == *original {
                row_mut(&mut rows, doc.inputs.payload_kg, doc.inputs.space, paper).before =
                    Some(cell(&doc.result, &doc.inputs.task.task.motors));
            }
        }
    }
    let mut ranges = Vec::new();
    for file in files {
        match file {
            ResultFile::Optimize(doc)
                if matches!(doc.inputs.settings.objective, Objective::Range(_)) =>
            {
                ranges.extend(range_row(doc));
            }
            ResultFile::Optimize(doc) => add_run(
                row_mut(&mut rows, doc.inputs.payload_kg, doc.inputs.space, paper),
                doc,
            ),
            _ => {}
        }
    }
    for row in &mut rows {
        complete_row(row, files);
    }
    rows.sort_by(|a, b| {
        a.payload_kg
            .total_cmp(&b.payload_kg)
            .then((a.space as u8).cmp(&(b.space as u8)))
    });
    let (solves, solve_seconds) = run_totals(files, true);
    let (capacity_evaluations, capacity_seconds) = run_totals(files, false);
    let linear_solvers = linear_solvers(files);
    PaperTable {
        title: task.title(),
        paper_task: paper,
        ends: files.first().map(ResultFile::ends),
        hold: Vec::new(),
        task_hash: task.hash,
        tool: ToolInfo::current(linear_solvers.first().copied().unwrap_or_default()),
        linear_solvers,
        rows,
        notes,
        solves,
        solve_seconds,
        capacity_evaluations,
        capacity_seconds,
        ranges,
    }
}

/// The row of a payload-range run.
fn range_row(doc: &OptimizeDocument) -> Option<RangeRow> {
    let Objective::Range(range) = &doc.inputs.settings.objective else {
        return None;
    };
    let costs = doc.payload_costs.as_ref();
    Some(RangeRow {
        payloads_kg: range.payloads_kg.clone(),
        space: doc.inputs.space,
        seed: doc.inputs.settings.cmaes.seed,
        ratios: doc.best_ratios.clone(),
        mean_cost: doc.best_cost,
        per_payload: costs.map_or_else(Vec::new, |c| c.best.clone()),
        original_mean_cost: doc.original_cost,
        original_feasible: costs
            .is_some_and(|c| !c.original.is_empty() && c.original.iter().all(|p| p.feasible)),
        evaluations: doc.evaluations,
    })
}

/// Whether every motor stays inside its torque-speed envelope (when `motors` has one) at the
/// nodes after the first (where the problem holds it), to 1e-6 of its torque limit.
fn within_envelope(result: &TrajectoryResult, motors: &Motors) -> bool {
    let t = &result.trajectory;
    let count = t.motor_torque.first().map_or(0, Vec::len);
    Envelope::of(motors, count).is_none_or(|envelope| {
        envelope_margins(&envelope, t)
            .all(|m| m.margin_nm >= -1e-6 * envelope.torque_limit(m.motor))
    })
}

/// One design's cell; the motors can execute it when each motor's largest torque and speed
/// on its trajectory are within that motor's own limits in `motors` to 1e-6 relative, and
/// within its torque-speed envelope when the task gives one.
fn cell(result: &TrajectoryResult, motors: &Motors) -> DesignCell {
    let within = |peaks: Vec<f64>, limits: &PerMotor| {
        peaks.iter().enumerate().all(|(motor, &peak)| {
            limits
                .get(motor)
                .is_some_and(|limit| peak <= limit * (1.0 + 1e-6))
        })
    };
    let t = &result.trajectory;
    DesignCell {
        motors_can_execute: within(t.motor_torque_peaks(), &motors.torque_limit_nm)
            && within(t.motor_speed_peaks(), &motors.speed_limit_rad_s)
            && within_envelope(result, motors),
        ratios: result.ratios.clone(),
        feasible: result.feasible,
        cost: result.cost,
        status: result.status.clone(),
        reason: result.reason.clone(),
        max_motor_torque: result.max_motor_torque,
        max_motor_speed: result.max_motor_speed,
        active_bounds: Vec::new(),
    }
}

/// `cell` of `doc`'s best design with the bounds of its design space it sits on.
fn with_bounds(mut cell: DesignCell, doc: &OptimizeDocument) -> DesignCell {
    cell.active_bounds = doc
        .best_at_bounds()
        .iter()
        .map(ToString::to_string)
        .collect();
    cell
}

/// The task of a table's files.
struct TableTask {
    /// The task hash the files record (or imply: see [`ResultFile::task`]); None: unknown.
    hash: Option<String>,
    /// The task file the first file records.
    file: String,
    /// Whether every file is of the paper's task, the built-in one, with its motion (`solve
    /// --steps` or `--duration` keep the task hash, as read, but change the problem).
    paper: bool,
}

impl TableTask {
    /// The task of `files`, which [`super::check_results`] has found to be of one task.
    fn of(files: &[ResultFile]) -> TableTask {
        // The built-in task always loads (tested); were it not to, no table is the paper's.
        let built_in = built_in_task_hash().ok();
        let tasks: Vec<Option<String>> = files.iter().map(ResultFile::task).collect();
        let paper_motion = Task::built_in()
            .ok()
            .map(|task| (task.motion.horizon, task.motion.steps));
        let own_motion = files
            .iter()
            .all(|file| motion(file).is_none_or(|m| Some(m) == paper_motion));
        TableTask {
            hash: tasks.iter().flatten().next().cloned(),
            file: files
                .first()
                .map_or_else(String::new, |f| f.task_file().to_owned()),
            paper: !files.is_empty()
                && built_in.is_some()
                && own_motion
                && tasks.iter().all(|task| *task == built_in),
        }
    }

    /// The table's title: the paper's table for the paper's task, else the task's file and
    /// hash.
    fn title(&self) -> String {
        let what = "gear ratios and cost per payload";
        if self.paper {
            return format!("Table II reproduced: {what}");
        }
        let hash = self.hash.as_deref().unwrap_or("unknown");
        format!("Co-design of task {} (task hash {hash}): {what}", self.file)
    }
}

/// The row of `payload_kg` and `space`, added empty (with the paper's values when `paper`)
/// when missing.
fn row_mut(rows: &mut Vec<TableRow>, payload_kg: f64, space: Space, paper: bool) -> &mut TableRow {
    let index = match rows
        .iter()
        .position(|r| r.payload_kg == payload_kg && r.space == space)
    {
        Some(index) => index,
        None => {
            let paper = PAPER
                .iter()
                .filter(|_| paper)
                .find(|(p, s, _, _)| *p == payload_kg && *s == space)
                .map(|(_, _, before, after)| PaperValues {
                    before: (*before).to_owned(),
                    after: (*after).to_owned(),
                });
            rows.push(TableRow {
                payload_kg,
                space,
                before: None,
                after: None,
                gradient: None,
                capacity_before_kg: None,
                capacity_after_kg: None,
                held_before_kg: None,
                held_after_kg: None,
                capacity_max: None,
                graded: None,
                graded_gradient: None,
                paper,
            });
            rows.len() - 1
        }
    };
    &mut rows[index]
}

/// Adds one co-design run to its row: a capacity run to the largest capacity found, a gradient
/// run to its penalty's gradient column, a CMA-ES run to "after" (and to "before" when still
/// empty) or with the graded penalty to "graded".
fn add_run(row: &mut TableRow, doc: &OptimizeDocument) {
    let motors = &doc.inputs.task.task.motors;
    if let Objective::Capacity(_) = doc.inputs.settings.objective {
        let capacity = doc.best_cost.map(|cost| -cost);
        if let Some(capacity) = capacity.filter(|&kg| kg >= 0.0) {
            if (row.capacity_max.as_ref()).is_none_or(|(_, best)| capacity > *best) {
                row.capacity_max = Some((doc.best_ratios.clone(), capacity));
            }
        }
        return;
    }
    if doc.inputs.settings.method == Method::Gradient {
        let column = match doc.inputs.settings.grading {
            Grading::Flat => &mut row.gradient,
            Grading::Graded => &mut row.graded_gradient,
        };
        if let Some(result) = doc.best_result.as_ref().filter(|r| r.feasible) {
            *column = Some((with_bounds(cell(result, motors), doc), doc.solves));
        }
        return;
    }
    if !doc.inputs.settings.grading.is_flat() {
        let graded = row.graded.get_or_insert_with(|| AfterCell::new(doc));
        add_seed(graded, doc, motors);
        return;
    }
    if row.before.is_none() {
        row.before = doc.original_result.as_ref().map(|r| cell(r, motors));
    }
    let after = row.after.get_or_insert_with(|| AfterCell::new(doc));
    add_seed(after, doc, motors);
}

impl AfterCell {
    /// An empty cell for the CMA-ES runs of `doc`'s budget.
    fn new(doc: &OptimizeDocument) -> AfterCell {
        AfterCell {
            best: None,
            per_seed: Vec::new(),
            early_stops: Vec::new(),
            evaluations: 0,
            solves: 0,
            median_solve_seconds: f64::NAN,
            population: doc.inputs.settings.cmaes.population,
            generations: doc.inputs.settings.cmaes.generations,
        }
    }
}

/// Adds one CMA-ES run (one seed) to "after": its best cost, an early stop, its evaluations and
/// its best design when that beats the others.
fn add_seed(after: &mut AfterCell, doc: &OptimizeDocument, motors: &Motors) {
    after
        .per_seed
        .push((doc.inputs.settings.cmaes.seed, doc.best_cost));
    if let Some(last) = doc.generations.last() {
        if last.generation < doc.inputs.settings.cmaes.generations {
            after.early_stops.push((
                doc.inputs.settings.cmaes.seed,
                last.generation,
                doc.stop_reason.clone(),
            ));
        }
    }
    after.evaluations += doc.evaluations;
    after.solves += doc.solves;
    if let Some(result) = doc.best_result.as_ref().filter(|r| r.feasible) {
        if after
            .best
            .as_ref()
            .is_none_or(|best| result.cost < best.cost)
        {
            after.best = Some(with_bounds(cell(result, motors), doc));
        }
    }
}

/// Fills in what needs every file: the capacities of the row's designs, the median solve time
/// of its CMA-ES runs, and its seeds in order.
fn complete_row(row: &mut TableRow, files: &[ResultFile]) {
    if let Some(before) = &row.before {
        (row.capacity_before_kg, row.held_before_kg) =
            capacity_of(files, row.space, &before.ratios);
    }
    if let Some(best) = row.after.as_ref().and_then(|a| a.best.as_ref()) {
        (row.capacity_after_kg, row.held_after_kg) = capacity_of(files, row.space, &best.ratios);
    }
    let (payload_kg, space) = (row.payload_kg, row.space);
    for (cell, grading) in [
        (&mut row.after, Grading::Flat),
        (&mut row.graded, Grading::Graded),
    ] {
        if let Some(cell) = cell {
            cell.median_solve_seconds = median_solve_seconds(files, payload_kg, space, grading);
            cell.per_seed.sort_by_key(|(seed, _)| *seed);
        }
    }
}

/// The capacity and the load held at rest, kg, of the first capacity file of `ratios` in
/// `space`.
fn capacity_of(files: &[ResultFile], space: Space, ratios: &[f64]) -> (Option<f64>, Option<f64>) {
    files
        .iter()
        .find_map(|f| match f {
            ResultFile::Capacity(d) if d.inputs.space == space && d.inputs.ratios == ratios => {
                Some((d.capacity.capacity_kg, d.capacity.hold_kg))
            }
            _ => None,
        })
        .unwrap_or((None, None))
}

/// The median over the CMA-ES runs on the cost of one row (with the penalty's `grading`) of each
/// run's median solve time, s (NaN without runs).
fn median_solve_seconds(
    files: &[ResultFile],
    payload_kg: f64,
    space: Space,
    grading: Grading,
) -> f64 {
    let medians: Vec<f64> = files
        .iter()
        .filter_map(|f| match f {
            ResultFile::Optimize(d)
                if d.inputs.payload_kg == payload_kg
                    && d.inputs.space == space
                    && d.inputs.settings.method == Method::Cmaes
                    && d.inputs.settings.objective == Objective::Cost
                    && d.inputs.settings.grading == grading =>
            {
                Some(d.median_solve_seconds)
            }
            _ => None,
        })
        .collect();
    median(&medians)
}

/// The inner solves and their summed wall time, s, of the co-design runs on the cost
/// (`objective_is_cost`) or on the capacity.
fn run_totals(files: &[ResultFile], objective_is_cost: bool) -> (usize, f64) {
    files
        .iter()
        .filter_map(|f| match f {
            ResultFile::Optimize(d)
                if matches!(d.inputs.settings.objective, Objective::Capacity(_))
                    != objective_is_cost =>
            {
                Some(d)
            }
            _ => None,
        })
        .fold((0, 0.0), |(n, s), d| {
            (n + d.solves, s + d.solve_seconds_total)
        })
}

/// The linear solvers of the files, each once, in a fixed order.
fn linear_solvers(files: &[ResultFile]) -> Vec<LinearSolver> {
    let mut solvers: Vec<LinearSolver> = files
        .iter()
        .map(|file| match file {
            ResultFile::Solve(d) => d.tool.linear_solver,
            ResultFile::Optimize(d) => d.tool.linear_solver,
            ResultFile::Capacity(d) => d.tool.linear_solver,
        })
        .collect();
    solvers.sort_by_key(|solver| solver.name());
    solvers.dedup();
    solvers
}

#[cfg(test)]
mod tests {
    use super::cell;
    use crate::design::run::OptimizeDocument;
    use codesign_core::model::task::PerMotor;

    #[test]
    fn motors_execute_a_design_only_inside_their_torque_speed_envelope() {
        // The best 1 kg design co-designed with a no-load speed of 149 rad/s: inside its
        // envelope; the same trajectory under a slower motor (60 rad/s) leaves it.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("results/motors/envelope/runs/actuation-1kg-seed0.json");
        let text = std::fs::read_to_string(path).unwrap();
        let document: OptimizeDocument = serde_json::from_str(&text).unwrap();
        let result = document
            .best_result
            .as_ref()
            .expect("a feasible best design");
        let mut motors = document.inputs.task.task.motors.clone();
        assert!(result.feasible && cell(result, &motors).motors_can_execute);
        motors.no_load_speed_rad_s = Some(PerMotor::All(60.0));
        assert!(!cell(result, &motors).motors_can_execute);
        motors.no_load_speed_rad_s = None;
        assert!(cell(result, &motors).motors_can_execute);
    }
}

//! The paper's Table II with our numbers beside the paper's, built from result files.

use super::codesign::{CapacityDocument, Method, OptimizeDocument};
use super::trajectory::{SolveDocument, ToolInfo};
use crate::design::evaluate::Objective;
use crate::ipopt::LinearSolver;
use crate::model::task::Motors;
use crate::problem::Space;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A result file of `solve`, `optimize` or `capacity`.
#[derive(Clone, Debug, PartialEq)]
pub enum ResultFile {
    /// One trajectory solve.
    Solve(Box<SolveDocument>),
    /// One co-design run.
    Optimize(Box<OptimizeDocument>),
    /// One payload-capacity search.
    Capacity(Box<CapacityDocument>),
}

/// Reads a result file, telling its kind by its fields; errors name the file.
pub fn read_result_file(path: &Path) -> Result<ResultFile, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: not JSON: {e}", path.display()))?;
    let kind = if value.get("best_ratios").is_some() {
        "optimize"
    } else if value.get("probes").is_some() {
        "capacity"
    } else {
        "solve"
    };
    let parsed = if kind == "capacity" {
        serde_json::from_value(value).map(|d| ResultFile::Capacity(Box::new(d)))
    } else if kind == "optimize" {
        serde_json::from_value(value).map(|d| ResultFile::Optimize(Box::new(d)))
    } else {
        serde_json::from_value(value).map(|d| ResultFile::Solve(Box::new(d)))
    };
    parsed.map_err(|e| format!("{}: not a codesign {kind} result: {e}", path.display()))
}

/// What the paper reports for one row (docs/model.md, section 13, from the paper's Table II).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperValues {
    /// Before co-design (original ratios 6, 3, 1, 1).
    pub before: String,
    /// After co-design.
    pub after: String,
}

/// The paper's Table II: (payload kg, space, before, after).
const PAPER: [(f64, Space, &str, &str); 6] = [
    (0.0, Space::Joint, "(6, 3, 1, 1): 66.77", "-"),
    (0.0, Space::Actuation, "(6, 3, 1, 1): 50.99", "-"),
    (1.0, Space::Joint, "infeasible", "(9, 4.09, 3, 3): 146.42"),
    (
        1.0,
        Space::Actuation,
        "(6, 3, 1, 1): 161.21",
        "(9, 5.62, 3, 1.8): 71.55",
    ),
    (3.0, Space::Joint, "infeasible", "none feasible"),
    (
        3.0,
        Space::Actuation,
        "(6, 3, 1, 1): 526.45",
        "(9, 4.62, 3, 3): 159.42",
    ),
];

/// One design's outcome in the table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignCell {
    /// The design r.
    pub ratios: Vec<f64>,
    /// Whether its trajectory problem was solved.
    pub feasible: bool,
    /// Its optimal cost (meaningful when feasible).
    pub cost: f64,
    /// IPOPT status.
    pub status: String,
    /// Largest motor torque its trajectory needs, N m.
    pub max_motor_torque: f64,
    /// Largest motor speed, rad/s.
    pub max_motor_speed: f64,
    /// Whether the real motors can execute the trajectory: motor torques and speeds within the
    /// task's limits (to 1e-6 relative). A joint-space solution under the `paper` limits may not.
    pub motors_can_execute: bool,
}

/// The co-design runs of one row.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AfterCell {
    /// The best design over the seeds (None when no run found a feasible design).
    pub best: Option<DesignCell>,
    /// Best cost per seed, (seed, cost).
    pub per_seed: Vec<(u64, f64)>,
    /// Runs that stopped before their last generation: (seed, last generation run, why).
    #[serde(default)]
    pub early_stops: Vec<(u64, usize, String)>,
    /// CMA-ES evaluations over all seeds.
    pub evaluations: usize,
    /// Those that ran an inner solve (the rest broke an order constraint).
    #[serde(default)]
    pub solves: usize,
    /// Median over the runs of each run's median solve time, s.
    pub median_solve_seconds: f64,
    /// CMA-ES population and generations of the runs.
    pub population: usize,
    /// CMA-ES generations.
    pub generations: usize,
}

/// One row: a payload and a space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TableRow {
    /// Payload, kg.
    pub payload_kg: f64,
    /// Joint or actuation space.
    pub space: Space,
    /// The original design's solve.
    pub before: Option<DesignCell>,
    /// The co-design runs with CMA-ES.
    pub after: Option<AfterCell>,
    /// The co-design run with the gradient method: its best design and its inner solves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gradient: Option<(DesignCell, usize)>,
    /// Payload capacity of the original design in this space, kg (from a capacity file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capacity_before_kg: Option<f64>,
    /// Payload capacity of the best CMA-ES design, kg (from a capacity file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capacity_after_kg: Option<f64>,
    /// The design of largest capacity found by `optimize --objective capacity` in this space,
    /// and its capacity, kg (on the row of the run's payload).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capacity_max: Option<(Vec<f64>, f64)>,
    /// The paper's values.
    pub paper: Option<PaperValues>,
}

/// The whole table, as written to `paper_table.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperTable {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The linear solvers the result files were solved with, each once.
    #[serde(default)]
    pub linear_solvers: Vec<LinearSolver>,
    /// Rows by payload, then joint before actuation.
    pub rows: Vec<TableRow>,
    /// Notes shown above the table (e.g. a reduced run).
    pub notes: Vec<String>,
    /// Inner solves of the co-design runs on the trajectory cost (CMA-ES and gradient).
    pub solves: usize,
    /// Their wall times summed, s.
    pub solve_seconds: f64,
    /// Evaluations of the co-design runs on the payload capacity that ran a capacity search
    /// (each a bracketing and bisection of several solves).
    #[serde(default)]
    pub capacity_evaluations: usize,
    /// The wall times of those searches summed, s.
    #[serde(default)]
    pub capacity_seconds: f64,
}

fn cell(result: &crate::solver::TrajectoryResult, motors: &Motors) -> DesignCell {
    let within = |value: f64, limit: f64| value <= limit * (1.0 + 1e-6);
    DesignCell {
        motors_can_execute: within(result.max_motor_torque, motors.torque_limit_nm)
            && within(result.max_motor_speed, motors.speed_limit_rad_s),
        ratios: result.ratios.clone(),
        feasible: result.feasible,
        cost: result.cost,
        status: result.status.clone(),
        max_motor_torque: result.max_motor_torque,
        max_motor_speed: result.max_motor_speed,
    }
}

fn row_mut(rows: &mut Vec<TableRow>, payload_kg: f64, space: Space) -> &mut TableRow {
    let index = match rows
        .iter()
        .position(|r| r.payload_kg == payload_kg && r.space == space)
    {
        Some(index) => index,
        None => {
            let paper = PAPER
                .iter()
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
                capacity_max: None,
                paper,
            });
            rows.len() - 1
        }
    };
    &mut rows[index]
}

/// Builds the table from result files: solves of the original design give "before"; co-design
/// runs give "after" (the best over their seeds) and, if no solve did, "before" too.
pub fn build_table(files: &[ResultFile], notes: Vec<String>) -> PaperTable {
    let mut rows: Vec<TableRow> = Vec::new();
    for file in files {
        if let ResultFile::Solve(doc) = file {
            let original = &doc.inputs.task.transmission.original;
            if doc.result.ratios == *original {
                row_mut(&mut rows, doc.inputs.payload_kg, doc.inputs.space).before =
                    Some(cell(&doc.result, &doc.inputs.task.motors));
            }
        }
    }
    for file in files {
        let ResultFile::Optimize(doc) = file else {
            continue;
        };
        let row = row_mut(&mut rows, doc.inputs.payload_kg, doc.inputs.space);
        if let Objective::Capacity(_) = doc.inputs.objective {
            let capacity = -doc.best_cost;
            if row
                .capacity_max
                .as_ref()
                .is_none_or(|(_, best)| capacity > *best)
                && capacity >= 0.0
            {
                row.capacity_max = Some((doc.best_ratios.clone(), capacity));
            }
            continue;
        }
        if doc.inputs.method == Method::Gradient {
            if let Some(result) = doc.best_result.as_ref().filter(|r| r.feasible) {
                row.gradient = Some((cell(result, &doc.inputs.task.motors), doc.solves));
            }
            continue;
        }
        if row.before.is_none() {
            row.before = doc
                .original_result
                .as_ref()
                .map(|r| cell(r, &doc.inputs.task.motors));
        }
        let after = row.after.get_or_insert_with(|| AfterCell {
            best: None,
            per_seed: Vec::new(),
            early_stops: Vec::new(),
            evaluations: 0,
            solves: 0,
            median_solve_seconds: f64::NAN,
            population: doc.inputs.population,
            generations: doc.inputs.generations,
        });
        after.per_seed.push((doc.inputs.seed, doc.best_cost));
        if let Some(last) = doc.generations.last() {
            if last.generation < doc.inputs.generations {
                after
                    .early_stops
                    .push((doc.inputs.seed, last.generation, doc.stop_reason.clone()));
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
                after.best = Some(cell(result, &doc.inputs.task.motors));
            }
        }
    }
    let capacity_of = |space: Space, ratios: &[f64]| {
        files.iter().find_map(|f| match f {
            ResultFile::Capacity(d) if d.space == space && d.ratios == ratios => {
                d.capacity.capacity_kg
            }
            _ => None,
        })
    };
    for row in &mut rows {
        if let Some(before) = &row.before {
            row.capacity_before_kg = capacity_of(row.space, &before.ratios);
        }
        if let Some(best) = row.after.as_ref().and_then(|a| a.best.as_ref()) {
            row.capacity_after_kg = capacity_of(row.space, &best.ratios);
        }
        if let Some(after) = &mut row.after {
            let mut medians: Vec<f64> = files
                .iter()
                .filter_map(|f| match f {
                    ResultFile::Optimize(d)
                        if d.inputs.payload_kg == row.payload_kg
                            && d.inputs.space == row.space
                            && d.inputs.method == Method::Cmaes
                            && d.inputs.objective == Objective::Cost =>
                    {
                        Some(d.median_solve_seconds)
                    }
                    _ => None,
                })
                .collect();
            medians.sort_by(f64::total_cmp);
            after.median_solve_seconds =
                medians.get(medians.len() / 2).copied().unwrap_or(f64::NAN);
            after.per_seed.sort_by_key(|(seed, _)| *seed);
        }
    }
    rows.sort_by(|a, b| {
        a.payload_kg
            .total_cmp(&b.payload_kg)
            .then((a.space as u8).cmp(&(b.space as u8)))
    });
    let totals = |objective_is_cost: bool| {
        files
            .iter()
            .filter_map(|f| match f {
                ResultFile::Optimize(d)
                    if (d.inputs.objective == Objective::Cost) == objective_is_cost =>
                {
                    Some(d)
                }
                _ => None,
            })
            .fold((0, 0.0), |(n, s), d| {
                (n + d.solves, s + d.solve_seconds_total)
            })
    };
    let (solves, solve_seconds) = totals(true);
    let (capacity_evaluations, capacity_seconds) = totals(false);
    let linear_solvers = linear_solvers(files);
    PaperTable {
        tool: ToolInfo::current(linear_solvers.first().copied().unwrap_or_default()),
        linear_solvers,
        rows,
        notes,
        solves,
        solve_seconds,
        capacity_evaluations,
        capacity_seconds,
    }
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

fn ratios_text(ratios: &[f64]) -> String {
    let parts: Vec<String> = ratios
        .iter()
        .map(|r| format!("{}", (r * 100.0).round() / 100.0))
        .collect();
    format!("({})", parts.join(", "))
}

fn design_text(cell: &DesignCell) -> String {
    if cell.feasible && !cell.motors_can_execute {
        format!(
            "{}: {:.2}, motors cannot execute it (max torque {:.2} N m, max speed {:.0} rad/s)",
            ratios_text(&cell.ratios),
            cell.cost,
            cell.max_motor_torque,
            cell.max_motor_speed
        )
    } else if cell.feasible {
        format!("{}: {:.2}", ratios_text(&cell.ratios), cell.cost)
    } else {
        format!(
            "{}: infeasible ({})",
            ratios_text(&cell.ratios),
            cell.status
        )
    }
}

/// "linear solver ldl", or the list when result files of several are merged.
fn linear_solvers_text(solvers: &[LinearSolver]) -> String {
    let names: Vec<&str> = solvers.iter().map(|solver| solver.name()).collect();
    match names.len() {
        0 | 1 => format!(
            "linear solver {}",
            names
                .first()
                .copied()
                .unwrap_or(LinearSolver::default().name())
        ),
        _ => format!("linear solvers {}, mixed", names.join(", ")),
    }
}

impl PaperTable {
    /// The table as Markdown.
    pub fn to_markdown(&self) -> String {
        let mut text = String::from("# Table II reproduced: gear ratios and cost per payload\n\n");
        text.push_str(&format!(
            "Made by {} {} with IPOPT {} ({}). Our arm, task and horizon differ from the paper's \
             (`docs/model.md`, section 1), so our costs differ from the paper's: compare the trends, not the digits. \
             \"after\" is the best design over the seeds of CMA-ES.\n\n",
            self.tool.name,
            self.tool.version,
            self.tool.ipopt_version,
            linear_solvers_text(&self.linear_solvers)
        ));
        for note in &self.notes {
            text.push_str(&format!("> {note}\n\n"));
        }
        text.push_str(&format!(
            "> Inner solves of the co-design runs on the cost (CMA-ES and gradient): {}, taking \
             {:.2} h of solver time in all (summed over the worker processes, which run side by side).",
            self.solves,
            self.solve_seconds / 3600.0
        ));
        if self.capacity_evaluations > 0 {
            text.push_str(&format!(
                " Co-design on the payload capacity: {} evaluations, each a capacity search of \
                 several solves, {:.2} h of solver time.",
                self.capacity_evaluations,
                self.capacity_seconds / 3600.0
            ));
        }
        text.push_str("\n\n");
        text.push_str("| payload | space | before (ours) | before (paper) | after (ours) | after (paper) | seeds: best J | inner solves of evaluations | median solve |\n");
        text.push_str("|---|---|---|---|---|---|---|---|---|\n");
        for row in &self.rows {
            let before = row
                .before
                .as_ref()
                .map_or_else(|| "-".to_owned(), design_text);
            let (after, seeds, solves, median) = match &row.after {
                Some(after) => (
                    after
                        .best
                        .as_ref()
                        .map_or_else(|| "none feasible".to_owned(), design_text),
                    after
                        .per_seed
                        .iter()
                        .map(
                            |(s, c)| match after.early_stops.iter().find(|e| e.0 == *s) {
                                Some((_, last, why)) => {
                                    format!("{s}: {c:.2} (stopped after generation {last}: {why})")
                                }
                                None => format!("{s}: {c:.2}"),
                            },
                        )
                        .collect::<Vec<_>>()
                        .join(", "),
                    format!("{} of {}", after.solves, after.evaluations),
                    format!("{:.1} ms", after.median_solve_seconds * 1e3),
                ),
                None => (
                    "-".to_owned(),
                    "-".to_owned(),
                    "-".to_owned(),
                    "-".to_owned(),
                ),
            };
            let (paper_before, paper_after) = row
                .paper
                .as_ref()
                .map_or(("-", "-"), |p| (p.before.as_str(), p.after.as_str()));
            text.push_str(&format!(
                "| {} kg | {} | {before} | {paper_before} | {after} | {paper_after} | {seeds} | {solves} | {median} |\n",
                row.payload_kg, row.space
            ));
        }
        let beyond = self.rows.iter().any(|r| {
            r.gradient.is_some()
                || r.capacity_before_kg.is_some()
                || r.capacity_after_kg.is_some()
                || r.capacity_max.is_some()
        });
        if beyond {
            text.push_str(
                "\n## Beyond the paper\n\nPayload capacity (the largest payload whose trajectory problem is feasible, \
                 `codesign capacity`, to 10 g; a lower bound, as IPOPT's infeasibility verdicts are local), the design of \
                 largest capacity CMA-ES found (`codesign optimize --objective capacity`), and co-design by the gradient method (`codesign optimize --method gradient`: \
                 projected quasi-Newton on the exact dJ*/dr) beside CMA-ES.\n\n",
            );
            text.push_str("| payload | space | capacity, original design | capacity, best CMA-ES design | largest capacity found (design) | gradient method (ours) | its inner solves | CMA-ES inner solves |\n");
            text.push_str("|---|---|---|---|---|---|---|---|\n");
            let kg = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.2} kg"));
            for row in &self.rows {
                let (gradient, solves) = row
                    .gradient
                    .as_ref()
                    .map_or(("-".to_owned(), "-".to_owned()), |(cell, n)| {
                        (design_text(cell), n.to_string())
                    });
                let cmaes = row
                    .after
                    .as_ref()
                    .map_or_else(|| "-".to_owned(), |a| a.solves.to_string());
                let largest = row.capacity_max.as_ref().map_or_else(
                    || "-".to_owned(),
                    |(ratios, capacity)| format!("{capacity:.2} kg {}", ratios_text(ratios)),
                );
                text.push_str(&format!(
                    "| {} kg | {} | {} | {} | {largest} | {gradient} | {solves} | {cmaes} |\n",
                    row.payload_kg,
                    row.space,
                    kg(row.capacity_before_kg),
                    kg(row.capacity_after_kg)
                ));
            }
        }
        text
    }
}

//! The table's text (`paper_table.md`, and the table of `index.html`): a header with the tool
//! and the solver time, the paper's Table II with our values (the paper's beside them for the
//! paper's task), and the sections beyond the paper, as [`Block`]s.

use super::blocks::{to_markdown, Block};
use super::{AfterCell, DesignCell, PaperTable, RangeRow, TableRow};
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::task::Ends;
use codesign_core::problem::Space;

/// What the table's formulation asks at the ends, under the paper's ends.
const PAPER_ENDS_NOTE: &str = "The paper's formulation (`--ends paper`): q and v are fixed at the first and \
     last node, nothing else. Whether the motors could hold the payload at rest there is reported in each \
     result (`static_hold`) and never judged; the section \"holding the load at rest\" below solves the same \
     cases with it required.";

/// What the table's formulation asks at the ends, when the load must be held at rest.
const HOLD_ENDS_NOTE: &str = "Unlike the paper's formulation, a design must hold its payload at rest at the \
     start and the goal within the problem's own control limits (`--ends hold`, `docs/model.md`, section 6); \
     one that cannot is infeasible whatever IPOPT finds, and its cell names the end and the motor or joint. \
     In the joint space, the paper's torque limits G^T tau_max give a joint whose column of G sums to 0 a \
     limit of 0 N m, so no design holds that joint against gravity.";

/// What the joint-space limit modes mean for the real motors.
const MODES_NOTE: &str = "Joint-space limits: `paper` applies G^T and G^-1 elementwise to the motors' \
     limits, as the paper prints them; `interval` is the smallest box around the motors' polytope, so a \
     trajectory feasible under it can still exceed a motor; only `exact`, the motors' limits themselves as \
     linear rows, cannot. A cell says where the motors cannot execute a joint-space trajectory.";

impl PaperTable {
    /// The table as Markdown.
    pub fn to_markdown(&self) -> String {
        to_markdown(&self.blocks())
    }

    /// The table's text: its header, Table II, and the sections beyond the paper.
    pub fn blocks(&self) -> Vec<Block> {
        let mut blocks = self.header();
        let header: &[&str] = if self.paper_task {
            &[
                "payload",
                "space",
                "before (ours)",
                "before (paper)",
                "after (ours)",
                "after (paper)",
                "seeds: best J",
                "inner solves of evaluations",
                "median solve",
            ]
        } else {
            &[
                "payload",
                "space",
                "before",
                "after",
                "seeds: best J",
                "inner solves of evaluations",
                "median solve",
            ]
        };
        // A row with nothing of its own here (a capacity run's row) shows below only.
        let shown = self
            .rows
            .iter()
            .filter(|r| r.before.is_some() || r.after.is_some() || r.paper.is_some());
        let rows = shown.map(|row| main_row(row, self.paper_task)).collect();
        blocks.push(Block::grid(header, rows));
        if self.paper_task {
            blocks.extend(self.agreement_blocks());
        }
        blocks.extend(self.bounds_blocks());
        let beyond = self.rows.iter().any(|r| {
            r.gradient.is_some()
                || r.capacity_before_kg.is_some()
                || r.capacity_after_kg.is_some()
                || r.capacity_max.is_some()
        });
        if beyond || !self.ranges.is_empty() {
            blocks.extend(self.beyond_the_paper());
        }
        if !self.ranges.is_empty() {
            blocks.extend(self.payload_ranges());
        }
        blocks.extend(self.hold_blocks());
        if self
            .rows
            .iter()
            .any(|row| row.graded.is_some() || row.graded_gradient.is_some())
        {
            blocks.extend(self.graded_runs());
        }
        blocks
    }

    /// The co-design runs with the graded penalty (CMA-ES and the gradient method), one line per
    /// payload and space.
    fn graded_runs(&self) -> [Block; 2] {
        let rows = self
            .rows
            .iter()
            .filter(|row| row.graded.is_some() || row.graded_gradient.is_some())
            .map(|row| {
                let [after, seeds, solves, median] = row
                    .graded
                    .as_ref()
                    .map_or_else(|| ["-", "-", "-", "-"].map(str::to_owned), after_columns);
                let (gradient, gradient_solves) = gradient_columns(row.graded_gradient.as_ref());
                vec![
                    format!("{} kg", row.payload_kg),
                    row.space.to_string(),
                    after,
                    seeds,
                    solves,
                    median,
                    gradient,
                    gradient_solves,
                ]
            })
            .collect();
        [
            Block::Paragraph(
                "With the graded penalty (`codesign optimize --penalty graded`): every design is solved as the \
                 elastic problem, and an infeasible one scores 1e6 to 2e6 by its torque deficit and speed excess instead of a \
                 flat 1e6, so that CMA-ES moves toward feasibility (`docs/model.md`, section 10); the gradient method \
                 descends on the elastic problem's optimal objective, from infeasible starts too (section 12)."
                    .to_owned(),
            ),
            Block::grid(
                &[
                    "payload",
                    "space",
                    "CMA-ES (graded penalty)",
                    "seeds: best J",
                    "inner solves of evaluations",
                    "median solve",
                    "gradient method (graded penalty)",
                    "its inner solves",
                ],
                rows,
            ),
        ]
    }

    /// Whether every cell agrees in kind with the paper's (feasible or not, improved by
    /// co-design or not), or where and why one does not.
    fn agreement_blocks(&self) -> Vec<Block> {
        let lines = self.disagreements();
        if lines.is_empty() {
            return vec![Block::Paragraph(
                "Every cell agrees in kind with the paper's: feasible or not before and after \
                 co-design, and improved by co-design or not."
                    .to_owned(),
            )];
        }
        vec![
            Block::Paragraph(
                "Where a cell differs in kind from the paper's (feasible or not, improved by \
                 co-design or not):"
                    .to_owned(),
            ),
            Block::List(lines.into_iter().map(|line| format!("{line}.")).collect()),
        ]
    }

    /// The co-design runs for a payload range, one line each.
    fn payload_ranges(&self) -> [Block; 2] {
        [
            Block::Paragraph(
                "One design for a payload range (`codesign optimize --objective range --payloads ..`): CMA-ES on the mean \
                 optimal cost over the payloads, a design infeasible at any of them penalised."
                    .to_owned(),
            ),
            Block::grid(
                &[
                    "payloads",
                    "space",
                    "seed",
                    "design",
                    "mean J",
                    "J per payload",
                    "original design, mean J",
                    "evaluations",
                ],
                self.ranges.iter().map(range_row).collect(),
            ),
        ]
    }

    /// The title, the tool and linear solvers, the notes and the solver time.
    fn header(&self) -> Vec<Block> {
        let comparison = if self.paper_task {
            "Our arm, task and horizon differ from the paper's (`docs/model.md`, section 1), so our \
             costs differ from the paper's: compare the trends, not the digits. "
        } else {
            ""
        };
        let mut blocks = vec![
            Block::Heading(1, self.title.clone()),
            Block::Paragraph(format!(
                "Made by {} {} with IPOPT {} ({}). {comparison}\"after\" is the best design over \
                 the seeds of CMA-ES.",
                self.tool.name,
                self.tool.version,
                self.tool.ipopt_version,
                linear_solvers_text(&self.linear_solvers)
            )),
        ];
        blocks.push(Block::Note(
            match self.ends {
                Some(Ends::Paper) => PAPER_ENDS_NOTE,
                // Tables written before the choice held the load too.
                Some(Ends::Hold | Ends::Rest) | None => HOLD_ENDS_NOTE,
            }
            .to_owned(),
        ));
        if self.rows.iter().any(|row| row.space == Space::Joint) {
            blocks.push(Block::Note(MODES_NOTE.to_owned()));
        }
        blocks.extend(self.notes.iter().map(|note| Block::Note(note.clone())));
        let mut time = format!(
            "Inner solves of the co-design runs on the cost (CMA-ES and gradient): {}, taking \
             {:.2} h of solver time in all (summed over the worker processes, which run side by side).",
            self.solves,
            self.solve_seconds / 3600.0
        );
        if self.capacity_evaluations > 0 {
            time.push_str(&format!(
                " Co-design on the payload capacity: {} evaluations, each a capacity search of \
                 several solves, {:.2} h of solver time.",
                self.capacity_evaluations,
                self.capacity_seconds / 3600.0
            ));
        }
        blocks.push(Block::Note(time));
        blocks
    }

    /// The best designs on bounds of the design space, each bound named with dJ*/dr_i and what
    /// widening it would gain; nothing when none is.
    fn bounds_blocks(&self) -> Vec<Block> {
        let mut lines = Vec::new();
        for row in &self.rows {
            let cells = [
                ("CMA-ES", row.after.as_ref().and_then(|a| a.best.as_ref())),
                (
                    "gradient method",
                    row.gradient.as_ref().map(|(cell, _)| cell),
                ),
            ];
            for (method, cell) in cells {
                let Some(cell) = cell.filter(|c| !c.active_bounds.is_empty()) else {
                    continue;
                };
                lines.push(format!(
                    "{} kg, {} space, {method}, r = {}: {}.",
                    row.payload_kg,
                    row.space,
                    ratios_text(&cell.ratios),
                    cell.active_bounds.join("; ")
                ));
            }
        }
        if lines.is_empty() {
            return Vec::new();
        }
        vec![
            Block::Paragraph(
                "**Designs at their bounds.** The best designs that sit on a bound of the design \
                 space, with dJ*/dr_i there: a negative slope at an upper bound (a positive one at a \
                 lower bound) is what a wider bound would gain."
                    .to_owned(),
            ),
            Block::List(lines),
        ]
    }

    /// The section beyond the paper: capacities, the largest capacity found and the gradient
    /// method, one line per row.
    fn beyond_the_paper(&self) -> [Block; 3] {
        [
            Block::Heading(2, "Beyond the paper".to_owned()),
            Block::Paragraph(
                "Payload capacity (the largest payload whose trajectory problem is feasible, \
                 `codesign capacity`, to 10 g; a lower bound, as IPOPT's infeasibility verdicts are local), the design of \
                 largest capacity CMA-ES found (`codesign optimize --objective capacity`), and co-design by the gradient method (`codesign optimize --method gradient`: \
                 projected quasi-Newton on the exact dJ*/dr) beside CMA-ES."
                    .to_owned(),
            ),
            Block::grid(
                &[
                    "payload",
                    "space",
                    "capacity, original design",
                    "capacity, best CMA-ES design",
                    "largest capacity found (design)",
                    "gradient method (ours)",
                    "its inner solves",
                    "CMA-ES inner solves",
                ],
                self.rows.iter().map(beyond_row).collect(),
            ),
        ]
    }
}

/// One line of the payload ranges' table.
fn range_row(range: &RangeRow) -> Vec<String> {
    let payloads: Vec<String> = range.payloads_kg.iter().map(|p| format!("{p}")).collect();
    let cost = |value: f64, feasible: bool| {
        if feasible {
            format!("{value:.2}")
        } else {
            "infeasible".to_owned()
        }
    };
    let per_payload: Vec<String> = range
        .per_payload
        .iter()
        .map(|c| format!("{} kg: {}", c.payload_kg, cost(c.cost, c.feasible)))
        .collect();
    let (design, mean, per_payload) = match range.mean_cost {
        Some(mean) => (
            ratios_text(&range.ratios),
            cost(mean, true),
            per_payload.join(", "),
        ),
        None => ("none feasible".to_owned(), "-".to_owned(), "-".to_owned()),
    };
    vec![
        format!("{} kg", payloads.join(", ")),
        range.space.to_string(),
        range.seed.to_string(),
        design,
        mean,
        per_payload,
        cost(range.original_mean_cost, range.original_feasible),
        range.evaluations.to_string(),
    ]
}

/// One line of the main table, with the paper's values when `paper`.
fn main_row(row: &TableRow, paper: bool) -> Vec<String> {
    let before = row
        .before
        .as_ref()
        .map_or_else(|| "-".to_owned(), design_text);
    let [after, seeds, solves, median] = match &row.after {
        Some(after) => after_columns(after),
        None => ["-", "-", "-", "-"].map(str::to_owned),
    };
    let mut cells = vec![format!("{} kg", row.payload_kg), row.space.to_string()];
    if paper {
        let (paper_before, paper_after) = row
            .paper
            .as_ref()
            .map_or(("-", "-"), |p| (p.before.as_str(), p.after.as_str()));
        cells.extend([
            before,
            paper_before.to_owned(),
            after,
            paper_after.to_owned(),
        ]);
    } else {
        cells.extend([before, after]);
    }
    cells.extend([seeds, solves, median]);
    cells
}

/// The CMA-ES columns: the best design, each seed's best cost (with why it stopped early), the
/// inner solves of the evaluations and the median solve time.
fn after_columns(after: &AfterCell) -> [String; 4] {
    let best = after
        .best
        .as_ref()
        .map_or_else(|| "none feasible".to_owned(), design_text);
    let seeds = after
        .per_seed
        .iter()
        .map(|(s, c)| {
            let cost = c.map_or_else(|| "none feasible".to_owned(), |c| format!("{c:.2}"));
            match after.early_stops.iter().find(|e| e.0 == *s) {
                Some((_, last, why)) => {
                    format!("{s}: {cost} (stopped after generation {last}: {why})")
                }
                None => format!("{s}: {cost}"),
            }
        })
        .collect::<Vec<_>>()
        .join(", ");
    [
        best,
        seeds,
        format!("{} of {}", after.solves, after.evaluations),
        solve_time_text(after.median_solve_seconds),
    ]
}

/// A median solve time in ms, or a dash when no design was solved (NaN).
fn solve_time_text(seconds: f64) -> String {
    if seconds.is_nan() {
        "-".to_owned()
    } else {
        format!("{:.1} ms", seconds * 1e3)
    }
}

/// One line of the section beyond the paper.
fn beyond_row(row: &TableRow) -> Vec<String> {
    let kg = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.2} kg"));
    let capacity = |v: Option<f64>, held: Option<f64>| match (v, held) {
        (Some(v), Some(held)) => format!("{v:.2} kg (holds {held:.2} kg at rest)"),
        (v, _) => kg(v),
    };
    let (gradient, solves) = gradient_columns(row.gradient.as_ref());
    let cmaes = row
        .after
        .as_ref()
        .map_or_else(|| "-".to_owned(), |a| a.solves.to_string());
    let largest = row.capacity_max.as_ref().map_or_else(
        || "-".to_owned(),
        |(ratios, capacity)| format!("{capacity:.2} kg {}", ratios_text(ratios)),
    );
    vec![
        format!("{} kg", row.payload_kg),
        row.space.to_string(),
        capacity(row.capacity_before_kg, row.held_before_kg),
        capacity(row.capacity_after_kg, row.held_after_kg),
        largest,
        gradient,
        solves,
        cmaes,
    ]
}

/// A gradient run's columns: its best design and its inner solves, or dashes.
fn gradient_columns(run: Option<&(DesignCell, usize)>) -> (String, String) {
    run.map_or(("-".to_owned(), "-".to_owned()), |(cell, n)| {
        (design_text(cell), n.to_string())
    })
}

/// The ratios rounded to two decimals, e.g. `(9, 5.62, 3, 1.8)`.
pub(super) fn ratios_text(ratios: &[f64]) -> String {
    let parts: Vec<String> = ratios
        .iter()
        .map(|r| format!("{}", (r * 100.0).round() / 100.0))
        .collect();
    format!("({})", parts.join(", "))
}

/// A design's cell: its ratios and cost, or why it is infeasible or the motors cannot execute it.
pub(super) fn design_text(cell: &DesignCell) -> String {
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
            cell.reason.as_deref().unwrap_or(&cell.status)
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

#[cfg(test)]
mod tests {
    use super::{design_text, solve_time_text, DesignCell};

    fn cell(feasible: bool, motors_can_execute: bool, reason: Option<&str>) -> DesignCell {
        DesignCell {
            ratios: vec![6.0, 3.0, 1.0, 1.0],
            feasible,
            cost: 68.7377,
            status: "Solve_Succeeded".to_owned(),
            reason: reason.map(str::to_owned),
            max_motor_torque: 2.5,
            max_motor_speed: 80.0,
            motors_can_execute,
            active_bounds: Vec::new(),
        }
    }

    #[test]
    fn a_cell_says_why_a_design_is_infeasible_or_unexecutable() {
        assert_eq!(design_text(&cell(true, true, None)), "(6, 3, 1, 1): 68.74");
        assert_eq!(
            design_text(&cell(true, false, None)),
            "(6, 3, 1, 1): 68.74, motors cannot execute it (max torque 2.50 N m, max speed 80 rad/s)"
        );
        // The reason (the load not held) before IPOPT's status, which succeeded.
        let hold =
            "cannot hold the load at rest at the start: joint 4 needs 0.002541 N m (limit 0)";
        assert_eq!(
            design_text(&cell(false, true, Some(hold))),
            format!("(6, 3, 1, 1): infeasible ({hold})")
        );
        assert_eq!(
            design_text(&cell(false, true, None)),
            "(6, 3, 1, 1): infeasible (Solve_Succeeded)"
        );
    }

    #[test]
    fn no_solve_has_no_median_time() {
        assert_eq!(solve_time_text(f64::NAN), "-");
        assert_eq!(solve_time_text(0.0656), "65.6 ms");
    }
}

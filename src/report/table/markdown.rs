//! The table as Markdown (`paper_table.md`): a header with the tool and the solver time, the
//! paper's Table II with our values (the paper's beside them for the paper's task), and the
//! section beyond the paper.

use super::{AfterCell, DesignCell, PaperTable, RangeRow, TableRow};
use crate::ipopt::LinearSolver;
use crate::model::task::Ends;
use crate::problem::Space;

/// What the table's formulation asks at the ends, under the paper's ends.
const PAPER_ENDS_NOTE: &str = "> The paper's formulation (`--ends paper`): q and v are fixed at the first and \
     last node, nothing else. Whether the motors could hold the payload at rest there is reported in each \
     result (`static_hold`) and never judged; the section \"holding the load at rest\" below solves the same \
     cases with it required.\n\n";

/// What the table's formulation asks at the ends, when the load must be held at rest.
const HOLD_ENDS_NOTE: &str = "> Unlike the paper's formulation, a design must hold its payload at rest at the \
     start and the goal within the problem's own control limits (`--ends hold`, `docs/model.md`, section 6); \
     one that cannot is infeasible whatever IPOPT finds, and its cell names the end and the motor or joint. \
     In the joint space, the paper's torque limits G^T tau_max give a joint whose column of G sums to 0 a \
     limit of 0 N m, so no design holds that joint against gravity.\n\n";

/// What the joint-space limit modes mean for the real motors.
const MODES_NOTE: &str = "> Joint-space limits: `paper` applies G^T and G^-1 elementwise to the motors' \
     limits, as the paper prints them; `interval` is the smallest box around the motors' polytope, so a \
     trajectory feasible under it can still exceed a motor; only `exact`, the motors' limits themselves as \
     linear rows, cannot. A cell says where the motors cannot execute a joint-space trajectory.\n\n";

impl PaperTable {
    /// The table as Markdown.
    pub fn to_markdown(&self) -> String {
        let mut text = self.header();
        if self.paper_task {
            text.push_str("| payload | space | before (ours) | before (paper) | after (ours) | after (paper) | seeds: best J | inner solves of evaluations | median solve |\n");
            text.push_str("|---|---|---|---|---|---|---|---|---|\n");
        } else {
            text.push_str("| payload | space | before | after | seeds: best J | inner solves of evaluations | median solve |\n");
            text.push_str("|---|---|---|---|---|---|---|\n");
        }
        // A row with nothing of its own here (a capacity run's row) shows below only.
        let shown = self
            .rows
            .iter()
            .filter(|r| r.before.is_some() || r.after.is_some() || r.paper.is_some());
        for row in shown {
            text.push_str(&main_row(row, self.paper_task));
        }
        if self.paper_task {
            text.push_str(&self.agreement_text());
        }
        text.push_str(&self.bounds_text());
        let beyond = self.rows.iter().any(|r| {
            r.gradient.is_some()
                || r.capacity_before_kg.is_some()
                || r.capacity_after_kg.is_some()
                || r.capacity_max.is_some()
        });
        if beyond || !self.ranges.is_empty() {
            text.push_str(&self.beyond_the_paper());
        }
        if !self.ranges.is_empty() {
            text.push_str(&self.payload_ranges());
        }
        text.push_str(&self.hold_markdown());
        if self
            .rows
            .iter()
            .any(|row| row.graded.is_some() || row.graded_gradient.is_some())
        {
            text.push_str(&self.graded_runs());
        }
        text
    }

    /// The co-design runs with the graded penalty (CMA-ES and the gradient method), one line per
    /// payload and space.
    fn graded_runs(&self) -> String {
        let mut text = String::from(
            "\nWith the graded penalty (`codesign optimize --penalty graded`): every design is solved as the \
             elastic problem, and an infeasible one scores 1e6 to 2e6 by its torque deficit and speed excess instead of a \
             flat 1e6, so that CMA-ES moves toward feasibility (`docs/model.md`, section 10); the gradient method \
             descends on the elastic problem's optimal objective, from infeasible starts too (section 12).\n\n\
             | payload | space | CMA-ES (graded penalty) | seeds: best J | inner solves of evaluations | median solve | gradient method (graded penalty) | its inner solves |\n\
             |---|---|---|---|---|---|---|---|\n",
        );
        for row in &self.rows {
            if row.graded.is_none() && row.graded_gradient.is_none() {
                continue;
            }
            let [after, seeds, solves, median] = row.graded.as_ref().map_or_else(
                || {
                    [
                        "-".to_owned(),
                        "-".to_owned(),
                        "-".to_owned(),
                        "-".to_owned(),
                    ]
                },
                after_columns,
            );
            let (gradient, gradient_solves) = gradient_columns(row.graded_gradient.as_ref());
            text.push_str(&format!(
                "| {} kg | {} | {after} | {seeds} | {solves} | {median} | {gradient} | {gradient_solves} |\n",
                row.payload_kg, row.space
            ));
        }
        text
    }

    /// Whether every cell agrees in kind with the paper's (feasible or not, improved by
    /// co-design or not), or where and why one does not.
    fn agreement_text(&self) -> String {
        let lines = self.disagreements();
        if lines.is_empty() {
            return "\nEvery cell agrees in kind with the paper's: feasible or not before and after \
                    co-design, and improved by co-design or not.\n"
                .to_owned();
        }
        let mut text = String::from(
            "\nWhere a cell differs in kind from the paper's (feasible or not, improved by co-design \
             or not):\n\n",
        );
        for line in lines {
            text.push_str(&format!("- {line}.\n"));
        }
        text
    }

    /// The co-design runs for a payload range, one line each.
    fn payload_ranges(&self) -> String {
        let mut text = String::from(
            "\nOne design for a payload range (`codesign optimize --objective range --payloads ..`): CMA-ES on the mean \
             optimal cost over the payloads, a design infeasible at any of them penalised.\n\n\
             | payloads | space | seed | design | mean J | J per payload | original design, mean J | evaluations |\n\
             |---|---|---|---|---|---|---|---|\n",
        );
        for range in &self.ranges {
            text.push_str(&range_row(range));
        }
        text
    }

    /// The title, the tool and linear solvers, the notes and the solver time, each a paragraph.
    fn header(&self) -> String {
        let mut text = format!("# {}\n\n", one_line(&self.title));
        let comparison = if self.paper_task {
            "Our arm, task and horizon differ from the paper's (`docs/model.md`, section 1), so our \
             costs differ from the paper's: compare the trends, not the digits. "
        } else {
            ""
        };
        text.push_str(&format!(
            "Made by {} {} with IPOPT {} ({}). {comparison}\"after\" is the best design over the \
             seeds of CMA-ES.\n\n",
            self.tool.name,
            self.tool.version,
            self.tool.ipopt_version,
            linear_solvers_text(&self.linear_solvers)
        ));
        match self.ends {
            Some(Ends::Paper) => text.push_str(PAPER_ENDS_NOTE),
            // Tables written before the choice held the load too.
            Some(Ends::Hold | Ends::Rest) | None => text.push_str(HOLD_ENDS_NOTE),
        }
        if self.rows.iter().any(|row| row.space == Space::Joint) {
            text.push_str(MODES_NOTE);
        }
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
        text
    }

    /// The best designs on bounds of the design space, each bound named with dJ*/dr_i and what
    /// widening it would gain; empty when none is.
    fn bounds_text(&self) -> String {
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
                    "- {} kg, {} space, {method}, r = {}: {}.\n",
                    row.payload_kg,
                    row.space,
                    ratios_text(&cell.ratios),
                    cell.active_bounds.join("; ")
                ));
            }
        }
        if lines.is_empty() {
            return String::new();
        }
        format!(
            "\n**Designs at their bounds.** The best designs that sit on a bound of the design \
             space, with dJ*/dr_i there: a negative slope at an upper bound (a positive one at a \
             lower bound) is what a wider bound would gain.\n\n{}",
            lines.concat()
        )
    }

    /// The section beyond the paper: capacities, the largest capacity found and the gradient
    /// method, one line per row.
    fn beyond_the_paper(&self) -> String {
        let mut text = String::from(
            "\n## Beyond the paper\n\nPayload capacity (the largest payload whose trajectory problem is feasible, \
             `codesign capacity`, to 10 g; a lower bound, as IPOPT's infeasibility verdicts are local), the design of \
             largest capacity CMA-ES found (`codesign optimize --objective capacity`), and co-design by the gradient method (`codesign optimize --method gradient`: \
             projected quasi-Newton on the exact dJ*/dr) beside CMA-ES.\n\n",
        );
        text.push_str("| payload | space | capacity, original design | capacity, best CMA-ES design | largest capacity found (design) | gradient method (ours) | its inner solves | CMA-ES inner solves |\n");
        text.push_str("|---|---|---|---|---|---|---|---|\n");
        for row in &self.rows {
            text.push_str(&beyond_row(row));
        }
        text
    }
}

/// One line of the payload ranges' table.
fn range_row(range: &RangeRow) -> String {
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
    let found = !range.ratios.is_empty();
    format!(
        "| {} kg | {} | {} | {} | {} | {} | {} | {} |\n",
        payloads.join(", "),
        range.space,
        range.seed,
        if found {
            ratios_text(&range.ratios)
        } else {
            "none feasible".to_owned()
        },
        if found {
            cost(range.mean_cost, true)
        } else {
            "-".to_owned()
        },
        if found {
            per_payload.join(", ")
        } else {
            "-".to_owned()
        },
        cost(range.original_mean_cost, range.original_feasible),
        range.evaluations
    )
}

/// One line of the main table, with the paper's values when `paper`.
fn main_row(row: &TableRow, paper: bool) -> String {
    let before = row
        .before
        .as_ref()
        .map_or_else(|| "-".to_owned(), design_text);
    let [after, seeds, solves, median] = match &row.after {
        Some(after) => after_columns(after),
        None => ["-", "-", "-", "-"].map(str::to_owned),
    };
    let (paper_before, paper_after) = row
        .paper
        .as_ref()
        .map_or(("-", "-"), |p| (p.before.as_str(), p.after.as_str()));
    let (before, after) = if paper {
        (
            format!("{before} | {paper_before}"),
            format!("{after} | {paper_after}"),
        )
    } else {
        (before, after)
    };
    format!(
        "| {} kg | {} | {before} | {after} | {seeds} | {solves} | {median} |\n",
        row.payload_kg, row.space
    )
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
        .map(
            |(s, c)| match after.early_stops.iter().find(|e| e.0 == *s) {
                Some((_, last, why)) => {
                    format!("{s}: {c:.2} (stopped after generation {last}: {why})")
                }
                None => format!("{s}: {c:.2}"),
            },
        )
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
fn beyond_row(row: &TableRow) -> String {
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
    format!(
        "| {} kg | {} | {} | {} | {largest} | {gradient} | {solves} | {cmaes} |\n",
        row.payload_kg,
        row.space,
        capacity(row.capacity_before_kg, row.held_before_kg),
        capacity(row.capacity_after_kg, row.held_after_kg)
    )
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
            one_line(cell.reason.as_deref().unwrap_or(&cell.status))
        )
    }
}

/// `text` kept on one line of Markdown (a heading, a table cell): each control character (a
/// newline in a file's name) written as its escape, `\n`, `\t`, `\u{7}`; a `|` escaped so that
/// it splits no cell.
fn one_line(text: &str) -> String {
    let mut line = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '|' => line.push_str("\\|"),
            c if c.is_control() => line.extend(c.escape_default()),
            c => line.push(c),
        }
    }
    line
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
    use super::{design_text, one_line, solve_time_text, DesignCell};

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
    fn a_name_or_reason_stays_on_its_line() {
        // Issue 38, item 16: a task file named with a newline broke the table's title.
        assert_eq!(one_line("tasks/a\nb.json"), "tasks/a\\nb.json");
        assert_eq!(one_line("a|b\tc\u{7}"), "a\\|b\\tc\\u{7}");
        assert_eq!(one_line("pick_place é.json"), "pick_place é.json");
        let reason = "line one\n| forged | row |";
        let text = design_text(&cell(false, true, Some(reason)));
        assert!(!text.contains('\n') && !text.contains(" | "), "{text}");
    }

    #[test]
    fn no_solve_has_no_median_time() {
        assert_eq!(solve_time_text(f64::NAN), "-");
        assert_eq!(solve_time_text(0.0656), "65.6 ms");
    }
}

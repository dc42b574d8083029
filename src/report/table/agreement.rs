//! Whether each Table II cell agrees in kind with the paper's: feasible or not before co-design
//! and after it, and improved by co-design or not; and, where a cell does not, why.

use super::{DesignCell, PaperTable, TableRow};
use codesign_core::problem::Space;

/// What a cell says, in kind.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// A feasible design with its cost J.
    Feasible(f64),
    /// No feasible design.
    Infeasible,
    /// Not part of the table (a case the paper does not co-design).
    Absent,
}

impl Kind {
    /// The kind of one of the paper's cells: `(6, 3, 1, 1): 161.21`, `infeasible`, `none
    /// feasible` or `-`.
    fn of_paper(text: &str) -> Kind {
        match text.rsplit_once(": ") {
            Some((_, cost)) => cost.parse().map_or(Kind::Absent, Kind::Feasible),
            None if text.contains("infeasible") || text.contains("none feasible") => {
                Kind::Infeasible
            }
            None => Kind::Absent,
        }
    }

    /// The kind of one of our cells.
    fn of_ours(cell: Option<&DesignCell>, present: bool) -> Kind {
        match cell {
            Some(cell) if cell.feasible => Kind::Feasible(cell.cost),
            Some(_) => Kind::Infeasible,
            None if present => Kind::Infeasible,
            None => Kind::Absent,
        }
    }

    fn feasible(self) -> bool {
        matches!(self, Kind::Feasible(_))
    }
}

/// Whether co-design improved on the original design: a feasible design after an infeasible
/// one, or a lower cost (None where the case is not co-designed).
fn improved(before: Kind, after: Kind) -> Option<bool> {
    match (before, after) {
        (_, Kind::Absent) => None,
        (Kind::Feasible(b), Kind::Feasible(a)) => Some(a < b),
        (_, Kind::Feasible(_)) => Some(true),
        _ => Some(false),
    }
}

impl PaperTable {
    /// One line per Table II cell that differs in kind from the paper's, saying why; empty
    /// when every cell agrees or the table is not of the paper's task.
    pub(super) fn disagreements(&self) -> Vec<String> {
        let mut lines = Vec::new();
        for row in &self.rows {
            let Some(paper) = &row.paper else { continue };
            let best = row.after.as_ref().and_then(|after| after.best.as_ref());
            let ours = (
                Kind::of_ours(row.before.as_ref(), true),
                Kind::of_ours(best, row.after.is_some()),
            );
            let theirs = (Kind::of_paper(&paper.before), Kind::of_paper(&paper.after));
            let case = format!("{} kg, {} space", row.payload_kg, row.space);
            for (which, mine, paper_kind, cell) in [
                ("before", ours.0, theirs.0, row.before.as_ref()),
                ("after", ours.1, theirs.1, best),
            ] {
                if paper_kind != Kind::Absent && mine.feasible() != paper_kind.feasible() {
                    lines.push(format!("{case}, {which}: {}", why(row, mine, cell)));
                }
            }
            let (mine, paper) = (improved(ours.0, ours.1), improved(theirs.0, theirs.1));
            if let (Some(mine), Some(paper)) = (mine, paper) {
                if mine != paper {
                    let word = |improved: bool| {
                        if improved {
                            "improves"
                        } else {
                            "does not improve"
                        }
                    };
                    lines.push(format!(
                        "{case}: co-design {} on the original design here and {} in the paper; our \
                         arm, task and horizon differ from the paper's (`docs/model.md`, section 1)",
                        word(mine),
                        word(paper)
                    ));
                }
            }
        }
        lines
    }
}

/// Why our cell `cell` of kind `mine` differs in feasibility from the paper's.
fn why(row: &TableRow, mine: Kind, cell: Option<&DesignCell>) -> String {
    match (mine, cell) {
        (Kind::Feasible(_), Some(cell))
            if row.space == Space::Joint && !cell.motors_can_execute =>
        {
            format!(
                "feasible here and not in the paper. The joint-space problem bounds the joints by \
                 the paper's limits G^T tau_max, not the motors: our trajectory stays within them, \
                 but the motors cannot execute it (peak motor torque {:.2} N m); the paper's \
                 solves of this case failed on an arm whose masses and horizon differ from ours \
                 (`docs/model.md`, section 1)",
                cell.max_motor_torque
            )
        }
        (Kind::Feasible(_), _) => "feasible here and not in the paper: our arm, task and horizon \
             differ from the paper's (`docs/model.md`, section 1)"
            .to_owned(),
        (_, Some(cell)) => format!(
            "infeasible here and feasible in the paper: our arm (its links' masses, \
             `docs/model.md`, section 1) asks more of the motors ({})",
            cell.reason.as_deref().unwrap_or(&cell.status)
        ),
        _ => "no feasible design here, one in the paper: our arm, task and horizon differ from \
              the paper's (`docs/model.md`, section 1)"
            .to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::{improved, Kind};

    #[test]
    fn the_papers_cells_read_as_kinds() {
        assert_eq!(
            Kind::of_paper("(6, 3, 1, 1): 161.21"),
            Kind::Feasible(161.21)
        );
        assert_eq!(Kind::of_paper("infeasible"), Kind::Infeasible);
        assert_eq!(Kind::of_paper("none feasible"), Kind::Infeasible);
        assert_eq!(Kind::of_paper("-"), Kind::Absent);
        assert_eq!(
            improved(Kind::Infeasible, Kind::Feasible(146.42)),
            Some(true)
        );
        assert_eq!(
            improved(Kind::Feasible(161.21), Kind::Feasible(71.55)),
            Some(true)
        );
        assert_eq!(improved(Kind::Infeasible, Kind::Infeasible), Some(false));
        assert_eq!(improved(Kind::Feasible(66.77), Kind::Absent), None);
    }
}

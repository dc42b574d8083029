//! Beyond the paper: Table II's cases with the load held at rest (`motion.ends` `hold`) beside
//! the paper's formulation, and what holding costs: the best design, its J and its capacity
//! under each.

use super::blocks::Block;
use super::markdown::{design_text, ratios_text};
use super::{DesignCell, PaperTable, TableRow};
use codesign_core::problem::Space;
use serde::{Deserialize, Serialize};

/// One case of Table II under `hold`, beside the same case under the paper's ends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HoldRow {
    /// Payload, kg.
    pub payload_kg: f64,
    /// Joint or actuation space.
    pub space: Space,
    /// The original design under `hold`.
    pub before: Option<DesignCell>,
    /// The best CMA-ES design under `hold` (None: no run found one, or the case is not
    /// co-designed).
    pub after: Option<DesignCell>,
    /// Whether the case is co-designed.
    pub codesigned: bool,
    /// The capacity under `hold` of the best design, kg.
    pub capacity_after_kg: Option<f64>,
    /// The best design under the paper's ends and its J (None: none feasible).
    pub paper_after: Option<DesignCell>,
    /// The capacity under the paper's ends of that design, kg, and the load it holds at rest.
    pub paper_capacity_after_kg: Option<f64>,
    /// The load the paper's best design holds at rest at both ends, kg.
    pub paper_held_after_kg: Option<f64>,
}

impl HoldRow {
    /// The row of `hold`, a row of the table under `hold`, beside `paper`, the same case's row
    /// under the paper's ends (if the table has it).
    fn of(hold: &TableRow, paper: Option<&TableRow>) -> HoldRow {
        let paper_after = paper.and_then(|row| row.after.as_ref()?.best.clone());
        HoldRow {
            payload_kg: hold.payload_kg,
            space: hold.space,
            before: hold.before.clone(),
            after: hold.after.as_ref().and_then(|a| a.best.clone()),
            codesigned: hold.after.is_some(),
            capacity_after_kg: hold.capacity_after_kg,
            paper_after,
            paper_capacity_after_kg: paper.and_then(|row| row.capacity_after_kg),
            paper_held_after_kg: paper.and_then(|row| row.held_after_kg),
        }
    }
}

impl PaperTable {
    /// Adds `hold`, the table of the same cases solved under `hold`, as the section on holding
    /// the load at rest.
    pub fn add_hold_section(&mut self, hold: &PaperTable) {
        self.hold = hold
            .rows
            .iter()
            .filter(|row| row.before.is_some() || row.after.is_some())
            .map(|row| {
                let paper = self
                    .rows
                    .iter()
                    .find(|r| r.payload_kg == row.payload_kg && r.space == row.space);
                HoldRow::of(row, paper)
            })
            .collect();
    }

    /// The section on holding the load at rest (nothing without hold rows).
    pub(super) fn hold_blocks(&self) -> Vec<Block> {
        if self.hold.is_empty() {
            return Vec::new();
        }
        vec![
            Block::Heading(2, "Beyond the paper: holding the load at rest".to_owned()),
            Block::Paragraph(
                "The same cases with `--ends hold` (results in `hold/`): the motors must also hold \
                 the payload at rest at the start and the goal within the problem's own control \
                 limits (`docs/model.md`, section 6), which the paper's formulation does not ask. \
                 \"Cost of holding\" is J of the best design under `hold` less J of the best \
                 design under the paper's ends; the capacities are the best designs' dynamic \
                 capacities under each formulation, with the load each holds at rest."
                    .to_owned(),
            ),
            Block::grid(
                &[
                    "payload",
                    "space",
                    "before (hold)",
                    "after (hold)",
                    "cost of holding",
                    "capacity of the best design: paper",
                    "hold",
                ],
                self.hold.iter().map(hold_line).collect(),
            ),
        ]
    }
}

/// One line of the hold section.
fn hold_line(row: &HoldRow) -> Vec<String> {
    let dash = || "-".to_owned();
    let before = row.before.as_ref().map_or_else(dash, design_text);
    let after = match (&row.after, row.codesigned) {
        (Some(cell), _) => design_text(cell),
        (None, true) => "none feasible".to_owned(),
        (None, false) => dash(),
    };
    let cost = match (&row.after, &row.paper_after) {
        (Some(hold), Some(paper)) => format!(
            "{:+.2} (paper's best {}: {:.2})",
            hold.cost - paper.cost,
            ratios_text(&paper.ratios),
            paper.cost
        ),
        (None, Some(_)) if row.codesigned => "no design holds the load".to_owned(),
        _ => dash(),
    };
    let kg = |v: Option<f64>| v.map_or_else(dash, |v| format!("{v:.2} kg"));
    let paper_capacity = match (row.paper_capacity_after_kg, row.paper_held_after_kg) {
        (Some(kg), Some(held)) => format!("{kg:.2} kg (holds {held:.2} kg at rest)"),
        (capacity, _) => kg(capacity),
    };
    vec![
        format!("{} kg", row.payload_kg),
        row.space.to_string(),
        before,
        after,
        cost,
        paper_capacity,
        kg(row.capacity_after_kg),
    ]
}

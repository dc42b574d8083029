//! The front of a search over parts drawn (`pareto.svg`): actuator mass against the
//! objective, the front's points joined and each named by its parts, the dominated points
//! faded, the infeasible combinations listed in the caption; and `pareto.json` written with it.

use super::plots::{Chart, Figure, Series};
use crate::design::parts::{ParetoDocument, PartsObjective, PartsPoint};
use crate::store::document::write_document;
use codesign_core::text::rounded;
use std::path::Path;

/// The file names of a search's front and its plot in its folder.
pub const PARETO_JSON: &str = "pareto.json";
/// The plot beside it.
pub const PARETO_SVG: &str = "pareto.svg";

/// The most infeasible combinations the caption names; the rest are counted.
const NAMED_INFEASIBLE: usize = 4;

/// Writes `document` as `pareto.json` in `dir` (whole or not at all) and its plot beside it as
/// `pareto.svg`.
pub fn write_pareto(dir: &Path, document: &ParetoDocument) -> Result<(), String> {
    write_document(&dir.join(PARETO_JSON), document).map_err(|e| e.to_string())?;
    pareto_chart(document)
        .write(&dir.join(PARETO_SVG))
        .map_err(|e| e.to_string())
}

/// The plot of `document`: x the actuator mass (kg), y the objective; the front joined by a
/// line, each of its points a disc named by its parts and numbers; the dominated points
/// faded dots.
pub fn pareto_chart(document: &ParetoDocument) -> Chart {
    let y = &document.axes.y;
    let unit = |value: f64| match y.unit.as_str() {
        "" => rounded(value).to_string(),
        unit => format!("{} {unit}", rounded(value)),
    };
    let placed = |points: &[PartsPoint]| -> Vec<(f64, f64)> {
        points.iter().filter_map(PartsPoint::placed).collect()
    };
    let mut series = vec![Series::line("the front", placed(&document.points))];
    for point in &document.points {
        if let Some((mass, value)) = point.placed() {
            let name = format!(
                "{mass:.3} kg, {}: {}",
                unit(value),
                parts_text(&point.parts)
            );
            series.push(Series::points(name, vec![(mass, value)]));
        }
    }
    let dominated = placed(&document.dominated);
    if !dominated.is_empty() {
        series.push(Series::dots("dominated", dominated));
    }
    let inputs = &document.inputs;
    let objective = match inputs.objective {
        PartsObjective::Cost => "J*",
        PartsObjective::Capacity => "payload capacity",
        PartsObjective::Time => "T*",
    };
    let better = match y.better {
        crate::design::parts::Better::Lower => "lower",
        crate::design::parts::Better::Higher => "higher",
    };
    let mut title = format!(
        "Actuator mass against {objective} ({better} is better), {} space, {} kg",
        inputs.space,
        rounded(inputs.payload_kg)
    );
    if !document.infeasible.is_empty() {
        title.push_str(&format!(
            "; infeasible: {}",
            infeasible_text(&document.infeasible)
        ));
    }
    Chart {
        title,
        x_label: "actuator mass (kg)".to_owned(),
        y_label: match y.unit.as_str() {
            "" => y.quantity.clone(),
            unit => format!("{} ({unit})", y.quantity),
        },
        series,
        guides: Vec::new(),
        log_y: false,
    }
}

/// A combination's parts, runs of one part written once with their count (`2 x A, B, B'`).
fn parts_text(parts: &[String]) -> String {
    let mut runs: Vec<(usize, &str)> = Vec::new();
    for part in parts {
        match runs.last_mut() {
            Some((count, last)) if *last == part.as_str() => *count += 1,
            _ => runs.push((1, part)),
        }
    }
    let each: Vec<String> = (runs.iter())
        .map(|&(count, part)| match count {
            1 => part.to_owned(),
            _ => format!("{count} x {part}"),
        })
        .collect();
    each.join(", ")
}

/// The infeasible combinations in words, the first few named and the rest counted.
fn infeasible_text(points: &[PartsPoint]) -> String {
    let named: Vec<String> = (points.iter().take(NAMED_INFEASIBLE))
        .map(|p| format!("[{}]", parts_text(&p.parts)))
        .collect();
    match points.len().saturating_sub(NAMED_INFEASIBLE) {
        0 => named.join(", "),
        more => format!("{} and {more} more", named.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_are_counted_in_runs() {
        let parts = ["A", "A", "B", "A"].map(str::to_owned);
        assert_eq!(parts_text(&parts), "2 x A, B, A");
    }
}

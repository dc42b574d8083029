//! The document of a search over parts (`pareto.json`, schema `codesign/pareto`): what was
//! searched, one record per combination of parts, and the front of actuator mass against the
//! objective; [`check_front`] checks a document's front against its own points.

use super::pareto::{dominates, front, Better};
use crate::design::run::RecordedHash;
use crate::store::document::read_document;
use codesign_core::problem::Space;
use codesign_core::solve::ToolInfo;
use serde::{Deserialize, Serialize};

/// What each combination's design is judged by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PartsObjective {
    /// The optimal trajectory cost J* at the payload, which the gradient method minimises.
    Cost,
    /// The payload capacity, kg, of the design the gradient method finds for the cost at the
    /// payload (the capacity is not differentiable in r).
    Capacity,
    /// The least duration T* of the motion, s, which the gradient method minimises.
    Time,
}

impl PartsObjective {
    /// The objective's axis: what its value is, its unit and which way it is better.
    pub fn axis(self) -> Axis {
        let (quantity, unit, better) = match self {
            PartsObjective::Cost => ("optimal trajectory cost J*", "", Better::Lower),
            PartsObjective::Capacity => ("payload capacity", "kg", Better::Higher),
            PartsObjective::Time => ("least duration T* of the motion", "s", Better::Lower),
        };
        Axis {
            key: "value".to_owned(),
            quantity: quantity.to_owned(),
            unit: unit.to_owned(),
            better,
        }
    }
}

/// One axis of the front: the point's field that gives it, in words, its unit, its direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// The field of a point holding the value: `actuator_mass_kg` or `value`.
    pub key: String,
    /// What it is, in words.
    pub quantity: String,
    /// Its unit ("" for none).
    pub unit: String,
    /// Which way it is better: `lower` or `higher`.
    pub better: Better,
}

impl Axis {
    /// The actuator mass's axis, better lower.
    pub fn mass() -> Axis {
        Axis {
            key: "actuator_mass_kg".to_owned(),
            quantity: "actuator mass (motors and carried parts)".to_owned(),
            unit: "kg".to_owned(),
            better: Better::Lower,
        }
    }
}

/// The two axes of the front.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axes {
    /// The actuator mass, kg.
    pub x: Axis,
    /// The objective's value.
    pub y: Axis,
}

/// What defined the search.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParetoInputs {
    /// The task file with candidates, as given.
    pub task_file: String,
    /// The family's hash: FNV-1a of its combinations' task hashes, in order, joined by commas
    /// (each combination's own is in its point).
    pub task_hash: RecordedHash,
    /// Joint or actuation space.
    pub space: Space,
    /// The payload the designs are co-designed at, kg.
    pub payload_kg: f64,
    /// What judges a design.
    pub objective: PartsObjective,
    /// Iterations per start of the gradient method.
    pub gradient_iterations: usize,
}

/// One combination of parts, co-designed in its ratios.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartsPoint {
    /// Each motor slot's part, by its catalogue name, in G's order.
    pub parts: Vec<String>,
    /// The combination's co-design result (`codesign/optimize`), beside `pareto.json`; null
    /// where the gradient method found no feasible start to descend from (the flat penalty),
    /// and so wrote none.
    pub file: Option<String>,
    /// The task hash of the combination's task.
    pub task_hash: String,
    /// The motors' mass, kg, which orders the search.
    pub motor_mass_kg: f64,
    /// Whether the gradient method found a feasible design (and, for the capacity, it carries
    /// a payload).
    pub feasible: bool,
    /// The best design r* (empty when none is feasible).
    pub ratios: Vec<f64>,
    /// The actuators' mass at r*, kg: the motors and the parts the links carry (null when no
    /// design is feasible).
    pub actuator_mass_kg: Option<f64>,
    /// The objective's value at r*: J*, the capacity in kg or T* in s (null when infeasible).
    pub value: Option<f64>,
    /// Inner solves (the gradient method's, and a capacity search's probes).
    pub solves: usize,
    /// IPOPT iterations of those solves.
    pub iterations: usize,
    /// Wall time of the combination's co-design (and capacity search), s.
    pub wall_seconds: f64,
    /// Why the gradient method stopped.
    pub stop_reason: String,
}

impl PartsPoint {
    /// (actuator mass, value) where both are known and the point is feasible.
    pub fn placed(&self) -> Option<(f64, f64)> {
        match (self.feasible, self.actuator_mass_kg, self.value) {
            (true, Some(mass), Some(value)) => Some((mass, value)),
            _ => None,
        }
    }
}

/// The file `codesign parts` writes as `pareto.json` (schema `codesign/pareto`, version 1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParetoDocument {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// What was searched.
    pub inputs: ParetoInputs,
    /// The axes: x the actuator mass, y the objective, each with its direction.
    pub axes: Axes,
    /// The non-dominated feasible combinations, by increasing actuator mass.
    pub points: Vec<PartsPoint>,
    /// The other feasible combinations, in the order searched.
    pub dominated: Vec<PartsPoint>,
    /// The combinations with no feasible design, in the order searched.
    pub infeasible: Vec<PartsPoint>,
}

impl crate::store::document::Document for ParetoDocument {
    const SCHEMA: crate::store::document::Schema = crate::store::document::Schema::Pareto;
}

impl ParetoDocument {
    /// The document of the combinations `searched` (in the order searched), their front taken.
    pub fn new(tool: ToolInfo, inputs: ParetoInputs, searched: Vec<PartsPoint>) -> Self {
        let axes = Axes {
            x: Axis::mass(),
            y: inputs.objective.axis(),
        };
        let (placed, infeasible): (Vec<PartsPoint>, Vec<PartsPoint>) =
            searched.into_iter().partition(|p| p.placed().is_some());
        let xy: Vec<(f64, f64)> = placed.iter().filter_map(PartsPoint::placed).collect();
        let (kept, dominated) = front(&xy, axes.y.better);
        let pick = |indices: Vec<usize>| indices.into_iter().map(|i| placed[i].clone()).collect();
        ParetoDocument {
            tool,
            inputs,
            points: pick(kept),
            dominated: pick(dominated),
            axes,
            infeasible,
        }
    }
}

/// Checks the front of `document` against its own points: every point of `points` feasible
/// and placed, and dominated by no other point of `points` or `dominated`; every point of
/// `dominated` dominated by one of `points`; every point of `infeasible` without a placed
/// design. The error names the point by its parts. Returns the number of points on the front.
pub fn check_front(document: &ParetoDocument) -> Result<usize, String> {
    let better = document.axes.y.better;
    let named = |p: &PartsPoint| format!("[{}]", p.parts.join(", "));
    let place = |p: &PartsPoint| {
        p.placed()
            .ok_or_else(|| format!("{} is not feasible with a mass and a value", named(p)))
    };
    let points: Vec<(f64, f64)> = document
        .points
        .iter()
        .map(place)
        .collect::<Result<_, _>>()?;
    let dominated: Vec<(f64, f64)> = (document.dominated.iter())
        .map(place)
        .collect::<Result<_, _>>()?;
    for (p, &at) in document.points.iter().zip(&points) {
        let all = points
            .iter()
            .chain(&dominated)
            .zip(document.points.iter().chain(&document.dominated));
        if let Some((_, by)) = all
            .into_iter()
            .find(|(&other, _)| dominates(other, at, better))
        {
            return Err(format!(
                "{} on the front is dominated by {}",
                named(p),
                named(by)
            ));
        }
    }
    for (p, &at) in document.dominated.iter().zip(&dominated) {
        if !points.iter().any(|&other| dominates(other, at, better)) {
            return Err(format!(
                "{} is listed as dominated, but no point of the front dominates it",
                named(p)
            ));
        }
    }
    if let Some(p) = document.infeasible.iter().find(|p| p.placed().is_some()) {
        return Err(format!(
            "{} is listed as infeasible, but has a feasible design",
            named(p)
        ));
    }
    Ok(points.len())
}

/// Reads the `pareto.json` at `path` and checks its front ([`check_front`]); the number of
/// points on the front. The error names the file.
pub fn check_front_file(path: &std::path::Path) -> Result<usize, String> {
    let named = |why: String| format!("{}: {why}", path.display());
    let document = read_document::<ParetoDocument>(path).map_err(named)?;
    check_front(&document).map_err(named)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(parts: &str, mass: f64, value: Option<f64>) -> PartsPoint {
        PartsPoint {
            parts: vec![parts.to_owned()],
            file: Some(format!("{parts}.json")),
            task_hash: "0".to_owned(),
            motor_mass_kg: mass,
            feasible: value.is_some(),
            ratios: vec![1.0],
            actuator_mass_kg: Some(mass),
            value,
            solves: 1,
            iterations: 1,
            wall_seconds: 0.0,
            stop_reason: String::new(),
        }
    }

    fn document(objective: PartsObjective, searched: Vec<PartsPoint>) -> ParetoDocument {
        let inputs = ParetoInputs {
            task_file: "t.json".to_owned(),
            task_hash: RecordedHash(None),
            space: Space::Actuation,
            payload_kg: 1.0,
            objective,
            gradient_iterations: 1,
        };
        ParetoDocument::new(ToolInfo::current(Default::default()), inputs, searched)
    }

    /// The document sorts its combinations into front, dominated and infeasible, and the
    /// checker accepts it; a front point moved among the dominated (or back) is refused.
    #[test]
    fn the_document_passes_its_own_check() {
        let searched = vec![
            point("a", 1.0, Some(3.0)),
            point("b", 2.0, Some(4.0)),
            point("c", 1.5, None),
            point("d", 3.0, Some(1.0)),
        ];
        let mut cost = document(PartsObjective::Cost, searched.clone());
        let parts = |points: &[PartsPoint]| -> Vec<String> {
            points.iter().map(|p| p.parts[0].clone()).collect()
        };
        assert_eq!(parts(&cost.points), ["a", "d"]);
        assert_eq!(parts(&cost.dominated), ["b"]);
        assert_eq!(parts(&cost.infeasible), ["c"]);
        assert_eq!(check_front(&cost), Ok(2));
        let capacity = document(PartsObjective::Capacity, searched);
        assert_eq!(parts(&capacity.points), ["a", "b"]);
        assert_eq!(capacity.axes.y.better, Better::Higher);
        assert_eq!(check_front(&capacity), Ok(2));
        let moved = cost.dominated.pop().unwrap();
        cost.points.push(moved);
        let error = check_front(&cost).unwrap_err();
        assert_eq!(error, "[b] on the front is dominated by [a]");
        let text = serde_json::to_value(&capacity).unwrap();
        assert_eq!(text["axes"]["y"]["better"], "higher");
        assert_eq!(text["axes"]["x"]["key"], "actuator_mass_kg");
    }
}

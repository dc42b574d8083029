//! The result file of a capacity search, and the plots of co-design runs: the evolution of the cost over the
//! evaluations (the paper's figure 6) and the optimal ratios per case (figure 10).

use super::plots::{Chart, Mark, Radar, Series};
use crate::design::capacity::{Capacity, CapacitySettings};
use crate::design::run::{OptimizeDocument, RecordedHash};
use crate::model::task::LimitModes;
use crate::problem::Space;
use crate::solve::ToolInfo;
use serde::{Deserialize, Serialize};

/// The JSON file `codesign capacity` writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CapacityDocument {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The task file as given.
    pub task_file: String,
    /// The task hash of the task as read on its robot (`model::identity::task_hash`); unknown in
    /// files written before it was recorded.
    #[serde(default, skip_serializing_if = "RecordedHash::is_unknown")]
    pub task_hash: RecordedHash,
    /// Joint or actuation space.
    pub space: Space,
    /// The design r.
    pub ratios: Vec<f64>,
    /// Limit modes.
    pub limit_modes: LimitModes,
    /// Resolution and range of the search.
    pub settings: CapacitySettings,
    /// The outcome, flattened into the document.
    #[serde(flatten)]
    pub capacity: Capacity,
}

/// The cost of every evaluation of each run, in order, as dots, and the best cost so far as a
/// line (the paper's figure 6); log scale, so the penalised designs show as a band at the
/// penalty.
pub fn cost_evolution_chart(title: &str, runs: &[&OptimizeDocument]) -> Chart {
    let dots = runs.iter().map(|run| Series {
        name: format!("seed {}: every evaluation", run.inputs.seed),
        points: run
            .costs
            .iter()
            .enumerate()
            .map(|(i, &c)| (i as f64, c))
            .collect(),
        mark: Mark::Dots,
    });
    let best = runs.iter().map(|run| {
        let mut best = f64::INFINITY;
        Series::line(
            format!("seed {}: best so far", run.inputs.seed),
            run.costs
                .iter()
                .enumerate()
                .map(|(i, &c)| {
                    best = best.min(c);
                    (i as f64, best)
                })
                .collect(),
        )
    });
    Chart {
        title: title.to_owned(),
        x_label: "evaluation".into(),
        y_label: "cost J".into(),
        series: dots.chain(best).collect(),
        guides: Vec::new(),
        log_y: true,
    }
}

/// The optimal ratios of each case as closed polygons on a radar (the paper's figure 10), each
/// ratio r_i on its spoke as a fraction of its upper bound.
pub fn radar_chart(title: &str, cases: &[(String, Vec<f64>)], upper: &[f64]) -> Radar {
    Radar {
        title: title.to_owned(),
        axes: upper
            .iter()
            .enumerate()
            .map(|(i, max)| format!("r{} (max {max})", i + 1))
            .collect(),
        cases: cases
            .iter()
            .map(|(name, ratios)| {
                let fractions = ratios.iter().zip(upper).map(|(r, max)| r / max).collect();
                (name.clone(), fractions)
            })
            .collect(),
    }
}

//! The result file of T* against payload (`codesign tradeoff --payloads`): one or more designs'
//! least durations at each payload, and their plot.

use super::plots::{Chart, Figure, Guide, Line, Series};
use crate::design::run::RecordedHash;
use crate::design::time_curve::TimeCurve;
use crate::store::document::write_document;
use codesign_core::model::task::{Ends, Horizon, LimitModes};
use codesign_core::problem::Space;
use codesign_core::solve::ToolInfo;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What defined the curves: the task, the space, the minimum-time problem's horizon and the
/// payloads.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeCurveInputs {
    /// The task file as given.
    pub task_file: String,
    /// The task hash of the task as read on its robot (`model::identity::task_hash`; the task's,
    /// not its minimum-time problem's).
    #[serde(default, skip_serializing_if = "RecordedHash::is_unknown")]
    pub task_hash: RecordedHash,
    /// Joint or actuation space.
    pub space: Space,
    /// Limit modes.
    pub limit_modes: LimitModes,
    /// What the motion asks at its ends (`motion.ends`).
    pub ends: Ends,
    /// The task's own duration (fixed T, or its free range).
    pub task_horizon_s: Horizon,
    /// The free horizon [T_min, T_max] of the minimum-time problem, s.
    pub horizon_s: Horizon,
    /// The payloads, kg, increasing.
    pub payloads_kg: Vec<f64>,
}

/// The JSON file `codesign tradeoff --payloads` writes (schema `codesign/time_curve`,
/// version 1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeCurveDocument {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The inputs.
    pub inputs: TimeCurveInputs,
    /// One curve per design, in the order given.
    pub curves: Vec<TimeCurve>,
}

impl crate::store::document::Document for TimeCurveDocument {
    const SCHEMA: crate::store::document::Schema = crate::store::document::Schema::TimeCurve;
}

impl TimeCurveDocument {
    /// Writes the document to `out` (whole or not at all) and its plot to `plot`.
    pub fn write_with_plot(&self, out: &Path, plot: &Path) -> Result<(), String> {
        write_document(out, self).map_err(|e| e.to_string())?;
        self.chart().write(plot).map_err(|e| e.to_string())
    }

    /// The plot: T*, s, against the payload, kg, one line per design through its feasible
    /// points, with the task's own duration as a guide where it is fixed.
    pub fn chart(&self) -> Chart {
        let inputs = &self.inputs;
        let series = (self.curves.iter())
            .map(|curve| {
                let points = (curve.points.iter())
                    .filter_map(|p| p.minimum_time_s.map(|t| (p.payload_kg, t)))
                    .collect();
                let ends = match curve.ends_at_kg {
                    Some(kg) => format!("; ends at {kg} kg"),
                    None => String::new(),
                };
                Series::line(
                    format!("r = ({}){ends}", ratios_text(&curve.ratios)),
                    points,
                )
            })
            .collect();
        let guides = match inputs.task_horizon_s {
            Horizon::Fixed(seconds) => vec![Guide {
                line: Line::Horizontal(seconds),
                owners: Vec::new(),
                label: "the task's duration".to_owned(),
            }],
            Horizon::Free { .. } => Vec::new(),
        };
        Chart {
            title: format!("Least duration T* against payload, {} space", inputs.space),
            x_label: "payload (kg)".to_owned(),
            y_label: "least duration T* of the motion (s)".to_owned(),
            series,
            guides,
            log_y: false,
        }
    }
}

/// A design's ratios to three decimals, comma-separated.
fn ratios_text(ratios: &[f64]) -> String {
    (ratios.iter())
        .map(|r| format!("{r:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
}

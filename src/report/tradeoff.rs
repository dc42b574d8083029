//! The result file of a trade-off of payload capacity against cycle time (`codesign tradeoff`),
//! and its plot.

use super::plots::{Chart, Series};
use crate::design::capacity::CapacitySettings;
use crate::design::run::RecordedHash;
use crate::design::tradeoff::TradeoffPoint;
use crate::report::plots::Figure;
use crate::store::document::write_document;
use codesign_core::model::task::{Ends, LimitModes};
use codesign_core::problem::Space;
use codesign_core::solve::ToolInfo;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What defined a trade-off: the task, the space, the design, the durations and the capacity
/// searches' settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TradeoffInputs {
    /// The task file as given.
    pub task_file: String,
    /// The task hash of the task as read on its robot (`model::identity::task_hash`).
    #[serde(default, skip_serializing_if = "RecordedHash::is_unknown")]
    pub task_hash: RecordedHash,
    /// Joint or actuation space.
    pub space: Space,
    /// The design r.
    pub ratios: Vec<f64>,
    /// Limit modes.
    pub limit_modes: LimitModes,
    /// What the motion asks at its ends (`motion.ends`).
    pub ends: Ends,
    /// Resolution and range of every capacity search.
    pub settings: CapacitySettings,
    /// The fixed durations T, s, in the order searched.
    pub durations_s: Vec<f64>,
}

/// The JSON file `codesign tradeoff` writes (schema `codesign/tradeoff`, version 1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TradeoffDocument {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The inputs.
    pub inputs: TradeoffInputs,
    /// The capacity at each duration, in the order of `inputs.durations_s`.
    pub points: Vec<TradeoffPoint>,
}

impl crate::store::document::Document for TradeoffDocument {
    const SCHEMA: crate::store::document::Schema = crate::store::document::Schema::Tradeoff;
}

/// Where the plot of a trade-off written to `out` goes: beside it, its extension replaced by
/// `.svg`; why not, in words, when that is `out` itself.
pub fn plot_beside(out: &Path) -> Result<PathBuf, String> {
    let plot = out.with_extension("svg");
    if plot == out {
        return Err(
            "the result is JSON and its plot is written beside it as .svg; name the \
                    result FILE.json"
                .to_owned(),
        );
    }
    Ok(plot)
}

impl TradeoffDocument {
    /// Writes the document to `out` (whole or not at all) and its plot to `plot`.
    pub fn write_with_plot(&self, out: &Path, plot: &Path) -> Result<(), String> {
        write_document(out, self).map_err(|e| e.to_string())?;
        self.chart().write(plot).map_err(|e| e.to_string())
    }

    /// The plot: the capacity, kg, against the duration, s, through the durations with a
    /// capacity (a duration in which not even the unloaded arm moves has none and is left out).
    pub fn chart(&self) -> Chart {
        let inputs = &self.inputs;
        let points: Vec<(f64, f64)> = self
            .points
            .iter()
            .filter_map(|p| p.capacity.capacity_kg.map(|kg| (p.duration_s, kg)))
            .collect();
        Chart {
            title: format!(
                "Payload capacity against cycle time, {} space, r = ({})",
                inputs.space,
                (inputs.ratios.iter())
                    .map(|r| format!("{r:.3}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            x_label: "duration T of the motion (s)".to_owned(),
            y_label: "payload capacity (kg)".to_owned(),
            series: vec![Series::line("payload capacity within T", points)],
            guides: Vec::new(),
            log_y: false,
        }
    }
}

//! The result file of a capacity search, and the plots of co-design runs: the evolution of the cost over the
//! evaluations (the paper's figure 6) and the optimal ratios per case (figure 10, a radar; a bar
//! chart for one or two ratios).

use super::plots::{Bars, CostEvolution, CostRun, DrawResult, Figure, Radar};
use crate::design::capacity::{Capacity, CapacitySettings};
use crate::design::run::{OptimizeDocument, RecordedHash};
use codesign_core::model::task::{Ends, LimitModes};
use codesign_core::problem::Space;
use codesign_core::solve::ToolInfo;
use serde::{Deserialize, Serialize};

/// What defined a capacity search: the task, the space, the design and the search's settings
/// (in `inputs`, as in every result document).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CapacityInputs {
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
    /// What the motion asks at its ends (`motion.ends`): under `paper` the capacity is the
    /// paper's dynamic one and `hold_kg` is reported beside it; under `hold` and `rest` it is
    /// bounded by `hold_kg`.
    pub ends: Ends,
    /// Resolution and range of the search.
    pub settings: CapacitySettings,
    /// The fixed duration T each payload was moved in, s, where it was set for the search
    /// (`capacity --duration`); absent: the task's `motion.horizon_s`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
}

/// The JSON file `codesign capacity` writes (version 2: the inputs under `inputs`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CapacityDocument {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The inputs.
    pub inputs: CapacityInputs,
    /// The outcome, flattened into the document.
    #[serde(flatten)]
    pub capacity: Capacity,
}

impl crate::store::document::Document for CapacityDocument {
    const SCHEMA: crate::store::document::Schema = crate::store::document::Schema::Capacity;
}

/// The cost of every evaluation of each run, in order (the paper's figure 6): feasible ones as
/// dots and the best so far as a line on a log axis, penalised ones (cost at or above the run's
/// penalty) as ticks in a band of their own, one run per seed.
pub fn cost_evolution_chart(title: &str, runs: &[&OptimizeDocument]) -> CostEvolution {
    CostEvolution {
        title: title.to_owned(),
        runs: runs
            .iter()
            .map(|run| CostRun {
                name: format!("seed {}", run.inputs.settings.cmaes.seed),
                costs: run.costs.clone(),
                penalty: run.inputs.settings.penalty,
            })
            .collect(),
    }
}

/// The chart of the optimal ratios per case: a radar for three ratios or more, bars otherwise.
#[derive(Clone, Debug, PartialEq)]
pub enum RatioChart {
    /// Each case a closed polygon on one spoke per ratio.
    Radar(Radar),
    /// One group of bars per ratio, one bar per case.
    Bars(Bars),
}

impl Figure for RatioChart {
    fn title(&self) -> &str {
        match self {
            RatioChart::Radar(radar) => radar.title(),
            RatioChart::Bars(bars) => bars.title(),
        }
    }

    fn draw(&self, svg: &mut String) -> DrawResult {
        match self {
            RatioChart::Radar(radar) => radar.draw(svg),
            RatioChart::Bars(bars) => bars.draw(svg),
        }
    }
}

/// The fewest ratios a radar is drawn for: with one or two its polygons have no area.
pub const RADAR_MIN_RATIOS: usize = 3;

/// The optimal ratios of each case, each ratio r_i as a fraction of its upper bound `upper[i]`:
/// closed polygons on a radar (the paper's figure 10) for [`RADAR_MIN_RATIOS`] ratios or more,
/// grouped bars (one group per ratio) for fewer.
pub fn ratio_chart(title: &str, cases: &[(String, Vec<f64>)], upper: &[f64]) -> RatioChart {
    let axes = upper
        .iter()
        .enumerate()
        .map(|(i, max)| format!("r{} (max {max})", i + 1))
        .collect();
    let cases = cases
        .iter()
        .map(|(name, ratios)| {
            let fractions = ratios.iter().zip(upper).map(|(r, max)| r / max).collect();
            (name.clone(), fractions)
        })
        .collect();
    if upper.len() >= RADAR_MIN_RATIOS {
        RatioChart::Radar(Radar {
            title: title.to_owned(),
            axes,
            cases,
        })
    } else {
        RatioChart::Bars(Bars {
            title: title.to_owned(),
            axes,
            y_label: "r_i / upper bound".into(),
            cases,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cases(ratios: usize) -> Vec<(String, Vec<f64>)> {
        ["joint, 1 kg", "actuation, 1 kg"]
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let values = (0..ratios).map(|i| 1.0 + (i + k) as f64).collect();
                (name.to_string(), values)
            })
            .collect()
    }

    #[test]
    fn a_radar_for_three_ratios_or_more_and_bars_below() {
        for ratios in 1..=6 {
            let upper = vec![9.0; ratios];
            let chart = ratio_chart("optimal ratios", &cases(ratios), &upper);
            let svg = chart.to_svg().unwrap();
            for i in 1..=ratios {
                assert!(svg.contains(&format!("r{i} (max 9)")), "r{i} missing");
            }
            assert!(svg.contains("joint, 1 kg") && svg.contains("actuation, 1 kg"));
            // Bars are rectangles: one per ratio and case, two legend keys and the background;
            // a radar draws only the background (its legend keys are lines).
            let rectangles = svg.matches("<rect").count();
            match chart {
                RatioChart::Radar(radar) => {
                    assert!(ratios >= 3, "{ratios} ratios on a radar");
                    assert_eq!(radar.cases[1].1[0], 2.0 / 9.0);
                    assert_eq!(rectangles, 1, "{ratios} ratios");
                }
                RatioChart::Bars(bars) => {
                    assert!(ratios < 3, "{ratios} ratios as bars");
                    assert_eq!(bars.cases[1].1[0], 2.0 / 9.0);
                    assert_eq!(rectangles, 2 * ratios + 3, "{ratios} ratios");
                }
            }
        }
    }
}

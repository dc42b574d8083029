//! The two trade-offs of one task as Python asks them: payload capacity against duration
//! (`codesign tradeoff`) and least duration T* against payload (`codesign tradeoff --payloads`),
//! each answering with the command line's document.

use crate::errors::{json, Failure, Outcome};
use crate::options::Posed;
use codesign::design::capacity::CapacitySettings;
use codesign::design::run::RecordedHash;
use codesign::design::time_curve::minimum_time_curve;
use codesign::design::tradeoff::{capacity_tradeoff, TradeoffProblem};
use codesign::report::time_curve::{TimeCurveDocument, TimeCurveInputs};
use codesign::report::tradeoff::{plot_beside, TradeoffDocument, TradeoffInputs};
use codesign_core::solve::ToolInfo;
use std::path::{Path, PathBuf};

/// Where the plot of a document written to `out` goes, the error naming `out=`.
fn plot_of(out: Option<&Path>) -> Outcome<Option<PathBuf>> {
    out.map(|out| {
        plot_beside(out).map_err(|why| Failure::input(format!("out={}: {why}", out.display())))
    })
    .transpose()
}

/// What a trade-off was asked.
pub struct TradeoffAsked {
    pub ratios: Option<Vec<f64>>,
    pub durations: Vec<f64>,
    pub settings: CapacitySettings,
    /// Where to write the document, its plot beside it (`.svg`).
    pub out: Option<PathBuf>,
}

impl TradeoffAsked {
    /// The capacities at every duration of design `ratios` (None: the original), the document
    /// as JSON, written with its plot where asked.
    pub fn run(self, posed: &Posed) -> Outcome<String> {
        let loaded = posed.load()?;
        let formulation = posed.formulation(&loaded)?;
        let ratios = posed.design(&formulation, self.ratios)?;
        let plot = plot_of(self.out.as_deref())?;
        let problem = TradeoffProblem {
            task: &loaded.task,
            robot: &loaded.robot,
            space: formulation.space(),
            modes: *formulation.modes(),
            solve: &loaded.settings,
        };
        let points = capacity_tradeoff(&problem, &ratios, &self.durations, &self.settings)
            .map_err(|e| Failure::solver(format!("{}: {e}", posed.model.source())))?;
        let document = TradeoffDocument {
            tool: ToolInfo::current(loaded.settings.linear_solver()),
            inputs: TradeoffInputs {
                task_file: posed.model.source().label(),
                task_hash: RecordedHash(Some(loaded.task_hash.clone())),
                space: formulation.space(),
                ratios,
                limit_modes: *formulation.modes(),
                ends: loaded.task.motion.ends,
                settings: self.settings,
                durations_s: self.durations,
            },
            points,
        };
        if let (Some(out), Some(plot)) = (&self.out, &plot) {
            (document.write_with_plot(out, plot))
                .map_err(|e| Failure::input(format!("out=: {e}")))?;
        }
        json(&document)
    }
}

/// What a curve of T* against payload was asked.
pub struct TimeCurveAsked {
    /// The designs (None: the original alone).
    pub designs: Option<Vec<Vec<f64>>>,
    /// The payloads, kg, checked.
    pub payloads: Vec<f64>,
    /// Where to write the document, its plot beside it (`.svg`).
    pub out: Option<PathBuf>,
}

impl TimeCurveAsked {
    /// T* at every payload of each design, every design checked before the first solve; the
    /// document as JSON, written with its plot where asked.
    pub fn run(self, posed: &Posed) -> Outcome<String> {
        let loaded = posed.load()?;
        let formulation = posed.formulation(&loaded)?;
        let designs = match self.designs {
            None => vec![posed.design(&formulation, None)?],
            Some(designs) => (designs.into_iter())
                .map(|ratios| posed.design(&formulation, Some(ratios)))
                .collect::<Outcome<Vec<_>>>()?,
        };
        let plot = plot_of(self.out.as_deref())?;
        let problem = TradeoffProblem {
            task: &loaded.task,
            robot: &loaded.robot,
            space: formulation.space(),
            modes: *formulation.modes(),
            solve: &loaded.settings,
        };
        let curves = (designs.iter())
            .map(|ratios| minimum_time_curve(&problem, ratios, &self.payloads))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| Failure::solver(format!("{}: {e}", posed.model.source())))?;
        let task = &loaded.task;
        let document = TimeCurveDocument {
            tool: ToolInfo::current(loaded.settings.linear_solver()),
            inputs: TimeCurveInputs {
                task_file: posed.model.source().label(),
                task_hash: RecordedHash(Some(loaded.task_hash.clone())),
                space: formulation.space(),
                limit_modes: *formulation.modes(),
                ends: task.motion.ends,
                task_horizon_s: task.motion.horizon,
                horizon_s: task.minimum_time().motion.horizon,
                payloads_kg: self.payloads,
            },
            curves,
        };
        if let (Some(out), Some(plot)) = (&self.out, &plot) {
            (document.write_with_plot(out, plot))
                .map_err(|e| Failure::input(format!("out=: {e}")))?;
        }
        json(&document)
    }
}

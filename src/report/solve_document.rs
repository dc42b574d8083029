//! The document of one trajectory solve, the JSON file `codesign solve --out` writes: what
//! defined the solve, the result, and the raw solution to start another solve from.

use crate::design::run::RecordedHash;
use codesign_core::model::task::LimitModes;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{SolveSettings, StartPoint, TaskRecord, ToolInfo, TrajectoryResult};
use serde::{Deserialize, Serialize};

/// What a solve's result records of the result it started from (`inputs.start`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StartRecord {
    /// The start's file, as given.
    pub file: String,
    /// The design the start was solved for.
    pub ratios: Vec<f64>,
    /// The payload it was solved for, kg.
    pub payload_kg: f64,
}

/// What defined a solve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolveInputs {
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
    /// Payload, kg.
    pub payload_kg: f64,
    /// Limit modes.
    pub limit_modes: LimitModes,
    /// The task with every override applied (horizon, payload, robot), and the solve settings.
    pub task: TaskRecord,
    /// The result the solve started from (`solve --start`); absent when it started cold.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<StartRecord>,
}

/// The JSON file `codesign solve --out` writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolveDocument {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The inputs.
    pub inputs: SolveInputs,
    /// The result, flattened into the document.
    #[serde(flatten)]
    pub result: TrajectoryResult,
    /// The raw solution nearest the verdict, to start another solve from (`solve --start`);
    /// written by `solve --out`, absent from `reproduce`'s results and from older files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_point: Option<StartPoint>,
}

impl crate::store::document::Document for SolveDocument {
    const SCHEMA: crate::store::document::Schema = crate::store::document::Schema::Solve;
}

impl SolveDocument {
    /// The document of `result`, solved for `formulation` (its task, space and modes) from the
    /// task file `task_file` of task hash `task_hash` with `settings`.
    pub fn new(
        task_file: &str,
        task_hash: &str,
        formulation: &Formulation,
        settings: &SolveSettings,
        result: TrajectoryResult,
    ) -> SolveDocument {
        let task = formulation.task();
        SolveDocument {
            tool: ToolInfo::current(settings.linear_solver()),
            inputs: SolveInputs {
                task_file: task_file.to_owned(),
                task_hash: RecordedHash(Some(task_hash.to_owned())),
                space: formulation.space(),
                ratios: result.ratios.clone(),
                payload_kg: task.payload.mass_kg,
                limit_modes: *formulation.modes(),
                task: TaskRecord {
                    task: task.clone(),
                    solver: settings.clone(),
                },
                start: None,
            },
            result,
            start_point: None,
        }
    }

    /// The solve document of a co-design run's best design, as the run recorded it (no raw
    /// solution kept); None where the run found no feasible design.
    pub fn of_run_best(run: &crate::design::run::OptimizeDocument) -> Option<SolveDocument> {
        let result = run.best_result.clone()?;
        let inputs = &run.inputs;
        Some(SolveDocument {
            tool: run.tool.clone(),
            inputs: SolveInputs {
                task_file: inputs.task_file.clone(),
                task_hash: inputs.task_hash.clone(),
                space: inputs.space,
                ratios: result.ratios.clone(),
                payload_kg: inputs.payload_kg,
                limit_modes: inputs.limit_modes,
                task: inputs.task.clone(),
                start: None,
            },
            result,
            start_point: None,
        })
    }

    /// The document with `point`, the raw solution of its solve, to start another solve from.
    pub fn with_start_point(mut self, point: StartPoint) -> SolveDocument {
        self.start_point = Some(point);
        self
    }

    /// The document of a solve that started from the result `record` names.
    pub fn started_from(mut self, record: StartRecord) -> SolveDocument {
        self.inputs.start = Some(record);
        self
    }
}

//! The paper's Table II with our numbers beside the paper's, built from result files (for any
//! other task than the paper's, the same table without the paper's numbers, titled by its task):
//! the table's types and the reading of result files here, the rows in `build`, the checks of a
//! set of files in `check`, its text in `markdown`, rendered as Markdown or HTML by `blocks`.

mod agreement;
mod blocks;
mod build;
mod check;
mod hold;
mod markdown;

pub use blocks::{escape_html, to_html, Block};
pub use hold::HoldRow;

pub use build::build_table;
pub use check::check_results;

use super::codesign::CapacityDocument;
use super::migrate::steps::untagged_kind;
use super::solve_document::SolveDocument;
use super::{ReadFailure, ReportError};
use crate::design::run::{OptimizeDocument, PayloadCost};
use crate::store::document::{self, Schema, Tagged};
use codesign_core::input::{read_text, MAX_RESULT_BYTES};
use codesign_core::ipopt::LinearSolver;
use codesign_core::json_keys::check_unique_keys;
use codesign_core::model::task::Ends;
use codesign_core::problem::Space;
use codesign_core::solve::ToolInfo;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A result file of `solve`, `optimize` or `capacity`.
#[derive(Clone, Debug, PartialEq)]
pub enum ResultFile {
    /// One trajectory solve.
    Solve(Box<SolveDocument>),
    /// One co-design run.
    Optimize(Box<OptimizeDocument>),
    /// One payload-capacity search.
    Capacity(Box<CapacityDocument>),
}

impl ResultFile {
    /// The task file as the result records it: a path as given, or `built-in`.
    pub fn task_file(&self) -> &str {
        match self {
            ResultFile::Solve(d) => &d.inputs.task_file,
            ResultFile::Optimize(d) => &d.inputs.task_file,
            ResultFile::Capacity(d) => &d.inputs.task_file,
        }
    }

    /// What the motion asked at its ends in the result's problem (`motion.ends`; files written
    /// before the choice: `hold`).
    pub fn ends(&self) -> Ends {
        match self {
            ResultFile::Solve(d) => d.inputs.task.task.motion.ends,
            ResultFile::Optimize(d) => d.inputs.task.task.motion.ends,
            ResultFile::Capacity(d) => d.inputs.ends,
        }
    }

    /// The task the result belongs to, by task hash (`model::identity::task_hash`): the hash it
    /// records; None, an unknown task, for a file of a task file written before the hash was
    /// recorded (`codesign migrate` gave one of the built-in task the built-in task's hash).
    pub fn task(&self) -> Option<String> {
        let recorded = match self {
            ResultFile::Solve(d) => &d.inputs.task_hash,
            ResultFile::Optimize(d) => &d.inputs.task_hash,
            ResultFile::Capacity(d) => &d.inputs.task_hash,
        };
        recorded.0.clone()
    }
}

/// Reads a result file of the version this build writes, telling its kind by its envelope's
/// tag, refusing an object that gives a key twice (an edited file, of which serde would keep
/// the last value silently) and an older version (`codesign migrate` upgrades it); errors name
/// the file.
pub fn read_result_file(path: &Path) -> Result<ResultFile, ReportError> {
    let (schema, value) = read_current(path)?;
    let parsed = match schema {
        Schema::Capacity => {
            serde_json::from_value(value).map(|d| ResultFile::Capacity(Box::new(d)))
        }
        Schema::Optimize => {
            serde_json::from_value(value).map(|d| ResultFile::Optimize(Box::new(d)))
        }
        Schema::Solve => serde_json::from_value(value).map(|d| ResultFile::Solve(Box::new(d))),
        Schema::Table => return Err(read_failure(path, ReadFailure::Table)),
        Schema::Tradeoff | Schema::TimeCurve => {
            return Err(read_failure(path, ReadFailure::Tradeoff))
        }
        Schema::Pareto => return Err(read_failure(path, ReadFailure::Pareto)),
    };
    parsed.map_err(|e| {
        let kind = schema.name();
        let why = e.to_string();
        read_failure(path, ReadFailure::NotAResult { kind, why })
    })
}

/// Reads a table (`paper_table.json`, a `codesign/table` document of this build's version),
/// with the checks of [`read_result_file`]; errors name the file.
pub fn read_table_file(path: &Path) -> Result<PaperTable, ReportError> {
    let (schema, value) = read_current(path)?;
    if schema != Schema::Table {
        return Err(read_failure(path, ReadFailure::NotATable(schema)));
    }
    serde_json::from_value(value).map_err(|e| {
        let kind = schema.name();
        let why = e.to_string();
        read_failure(path, ReadFailure::NotAResult { kind, why })
    })
}

/// The error of reading `path`, for `why`.
fn read_failure(path: &Path, why: ReadFailure) -> ReportError {
    ReportError::Read {
        path: path.to_owned(),
        why,
    }
}

/// A codesign document of this build's version at `path`: its kind and its fields, the
/// envelope taken off.
fn read_current(path: &Path) -> Result<(Schema, serde_json::Value), ReportError> {
    let failed = |why| read_failure(path, why);
    let text = read_text(path, MAX_RESULT_BYTES).map_err(|e| failed(ReadFailure::Input(e)))?;
    let mut value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| failed(ReadFailure::NotJson(e.to_string())))?;
    check_unique_keys(&text).map_err(|e| failed(ReadFailure::RepeatedKey(e)))?;
    let tagged = document::open(&mut value).map_err(|e| failed(ReadFailure::Envelope(e)))?;
    match tagged {
        Tagged::Kind(schema, version) if version == schema.version() => Ok((schema, value)),
        Tagged::Kind(schema, version) => Err(failed(ReadFailure::Old {
            schema: Some(schema),
            version,
        })),
        Tagged::Untagged => Err(failed(ReadFailure::Old {
            schema: untagged_kind(&value),
            version: 0,
        })),
    }
}

/// What the paper reports for one row (docs/model.md, section 13, from the paper's Table II).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperValues {
    /// Before co-design (original ratios 6, 3, 1, 1).
    pub before: String,
    /// After co-design.
    pub after: String,
}

/// The paper's Table II: (payload kg, space, before, after).
const PAPER: [(f64, Space, &str, &str); 6] = [
    (0.0, Space::Joint, "(6, 3, 1, 1): 66.77", "-"),
    (0.0, Space::Actuation, "(6, 3, 1, 1): 50.99", "-"),
    (1.0, Space::Joint, "infeasible", "(9, 4.09, 3, 3): 146.42"),
    (
        1.0,
        Space::Actuation,
        "(6, 3, 1, 1): 161.21",
        "(9, 5.62, 3, 1.8): 71.55",
    ),
    (3.0, Space::Joint, "infeasible", "none feasible"),
    (
        3.0,
        Space::Actuation,
        "(6, 3, 1, 1): 526.45",
        "(9, 4.62, 3, 3): 159.42",
    ),
];

/// One design's outcome in the table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignCell {
    /// The design r.
    pub ratios: Vec<f64>,
    /// Whether its trajectory problem was solved.
    pub feasible: bool,
    /// Its optimal cost (meaningful when feasible).
    pub cost: f64,
    /// IPOPT status.
    pub status: String,
    /// Why it is infeasible (the load not held at rest, or IPOPT's reason), when it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Largest motor torque its trajectory needs, N m.
    pub max_motor_torque: f64,
    /// Largest motor speed, rad/s.
    pub max_motor_speed: f64,
    /// Whether the real motors can execute the trajectory: motor torques and speeds within the
    /// task's limits (to 1e-6 relative). A joint-space solution under the `paper` limits may not.
    pub motors_can_execute: bool,
    /// The design-space bounds it sits on, each with dJ*/dr_i and what widening it would gain
    /// (`ActiveBound`); empty inside the bounds and in tables written before they were said.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub active_bounds: Vec<String>,
}

/// The co-design runs of one row.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AfterCell {
    /// The best design over the seeds (None when no run found a feasible design).
    pub best: Option<DesignCell>,
    /// Best cost per seed, (seed, cost); the cost None (null) for a seed that found no feasible
    /// design.
    pub per_seed: Vec<(u64, Option<f64>)>,
    /// Runs that stopped before their last generation: (seed, last generation run, why).
    pub early_stops: Vec<(u64, usize, String)>,
    /// CMA-ES evaluations over all seeds.
    pub evaluations: usize,
    /// Those that ran an inner solve (the rest broke an order constraint).
    pub solves: usize,
    /// Median over the runs of each run's median solve time, s (NaN, written as null, when no
    /// solve ran).
    #[serde(deserialize_with = "crate::design::run::number_or_nan")]
    pub median_solve_seconds: f64,
    /// CMA-ES population and generations of the runs.
    pub population: usize,
    /// CMA-ES generations.
    pub generations: usize,
}

/// One row: a payload and a space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TableRow {
    /// Payload, kg.
    pub payload_kg: f64,
    /// Joint or actuation space.
    pub space: Space,
    /// The original design's solve.
    pub before: Option<DesignCell>,
    /// The co-design runs with CMA-ES.
    pub after: Option<AfterCell>,
    /// The co-design run with the gradient method: its best design and its inner solves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gradient: Option<(DesignCell, usize)>,
    /// Payload capacity of the original design in this space, kg (from a capacity file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capacity_before_kg: Option<f64>,
    /// Payload capacity of the best CMA-ES design, kg (from a capacity file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capacity_after_kg: Option<f64>,
    /// The largest payload the original design holds at rest at both ends, kg (from its
    /// capacity file; absent where no payload is too heavy, none is held, or not recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub held_before_kg: Option<f64>,
    /// The largest payload the best CMA-ES design holds at rest at both ends, kg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub held_after_kg: Option<f64>,
    /// The design of largest capacity found by `optimize --objective capacity` in this space,
    /// and its capacity, kg (on the row of the run's payload).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capacity_max: Option<(Vec<f64>, f64)>,
    /// CMA-ES with the graded penalty (`--penalty graded`), beyond the paper: like `after`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub graded: Option<AfterCell>,
    /// The gradient method with the graded penalty: its best design and its inner solves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub graded_gradient: Option<(DesignCell, usize)>,
    /// The paper's values (only in a table of the paper's task).
    pub paper: Option<PaperValues>,
}

/// The whole table, as written to `paper_table.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperTable {
    /// The title: "Table II reproduced" for the paper's task, else naming the task.
    pub title: String,
    /// Whether the results are of the paper's task (the built-in one, by task hash): only then
    /// does the table show the paper's values.
    pub paper_task: bool,
    /// What the motion asks at its ends in the table's problems (`motion.ends`; absent in
    /// tables written before the choice, whose results held the load at rest).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ends: Option<Ends>,
    /// Beyond the paper, under `paper` ends: the same cases with the load held at rest.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hold: Vec<HoldRow>,
    /// The task hash of the results (None: no result records one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub task_hash: Option<String>,
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The linear solvers the result files were solved with, each once.
    pub linear_solvers: Vec<LinearSolver>,
    /// Rows by payload, then joint before actuation.
    pub rows: Vec<TableRow>,
    /// Notes shown above the table (e.g. a reduced run).
    pub notes: Vec<String>,
    /// Inner solves of the co-design runs on the trajectory cost (CMA-ES and gradient).
    pub solves: usize,
    /// Their wall times summed, s.
    pub solve_seconds: f64,
    /// Evaluations of the co-design runs on the payload capacity that ran a capacity search
    /// (each a bracketing and bisection of several solves).
    pub capacity_evaluations: usize,
    /// The wall times of those searches summed, s.
    pub capacity_seconds: f64,
    /// Co-design runs for a payload range (`--objective range`), beyond the paper.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ranges: Vec<RangeRow>,
}

impl crate::store::document::Document for PaperTable {
    const SCHEMA: crate::store::document::Schema = crate::store::document::Schema::Table;
}

/// A co-design run for a payload range: one design for every payload of it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RangeRow {
    /// The payloads, kg.
    pub payloads_kg: Vec<f64>,
    /// Joint or actuation space.
    pub space: Space,
    /// CMA-ES seed.
    pub seed: u64,
    /// The best design (empty when none was feasible at every payload).
    pub ratios: Vec<f64>,
    /// Its mean cost over the payloads (None, null, when none was feasible).
    pub mean_cost: Option<f64>,
    /// Its cost at each payload.
    pub per_payload: Vec<PayloadCost>,
    /// The original design's mean cost (the penalty when infeasible at some payload).
    pub original_mean_cost: f64,
    /// Whether the original design is feasible at every payload.
    pub original_feasible: bool,
    /// Evaluations of the run.
    pub evaluations: usize,
}

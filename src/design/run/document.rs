//! The document of a co-design run: its settings ([`OptimizeInputs`], also the header of its
//! evaluation log) and what it found ([`OptimizeDocument`], the JSON file `optimize` writes).

use super::settings::RunSettings;
use crate::design::outcome::GenerationSummary;
use crate::design::outcome::GradientIterate;
use crate::design::verdicts::VerdictTally;
use crate::store::log::LoggedRun;
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::task::{LimitModes, MotionsScore};
use codesign_core::problem::Space;
use codesign_core::solve::{TaskRecord, ToolInfo, TrajectoryResult};
use codesign_core::transmission::{ActiveBound, Transmission};
use serde::{Deserialize, Serialize};

/// Everything that defines a co-design run; two runs with equal inputs give equal results.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptimizeInputs {
    /// The settings of the run (method, objective, CMA-ES, penalty, bounds, warm starts),
    /// written at this level of the document.
    #[serde(flatten)]
    pub settings: RunSettings,
    /// The task file as given.
    pub task_file: String,
    /// The task with every override applied, and its solve settings, the linear solver aside.
    pub task: TaskRecord,
    /// The linear solver of the inner solves.
    pub linear_solver: LinearSolver,
    /// FNV-1a of the robot's URDF text, so that a run is never resumed with an edited robot
    /// (logs written before it was recorded leave it unknown).
    #[serde(default, skip_serializing_if = "RecordedHash::is_unknown")]
    pub robot_hash: RecordedHash,
    /// The task hash of the task as read on its robot (`model::identity::task_hash`), so that
    /// `table` never merges runs of two tasks (files written before it was recorded leave it
    /// unknown).
    #[serde(default, skip_serializing_if = "RecordedHash::is_unknown")]
    pub task_hash: RecordedHash,
    /// Joint or actuation space.
    pub space: Space,
    /// Payload, kg.
    pub payload_kg: f64,
    /// Limit modes.
    pub limit_modes: LimitModes,
    /// The rule that judged each design feasible; a log is resumed only under its own rule, so
    /// that no verdict of an older rule is replayed as today's.
    pub verdict_rule: VerdictRule,
}

/// What makes a design feasible in a run's evaluations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VerdictRule {
    /// An optimum found by IPOPT (or an elastic optimum without slack), the only rule before the
    /// static hold.
    Ipopt,
    /// That, and the motors hold the load at rest at both ends (`problem::hold`).
    StaticHold,
    /// That, judged over several starts: a design is infeasible only when no start (the hard
    /// problem from the standard guess, the elastic problem, the hard problem from the elastic
    /// trajectory) finds a feasible trajectory.
    AnyStart,
    /// Any start, the payload continuation from the unloaded arm among them
    /// (`solve::solve_design_from`, docs/model.md section 8).
    #[default]
    AnyStartOrContinuation,
}

/// A hash a run recorded, or unknown in records written before it was kept. Unknown equals
/// only unknown: a record that cannot say what it ran on is never taken for a known run.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct RecordedHash(pub Option<String>);

impl RecordedHash {
    /// Whether no hash was recorded.
    pub fn is_unknown(&self) -> bool {
        self.0.is_none()
    }
}

impl LoggedRun for OptimizeInputs {
    /// Equal, the spelling of the task file's path aside (the task's content is recorded), and
    /// of the robot's where both record the hash of its text.
    fn same_run(&self, run: &OptimizeInputs) -> bool {
        let hashed = !self.robot_hash.is_unknown() && !run.robot_hash.is_unknown();
        let unspelled = |inputs: &OptimizeInputs| {
            let mut inputs = inputs.clone();
            inputs.task_file = String::new();
            if hashed {
                inputs.task.task.robot = None;
            }
            inputs
        };
        unspelled(self) == unspelled(run)
    }
}

/// The JSON file `codesign optimize` writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptimizeDocument {
    /// Program and solver versions.
    pub tool: ToolInfo,
    /// The run's settings.
    pub inputs: OptimizeInputs,
    /// The best design found; empty when no evaluation found a design feasible (files written
    /// before this rule may hold an infeasible design here, with the penalty as its cost).
    pub best_ratios: Vec<f64>,
    /// Its cost; None (null) with no best design, under any penalty.
    pub best_cost: Option<f64>,
    /// The full solve of the best design.
    pub best_result: Option<TrajectoryResult>,
    /// The original design.
    pub original_ratios: Vec<f64>,
    /// The original design's cost (the penalty when infeasible).
    pub original_cost: f64,
    /// The full solve of the original design.
    pub original_result: Option<TrajectoryResult>,
    /// Per generation: best, median, feasible count.
    pub generations: Vec<GenerationSummary>,
    /// Inner solves of the run (including replayed ones).
    pub evaluations: usize,
    /// Every evaluation's fitness in (generation, index) order.
    pub costs: Vec<f64>,
    /// The accepted iterates of the gradient method (empty for CMA-ES).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub iterates: Vec<GradientIterate>,
    /// Evaluations replayed from the log on resume.
    pub replayed: usize,
    /// Evaluations that ran IPOPT (designs that break a bound or an order constraint are scored
    /// without a solve).
    pub solves: usize,
    /// Wall time of those solves summed, s (replayed ones included, from the log).
    pub solve_seconds_total: f64,
    /// The evaluations by kind of verdict (feasible, infeasible, invalid, not judged), each
    /// with its IPOPT iterations and solve time (replayed ones included, from the log); None in
    /// files written before it was counted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verdicts: Option<VerdictTally>,
    /// Median wall time of an inner solve, s (NaN, written as null, when no solve ran).
    #[serde(deserialize_with = "number_or_nan")]
    pub median_solve_seconds: f64,
    /// Why the method stopped.
    pub stop_reason: String,
    /// Wall time of this invocation, s (a resumed run's earlier invocations not included).
    pub wall_seconds: f64,
    /// Working time of the run's earlier invocations, s, from its evaluation log (0 for a run
    /// done in one invocation; None when the log predates that record): the run took this plus
    /// `wall_seconds` in all.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub earlier_seconds: Option<f64>,
    /// For `--objective range`: the best and the original design solved at every payload (their
    /// `best_result` and `original_result` are then None).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub payload_costs: Option<RangeCosts>,
    /// For a task with several motions (`motions`): the best and the original design solved
    /// for every motion (their `best_result` and `original_result` are then None); absent for
    /// a task of one motion.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion_costs: Option<MotionCosts>,
    /// For `--objective capacity`: the evaluations whose design carried the search's largest
    /// payload (`max_kg`), where the search stops, so that their capacities tie there; absent
    /// for the other objectives and in files written before it was counted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at_max: Option<usize>,
}

impl OptimizeDocument {
    /// The bounds of the run's design space that its best design sits on, with dJ*/dr_i from
    /// the best design's result where it has one; none when no design was found.
    pub fn best_at_bounds(&self) -> Vec<ActiveBound> {
        let spec = &self.inputs.task.task.transmission;
        let Ok(space) = Transmission::design_space_of(spec) else {
            return Vec::new();
        };
        if self.best_ratios.is_empty() {
            return Vec::new();
        }
        let gradient = self
            .best_result
            .as_ref()
            .and_then(|r| r.cost_gradient.as_deref());
        space.active_bounds(&self.best_ratios, gradient)
    }
}

impl crate::store::document::Document for OptimizeDocument {
    const SCHEMA: crate::store::document::Schema = crate::store::document::Schema::Optimize;
}

/// The designs of a payload-range run, solved at each payload.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RangeCosts {
    /// The best design, per payload.
    pub best: Vec<PayloadCost>,
    /// The original design, per payload.
    pub original: Vec<PayloadCost>,
}

/// One design solved at one payload.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PayloadCost {
    /// The payload, kg.
    pub payload_kg: f64,
    /// Whether its trajectory problem was solved.
    pub feasible: bool,
    /// The optimal cost J (meaningful when feasible).
    pub cost: f64,
    /// IPOPT's status, or why no solve ran.
    pub status: String,
}

/// The designs of a run over a task's several motions, solved for each motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotionCosts {
    /// How the motions' costs make the score: `sum` or `worst`.
    pub score: MotionsScore,
    /// The best design, per motion (empty when no design was found).
    pub best: Vec<MotionCost>,
    /// The original design, per motion.
    pub original: Vec<MotionCost>,
}

/// One design solved for one motion of a task.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotionCost {
    /// The motion's name.
    pub name: String,
    /// Its weight w_i.
    pub weight: f64,
    /// Its payload, kg.
    pub payload_kg: f64,
    /// Whether its trajectory problem was solved feasibly.
    pub feasible: bool,
    /// Its optimal cost J_i (meaningful when feasible; null when no solve ran).
    #[serde(deserialize_with = "number_or_nan")]
    pub cost: f64,
    /// IPOPT's status, or why no solve ran.
    pub status: String,
    /// The solve's full result (None when no solve ran).
    pub result: Option<TrajectoryResult>,
}

/// Reads a number that serde_json wrote as null because it was NaN.
pub fn number_or_nan<'de, D: serde::Deserializer<'de>>(reader: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(reader)?.unwrap_or(f64::NAN))
}

#[cfg(test)]
mod tests {
    use super::{OptimizeDocument, OptimizeInputs, RecordedHash, VerdictRule};

    /// An unknown hash (a record written before hashes were kept) equals only another unknown
    /// one, never a known hash.
    #[test]
    fn an_unknown_hash_is_never_a_known_one() {
        let known = RecordedHash(Some("0123abcd".to_owned()));
        assert_ne!(RecordedHash(None), known);
        assert_ne!(known, RecordedHash(None));
        assert_eq!(RecordedHash(None), RecordedHash(None));
        assert_eq!(known, RecordedHash(Some("0123abcd".to_owned())));
    }

    #[test]
    fn a_run_without_a_verdict_rule_does_not_read() {
        // The inputs of a log written before the rule was recorded are of an older format,
        // which `codesign migrate` brings to this one (the rule: `ipopt`); a reader of this
        // build does not take a rule for them.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("results/quick/runs/actuation-1kg-seed0.json");
        let text = std::fs::read_to_string(path).unwrap();
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        let today: OptimizeInputs = serde_json::from_value(value["inputs"].clone()).unwrap();
        assert_eq!(today.verdict_rule, VerdictRule::default());
        let mut older = value["inputs"].clone();
        older.as_object_mut().unwrap().remove("verdict_rule");
        let error = serde_json::from_value::<OptimizeInputs>(older).unwrap_err();
        assert!(error.to_string().contains("verdict_rule"), "{error}");
    }

    #[test]
    fn a_run_without_timed_solves_reads_back() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("results/quick/runs/actuation-1kg-seed0.json");
        let text = std::fs::read_to_string(path).unwrap();
        let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
        value["median_solve_seconds"] = serde_json::Value::Null;
        let document: OptimizeDocument = serde_json::from_value(value).unwrap();
        assert!(document.median_solve_seconds.is_nan());
    }

    /// A run whose transmission has linkage rows lists its bounds too: the four-bar's best
    /// design has its crank radius on the lower bound and its reduction on the upper one.
    #[test]
    fn a_linkage_runs_best_design_lists_its_bounds() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("results/linkage/four_bar-actuation-gradient.json");
        let text = std::fs::read_to_string(path).unwrap();
        let document: OptimizeDocument = serde_json::from_str(&text).unwrap();
        let bounds: Vec<(usize, f64)> = (document.best_at_bounds().iter())
            .map(|bound| (bound.index, bound.bound))
            .collect();
        assert_eq!(bounds, [(1, 52.0), (2, 40.0)]);
    }
}

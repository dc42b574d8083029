//! Several motions of one task (docs/model.md, "Several motions"): the task file's optional
//! `motions` list, each entry a named, weighted motion whose fields override the task's
//! `motion` and whose payload overrides the task's, and `motions_score`, how their optimal
//! costs make one: their weighted sum (the default) or the worst weighted one.
//!
//! A task with a `motions` list is a set of single-motion tasks ([`Task::motion_tasks`]); every
//! layer below co-design solves each of them as the task it is.

use super::ranges::{check_payload, Bounds, FieldError, MAX_WEIGHT};
use super::task::{Ends, Goal, Horizon, Motion, Task, Upright, Via};
use crate::choice::Choice;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize};

/// Longest name of a motion, in characters: a label of messages and result files.
pub const MAX_MOTION_NAME: usize = 64;

/// One motion of a task's `motions` list: its name and weight, its payload, and the fields of
/// the task's `motion` it changes (those left out are the task's).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionEntry {
    /// The motion's name, unique in the list (`solve --motion NAME`).
    pub name: String,
    /// w_i >= 0, dimensionless: its weight in the task's score (1 when absent).
    #[serde(default = "unit_weight")]
    pub weight: f64,
    /// Its payload, kg (absent: the task's `payload.mass_kg`, which `--payload` sets).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub payload_kg: Option<f64>,
    /// Joint positions at t = 0, rad (absent: the task's `motion.start`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<Vec<f64>>,
    /// Where it ends, joint positions at t = T, rad, or a TCP position within a tolerance
    /// (absent: the task's `motion.goal`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub goal: Option<Goal>,
    /// Its duration, s, fixed or free (absent: the task's `motion.horizon_s`).
    #[serde(default, rename = "horizon_s", skip_serializing_if = "Option::is_none")]
    pub horizon: Option<Horizon>,
    /// Its number of intervals N (absent: the task's `motion.steps`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<usize>,
    /// What it asks at its ends (absent: the task's `motion.ends`, which `--ends` sets).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ends: Option<Ends>,
    /// The points it passes (absent: the task's `motion.via`; `[]`: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub via: Option<Vec<Via>>,
    /// A link it holds upright (absent: the task's `motion.upright`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub upright: Option<Upright>,
}

/// Reads a `motions` list, refusing an empty one: a task of one motion leaves the key out.
pub(super) fn non_empty<'de, D: Deserializer<'de>>(
    reader: D,
) -> Result<Vec<MotionEntry>, D::Error> {
    let entries = Vec::<MotionEntry>::deserialize(reader)?;
    if entries.is_empty() {
        return Err(D::Error::custom(
            "an empty list; a task of one motion leaves `motions` out",
        ));
    }
    Ok(entries)
}

/// The weight of an entry that gives none.
fn unit_weight() -> f64 {
    1.0
}

/// How the optimal costs J_i* of a task's motions make its score.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MotionsScore {
    /// sum_i w_i J_i*: what a cell pays that runs each motion as often as its weight;
    /// differentiable wherever each J_i* is.
    #[default]
    Sum,
    /// max_i w_i J_i*: the worst motion; its gradient is the active motion's, and it is not
    /// differentiable where two motions tie.
    Worst,
}

impl Choice for MotionsScore {
    const ALL: &'static [MotionsScore] = &[MotionsScore::Sum, MotionsScore::Worst];

    fn name(self) -> &'static str {
        match self {
            MotionsScore::Sum => "sum",
            MotionsScore::Worst => "worst",
        }
    }
}

impl MotionsScore {
    /// Whether this is the default, the weighted sum (then not written, so that a task without
    /// motions keeps its task hash).
    pub fn is_sum(&self) -> bool {
        *self == MotionsScore::Sum
    }

    /// The score of the weighted costs `weighted` (w_i J_i*, in the list's order), with the
    /// index of the active motion of `worst` (the first of those that tie); None for an empty
    /// list. The sum adds in order, so the same costs give the same bits.
    pub fn combine(self, weighted: &[f64]) -> Option<(f64, Option<usize>)> {
        if weighted.is_empty() {
            return None;
        }
        Some(match self {
            MotionsScore::Sum => (weighted.iter().sum(), None),
            MotionsScore::Worst => {
                let mut active = 0;
                for (i, &value) in weighted.iter().enumerate() {
                    if value > weighted[active] {
                        active = i;
                    }
                }
                (weighted[active], Some(active))
            }
        })
    }
}

/// One motion of a task as a task of its own: its name, its weight and the single-motion task
/// it is.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionTask {
    /// The entry's name.
    pub name: String,
    /// Its weight w_i.
    pub weight: f64,
    /// The task with the entry's fields over its `motion` and payload, and no `motions` list.
    pub task: Task,
}

impl Task {
    /// Whether the task lists several motions (a `motions` list).
    pub fn has_motions(&self) -> bool {
        !self.motions.is_empty()
    }

    /// Each motion of the `motions` list as a task of its own, in the list's order (empty for
    /// a task without the list): the entry's fields over the task's `motion`, its payload over
    /// `payload.mass_kg`.
    pub fn motion_tasks(&self) -> Vec<MotionTask> {
        (self.motions.iter())
            .map(|entry| MotionTask {
                name: entry.name.clone(),
                weight: entry.weight,
                task: self.one_motion(entry),
            })
            .collect()
    }

    /// The task of `entry`: this task with its fields applied, and no list.
    fn one_motion(&self, entry: &MotionEntry) -> Task {
        let base = &self.motion;
        let mut task = self.clone();
        task.motions = Vec::new();
        task.motions_score = MotionsScore::default();
        task.motion = Motion {
            start: entry.start.clone().unwrap_or_else(|| base.start.clone()),
            goal: entry.goal.clone().unwrap_or_else(|| base.goal.clone()),
            horizon: entry.horizon.unwrap_or(base.horizon),
            steps: entry.steps.unwrap_or(base.steps),
            ends: entry.ends.unwrap_or(base.ends),
            via: entry.via.clone().unwrap_or_else(|| base.via.clone()),
            upright: entry.upright.clone().or_else(|| base.upright.clone()),
        };
        if let Some(kg) = entry.payload_kg {
            task.payload.mass_kg = kg;
        }
        task
    }

    /// Checks the `motions` list and `motions_score`: a list not empty, names unique, not blank
    /// and at most [`MAX_MOTION_NAME`] characters, weights within [0, 1e6] and not all 0,
    /// payloads within range, end points with as many joints as `motion.start`, and each
    /// motion's own fields; the error names the entry's field (`motions[1].weight`).
    pub(super) fn validate_motions(&self) -> Result<(), FieldError> {
        if self.motions.is_empty() {
            if !self.motions_score.is_sum() {
                return Err(FieldError::new(
                    "motions_score",
                    format!(
                        " = {}: scores a motions list, and the task has none",
                        self.motions_score.name()
                    ),
                ));
            }
            return Ok(());
        }
        for (i, entry) in self.motions.iter().enumerate() {
            let field = format!("motions[{i}]");
            self.check_entry(&field, entry)?;
            if let Some(j) = self.motions[..i].iter().position(|e| e.name == entry.name) {
                return Err(FieldError::new(
                    format!("{field}.name"),
                    format!(
                        " = {:?} is the name of motions[{j}] too: each motion needs its own",
                        entry.name
                    ),
                ));
            }
            self.one_motion(entry).motion.validate(&field)?;
        }
        if self.motions.iter().all(|entry| entry.weight == 0.0) {
            return Err(FieldError::new(
                "motions",
                ": every weight is 0, so every design would score 0; give a motion a positive \
                 weight",
            ));
        }
        Ok(())
    }

    /// Checks one entry's name, weight, payload and joint counts; `field` names it.
    fn check_entry(&self, field: &str, entry: &MotionEntry) -> Result<(), FieldError> {
        let name = &entry.name;
        let blank = name.trim().is_empty() || name.trim() != name;
        if blank || name.chars().count() > MAX_MOTION_NAME || name.chars().any(char::is_control) {
            return Err(FieldError::new(
                format!("{field}.name"),
                format!(
                    " = {name:?} must be 1 to {MAX_MOTION_NAME} characters, without control \
                     characters or spaces at its ends"
                ),
            ));
        }
        let weight = Bounds {
            zero: true,
            least: f64::MIN_POSITIVE,
            most: MAX_WEIGHT,
            unit: "",
            why: "how much a motion counts: 0 or more, at most a million as every weight of a \
                  task; positive ones below 2.2e-308 are subnormal",
        };
        weight.check(&format!("{field}.weight"), entry.weight)?;
        if let Some(kg) = entry.payload_kg {
            check_payload(kg)
                .map_err(|why| FieldError::out_of_range(&format!("{field}.payload_kg"), kg, why))?;
        }
        let joints = self.motion.start.len();
        if let Some(goal) = &entry.goal {
            goal.validate(&format!("{field}.goal"))?;
        }
        let goal = entry
            .goal
            .as_ref()
            .and_then(|goal| goal.joints().map(<[f64]>::to_vec));
        let points = [("start", &entry.start), ("goal", &goal)];
        for (key, point) in points {
            if let Some(point) = point.as_ref().filter(|p| p.len() != joints) {
                return Err(FieldError::new(
                    format!("{field}.{key}"),
                    format!(" has {} joints but motion.start has {joints}", point.len()),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::{TaskFile, TaskSource, BUILT_IN_TASK};

    /// The built-in task with `extra` (top-level fields, JSON) added.
    fn with(extra: &str) -> Result<TaskFile, String> {
        let text = BUILT_IN_TASK.replacen('{', &format!("{{ {extra},"), 1);
        TaskFile::from_text(&text, "test", std::path::Path::new("."))
            .map_err(|e| e.to_string())
            .map(|file| TaskFile {
                task: Task {
                    robot: None,
                    ..file.task
                },
                ..file
            })
    }

    #[test]
    fn entries_override_the_tasks_motion_and_payload() {
        let file = with(
            r#""motions": [
                {"name": "low", "goal": [-3.0, -1.5, -1.5, 0.0], "payload_kg": 1.0},
                {"name": "slow", "weight": 2, "horizon_s": 1.2, "steps": 20, "ends": "rest"}
            ], "motions_score": "worst""#,
        )
        .unwrap();
        let task = &file.task;
        assert!(task.has_motions());
        assert_eq!(task.motions_score, MotionsScore::Worst);
        let each = task.motion_tasks();
        assert_eq!(each.len(), 2);
        assert_eq!((each[0].name.as_str(), each[0].weight), ("low", 1.0));
        assert_eq!(each[0].task.motion.goal, vec![-3.0, -1.5, -1.5, 0.0].into());
        assert_eq!(each[0].task.motion.start, task.motion.start);
        assert_eq!(each[0].task.payload.mass_kg, 1.0);
        assert_eq!(each[1].weight, 2.0);
        assert_eq!(each[1].task.payload.mass_kg, task.payload.mass_kg);
        assert_eq!(each[1].task.motion.horizon, Horizon::Fixed(1.2));
        assert_eq!(each[1].task.motion.steps, 20);
        assert_eq!(each[1].task.motion.ends, Ends::Rest);
        assert!(each.iter().all(|m| !m.task.has_motions()));
        // Written and read again, the task is the same.
        let json = serde_json::to_string(task).unwrap();
        assert_eq!(&serde_json::from_str::<Task>(&json).unwrap(), task);
    }

    #[test]
    fn an_entry_gives_its_own_via_points_and_upright_link() {
        let file = with(
            r#""motions": [
                {"name": "through", "via": [{"t_s": 0.4, "tcp": [0.0, -0.7, -0.1], "tol_m": 0.01}]},
                {"name": "level", "upright": {"link": "link_4", "axis": [0, 0, 1], "tol_rad": 3}}
            ]"#,
        )
        .unwrap();
        let each = file.task.motion_tasks();
        assert_eq!(each[0].task.motion.via.len(), 1);
        assert_eq!(each[0].task.motion.upright, None);
        assert!(each[1].task.motion.via.is_empty());
        assert_eq!(each[1].task.motion.upright.as_ref().unwrap().link, "link_4");
        let bad = with(
            r#""motions": [{"name": "a", "via": [{"t_s": 0.4, "tcp": [0, 0, 0], "tol_m": 0}]}]"#,
        );
        let error = bad.unwrap_err();
        assert!(error.contains("motions[0].via[0].tol_m = 0"), "{error}");
    }

    #[test]
    fn a_task_without_motions_writes_neither_key() {
        let task = Task::built_in().unwrap();
        assert!(!task.has_motions() && task.motion_tasks().is_empty());
        let json = serde_json::to_string(&task).unwrap();
        assert!(!json.contains("motions"), "{json}");
    }

    #[test]
    fn bad_lists_are_named_by_their_field() {
        let cases = [
            (
                r#""motions": []"#,
                "motions at line 1: an empty list; a task of one motion leaves `motions` out",
            ),
            (
                r#""motions": [{"name": "a"}, {"name": "a"}]"#,
                "motions[1].name = \"a\" is the name of motions[0] too",
            ),
            (
                r#""motions": [{"name": "a", "weight": -1}]"#,
                "motions[0].weight = -1 must be >= 0",
            ),
            (
                r#""motions": [{"name": "a", "weight": 0}]"#,
                "motions: every weight is 0",
            ),
            (
                r#""motions": [{"name": "a", "start": [0, 0]}]"#,
                "motions[0].start has 2 joints but motion.start has 4",
            ),
            (
                r#""motions": [{"name": " a"}]"#,
                "motions[0].name = \" a\" must be 1 to 64 characters",
            ),
            (
                r#""motions": [{"name": "a", "payload_kg": -1}]"#,
                "motions[0].payload_kg = -1",
            ),
            (
                r#""motions": [{"name": "a", "steps": 0}]"#,
                "motions[0].steps = 0: the number of intervals",
            ),
            (
                r#""motions": [{"name": "a", "horizon_s": 1e9}]"#,
                "motions[0].horizon_s = 1000000000",
            ),
            (
                r#""motions": [{"name": "a", "speed": 1}]"#,
                "unknown field `speed`",
            ),
            (r#""motions_score": "worst""#, "motions_score = worst"),
            (
                r#""motions": [{"name": "a"}], "motions_score": "best""#,
                "unknown variant `best`",
            ),
        ];
        for (extra, expected) in cases {
            let message = with(extra).unwrap_err();
            assert!(message.contains(expected), "{extra}: {message}");
        }
        assert_eq!(TaskSource::BuiltIn.to_string(), "built-in task");
    }

    #[test]
    fn the_sum_adds_in_order_and_the_worst_names_the_first_maximum() {
        assert_eq!(MotionsScore::Sum.combine(&[]), None);
        assert_eq!(
            MotionsScore::Sum.combine(&[1.0, 2.5, 0.25]),
            Some((3.75, None))
        );
        assert_eq!(
            MotionsScore::Worst.combine(&[1.0, 2.5, 2.5]),
            Some((2.5, Some(1)))
        );
    }
}

//! What `check` finds of a task as a whole: its one inspection, or one per motion of its
//! `motions` list, each motion inspected as a task of one motion with its robot carrying that
//! motion's payload.

use super::Inspection;
use codesign_core::model::task::Task;
use codesign_core::model::Robot;
use codesign_core::text::number;
use serde::Serialize;

/// The inspection of one motion of a task's `motions` list.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MotionInspection {
    /// The motion's name.
    pub motion: String,
    /// Its weight w_i.
    pub weight: f64,
    /// Its inspection, as a task of one motion.
    #[serde(flatten)]
    pub inspection: Inspection,
}

/// The inspection of a task: one, or one per motion (written as a JSON object, or as a list of
/// objects each with its `motion` and `weight`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum TaskInspection {
    /// A task of one motion.
    One(Box<Inspection>),
    /// A task with a `motions` list, in its order.
    Motions(Vec<MotionInspection>),
}

impl TaskInspection {
    /// Inspects `task` on `robot` at `ratios` (None: the original design), each motion of a
    /// `motions` list in turn; see [`Inspection::of_task`].
    pub fn of(
        task: &Task,
        robot: &Robot,
        ratios: Option<&[f64]>,
        hold_tolerance_nm: f64,
    ) -> Result<TaskInspection, String> {
        if !task.has_motions() {
            return Inspection::of_task(task, robot, ratios, hold_tolerance_nm)
                .map(|one| TaskInspection::One(Box::new(one)));
        }
        (task.motion_tasks().into_iter())
            .map(|motion| {
                let robot = robot.with_payload(motion.task.payload.mass_kg);
                let inspection =
                    Inspection::of_task(&motion.task, &robot, ratios, hold_tolerance_nm)
                        .map_err(|e| format!("motion {}: {e}", motion.name))?;
                Ok(MotionInspection {
                    motion: motion.name,
                    weight: motion.weight,
                    inspection,
                })
            })
            .collect::<Result<_, String>>()
            .map(TaskInspection::Motions)
    }

    /// The inspection as text: each motion's under its name and weight.
    pub fn to_text(&self) -> String {
        match self {
            TaskInspection::One(inspection) => inspection.to_text(),
            TaskInspection::Motions(motions) => (motions.iter())
                .map(|m| {
                    let head = format!("motion {} (weight {}):\n", m.motion, number(m.weight));
                    head + &m.inspection.to_text()
                })
                .collect(),
        }
    }

    /// Every problem found, each motion's prefixed with `motion NAME: `.
    pub fn problems(&self) -> Vec<String> {
        self.findings(|inspection| &inspection.problems)
    }

    /// Every warning found, each motion's prefixed with `motion NAME: `.
    pub fn warnings(&self) -> Vec<String> {
        self.findings(|inspection| &inspection.warnings)
    }

    /// The findings `of` each inspection gives, named by motion.
    fn findings(&self, of: impl Fn(&Inspection) -> &Vec<String>) -> Vec<String> {
        match self {
            TaskInspection::One(inspection) => of(inspection).clone(),
            TaskInspection::Motions(motions) => (motions.iter())
                .flat_map(|m| {
                    of(&m.inspection)
                        .iter()
                        .map(|f| format!("motion {}: {f}", m.motion))
                })
                .collect(),
        }
    }
}

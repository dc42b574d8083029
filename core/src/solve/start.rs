//! A warm start kept outside the process: the raw solution of one solve (its primal point and
//! IPOPT's multipliers) with what says which problem it belongs to, and the checks that it fits
//! another solve's problem before IPOPT sees it. `codesign solve --out` writes one into its
//! result (`start_point`) and `solve --start` reads it back; a binding can do the same.

use crate::ipopt::{Solution, Status, Timing};
use crate::problem::{Formulation, ProblemKind, Space};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The raw solution of a solve, kept to start a solve of the same problem from: the primal
/// point x and IPOPT's multipliers (in IPOPT's sign convention), with the task hash, space,
/// kind and steps of the problem they belong to. Another design or payload of that problem is
/// the warm start's purpose; another problem is refused by [`StartPoint::check_fits`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StartPoint {
    /// The task hash of the task solved (`model::identity::task_hash`).
    pub task_hash: String,
    /// Joint or actuation space.
    pub space: Space,
    /// The problem the point is of: hard, or elastic (with its slacks among the variables).
    pub kind: ProblemKind,
    /// The number of intervals N.
    pub steps: usize,
    /// IPOPT's return status of the solve the point ended (an infeasible design's: of its
    /// last hard solve).
    #[serde(with = "status_name")]
    pub status: Status,
    /// The primal point, in the order of the problem's variables (`problem::Layout`).
    pub x: Vec<f64>,
    /// The constraint multipliers, one per constraint row.
    pub lambda: Vec<f64>,
    /// The multipliers of the variables' lower bounds, one per variable, >= 0.
    pub z_lower: Vec<f64>,
    /// The multipliers of the variables' upper bounds, one per variable, >= 0.
    pub z_upper: Vec<f64>,
}

impl StartPoint {
    /// The start point of `solution`, a solve of `formulation`'s problem (the kind included) for
    /// the task of hash `task_hash`.
    pub fn from_solution(
        solution: &Solution,
        formulation: &Formulation,
        task_hash: &str,
    ) -> StartPoint {
        StartPoint {
            task_hash: task_hash.to_owned(),
            space: formulation.space(),
            kind: formulation.kind(),
            steps: formulation.task().motion.steps,
            status: solution.status,
            x: solution.x.clone(),
            lambda: solution.lambda.clone(),
            z_lower: solution.z_lower.clone(),
            z_upper: solution.z_upper.clone(),
        }
    }

    /// The point as IPOPT's warm start takes it (`solve::solve_design_from`): x and the
    /// multipliers as kept. It is a start, not a solve's outcome: g is empty, the objective NaN,
    /// the iterations and times zero.
    pub fn to_solution(&self) -> Solution {
        Solution {
            status: self.status,
            x: self.x.clone(),
            g: Vec::new(),
            lambda: self.lambda.clone(),
            z_lower: self.z_lower.clone(),
            z_upper: self.z_upper.clone(),
            objective: f64::NAN,
            iterations: 0,
            timing: Timing::default(),
            outside_domain: None,
        }
    }

    /// Checks that the point can start a solve of `formulation`'s problem for the task of hash
    /// `task_hash`: the same task, space, kind and steps, arrays of the problem's sizes (the
    /// limit modes and the ends set the rows), finite values and bound multipliers >= 0. The
    /// design and the payload may differ: that is what a warm start is for.
    pub fn check_fits(&self, formulation: &Formulation, task_hash: &str) -> Result<(), StartError> {
        if self.task_hash != task_hash {
            return Err(StartError::Task {
                start: self.task_hash.clone(),
                this: task_hash.to_owned(),
            });
        }
        if self.space != formulation.space() {
            return Err(StartError::Space {
                start: self.space,
                this: formulation.space(),
            });
        }
        if self.kind != formulation.kind() {
            return Err(StartError::Kind {
                start: self.kind,
                this: formulation.kind(),
            });
        }
        let steps = formulation.task().motion.steps;
        if self.steps != steps {
            return Err(StartError::Steps {
                start: self.steps,
                this: steps,
            });
        }
        self.check_sizes(formulation)?;
        self.check_values()
    }

    /// The parts of the point by name, each with the size `formulation`'s problem gives it.
    fn parts(&self, formulation: &Formulation) -> [(StartPart, &[f64], usize); 4] {
        let layout = formulation.layout();
        let (n, m) = (layout.num_variables(), layout.num_constraints());
        [
            (StartPart::X, &self.x, n),
            (StartPart::Lambda, &self.lambda, m),
            (StartPart::ZLower, &self.z_lower, n),
            (StartPart::ZUpper, &self.z_upper, n),
        ]
    }

    /// Every part has the length of its kind in `formulation`'s problem.
    fn check_sizes(&self, formulation: &Formulation) -> Result<(), StartError> {
        for (part, values, size) in self.parts(formulation) {
            if values.len() != size {
                return Err(StartError::Length {
                    part,
                    start: values.len(),
                    this: size,
                });
            }
        }
        Ok(())
    }

    /// Every value is finite, and no bound multiplier is negative.
    fn check_values(&self) -> Result<(), StartError> {
        let parts = [
            (StartPart::X, &self.x),
            (StartPart::Lambda, &self.lambda),
            (StartPart::ZLower, &self.z_lower),
            (StartPart::ZUpper, &self.z_upper),
        ];
        for (part, values) in parts {
            if let Some(index) = values.iter().position(|v| !v.is_finite()) {
                let value = values[index];
                return Err(StartError::NotFinite { part, index, value });
            }
            let bound = matches!(part, StartPart::ZLower | StartPart::ZUpper);
            if let Some(index) = values.iter().position(|&v| bound && v < 0.0) {
                let value = values[index];
                return Err(StartError::NegativeMultiplier { part, index, value });
            }
        }
        Ok(())
    }
}

/// An array of a [`StartPoint`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StartPart {
    /// The primal point.
    X,
    /// The constraint multipliers.
    Lambda,
    /// The lower bounds' multipliers.
    ZLower,
    /// The upper bounds' multipliers.
    ZUpper,
}

impl StartPart {
    /// Its key in a file: `x`, `lambda`, `z_lower`, `z_upper`.
    pub fn name(self) -> &'static str {
        match self {
            StartPart::X => "x",
            StartPart::Lambda => "lambda",
            StartPart::ZLower => "z_lower",
            StartPart::ZUpper => "z_upper",
        }
    }

    /// What one entry stands for, in the plural: `variables` or `constraint rows`.
    fn entries(self) -> &'static str {
        match self {
            StartPart::Lambda => "constraint rows",
            _ => "variables",
        }
    }
}

/// Why a [`StartPoint`] cannot start a solve ([`StartPoint::check_fits`]): each names what
/// the start has and what this solve has.
#[derive(Clone, Debug, PartialEq)]
pub enum StartError {
    /// The start belongs to another task (by task hash).
    Task {
        /// The start's task hash.
        start: String,
        /// This solve's.
        this: String,
    },
    /// The start is of the other space.
    Space {
        /// The start's space.
        start: Space,
        /// This solve's.
        this: Space,
    },
    /// The start is of the other kind of problem (hard or elastic).
    Kind {
        /// The start's kind.
        start: ProblemKind,
        /// This solve's.
        this: ProblemKind,
    },
    /// The start has another number of intervals.
    Steps {
        /// The start's steps.
        start: usize,
        /// This solve's.
        this: usize,
    },
    /// An array of the start is not of this problem's size (other limit modes or ends, or a
    /// file cut or edited).
    Length {
        /// Which array.
        part: StartPart,
        /// Its length.
        start: usize,
        /// The length this problem takes.
        this: usize,
    },
    /// A value of the start is not finite.
    NotFinite {
        /// Which array.
        part: StartPart,
        /// The entry.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A bound multiplier of the start is negative.
    NegativeMultiplier {
        /// Which array.
        part: StartPart,
        /// The entry.
        index: usize,
        /// Its value.
        value: f64,
    },
}

impl fmt::Display for StartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StartError::Task { start, this } => write!(
                f,
                "the start was solved for another task (task hash {start}, this solve's {this}; \
                 the hash covers the task's content, its robot and its ends)"
            ),
            StartError::Space { start, this } => write!(
                f,
                "the start was solved in the {start} space, this solve is in the {this} space"
            ),
            StartError::Kind { start, this } => write!(
                f,
                "the start is a point of the {start} problem, this solve poses the {this} problem"
            ),
            StartError::Steps { start, this } => write!(
                f,
                "the start was solved on {start} steps, this solve on {this}"
            ),
            StartError::Length { part, start, this } => write!(
                f,
                "the start's {} has {start} entries, this problem {this} {} (other limit modes \
                 or ends?)",
                part.name(),
                part.entries()
            ),
            StartError::NotFinite { part, index, value } => write!(
                f,
                "the start's {}[{index}] is {value}, not a finite number",
                part.name()
            ),
            StartError::NegativeMultiplier { part, index, value } => write!(
                f,
                "the start's {}[{index}] is {value}: a bound multiplier is never negative",
                part.name()
            ),
        }
    }
}

impl std::error::Error for StartError {}

/// [`Status`] in a file as IPOPT's own name of it (`Solve_Succeeded`).
mod status_name {
    use crate::ipopt::Status;
    use serde::de::Error;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(status: &Status, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&status.name())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Status, D::Error> {
        let text = String::deserialize(deserializer)?;
        Status::from_name(&text)
            .ok_or_else(|| D::Error::custom(format!("{text:?} is no IPOPT status")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    /// A start point of the sizes of `formulation`'s problem, as a solve of it would give.
    fn point_of(formulation: &Formulation) -> StartPoint {
        let layout = formulation.layout();
        let (n, m) = (layout.num_variables(), layout.num_constraints());
        let solution = Solution {
            status: Status::SolveSucceeded,
            x: (0..n).map(|i| i as f64 * 1e-3).collect(),
            g: vec![0.0; m],
            lambda: vec![-0.5; m],
            z_lower: vec![0.0; n],
            z_upper: vec![1e-9; n],
            objective: 1.0,
            iterations: 12,
            timing: Timing::default(),
            outside_domain: None,
        };
        StartPoint::from_solution(&solution, formulation, "0123456789abcdef")
    }

    #[test]
    fn a_start_fits_its_own_problem_at_another_payload_and_reads_back() {
        let formulation = testing::formulation(0.0, Space::Actuation);
        let point = point_of(&formulation);
        assert_eq!(point.kind, ProblemKind::Hard);
        let heavier = testing::formulation(2.0, Space::Actuation);
        assert_eq!(point.check_fits(&heavier, "0123456789abcdef"), Ok(()));
        let solution = point.to_solution();
        assert_eq!(
            (solution.x.len(), solution.lambda),
            (point.x.len(), point.lambda.clone())
        );
        let text = serde_json::to_string(&point).unwrap();
        assert!(text.contains(r#""status":"Solve_Succeeded""#), "{text}");
        assert!(text.contains(r#""kind":"hard""#), "{text}");
        let back: StartPoint = serde_json::from_str(&text).unwrap();
        assert_eq!(back, point);
        let renamed = text.replace("Solve_Succeeded", "Solved");
        let error = serde_json::from_str::<StartPoint>(&renamed).unwrap_err();
        assert!(error.to_string().contains("is no IPOPT status"), "{error}");
    }

    #[test]
    fn a_start_of_another_problem_is_refused_naming_both() {
        let formulation = testing::formulation(0.0, Space::Actuation);
        let point = point_of(&formulation);
        let refused = |fits: Result<(), StartError>| fits.unwrap_err().to_string();
        assert_eq!(
            refused(point.check_fits(&formulation, "fedcba9876543210")),
            "the start was solved for another task (task hash 0123456789abcdef, this solve's \
             fedcba9876543210; the hash covers the task's content, its robot and its ends)"
        );
        let joint = testing::formulation(0.0, Space::Joint);
        assert_eq!(
            refused(point.check_fits(&joint, &point.task_hash)),
            "the start was solved in the actuation space, this solve is in the joint space"
        );
        assert_eq!(
            refused(point.check_fits(&formulation.elastic(), &point.task_hash)),
            "the start is a point of the hard problem, this solve poses the elastic problem"
        );
        let mut task = testing::task();
        task.motion.steps = 10;
        let robot = crate::model::Robot::load(&task).unwrap();
        let short = Formulation::new(&task, robot, Space::Actuation, task.limit_modes).unwrap();
        assert_eq!(
            refused(point.check_fits(&short, &point.task_hash)),
            format!(
                "the start was solved on {} steps, this solve on 10",
                point.steps
            )
        );
    }

    #[test]
    fn a_start_cut_or_spoilt_is_refused_naming_the_entry() {
        let formulation = testing::formulation(0.0, Space::Actuation);
        let hash = "0123456789abcdef";
        let mut cut = point_of(&formulation);
        let rows = cut.lambda.len();
        cut.lambda.pop();
        let error = cut.check_fits(&formulation, hash).unwrap_err();
        assert_eq!(
            error,
            StartError::Length {
                part: StartPart::Lambda,
                start: rows - 1,
                this: rows
            }
        );
        assert!(error.to_string().contains("constraint rows"), "{error}");
        let mut spoilt = point_of(&formulation);
        spoilt.x[7] = f64::NAN;
        let error = spoilt.check_fits(&formulation, hash).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the start's x[7] is NaN, not a finite number"
        );
        let mut negative = point_of(&formulation);
        negative.z_upper[3] = -1.0;
        assert!(matches!(
            negative.check_fits(&formulation, hash),
            Err(StartError::NegativeMultiplier {
                part: StartPart::ZUpper,
                index: 3,
                ..
            })
        ));
    }
}

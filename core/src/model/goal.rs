//! The goal of a motion (`motion.goal`, docs/model.md, section 6): joint angles that fix the last
//! node's pose, or a TCP position in the world with a radius, which leaves the last node's joint
//! angles free within the joint limits and holds the TCP inside the ball there.

use super::ranges::{FieldError, MAX_POINT_M};
use super::via::MIN_TOL_M;
use crate::text::number;
use serde::{Deserialize, Serialize};

/// Where the motion ends: joint angles, or a TCP position within a tolerance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged, try_from = "GoalWritten")]
pub enum Goal {
    /// Joint positions at t = T, rad (m for a prismatic joint), one per moving joint.
    Joints(Vec<f64>),
    /// A TCP position at t = T.
    Tcp(TcpGoal),
}

/// A TCP position the motion ends at: |p(q_N) - tcp| <= tol_m, p the TCP's world position.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TcpGoal {
    /// The point in the world frame, m.
    pub tcp: [f64; 3],
    /// The radius of the ball around it, m, at least [`MIN_TOL_M`].
    pub tol_m: f64,
}

/// A goal as written, before it is known which kind it is.
#[derive(Deserialize)]
#[serde(untagged)]
enum GoalWritten {
    Joints(Vec<f64>),
    Other(serde_json::Value),
}

impl TryFrom<GoalWritten> for Goal {
    type Error = String;

    fn try_from(written: GoalWritten) -> Result<Goal, String> {
        match written {
            GoalWritten::Joints(q) => Ok(Goal::Joints(q)),
            GoalWritten::Other(value) => {
                serde_json::from_value(value).map(Goal::Tcp).map_err(|e| {
                    format!(
                    "a goal is a list of joint angles (rad) or {{\"tcp\": [x, y, z], \"tol_m\": \
                     tol}} (a TCP position in the world, m): {e}"
                )
                })
            }
        }
    }
}

impl From<Vec<f64>> for Goal {
    fn from(q: Vec<f64>) -> Goal {
        Goal::Joints(q)
    }
}

impl Goal {
    /// The joint angles of a joint goal, None for a TCP goal.
    pub fn joints(&self) -> Option<&[f64]> {
        match self {
            Goal::Joints(q) => Some(q),
            Goal::Tcp(_) => None,
        }
    }

    /// The joint angles of a joint goal, to change them; None for a TCP goal.
    pub fn joints_mut(&mut self) -> Option<&mut Vec<f64>> {
        match self {
            Goal::Joints(q) => Some(q),
            Goal::Tcp(_) => None,
        }
    }

    /// The TCP goal, None for joint angles.
    pub fn tcp(&self) -> Option<&TcpGoal> {
        match self {
            Goal::Joints(_) => None,
            Goal::Tcp(goal) => Some(goal),
        }
    }

    /// The joint angles, or an error naming `field` (`motion.goal`) saying that `what` needs
    /// them, for the parts of the tool that read the goal as a pose.
    pub fn joints_for(&self, field: &str, what: &str) -> Result<&[f64], FieldError> {
        self.joints().ok_or_else(|| {
            FieldError::new(
                field,
                format!(
                    " is a TCP position, but {what} needs the goal as joint angles (a list of \
                     one angle per joint)"
                ),
            )
        })
    }

    /// Checks its numbers, `field` naming it (`motion.goal`): finite angles, or a finite point
    /// within [`MAX_POINT_M`] of the origin and a radius from [`MIN_TOL_M`] to [`MAX_POINT_M`].
    pub(super) fn validate(&self, field: &str) -> Result<(), FieldError> {
        let finite = |name: String, values: &[f64]| match values.iter().position(|v| !v.is_finite())
        {
            Some(i) => Err(FieldError::new(
                format!("{name}[{i}]"),
                " is not a finite number",
            )),
            None => Ok(()),
        };
        let goal = match self {
            Goal::Joints(q) => return finite(field.to_owned(), q),
            Goal::Tcp(goal) => goal,
        };
        finite(format!("{field}.tcp"), &goal.tcp)?;
        if goal.tcp.iter().map(|p| p * p).sum::<f64>().sqrt() > MAX_POINT_M {
            return Err(FieldError::new(
                format!("{field}.tcp"),
                format!(" lies farther than {MAX_POINT_M} m from the world's origin"),
            ));
        }
        if !(goal.tol_m.is_finite() && goal.tol_m >= MIN_TOL_M && goal.tol_m <= MAX_POINT_M) {
            return Err(FieldError::new(
                format!("{field}.tol_m"),
                format!(
                    " = {} must be from {MIN_TOL_M} to {MAX_POINT_M} m (a ball of radius 0 has \
                     no interior, and its row's gradient vanishes at its centre)",
                    number(goal.tol_m)
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_goal_reads_as_joints_or_tcp_and_writes_back() {
        for text in [r#"[0.0,1.0]"#, r#"{"tcp":[0.1,0.2,0.3],"tol_m":0.005}"#] {
            let goal: Goal = serde_json::from_str(text).unwrap();
            assert_eq!(serde_json::to_string(&goal).unwrap(), text);
        }
        for bad in [
            r#"{"tcp":[0.1,0.2,0.3]}"#,
            r#"{"tcp":[0.1,0.2,0.3],"tol_m":0.1,"x":1}"#,
            r#""up""#,
        ] {
            let error = serde_json::from_str::<Goal>(bad).unwrap_err().to_string();
            assert!(
                error.starts_with("a goal is a list of joint angles"),
                "{bad}: {error}"
            );
        }
    }

    #[test]
    fn a_tcp_goals_numbers_are_checked_naming_their_fields() {
        let tcp = |tcp, tol_m| Goal::Tcp(TcpGoal { tcp, tol_m });
        for (goal, field) in [
            (tcp([0.0; 3], 0.0), "motion.goal.tol_m = 0 must be"),
            (tcp([0.0; 3], 1e-7), "motion.goal.tol_m = "),
            (tcp([f64::NAN, 0.0, 0.0], 0.01), "motion.goal.tcp[0]"),
            (tcp([1e6, 0.0, 0.0], 0.01), "motion.goal.tcp lies farther"),
            (Goal::Joints(vec![0.0, f64::INFINITY]), "motion.goal[1]"),
        ] {
            let error = goal.validate("motion.goal").unwrap_err().to_string();
            assert!(error.starts_with(field), "{error}");
        }
        assert!(tcp([0.1, 0.2, 0.3], 1e-6).validate("motion.goal").is_ok());
        let error = (tcp([0.0; 3], 0.01).joints_for("motion.goal", "the mechanism's check"))
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with("motion.goal is a TCP position"),
            "{error}"
        );
    }
}

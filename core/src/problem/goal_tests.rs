//! Tests of a TCP goal (`motion.goal` as `{"tcp", "tol_m"}`, docs/model.md, section 6): its row's
//! derivatives against central differences and IPOPT's checker, in both spaces and kinds, for a
//! constant transmission (the built-in arm) and a linkage (the planar example's four-bar); a
//! solve whose goal is the joint goal's TCP within a tiny ball costs no more than the joint
//! goal; the inverse kinematics' pose of the guess; the refusal of a bad goal, naming its field.

use super::tests::{assert_checker_finds_nothing, assert_derivatives_match};
use super::*;
use crate::dynamics::Dynamics;
use crate::model::task::{Goal, LimitMode, LimitModes, Task, TcpGoal};
use crate::model::Robot;
use crate::solve::{solve_design, SolveSettings};
use crate::testing;
use std::path::Path;

/// `task` with its goal replaced by the TCP of its joint goal moved by `offset`, m, within
/// `tol_m`.
fn with_tcp_goal(mut task: Task, offset: [f64; 3], tol_m: f64) -> Task {
    let dynamics = Dynamics::new(Robot::load(&task).unwrap());
    let goal = task.motion.goal.joints().unwrap();
    let p = dynamics.tcp_position(&mut dynamics.workspace(), goal);
    let tcp = [p.x + offset[0], p.y + offset[1], p.z + offset[2]];
    task.motion.goal = Goal::Tcp(TcpGoal { tcp, tol_m });
    task
}

/// `task`'s formulations in both spaces (the joint space under the modes `exact`), hard and
/// elastic.
fn formulations(task: &Task) -> Vec<Formulation> {
    let exact = LimitModes {
        torque: LimitMode::Exact,
        speed: LimitMode::Exact,
    };
    let mut list = Vec::new();
    for (space, modes) in [(Space::Actuation, task.limit_modes), (Space::Joint, exact)] {
        let robot = Robot::load(task).unwrap();
        let hard = Formulation::new(task, robot, space, modes).unwrap();
        list.push(hard.elastic());
        list.push(hard);
    }
    list
}

/// The built-in arm at 1 kg and the planar example's four-bar elbow, on 5 steps, each with a
/// TCP goal 3 cm off its joint goal's TCP within 1 cm (so that the row's d is not 0).
fn cases() -> Vec<(Formulation, Vec<f64>)> {
    let mut arm = testing::task();
    (arm.payload.mass_kg, arm.motion.steps) = (1.0, 5);
    let arm = with_tcp_goal(arm, [0.02, -0.02, 0.01], 0.01);
    let path = testing::repository().join("robots/examples/planar_2dof/four_bar.json");
    let mut four_bar = Task::load(&path).unwrap();
    four_bar.motion.steps = 5;
    let four_bar = with_tcp_goal(four_bar, [0.03, 0.0, -0.01], 0.01);
    let arm = formulations(&arm).into_iter();
    let four_bar = formulations(&four_bar).into_iter();
    (arm.map(|f| (f, vec![7.0, 4.0, 2.0, 1.5])))
        .chain(four_bar.map(|f| (f, vec![50.0, 60.0, 10.0])))
        .collect()
}

#[test]
fn the_goal_row_sits_at_the_last_node_with_a_rows_block() {
    for (f, _) in cases() {
        let layout = f.layout();
        let rows: Vec<usize> = (0..layout.steps)
            .filter(|&k| layout.first_row(FamilyId::Goal, k).is_some())
            .collect();
        assert_eq!(rows, [layout.steps - 1]);
        let goal = f.setting().targets().goal.as_ref().unwrap();
        assert_eq!(goal.ball.node, layout.steps);
    }
}

#[test]
fn the_tcp_goals_derivatives_match_finite_differences() {
    for (f, design) in cases() {
        assert_derivatives_match(&f, &design);
    }
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_a_tcp_goal() {
    for (f, design) in cases() {
        assert_checker_finds_nothing(&f, &design);
    }
}

/// The joint goal's own TCP within 10 micrometres is a relaxation of the joint goal: the solve
/// ends inside the ball, at rest, and its J is no larger than the joint goal's (to the solver's
/// tolerance), in both spaces. Its guess's pose reaches the ball too.
#[test]
fn a_tcp_goal_at_the_joint_goals_tcp_costs_no_more_than_the_joint_goal() {
    let mut task = testing::task();
    (task.payload.mass_kg, task.motion.steps) = (1.0, 20);
    let design = [6.0, 3.0, 1.0, 1.0];
    let tcp_task = with_tcp_goal(task.clone(), [0.0; 3], 1e-5);
    for space in [Space::Actuation, Space::Joint] {
        let solve = |task: &Task| {
            let robot = Robot::load(task).unwrap();
            let f = Formulation::new(task, robot, space, task.limit_modes).unwrap();
            let result = solve_design(&f, &design, &SolveSettings::default()).unwrap();
            (f, result)
        };
        let (_, joint) = solve(&task);
        let (f, tcp) = solve(&tcp_task);
        assert!(joint.feasible && tcp.feasible, "{:?}", tcp.reason);
        let goal = f.setting().targets().goal.clone().unwrap();
        assert!(goal.distance_m <= 1e-5, "{}", goal.distance_m);
        let last = tcp.trajectory.q.last().unwrap();
        let p = f
            .dynamics()
            .tcp_position(&mut f.dynamics().workspace(), last);
        assert!((p - goal.ball.point).norm() <= 1e-5 + 1e-7);
        assert!(tcp.violations.get("goal_tcp").unwrap() <= 1e-7);
        assert!(tcp
            .trajectory
            .v
            .last()
            .unwrap()
            .iter()
            .all(|v| v.abs() < 1e-9));
        assert!(tcp
            .trajectory
            .a
            .last()
            .unwrap()
            .iter()
            .all(|a| a.abs() < 1e-9));
        assert!(
            tcp.cost <= joint.cost * (1.0 + 1e-6),
            "{space}: {} > {}",
            tcp.cost,
            joint.cost
        );
    }
}

#[test]
fn a_formulation_refuses_a_bad_goal_naming_its_field() {
    let mut task = testing::task();
    task.motion.goal = Goal::Joints(vec![0.0; 3]);
    let robot = Robot::load(&task).unwrap();
    let error = Formulation::new(&task, robot, Space::Actuation, task.limit_modes)
        .unwrap_err()
        .to_string();
    assert!(error.contains("motion.goal has 3 values"), "{error}");
    let goal = "[-3.141592653589793, -1.5707963267948966, -1.5707963267948966, 0.0]";
    for (written, field) in [
        (
            r#"{"tcp": [0.1, 0.2, 0.3], "tol_m": 1e-9}"#,
            "motion.goal.tol_m = 1e-9",
        ),
        (
            r#"{"tcp": [0.1, 0.2, 3000], "tol_m": 0.01}"#,
            "motion.goal.tcp lies farther",
        ),
    ] {
        let text = crate::model::task::BUILT_IN_TASK.replacen(goal, written, 1);
        let error = crate::model::task::TaskFile::from_text(&text, "test", Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(error.contains(field), "{error}");
    }
}

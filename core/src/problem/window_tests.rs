//! Tests of the via points passed within a window of time (docs/model.md, section 6): the
//! phases' steps and their derivatives in the via times and T against central differences and
//! IPOPT's checker, in both spaces and kinds, for a constant transmission and a linkage, under a
//! fixed and a free horizon; a window that lets the solve lower J; the time a result reports.

use super::tests::{assert_checker_finds_nothing, assert_derivatives_match};
use super::via_tests::{formulations, with_targets};
use super::*;
use crate::model::task::{Horizon, Task, Via, ViaTime};
use crate::model::Robot;
use crate::solve::{solve_design, solve_design_from, SolveSettings};
use crate::testing::{self, posed_task, SCREW_ROW};

/// Sets when each of `task`'s via points is passed.
fn timed(mut task: Task, times: [ViaTime; 2]) -> Task {
    for (via, time) in task.motion.via.iter_mut().zip(times) {
        match via {
            Via::Joints(via) => via.time = time,
            Via::Tcp(via) => via.time = time,
        }
    }
    task
}

/// [`with_targets`]'s task (5 steps, T0 its duration) with its via points in time order: the
/// joint via point within [0.3, 0.45] T0 and the TCP via point within [0.5, 0.7] T0 (nodes 2
/// and 3) under the fixed T0; under T free in [T0, 1.5 T0], the joint via point within the same
/// window and the TCP via point at 0.6 T0 (nodes 1 and 2 of T_max's grid), with w_T = 2 per s.
fn windowed(task: Task, link: &str) -> [Task; 2] {
    let mut task = with_targets(task, link);
    task.motion.via.reverse();
    let t0 = task.motion.horizon.fixed_s().unwrap();
    let joints = ViaTime::Within([0.3 * t0, 0.45 * t0]);
    let fixed = timed(
        task.clone(),
        [joints, ViaTime::Within([0.5 * t0, 0.7 * t0])],
    );
    let mut free = timed(task, [joints, ViaTime::At(0.6 * t0)]);
    free.motion.horizon = Horizon::Free {
        min_s: t0,
        max_s: 1.5 * t0,
    };
    free.weights.time = 2.0;
    [fixed, free]
}

/// The built-in arm at 1 kg and the planar example with a ball screw at its elbow, each under a
/// fixed and a free horizon, in both spaces and kinds.
fn cases() -> Vec<(Formulation, Vec<f64>)> {
    let mut task = testing::task();
    task.payload.mass_kg = 1.0;
    let mut screw = posed_task(SCREW_ROW);
    screw.payload.mass_kg = 0.5;
    let mut list = Vec::new();
    for (task, link, design) in [
        (task, "link_4", vec![7.0, 4.0, 2.0, 1.5]),
        (screw, "gripper", vec![50.0, 12.0]),
    ] {
        for task in windowed(task, link) {
            let each = formulations(&task).into_iter();
            list.extend(each.map(|f| (f, design.clone())));
        }
    }
    list
}

#[test]
fn the_windows_split_the_grid_at_their_nodes() {
    for (f, _) in cases() {
        let targets = f.setting().targets();
        let free = f.layout().horizon().is_some();
        assert_eq!(targets.nodes, if free { [1, 2] } else { [2, 3] });
        assert_eq!(targets.boundaries.len(), 2);
        let windows = [WindowColumn::Joint, WindowColumn::Tcp].map(|c| c.column(&f));
        assert!(windows[0].is_some());
        assert_eq!(windows[1].is_some(), !free);
    }
}

/// Which via point's time column.
enum WindowColumn {
    Joint,
    Tcp,
}

impl WindowColumn {
    fn column(&self, f: &Formulation) -> Option<usize> {
        let via = match self {
            WindowColumn::Joint => 0,
            WindowColumn::Tcp => 1,
        };
        f.layout().wide(layout::WideVariable::ViaTime(via))
    }
}

#[test]
fn the_windows_derivatives_match_finite_differences() {
    for (f, design) in cases() {
        assert_derivatives_match(&f, &design);
    }
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_via_windows() {
    for (f, design) in cases() {
        assert_checker_finds_nothing(&f, &design);
    }
}

/// A via time is a variable bounded to its window, started at its node's time on the uniform
/// grid; the copper losses, weighted by a step that is no longer a constant, are refused.
#[test]
fn a_via_time_is_bounded_to_its_window() {
    let [fixed, _] = windowed(testing::task(), "link_4");
    let f = formulations(&fixed).remove(1);
    let problem = f.problem(&[6.0, 3.0, 1.0, 1.0]).unwrap();
    let n = f.layout().num_variables();
    let (mut lower, mut upper, mut x) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    crate::ipopt::Nlp::variable_bounds(&problem, &mut lower, &mut upper);
    crate::ipopt::Nlp::initial_point(&problem, &mut x);
    let column = WindowColumn::Tcp.column(&f).unwrap();
    assert_eq!((lower[column], upper[column]), (0.5 * 0.8, 0.7 * 0.8));
    assert!((x[column] - 3.0 * 0.8 / 5.0).abs() < 1e-15);
    let error = f.minimising_copper_loss().unwrap_err().to_string();
    assert!(error.contains("a via point's window"), "{error}");
}

/// The built-in arm at 1 kg on 20 steps passes a TCP point 0.1 m above its free path at node 10:
/// at t = 0.4 s, or within [0.3, 0.5] s, which holds the time 0.4 s and so the fixed-time
/// solution. Solved from the fixed-time solution, the window gives a J no larger; the result
/// reports the time the solve chose, within the window, where the TCP passes within tol.
#[test]
fn a_window_around_a_via_time_gives_no_larger_cost() {
    let mut task = testing::task();
    task.motion.steps = 20;
    task.payload.mass_kg = 1.0;
    let design = [6.0, 3.0, 1.0, 1.0];
    let formulation = |task: &Task| {
        let robot = Robot::load(task).unwrap();
        Formulation::new(task, robot, Space::Actuation, task.limit_modes).unwrap()
    };
    let settings = SolveSettings::default();
    let free = solve_design(&formulation(&task), &design, &settings).unwrap();
    let dynamics = crate::dynamics::Dynamics::new(Robot::load(&task).unwrap());
    let mut data = dynamics.workspace();
    let passed = dynamics.tcp_position(&mut data, &free.trajectory.q[10]);
    let target = passed + nalgebra::Vector3::new(0.0, 0.0, 0.1);
    let tol = 0.01;
    let via = |time| {
        Via::Tcp(crate::model::task::TcpVia {
            time,
            tcp: target.into(),
            tol_m: tol,
        })
    };
    task.motion.via = vec![via(ViaTime::At(0.4))];
    let (at, mut warm) = solve_design_from(&formulation(&task), &design, &settings, None).unwrap();
    assert!(at.feasible, "{:?}", at.reason);
    assert_eq!(at.via_times_s, [0.4]);
    task.motion.via = vec![via(ViaTime::Within([0.3, 0.5]))];
    let f = formulation(&task);
    assert_eq!(WindowColumn::Joint.column(&f), Some(warm.x.len()));
    warm.x.push(0.4);
    warm.z_lower.push(0.0);
    warm.z_upper.push(0.0);
    let (within, _) = solve_design_from(&f, &design, &settings, Some(&warm)).unwrap();
    assert!(within.feasible, "{:?}", within.reason);
    let t = within.via_times_s[0];
    assert!((0.3..=0.5).contains(&t), "{t}");
    assert_eq!(within.trajectory.time[10], t);
    let p = dynamics.tcp_position(&mut data, &within.trajectory.q[10]);
    assert!((p - target).norm() <= tol + 1e-6);
    assert!(
        within.cost <= at.cost + 1e-9,
        "{} > {}",
        within.cost,
        at.cost
    );
    let cold = solve_design(&f, &design, &settings).unwrap();
    eprintln!(
        "J at 0.4 s: {}, within [0.3, 0.5] s: {} at t = {t} s ({} iterations), cold: {} at {} s",
        at.cost, within.cost, within.iterations, cold.cost, cold.via_times_s[0]
    );
}

/// Under a free horizon (the built-in arm's pure minimum-time problem at 0 kg, 20 steps, T in
/// [0.3, 1.2] s), a TCP via point 5 cm above the straight path's point at 0.25 s: within [0.15,
/// 0.29] s, solved from the solution at 0.25 s, the least duration is no longer, and the time
/// the solve chose lies in the window.
#[test]
fn a_window_under_a_free_horizon_gives_no_longer_minimum_time() {
    let mut task = testing::task().minimum_time();
    task.motion.steps = 20;
    task.motion.horizon = Horizon::Free {
        min_s: 0.3,
        max_s: 1.2,
    };
    let design = [6.0, 3.0, 1.0, 1.0];
    let formulation = |task: &Task| {
        let robot = Robot::load(task).unwrap();
        Formulation::new(task, robot, Space::Actuation, task.limit_modes).unwrap()
    };
    let (start, goal) = (&task.motion.start, task.motion.goal.joints().unwrap());
    let pose: Vec<f64> = (start.iter().zip(goal))
        .map(|(s, g)| 0.6 * s + 0.4 * g)
        .collect();
    let dynamics = crate::dynamics::Dynamics::new(Robot::load(&task).unwrap());
    let point = dynamics.tcp_position(&mut dynamics.workspace(), &pose);
    let target = point + nalgebra::Vector3::new(0.0, 0.0, 0.05);
    let via = |time| {
        Via::Tcp(crate::model::task::TcpVia {
            time,
            tcp: target.into(),
            tol_m: 0.01,
        })
    };
    let settings = SolveSettings::default();
    task.motion.via = vec![via(ViaTime::At(0.25))];
    let f = formulation(&task);
    assert_eq!(f.setting().targets().nodes, [4]);
    let (at, mut warm) = solve_design_from(&f, &design, &settings, None).unwrap();
    assert!(at.feasible, "{:?}", at.reason);
    assert!((at.via_times_s[0] - 0.25).abs() < 1e-15);
    task.motion.via = vec![via(ViaTime::Within([0.15, 0.29]))];
    let f = formulation(&task);
    assert_eq!(WindowColumn::Joint.column(&f), Some(warm.x.len()));
    warm.x.push(0.25);
    warm.z_lower.push(0.0);
    warm.z_upper.push(0.0);
    let (within, _) = solve_design_from(&f, &design, &settings, Some(&warm)).unwrap();
    assert!(within.feasible, "{:?}", within.reason);
    let t = within.via_times_s[0];
    assert!((0.15..=0.29).contains(&t), "{t}");
    let (t_at, t_within) = (at.horizon_s.unwrap(), within.horizon_s.unwrap());
    assert!(t_within <= t_at + 1e-9, "{t_within} > {t_at}");
    eprintln!(
        "T* with the via point at 0.25 s: {t_at}, within [0.15, 0.29] s: {t_within} (at {t} s)"
    );
}

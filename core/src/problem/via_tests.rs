//! Tests of the via points and the upright link (docs/model.md, section 6): their rows'
//! derivatives against central differences and IPOPT's checker, in both spaces and kinds, for a
//! constant transmission (the built-in arm) and a linkage (the planar example's ball screw); a
//! via point that moves the solution; the refusals of a formulation.

use super::tests::{assert_checker_finds_nothing, assert_derivatives_match};
use super::*;
use crate::dynamics::Dynamics;
use crate::model::task::{
    Horizon, JointVia, LimitMode, LimitModes, Task, TcpVia, Upright, Via, ViaTime,
};
use crate::model::Robot;
use crate::solve::{solve_design, SolveSettings};
use crate::testing::{self, posed_task, SCREW_ROW};
use nalgebra::Vector3;

/// The axis (in `link`'s frame) halfway between the link's frame's directions that the start and
/// the goal turn to the world's +z, and the angle of either from +z, rad: held upright within a
/// little more than that angle, the start and the goal are upright.
fn bisecting_axis(task: &Task, link: &str) -> ([f64; 3], f64) {
    let dynamics = Dynamics::new(Robot::load(task).unwrap());
    let frame = (dynamics.robot().chain().links.iter())
        .find(|frame| frame.name == link)
        .unwrap()
        .clone();
    let mut data = dynamics.workspace();
    let mut up = |q: &[f64]| {
        let pose = dynamics.body_pose(&mut data, q, frame.body);
        (pose.rotation * frame.placement.rotation).transpose() * Vector3::z()
    };
    let (start, goal) = (
        up(&task.motion.start),
        up(task.motion.goal.joints().unwrap()),
    );
    let axis = (start + goal).normalize();
    (axis.into(), axis.dot(&start).clamp(-1.0, 1.0).acos())
}

/// `task` on 5 steps (h = T/5) with a joint via point at node 2, a TCP via point at node 3 and
/// `link` held upright.
pub(super) fn with_targets(mut task: Task, link: &str) -> Task {
    task.motion.steps = 5;
    let horizon = task.motion.horizon.fixed_s().unwrap();
    let (start, goal) = (&task.motion.start, task.motion.goal.joints().unwrap());
    let middle: Vec<f64> = start
        .iter()
        .zip(goal)
        .map(|(s, g)| 0.4 * s + 0.6 * g)
        .collect();
    let dynamics = Dynamics::new(Robot::load(&task).unwrap());
    let tcp =
        dynamics.tcp_position(&mut dynamics.workspace(), &middle) + Vector3::new(0.0, 0.0, 0.05);
    let quarter: Vec<f64> = start
        .iter()
        .zip(goal)
        .map(|(s, g)| 0.6 * s + 0.4 * g)
        .collect();
    task.motion.via = vec![
        Via::Tcp(TcpVia {
            time: ViaTime::At(0.6 * horizon),
            tcp: tcp.into(),
            tol_m: 0.02,
        }),
        Via::Joints(JointVia {
            time: ViaTime::At(0.4 * horizon),
            q: quarter,
            tol_rad: 0.1,
        }),
    ];
    let (axis, tilt) = bisecting_axis(&task, link);
    task.motion.upright = Some(Upright {
        link: link.into(),
        axis,
        tol_rad: tilt + 0.2,
    });
    task
}

/// `task`'s formulations in both spaces (the joint space under the modes `exact`), hard and
/// elastic.
pub(super) fn formulations(task: &Task) -> Vec<Formulation> {
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

/// The built-in arm at 1 kg and the planar example with a ball screw at its elbow, each with a
/// joint and a TCP via point and a link upright.
fn cases() -> Vec<(Formulation, Vec<f64>)> {
    let mut task = testing::task();
    task.payload.mass_kg = 1.0;
    let built_in = formulations(&with_targets(task, "link_4")).into_iter();
    let mut screw = posed_task(SCREW_ROW);
    screw.payload.mass_kg = 0.5;
    let screw = formulations(&with_targets(screw, "gripper")).into_iter();
    (built_in.map(|f| (f, vec![7.0, 4.0, 2.0, 1.5])))
        .chain(screw.map(|f| (f, vec![50.0, 12.0])))
        .collect()
}

#[test]
fn the_targets_sit_on_their_nodes() {
    for (f, _) in cases() {
        let layout = f.layout();
        let via: Vec<usize> = (0..layout.steps)
            .filter(|&k| layout.first_row(FamilyId::Via, k).is_some())
            .collect();
        assert_eq!(via, [3]);
        let upright =
            (0..layout.steps).filter(|&k| layout.first_row(FamilyId::Upright, k).is_some());
        assert_eq!(upright.collect::<Vec<_>>(), [1, 2, 3, 4]);
        assert_eq!(f.setting().targets().joints[0].node, 2);
    }
}

#[test]
fn the_via_and_upright_derivatives_match_finite_differences() {
    for (f, design) in cases() {
        assert_derivatives_match(&f, &design);
    }
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_via_points_and_an_upright_link() {
    for (f, design) in cases() {
        assert_checker_finds_nothing(&f, &design);
    }
}

/// A TCP via point 0.1 m above where the solution without it passes at its node moves the
/// solution there (within tol), costs J, and the result is judged feasible by the one rule with
/// its violation measured; bounded joint via points hold their nodes' angles.
#[test]
fn a_via_point_moves_the_solution_through_it() {
    let mut task = testing::task();
    task.motion.steps = 20;
    task.payload.mass_kg = 1.0;
    let design = [6.0, 3.0, 1.0, 1.0];
    let solve = |task: &Task| {
        let robot = Robot::load(task).unwrap();
        let f = Formulation::new(task, robot, Space::Actuation, task.limit_modes).unwrap();
        solve_design(&f, &design, &SolveSettings::default()).unwrap()
    };
    let free = solve(&task);
    assert!(free.feasible);
    let dynamics = Dynamics::new(Robot::load(&task).unwrap());
    let mut data = dynamics.workspace();
    let (k, tol) = (10, 0.01);
    let passed = dynamics.tcp_position(&mut data, &free.trajectory.q[k]);
    let target = passed + Vector3::new(0.0, 0.0, 0.1);
    task.motion.via = vec![Via::Tcp(TcpVia {
        time: ViaTime::At(0.4),
        tcp: target.into(),
        tol_m: tol,
    })];
    let through = solve(&task);
    assert!(through.feasible, "{:?}", through.reason);
    let p = dynamics.tcp_position(&mut data, &through.trajectory.q[k]);
    assert!((p - target).norm() <= tol + 1e-6, "{}", (p - target).norm());
    assert!(
        through.cost > free.cost,
        "{} vs {}",
        through.cost,
        free.cost
    );
    assert!(through.violations.get("via_tcp").unwrap() <= 1e-6);
    assert_eq!(free.violations.get("via_tcp"), None);
}

#[test]
fn a_formulation_refuses_targets_that_cannot_hold() {
    let refusal = |change: &dyn Fn(&mut Task)| {
        let mut task = testing::task();
        change(&mut task);
        let robot = Robot::load(&task).unwrap();
        Formulation::new(&task, robot, Space::Actuation, task.limit_modes)
            .unwrap_err()
            .to_string()
    };
    let via = |t_s, q: Vec<f64>| {
        Via::Joints(JointVia {
            time: ViaTime::At(t_s),
            q,
            tol_rad: 0.1,
        })
    };
    let error = refusal(&|task| task.motion.via = vec![via(0.4, vec![0.0, 9.0, 0.0, 0.0])]);
    assert!(
        error.contains("motion.via[0].q[1] = 9 lies outside the joint limits"),
        "{error}"
    );
    let error = refusal(&|task| task.motion.via = vec![via(0.4, vec![0.0; 3])]);
    assert!(error.contains("motion.via[0].q has 3 values"), "{error}");
    let error =
        refusal(&|task| task.motion.via = vec![via(0.4, vec![0.0; 4]), via(0.401, vec![0.0; 4])]);
    assert!(
        error.contains("motion.via[1].t_s = 0.401 falls on node 25"),
        "{error}"
    );
    let error = refusal(&|task| {
        task.motion.via = vec![via(0.4, vec![0.0; 4])];
        task.motion.horizon = Horizon::Free {
            min_s: 0.3,
            max_s: 1.2,
        };
    });
    assert!(
        error.contains("motion.via[0].t_s = 0.4 lies outside the motion's (0, 0.3) s, T_min"),
        "{error}"
    );
    let upright = |link: &str, tol_rad| Upright {
        link: link.into(),
        axis: [0.0, 0.0, 1.0],
        tol_rad,
    };
    let error = refusal(&|task| task.motion.upright = Some(upright("nowhere", 0.5)));
    assert!(
        error.contains("motion.upright.link: 'nowhere' is not a link"),
        "{error}"
    );
    let error = refusal(&|task| task.motion.upright = Some(upright("link_4", 1e-3)));
    assert!(
        error.contains("pose (motion.start) tilts link 'link_4'"),
        "{error}"
    );
}

/// No pose within the joint limits takes the TCP out of the ball `Robot::reach` gives, and some
/// come near its surface (the built-in arm stretched out reaches 0.948 m).
#[test]
fn the_tcp_stays_within_the_arms_reach() {
    for task in [testing::task(), posed_task(SCREW_ROW)] {
        let robot = Robot::load(&task).unwrap();
        let (centre, radius) = robot.reach().unwrap();
        let limits = robot.position_limits().to_vec();
        let dynamics = Dynamics::new(robot);
        let mut data = dynamics.workspace();
        let mut rng = testing::Random::new(5);
        let mut farthest: f64 = 0.0;
        for _ in 0..2000 {
            let q: Vec<f64> = (limits.iter())
                .map(|&(lo, hi)| rng.real(lo.max(-4.0)..hi.min(4.0)))
                .collect();
            let distance = (dynamics.tcp_position(&mut data, &q) - centre).norm();
            assert!(distance <= radius + 1e-12, "{distance} > {radius}");
            farthest = farthest.max(distance);
        }
        assert!(farthest > 0.8 * radius, "{farthest} of {radius}");
    }
}

/// A TCP via point out of reach (1.002 m from the shoulder, which reaches 0.948 m) is no error of the solve but a verdict of the one rule: no start
/// finds a trajectory, and the result says infeasible with IPOPT's reason.
#[test]
fn an_unreachable_via_point_is_judged_infeasible_by_the_one_rule() {
    let mut task = testing::task();
    task.motion.steps = 10;
    task.motion.via = vec![Via::Tcp(TcpVia {
        time: ViaTime::At(0.4),
        tcp: [0.0, 0.5, 0.0],
        tol_m: 0.01,
    })];
    let robot = Robot::load(&task).unwrap();
    let (centre, radius) = robot.reach().unwrap();
    assert!((Vector3::new(0.0, 0.5, 0.0) - centre).norm() > radius + 0.05);
    let f = Formulation::new(&task, robot, Space::Actuation, task.limit_modes).unwrap();
    let result = solve_design(&f, &[6.0, 3.0, 1.0, 1.0], &SolveSettings::default()).unwrap();
    assert!(
        !result.feasible,
        "{:?} {:?}",
        result.violations, result.status
    );
    assert!(result.reason.is_some());
    assert!(result.violations.get("via_tcp").unwrap() > 0.1);
}

/// Held upright within a little more than its tilt at the start and the goal, the built-in
/// arm's end effector, which tilts far beyond that on its way without the rows, stays within it
/// at every node, and the one rule judges the result feasible.
#[test]
fn an_upright_link_stays_within_its_tolerance() {
    let mut task = testing::task();
    task.motion.steps = 20;
    task.motion.horizon = Horizon::Fixed(1.5);
    let design = [6.0, 3.0, 1.0, 1.0];
    let solve = |task: &Task| {
        let robot = Robot::load(task).unwrap();
        let f = Formulation::new(task, robot, Space::Actuation, task.limit_modes).unwrap();
        let result = solve_design(&f, &design, &SolveSettings::default()).unwrap();
        (f, result)
    };
    let (axis, tilt) = bisecting_axis(&task, "link_4");
    let tol_rad = tilt + 0.3;
    task.motion.upright = Some(Upright {
        link: "link_4".into(),
        axis,
        tol_rad,
    });
    let (f, upright) = solve(&task);
    assert!(upright.feasible, "{tilt} {:?}", upright.reason);
    assert!(upright.violations.get("upright").unwrap() <= 1e-6);
    let target = f.setting().targets().upright.clone().unwrap();
    let dynamics = f.dynamics();
    let mut data = dynamics.workspace();
    let mut tilts = |q: &[Vec<f64>]| {
        (q.iter())
            .map(|q| target.tilt(dynamics, &mut data, q))
            .fold(0.0, f64::max)
    };
    assert!(tilts(&upright.trajectory.q) <= tol_rad + 1e-6);
    task.motion.upright = None;
    let (_, free) = solve(&task);
    assert!(free.feasible);
    let free_tilt = tilts(&free.trajectory.q);
    assert!(free_tilt > tol_rad + 0.1, "{free_tilt} {tol_rad}");
    assert!(upright.cost > free.cost);
}

/// An upright link under a free horizon: its rows read neither h nor T, and the problem's
/// derivatives in T and q stay exact (central differences and IPOPT's checker, both spaces).
#[test]
fn an_upright_link_under_a_free_horizon_has_exact_derivatives() {
    let mut task = with_targets(testing::task(), "link_4");
    task.motion.via.clear();
    task.motion.horizon = Horizon::Free {
        min_s: 0.4,
        max_s: 1.2,
    };
    task.weights.time = 2.0;
    for f in formulations(&task) {
        assert!(f.layout().horizon().is_some());
        assert_derivatives_match(&f, &[7.0, 4.0, 2.0, 1.5]);
        assert_checker_finds_nothing(&f, &[7.0, 4.0, 2.0, 1.5]);
    }
}

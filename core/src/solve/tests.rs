//! Tests of the solve layer: results and their verification on the repository's task, and the
//! exact sensitivity dJ*/dr that results report, against differences of re-solved problems.

use super::{solve_design, solve_design_from, SolveError, SolveSettings, TrajectoryResult};
use crate::ipopt::{self, Solution};
use crate::model::task::{Ends, LimitMode, LimitModes, PerMotor, Task};
use crate::model::Robot;
use crate::problem::{Formulation, Space};
use crate::testing;

/// The original design carries 0.5 kg in actuation space (its motors hold up to 0.585 kg at
/// rest): the result is feasible, its trajectory has N + 1 nodes and N intervals, and the
/// residuals evaluated again on the trajectory read back are within IPOPT's tolerance.
#[test]
fn a_feasible_result_satisfies_every_constraint_family() {
    let formulation = testing::formulation(0.5, Space::Actuation);
    let original = formulation.transmission().original().to_vec();
    let result = solve_design(&formulation, &original, &testing::settings()).unwrap();
    assert!(
        result.feasible && result.reason.is_none(),
        "{}",
        result.status
    );
    let steps = formulation.layout().steps;
    let t = &result.trajectory;
    assert_eq!(
        (t.q.len(), t.v.len(), t.tcp_y.len()),
        (steps + 1, steps + 1, steps + 1)
    );
    assert_eq!(
        (t.a.len(), t.joint_torque.len(), t.motor_torque.len()),
        (steps, steps, steps)
    );
    let v = &result.violations;
    for family in [
        "dynamics",
        "integration",
        "boundary",
        "joint_position",
        "speed_limits",
        "control_limits",
    ] {
        let value = v.get(family).unwrap();
        assert!(value <= 1e-6, "{family}: {value:e}");
    }
    let peaks = t.motor_torque_peaks();
    let limits = formulation.motor_torque_limits();
    assert_eq!(peaks.len(), limits.len());
    assert!(peaks
        .iter()
        .zip(limits)
        .all(|(peak, limit)| *peak <= limit * (1.0 + 1e-6)));
    assert_eq!(
        result.max_motor_torque,
        peaks.iter().fold(0.0_f64, |m, p| m.max(*p))
    );
    assert!(result
        .cost_gradient
        .as_ref()
        .is_some_and(|g| g.len() == original.len()));
    let seconds = &result.solve_seconds;
    assert!(seconds.total >= seconds.callbacks && seconds.callbacks > 0.0);
    // J by term sums to J; the joints are named, the TCP has its three coordinates.
    let terms = result.cost_terms.unwrap();
    let sum = terms.position + terms.velocity + terms.control + terms.cartesian_box;
    assert!(
        (sum - result.cost).abs() <= 1e-9 * result.cost,
        "{terms:?} against {}",
        result.cost
    );
    assert!(terms.control > 0.0 && terms.position > 0.0);
    assert_eq!(result.joints.len(), 4);
    assert_eq!(result.joints[0], "joint_arm_1");
    assert_eq!(t.tcp_x.len(), steps + 1);
}

/// An infeasible design is a result that says why; a design outside its space is an error.
#[test]
fn infeasible_designs_are_results_and_invalid_ones_errors() {
    let formulation = testing::held_formulation(3.0, Space::Actuation);
    let settings = testing::settings();
    let original = formulation.transmission().original().to_vec();
    let result = solve_design(&formulation, &original, &settings).unwrap();
    assert!(!result.feasible, "the original design does not carry 3 kg");
    // Its motors cannot even hold 3 kg at rest; the solve still runs and says so too.
    let reason = result.reason.unwrap();
    assert!(
        reason.starts_with("cannot hold the load at rest at the start: motor 2 needs "),
        "{reason}"
    );
    assert!(reason.contains("; IPOPT returned "), "{reason}");
    assert!(result.cost_gradient.is_none());
    let outside = [100.0, 3.0, 1.0, 1.0];
    let error = solve_design(&formulation, &outside, &settings).unwrap_err();
    assert!(matches!(error, SolveError::Design(_)), "{error}");
}

/// The settings reach IPOPT: its iteration limit, and an option it rejects, named (on a design
/// whose motors cannot hold 1 kg at rest under `hold`, so that one solve runs).
#[test]
fn the_settings_reach_ipopt() {
    let formulation = testing::held_formulation(1.0, Space::Actuation);
    let original = formulation.transmission().original().to_vec();
    let few = SolveSettings {
        max_iter: 3,
        ..testing::settings()
    };
    let result = solve_design(&formulation, &original, &few).unwrap();
    assert_eq!(result.status, "Maximum_Iterations_Exceeded");
    assert_eq!(result.iterations, 3);
    assert!(!result.feasible);
    let mut unknown = testing::settings();
    unknown.options.insert("no_such_option".into(), 1.into());
    match solve_design(&formulation, &original, &unknown) {
        Err(SolveError::Ipopt(ipopt::Error::InvalidOption { name, .. })) => {
            assert_eq!(name, "no_such_option")
        }
        other => panic!("{other:?}"),
    }
}

/// Checks `gradient` at `ratios` against central differences (step 1e-4) of `value`, to 1e-4
/// relative to its largest entry; `label` names the case.
pub(super) fn assert_matches_differences(
    label: &str,
    gradient: &[f64],
    ratios: &[f64],
    value: impl Fn(&[f64]) -> f64,
) {
    let step = 1e-4;
    let scale = gradient.iter().fold(1.0_f64, |m, g| m.max(g.abs()));
    for l in 0..ratios.len() {
        let at = |sign: f64| {
            let mut r = ratios.to_vec();
            r[l] += sign * step;
            value(&r)
        };
        let fd = (at(1.0) - at(-1.0)) / (2.0 * step);
        assert!(
            (fd - gradient[l]).abs() <= 1e-4 * scale,
            "{label} r = {ratios:?}: d/dr{} = {} but differences give {fd}",
            l + 1,
            gradient[l]
        );
    }
}

/// dJ*/dr against central differences of re-solved problems, at designs where the active
/// set is stable, in both spaces and with box (paper, interval) and linear (exact) limits.
#[test]
fn cost_gradient_matches_differences_of_resolved_problems() {
    let mut task = crate::testing::task();
    let cases = [
        (
            Space::Actuation,
            1.0,
            LimitMode::Paper,
            LimitMode::Exact,
            [7.0, 4.0, 2.0, 2.0],
        ),
        (
            Space::Actuation,
            0.0,
            LimitMode::Paper,
            LimitMode::Interval,
            [6.0, 3.0, 1.5, 1.5],
        ),
        (
            Space::Joint,
            0.0,
            LimitMode::Interval,
            LimitMode::Exact,
            [6.5, 3.5, 1.5, 1.2],
        ),
        (
            Space::Joint,
            0.0,
            LimitMode::Exact,
            LimitMode::Paper,
            [8.0, 4.0, 2.0, 2.5],
        ),
        // The paper's joint-space problem (torque mode `paper`, joint 4 limited to 0 N m),
        // feasible under the paper's ends although no design holds 1 kg at rest in it
        // (the best design of the quick reproduction's run, inside the bounds).
        (
            Space::Joint,
            1.0,
            LimitMode::Paper,
            LimitMode::Exact,
            [7.38, 5.24, 1.83, 1.89],
        ),
    ];
    for (space, payload, torque, speed, ratios) in cases {
        task.payload.mass_kg = payload;
        assert_cost_gradient(&task, space, LimitModes { torque, speed }, ratios);
    }
}

/// Checks dJ*/dr of `task` in `space` with `modes` at `ratios` (a feasible design) against
/// central differences of re-solved problems.
pub(super) fn assert_cost_gradient(task: &Task, space: Space, modes: LimitModes, ratios: [f64; 4]) {
    let settings = SolveSettings {
        tol: 1e-11,
        ..crate::testing::settings()
    };
    let robot = Robot::load(task).unwrap();
    let formulation = Formulation::new(task, robot, space, modes).unwrap();
    let result = solve_design(&formulation, &ratios, &settings).unwrap();
    assert!(result.feasible, "{space} {ratios:?}: {}", result.status);
    let gradient = result.cost_gradient.clone().unwrap();
    let label = format!("{space} {:?}/{:?}", modes.torque, modes.speed);
    assert_matches_differences(&label, &gradient, &ratios, |r| {
        solve_design(&formulation, r, &settings).unwrap().cost
    });
}

/// dJ*/dr with a different limit per motor, where those limits bound the solution (the bound
/// multipliers are non-zero): the `interval` and `paper` bounds' derivatives weigh each motor
/// by its own limit.
#[test]
fn cost_gradient_with_per_motor_limits_matches_differences() {
    let mut task = crate::testing::task();
    let cases = [
        (
            LimitMode::Interval,
            LimitMode::Interval,
            [6.5, 3.5, 1.5, 1.2],
            [1.7, 1.2, 1.5, 1.4],
            [40.0, 30.0, 40.0, 100.0],
        ),
        (
            LimitMode::Paper,
            LimitMode::Exact,
            [7.0, 4.0, 2.0, 2.0],
            [1.7, 1.5, 1.2, 1.6],
            [100.0, 80.0, 90.0, 100.0],
        ),
        (
            LimitMode::Exact,
            LimitMode::Paper,
            [8.0, 4.0, 2.0, 2.5],
            [1.7, 1.5, 1.2, 1.6],
            [90.0, 80.0, 70.0, 100.0],
        ),
    ];
    task.payload.mass_kg = 0.0;
    for (torque, speed, ratios, torques, speeds) in cases {
        task.motors.torque_limit_nm = PerMotor::Each(torques.to_vec());
        task.motors.speed_limit_rad_s = PerMotor::Each(speeds.to_vec());
        assert_cost_gradient(&task, Space::Joint, LimitModes { torque, speed }, ratios);
    }
}

/// The task's limits written as one number per motor, all equal, solve to the bit as the one
/// number does: the same iterations, trajectory, cost and dJ*/dr.
#[test]
fn equal_limits_per_motor_solve_as_one_limit() {
    let settings = testing::settings();
    // Payloads the original design holds at rest: 0.5 kg in actuation space, the unloaded arm
    // in joint space with the interval torque mode (mode `paper` gives joint 4 no torque).
    let cases = [
        (Space::Actuation, 0.5, testing::task().limit_modes),
        (
            Space::Joint,
            0.0,
            LimitModes {
                torque: LimitMode::Interval,
                speed: LimitMode::Interval,
            },
        ),
    ];
    for (space, payload, modes) in cases {
        let mut task = testing::task();
        task.payload.mass_kg = payload;
        let mut listed = task.clone();
        listed.motors.torque_limit_nm = PerMotor::Each(vec![1.7; 4]);
        listed.motors.speed_limit_rad_s = PerMotor::Each(vec![100.0; 4]);
        let [one, each] = [task, listed].map(|task| {
            let robot = Robot::load(&task).unwrap();
            let formulation = Formulation::new(&task, robot, space, modes).unwrap();
            let original = formulation.transmission().original().to_vec();
            let mut result = solve_design(&formulation, &original, &settings).unwrap();
            result.solve_seconds = Default::default();
            result
        });
        assert!(one.feasible && one.cost_gradient.is_some(), "{space}");
        assert_eq!(one, each, "{space}");
    }
}

/// The elastic kind's d(penalised objective)/dr against central differences of re-solved
/// problems, at infeasible designs (slacks active) of both spaces inside the design box, with
/// the box speed limits it holds as rows (paper, interval) and the linear ones (exact), for
/// one speed limit and for one per motor.
#[test]
fn elastic_objective_gradient_matches_differences_of_resolved_problems() {
    let mut task = crate::testing::held_task();
    let settings = SolveSettings {
        tol: 1e-10,
        ..crate::testing::settings()
    };
    task.payload.mass_kg = 3.0;
    let one = task.motors.speed_limit_rad_s.clone();
    let each = PerMotor::Each(vec![100.0, 100.0, 60.0, 90.0]);
    let cases = [
        (
            Space::Actuation,
            LimitMode::Paper,
            [6.0, 3.0, 1.5, 1.5],
            &one,
        ),
        (
            Space::Actuation,
            LimitMode::Exact,
            [8.0, 5.0, 2.5, 2.0],
            &one,
        ),
        (
            Space::Joint,
            LimitMode::Interval,
            [4.0, 2.0, 1.2, 1.2],
            &one,
        ),
        (
            Space::Actuation,
            LimitMode::Paper,
            [6.0, 3.0, 1.5, 1.5],
            &each,
        ),
        (
            Space::Joint,
            LimitMode::Interval,
            [4.0, 2.0, 1.2, 1.2],
            &each,
        ),
    ];
    for (space, speed, ratios, speeds) in cases {
        task.motors.speed_limit_rad_s = speeds.clone();
        let robot = Robot::load(&task).unwrap();
        let modes = LimitModes {
            speed,
            ..task.limit_modes
        };
        let formulation = Formulation::new(&task, robot, space, modes)
            .unwrap()
            .elastic();
        // The perturbed problems start from the solution at `ratios`, so that they stay in
        // its local optimum (cold starts of this non-convex problem may land in others).
        let solve = |r: &[f64], warm: Option<&Solution>| {
            let (result, solution) = solve_design_from(&formulation, r, &settings, warm).unwrap();
            assert!(solution.status.is_success(), "{r:?}: {}", result.status);
            (result, solution)
        };
        let (result, solution) = solve(&ratios, None);
        assert!(
            !result.feasible,
            "{space} {ratios:?} is meant to be infeasible"
        );
        let gradient = result.elastic.unwrap().objective_gradient.unwrap();
        let label = format!("{space} {speed:?} elastic, speed limits {speeds}");
        assert_matches_differences(&label, &gradient, &ratios, |r| {
            solve(r, Some(&solution)).0.elastic.unwrap().objective
        });
    }
}

/// dJ*/dr against central differences of re-solved problems with scaled entries in G
/// (`0.5*r2`, `-2*r3`): the envelope formula carries the scales through dG/dr.
#[test]
fn cost_gradient_with_scaled_entries_matches_differences() {
    use crate::model::task::MatrixEntry;
    let mut task = crate::testing::task();
    let settings = SolveSettings {
        tol: 1e-11,
        ..crate::testing::settings()
    };
    let matrix = &mut task.transmission.matrix;
    *matrix[1].entry_mut(0).unwrap() = MatrixEntry::Ratio("0.5*r2".into());
    for row in [2, 3] {
        *matrix[row].entry_mut(1).unwrap() = MatrixEntry::Ratio("-2*r3".into());
    }
    let ratios = [7.0, 4.0, 2.0, 2.0];
    for space in [Space::Actuation, Space::Joint] {
        let robot = Robot::load(&task).unwrap();
        let modes = LimitModes {
            torque: LimitMode::Exact,
            speed: LimitMode::Exact,
        };
        let formulation = Formulation::new(&task, robot, space, modes).unwrap();
        let result = solve_design(&formulation, &ratios, &settings).unwrap();
        assert!(result.feasible, "{space}: {}", result.status);
        let gradient = result.cost_gradient.clone().unwrap();
        assert_matches_differences(&format!("{space} scaled"), &gradient, &ratios, |r| {
            solve_design(&formulation, r, &settings).unwrap().cost
        });
    }
}

/// The task with rotor inertia (kg m^2) and viscous friction (N m s/rad) set per motor: a
/// geared servo's order of magnitude, reflected by r^2 and r into the joints.
pub(super) fn with_motor_terms(task: &Task) -> Task {
    let mut task = task.clone();
    task.motors.rotor_inertia_kgm2 = Some(PerMotor::Each(vec![1e-4, 1e-4, 5e-5, 5e-5]));
    task.motors.viscous_friction_nm_s_per_rad = Some(PerMotor::Each(vec![2e-3, 2e-3, 1e-3, 1e-3]));
    task
}

/// dJ*/dr with rotor inertia and friction, which depend on r through G in both spaces, against
/// central differences of re-solved problems at three feasible designs.
#[test]
fn cost_gradient_with_motor_terms_matches_differences() {
    let cases = [
        (
            Space::Actuation,
            1.0,
            LimitMode::Paper,
            LimitMode::Exact,
            [7.0, 4.0, 2.0, 2.0],
        ),
        (
            Space::Joint,
            0.0,
            LimitMode::Interval,
            LimitMode::Exact,
            [6.5, 3.5, 1.5, 1.2],
        ),
        (
            Space::Joint,
            0.0,
            LimitMode::Exact,
            LimitMode::Paper,
            [8.0, 4.0, 2.0, 2.5],
        ),
    ];
    for (space, payload, torque, speed, ratios) in cases {
        let mut task = with_motor_terms(&crate::testing::task());
        task.payload.mass_kg = payload;
        assert_cost_gradient(&task, space, LimitModes { torque, speed }, ratios);
    }
}

/// Rotor inertia and friction given as 0 solve to the bit as no motor keys: the same
/// iterations, trajectory, cost and dJ*/dr; set, they move the cost and the motor torques
/// include the rotors' and the friction's share.
#[test]
fn zero_motor_terms_solve_as_none() {
    let settings = testing::settings();
    // Payloads the original design holds at rest: 0.5 kg in actuation space, the unloaded arm
    // in joint space with the interval torque mode (mode `paper` gives joint 4 no torque).
    for (space, payload) in [(Space::Actuation, 0.5), (Space::Joint, 0.0)] {
        let mut task = testing::task();
        task.payload.mass_kg = payload;
        if space == Space::Joint {
            task.limit_modes.torque = LimitMode::Interval;
        }
        let mut zero = task.clone();
        zero.motors.rotor_inertia_kgm2 = Some(PerMotor::All(0.0));
        zero.motors.viscous_friction_nm_s_per_rad = Some(PerMotor::All(0.0));
        let [none, zero, set] = [task.clone(), zero, with_motor_terms(&task)].map(|task| {
            let robot = Robot::load(&task).unwrap();
            let formulation = Formulation::new(&task, robot, space, task.limit_modes).unwrap();
            let original = formulation.transmission().original().to_vec();
            let mut result = solve_design(&formulation, &original, &settings).unwrap();
            result.solve_seconds = Default::default();
            result
        });
        assert!(none.feasible && none.cost_gradient.is_some(), "{space}");
        assert_eq!(none, zero, "{space}");
        assert!(
            set.feasible && set.cost != none.cost,
            "{space}: {}",
            set.cost
        );
        let t = &set.trajectory;
        let g = crate::transmission::Transmission::from_spec(&task.transmission)
            .unwrap()
            .coupling(&[6.0, 3.0, 1.0, 1.0])
            .unwrap();
        for k in [1, t.a.len() / 2] {
            let (speed, acceleration) = (g.motor_speeds(&t.v[k]), g.motor_speeds(&t.a[k]));
            let links = g.motor_torques(&t.joint_torque[k]);
            for i in 0..4 {
                let (inertia, friction) =
                    ([1e-4, 1e-4, 5e-5, 5e-5][i], [2e-3, 2e-3, 1e-3, 1e-3][i]);
                let expected = links[i] + inertia * acceleration[i] + friction * speed[i];
                let motor = t.motor_torque[k][i];
                assert!(
                    (motor - expected).abs() < 1e-9,
                    "{space} k {k} motor {i}: {motor} vs {expected}"
                );
            }
        }
    }
}

/// The original design solved under `ends` in `space` at `payload_kg` kg.
fn solve_original_with(ends: Ends, space: Space, payload_kg: f64) -> TrajectoryResult {
    let mut task = testing::task();
    task.payload.mass_kg = payload_kg;
    task.motion.ends = ends;
    let robot = Robot::load(&task).unwrap();
    let formulation = Formulation::new(&task, robot, space, task.limit_modes).unwrap();
    let original = formulation.transmission().original().to_vec();
    solve_design(&formulation, &original, &testing::settings()).unwrap()
}

/// Under `paper` the original design at 1 kg (actuation) and 0 kg (joint space, whose mode
/// `paper` gives joint 4 a limit of 0 N m) is feasible, with dJ*/dr, although its motors cannot
/// hold the load at rest, which the result still reports; under `hold` the same designs are
/// infeasible, naming the end and the row.
#[test]
fn paper_ends_report_the_hold_and_hold_ends_judge_it() {
    for (space, payload, row) in [
        (Space::Actuation, 1.0, "motor 2 needs"),
        (Space::Joint, 0.0, "joint 4 needs 0.002541 N m (limit 0)"),
    ] {
        let paper = solve_original_with(Ends::Paper, space, payload);
        assert!(
            paper.feasible && paper.reason.is_none(),
            "{space}: {:?}",
            paper.reason
        );
        let hold = paper.static_hold.as_ref().unwrap();
        assert!(!hold.judged && !hold.holds());
        assert!(hold.reason().unwrap().contains(row), "{:?}", hold.reason());
        let gradient = paper.cost_gradient.as_ref().unwrap();
        assert!(gradient.iter().all(|g| g.is_finite()) && gradient.len() == 4);
        let held = solve_original_with(Ends::Hold, space, payload);
        assert!(!held.feasible, "{space}");
        let reason = held.reason.unwrap();
        assert!(
            reason.starts_with("cannot hold the load at rest at the "),
            "{reason}"
        );
        assert!(reason.contains(row), "{reason}");
        assert!(held.static_hold.unwrap().judged);
        assert!(held.cost_gradient.is_none());
    }
}

/// Under `rest`, a design that holds its load (the original one unloaded, in actuation space:
/// it holds up to 0.585 kg) starts and ends the motion at rest: the result is feasible and a_0
/// and a_{N-1} are 0, which they are not under `hold`.
#[test]
fn rest_ends_start_and_end_the_motion_at_rest() {
    let largest = |a: &[f64]| a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let rested = solve_original_with(Ends::Rest, Space::Actuation, 0.0);
    assert!(
        rested.feasible && rested.reason.is_none(),
        "{}",
        rested.status
    );
    assert!(rested
        .static_hold
        .as_ref()
        .is_some_and(|h| h.holds() && h.judged));
    let a = &rested.trajectory.a;
    for k in [0, a.len() - 1] {
        assert!(largest(&a[k]) <= 1e-9, "a_{k} = {:?}", a[k]);
    }
    assert!(rested.violations.get("boundary").unwrap() <= 1e-6);
    let free = solve_original_with(Ends::Hold, Space::Actuation, 0.0);
    assert!(free.feasible);
    let a = &free.trajectory.a;
    assert!(largest(&a[0]).max(largest(&a[a.len() - 1])) > 1e-3);
    assert!(rested.cost >= free.cost * (1.0 - 1e-6));
}

/// A solved result holds only finite numbers; one made infinite or NaN in any part is named
/// by that part, which `solve` then refuses to write (JSON would write it as null).
#[test]
fn a_number_that_is_not_finite_is_named_by_its_part() {
    let formulation = testing::formulation(0.5, Space::Actuation);
    let original = formulation.transmission().original().to_vec();
    let result = solve_design(&formulation, &original, &testing::settings()).unwrap();
    assert_eq!(result.non_finite(), None);
    let mut cost = result.clone();
    cost.cost = f64::INFINITY;
    assert_eq!(cost.non_finite(), Some("cost"));
    let mut torque = result.clone();
    torque.trajectory.joint_torque[1][0] = f64::NAN;
    assert_eq!(torque.non_finite(), Some("trajectory"));
    let mut gradient = result.clone();
    gradient.cost_gradient = Some(vec![0.0, f64::NEG_INFINITY]);
    assert_eq!(gradient.non_finite(), Some("cost_gradient"));
    let mut hold = result;
    hold.static_hold.as_mut().unwrap().start.margins_nm[0] = f64::INFINITY;
    assert_eq!(hold.non_finite(), Some("static_hold"));
}

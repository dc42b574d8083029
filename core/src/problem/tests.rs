//! Tests of the trajectory NLP: its derivatives against finite differences and IPOPT's
//! checker, its patterns, the elastic kind against the hard one, and its bounds.

use super::*;
use crate::ipopt::{check_derivatives, DerivativeOrder, Nlp, Options, Solution, Status, Timing};
use crate::model::task::{LimitMode, LimitModes, Task};
use crate::model::Robot;
use crate::problem::penalty_weights;
use crate::testing::{self, Random};
use crate::transmission::{JointLimits, Side};
use nalgebra::DMatrix;

/// Row `side` of motor i's torque-speed envelope at node k, where it has one: a node's P rows,
/// then its M rows.
pub(crate) fn envelope_row(layout: &Layout, k: usize, i: usize, side: Side) -> Option<usize> {
    let offset = match side {
        Side::Plus => 0,
        Side::Minus => layout.dof,
    };
    layout.row(FamilyId::Envelope, k, offset + i)
}

fn task() -> Task {
    testing::task()
}

/// The default task with 5 steps: every block of the full problem's structure (first, inner
/// and last nodes) is there, and IPOPT 3.11's derivative checker, whose cost grows with the
/// fourth power of the size, takes 0.1 s instead of 10 minutes.
fn formulation(space: Space, torque: LimitMode, speed: LimitMode, payload: f64) -> Formulation {
    let mut task = task();
    task.motion.steps = 5;
    task.payload.mass_kg = payload;
    let robot = Robot::load(&task).unwrap();
    Formulation::new(&task, robot, space, LimitModes { torque, speed }).unwrap()
}

/// [`formulation`] with scaled entries in G (`0.5*r2`, `-2*r3`), in both spaces with the
/// linear (exact) limits, whose rows carry G's entries.
fn scaled_formulations() -> Vec<Formulation> {
    use crate::model::task::MatrixEntry;
    [Space::Actuation, Space::Joint]
        .into_iter()
        .map(|space| {
            let mut task = task();
            task.motion.steps = 5;
            task.payload.mass_kg = 1.0;
            let matrix = &mut task.transmission.matrix;
            *matrix[1].entry_mut(0).unwrap() = MatrixEntry::Ratio("0.5*r2".into());
            for row in [2, 3] {
                *matrix[row].entry_mut(1).unwrap() = MatrixEntry::Ratio("-2*r3".into());
            }
            let robot = Robot::load(&task).unwrap();
            let modes = LimitModes {
                torque: LimitMode::Exact,
                speed: LimitMode::Exact,
            };
            Formulation::new(&task, robot, space, modes).unwrap()
        })
        .collect()
}

/// Every combination of space and modes (torque modes only matter in joint space), and a G
/// with scaled entries, each in the hard and the elastic kind.
/// The rotor inertias (kg m^2) and frictions (N m s/rad) of the motor-term tests, one per
/// motor: larger than real ones, so that their reflected terms weigh in the derivatives.
pub(crate) fn motor_terms() -> (Vec<f64>, Vec<f64>) {
    (vec![3e-3, 2e-3, 1e-3, 5e-4], vec![2e-2, 1e-2, 0.0, 5e-3])
}

/// The motors' no-load speeds (rad/s) of the envelope tests, one per motor: low enough for
/// the envelope to bind in the 5-step problems' solutions.
pub(crate) fn no_load_speeds() -> Vec<f64> {
    vec![60.0, 50.0, 40.0, 45.0]
}

/// [`formulation`]s with every motor term set (rotor inertia, friction, torque-speed
/// envelope): actuation space, and joint space in every torque mode, speed mode `exact`.
fn motor_formulations() -> Vec<Formulation> {
    use crate::model::task::PerMotor;
    let (inertia, friction) = motor_terms();
    [
        (Space::Actuation, LimitMode::Paper),
        (Space::Joint, LimitMode::Paper),
        (Space::Joint, LimitMode::Interval),
        (Space::Joint, LimitMode::Exact),
    ]
    .into_iter()
    .map(|(space, torque)| {
        let mut task = task();
        task.motion.steps = 5;
        task.payload.mass_kg = 1.0;
        task.motors.rotor_inertia_kgm2 = Some(PerMotor::Each(inertia.clone()));
        task.motors.viscous_friction_nm_s_per_rad = Some(PerMotor::Each(friction.clone()));
        task.motors.no_load_speed_rad_s = Some(PerMotor::Each(no_load_speeds()));
        let robot = Robot::load(&task).unwrap();
        let modes = LimitModes {
            torque,
            speed: LimitMode::Exact,
        };
        Formulation::new(&task, robot, space, modes).unwrap()
    })
    .collect()
}

/// [`formulation`]s with the torque-speed envelope alone, under the box speed modes (whose
/// elastic kind relaxes joint speeds, which reach the envelope rows through G), both spaces,
/// and with one no-load speed for every motor.
fn envelope_formulations() -> Vec<Formulation> {
    use crate::model::task::PerMotor;
    [
        (Space::Actuation, LimitMode::Paper, LimitMode::Interval),
        (Space::Joint, LimitMode::Exact, LimitMode::Paper),
        (Space::Joint, LimitMode::Interval, LimitMode::Interval),
    ]
    .into_iter()
    .map(|(space, torque, speed)| {
        let f = formulation(space, torque, speed, 1.0);
        let mut task = f.task().clone();
        task.motors.no_load_speed_rad_s = Some(PerMotor::All(45.0));
        Formulation::new(&task, f.dynamics().robot().clone(), space, *f.modes()).unwrap()
    })
    .collect()
}

/// [`formulation`]s with `motion.ends` `rest`: the accelerations at nodes 0 and N-1 fixed
/// at 0, in both spaces.
fn rest_formulations() -> Vec<Formulation> {
    [
        (Space::Actuation, LimitMode::Paper),
        (Space::Joint, LimitMode::Exact),
    ]
    .into_iter()
    .map(|(space, torque)| {
        let mut task = task();
        task.motion.steps = 5;
        task.motion.ends = crate::model::task::Ends::Rest;
        let robot = Robot::load(&task).unwrap();
        let modes = LimitModes {
            torque,
            speed: LimitMode::Exact,
        };
        Formulation::new(&task, robot, space, modes).unwrap()
    })
    .collect()
}

/// The transmissions' efficiencies of the loss tests, one per motor: lower than real ones, so
/// that the losses weigh in the derivatives.
pub(crate) fn efficiencies() -> Vec<f64> {
    vec![0.7, 0.85, 0.6, 0.9]
}

/// [`formulation`]s with lossy transmissions: actuation space, and joint space in every torque
/// mode, speed mode `exact`; and one with every motor term (rotor inertia, friction, envelope)
/// beside the losses.
fn loss_formulations() -> Vec<Formulation> {
    use crate::model::task::PerMotor;
    let with_loss = |f: Formulation| {
        let mut task = f.task().clone();
        task.motors.efficiency = Some(PerMotor::Each(efficiencies()));
        Formulation::new(&task, f.dynamics().robot().clone(), f.space(), *f.modes()).unwrap()
    };
    let mut list: Vec<Formulation> = [
        (Space::Actuation, LimitMode::Paper),
        (Space::Joint, LimitMode::Paper),
        (Space::Joint, LimitMode::Interval),
        (Space::Joint, LimitMode::Exact),
    ]
    .into_iter()
    .map(|(space, torque)| with_loss(formulation(space, torque, LimitMode::Exact, 1.0)))
    .collect();
    list.extend(motor_formulations().into_iter().take(1).map(with_loss));
    list
}

/// The motors' torque constants (N m/A) and winding resistances (ohm) of the copper-loss tests.
pub(crate) fn electrical() -> (Vec<f64>, Vec<f64>) {
    (vec![0.05, 0.05, 0.03, 0.04], vec![1.2, 0.8, 2.0, 1.5])
}

/// [`formulation`]s minimising the motors' copper losses (actuation space), with ideal motors
/// and with every motor term and lossy transmissions.
fn copper_loss_formulations() -> Vec<Formulation> {
    use crate::model::task::PerMotor;
    let (k_t, r) = electrical();
    let plain = formulation(Space::Actuation, LimitMode::Paper, LimitMode::Exact, 1.0);
    let lossy = loss_formulations().pop().unwrap();
    [plain, lossy]
        .into_iter()
        .map(|f| {
            let mut task = f.task().clone();
            task.motors.torque_constant_nm_per_a = Some(PerMotor::Each(k_t.clone()));
            task.motors.resistance_ohm = Some(PerMotor::Each(r.clone()));
            let robot = f.dynamics().robot().clone();
            let f = Formulation::new(&task, robot, f.space(), *f.modes()).unwrap();
            f.minimising_copper_loss().unwrap()
        })
        .collect()
}

/// Every torque mode in both spaces under the speed modes `speeds`, with the default motors.
fn mode_formulations(speeds: &[LimitMode]) -> Vec<Formulation> {
    let modes = [LimitMode::Paper, LimitMode::Interval, LimitMode::Exact];
    let mut list = Vec::new();
    for &speed in speeds {
        list.push(formulation(Space::Actuation, LimitMode::Paper, speed, 1.0));
        for torque in modes {
            list.push(formulation(Space::Joint, torque, speed, 1.0));
        }
    }
    list
}

/// The test formulations in groups of about equal checking time: the box speed modes; the
/// speed mode `exact`; scaled entries and motor dynamics; the envelope and the ends held at
/// rest; the losses; the copper-loss criterion. Each group in the hard kind, then the elastic.
fn formulation_groups() -> [Vec<Formulation>; 6] {
    let join = |a: Vec<Formulation>, b: Vec<Formulation>| a.into_iter().chain(b).collect();
    [
        mode_formulations(&[LimitMode::Paper, LimitMode::Interval]),
        mode_formulations(&[LimitMode::Exact]),
        join(scaled_formulations(), motor_formulations()),
        join(envelope_formulations(), rest_formulations()),
        loss_formulations(),
        copper_loss_formulations(),
    ]
    .map(|hard: Vec<Formulation>| {
        let elastic: Vec<_> = hard.iter().map(Formulation::elastic).collect();
        join(hard, elastic)
    })
}

fn all_formulations() -> Vec<Formulation> {
    formulation_groups().into_iter().flatten().collect()
}

/// A point near the initial guess with every trajectory variable moved: the TCP leaves the
/// box at some nodes, so the penalty's derivatives are exercised too. The elastic kind's
/// slacks stay at 0: they enter linearly, so their derivatives are the same everywhere, and
/// at a moved slack the l1 penalty (weights up to 3e5) would make the objective so large
/// that its differences lose the gradient's digits.
fn random_point(problem: &TrajectoryProblem<'_>, seed: u64) -> Vec<f64> {
    let mut x = vec![0.0; problem.num_variables()];
    problem.initial_point(&mut x);
    let mut rng = Random::new(seed);
    for value in &mut x {
        *value += 0.6 * (rng.unit() - 0.5);
    }
    x[problem.formulation().layout().slacks()].fill(0.0);
    x
}

#[test]
fn sparse_derivatives_match_finite_differences() {
    for f in all_formulations() {
        assert_derivatives_match(&f, &[7.0, 4.0, 2.0, 1.5]);
    }
}

/// The gradient, the Jacobian and the Hessian of `f`'s problem at design `ratios` against
/// central differences at a point near the initial guess.
pub(super) fn assert_derivatives_match(f: &Formulation, ratios: &[f64]) {
    let mut problem = f.problem(ratios).unwrap();
    let (n, m) = (problem.num_variables(), problem.num_constraints());
    let x = random_point(&problem, 7);
    let lambda: Vec<f64> = {
        let mut rng = Random::new(11);
        (0..m).map(|_| rng.unit() - 0.5).collect()
    };
    let obj_factor = 0.7;
    let mut gradient = vec![0.0; n];
    problem.gradient(&x, true, &mut gradient).unwrap();
    let mut jacobian = vec![0.0; f.jacobian_nonzeros()];
    problem.jacobian_values(&x, false, &mut jacobian).unwrap();
    let mut hessian = vec![0.0; f.hessian_nonzeros()];
    problem
        .hessian_values(&x, false, obj_factor, &lambda, &mut hessian)
        .unwrap();
    let mut dense_jacobian = DMatrix::<f64>::zeros(m, n);
    for (&(r, c), &value) in f.jacobian().iter().zip(&jacobian) {
        dense_jacobian[(r, c)] += value;
    }
    let mut dense_hessian = DMatrix::<f64>::zeros(n, n);
    for (&(r, c), &value) in f.hessian().iter().zip(&hessian) {
        dense_hessian[(r, c)] += value;
        if r != c {
            dense_hessian[(c, r)] += value;
        }
    }
    // Central differences of the objective/constraints and of the Lagrangian's gradient.
    let lagrangian_gradient = |problem: &mut TrajectoryProblem<'_>, x: &[f64]| {
        let mut grad = vec![0.0; n];
        problem.gradient(x, true, &mut grad).unwrap();
        let mut values = vec![0.0; f.jacobian_nonzeros()];
        problem.jacobian_values(x, false, &mut values).unwrap();
        let mut out: Vec<f64> = grad.iter().map(|g| obj_factor * g).collect();
        for (&(r, c), &value) in f.jacobian().iter().zip(&values) {
            out[c] += lambda[r] * value;
        }
        out
    };
    let step = 1e-6;
    for j in 0..n {
        let (mut plus, mut minus) = (x.clone(), x.clone());
        plus[j] += step;
        minus[j] -= step;
        let fd = (problem.objective(&plus, true).unwrap()
            - problem.objective(&minus, true).unwrap())
            / (2.0 * step);
        assert!(
            (fd - gradient[j]).abs() <= 1e-5 * (1.0 + fd.abs()),
            "gradient[{j}]: {} vs fd {fd}",
            gradient[j]
        );
        let (mut g_plus, mut g_minus) = (vec![0.0; m], vec![0.0; m]);
        problem.constraints(&plus, true, &mut g_plus).unwrap();
        problem.constraints(&minus, true, &mut g_minus).unwrap();
        for i in 0..m {
            let fd = (g_plus[i] - g_minus[i]) / (2.0 * step);
            let exact = dense_jacobian[(i, j)];
            assert!(
                (fd - exact).abs() <= 1e-5 * (1.0 + fd.abs()),
                "jacobian ({i}, {j}): {exact} vs fd {fd}"
            );
        }
        let (l_plus, l_minus) = (
            lagrangian_gradient(&mut problem, &plus),
            lagrangian_gradient(&mut problem, &minus),
        );
        for i in 0..n {
            let fd = (l_plus[i] - l_minus[i]) / (2.0 * step);
            let exact = dense_hessian[(i, j)];
            assert!(
                (fd - exact).abs() <= 1e-5 * (1.0 + fd.abs()),
                "hessian ({i}, {j}): {exact} vs fd {fd}"
            );
        }
    }
}

/// The sensitivity's partial derivative in r of the Lagrangian f(x) + lambda . g(x; r) -
/// z_L . (x - x_L(r)) + z_U . (x - x_U(r)), at a fixed point x near the initial guess and random
/// multipliers, against central differences in r: every family's design terms, its rows' and
/// its bounds', at once and without a solve.
pub(super) fn assert_design_partials_match(f: &Formulation, design: &[f64]) {
    let problem = f.problem(design).unwrap();
    let (n, m) = (problem.num_variables(), problem.num_constraints());
    let x = random_point(&problem, 5);
    let mut rng = Random::new(13);
    let lambda: Vec<f64> = (0..m).map(|_| rng.unit() - 0.5).collect();
    let (z_lower, z_upper): (Vec<f64>, Vec<f64>) = (0..n).map(|_| (rng.unit(), rng.unit())).unzip();
    let solution = Solution {
        status: Status::SolveSucceeded,
        x: x.clone(),
        g: vec![0.0; m],
        lambda: lambda.clone(),
        z_lower: z_lower.clone(),
        z_upper: z_upper.clone(),
        objective: 0.0,
        iterations: 0,
        timing: Timing::default(),
        outside_domain: None,
    };
    let exact = cost_gradient(&problem, &solution).unwrap();
    // f + lambda . (g - b): b the bound each multiplier's sign makes active (IPOPT's sign
    // convention: lambda > 0 at an upper bound), for the bounds that depend on r; an infinite
    // one contributes nothing.
    let lagrangian = |r: &[f64]| {
        let mut problem = f.problem(r).unwrap();
        let (mut g, mut lower, mut upper) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        problem.constraints(&x, true, &mut g).unwrap();
        problem.constraint_bounds(&mut lower, &mut upper);
        let active = |i: usize| match lambda[i] > 0.0 {
            true => upper[i],
            false => lower[i],
        };
        let finite = |b: f64| if b.is_finite() { b } else { 0.0 };
        let constraints: f64 = (0..m).map(|i| lambda[i] * (g[i] - finite(active(i)))).sum();
        let (mut x_lower, mut x_upper) = (vec![0.0; n], vec![0.0; n]);
        problem.variable_bounds(&mut x_lower, &mut x_upper);
        let bound = |z: &[f64], x_bound: &[f64], j: usize| z[j] * (x[j] - finite(x_bound[j]));
        let bounds: f64 = (0..n)
            .map(|j| bound(&z_upper, &x_upper, j) - bound(&z_lower, &x_lower, j))
            .sum();
        problem.objective(&x, false).unwrap() + constraints + bounds
    };
    for l in 0..design.len() {
        let step = 1e-5 * design[l].abs().max(1.0);
        let (mut plus, mut minus) = (design.to_vec(), design.to_vec());
        plus[l] += step;
        minus[l] -= step;
        let fd = (lagrangian(&plus) - lagrangian(&minus)) / (2.0 * step);
        assert!(
            (fd - exact[l]).abs() <= 1e-6 * (1.0 + fd.abs()),
            "{:?} {} space, modes {:?}, r{}: {} vs fd {fd}",
            f.kind(),
            f.space(),
            f.modes(),
            l + 1,
            exact[l]
        );
    }
}

#[test]
fn design_partials_match_finite_differences() {
    for f in all_formulations() {
        assert_design_partials_match(&f, &[7.0, 4.0, 2.0, 1.5]);
    }
}

/// IPOPT's derivative checker on every test formulation, a group per test (each group takes a
/// few seconds; all of them in one test took 35 s).
fn assert_checker_finds_nothing_in_group(group: usize) {
    for f in formulation_groups().into_iter().nth(group).unwrap() {
        assert_checker_finds_nothing(&f, &[6.0, 3.0, 1.0, 1.0]);
    }
}

#[test]
fn ipopt_derivative_checker_finds_nothing_under_the_box_speed_modes() {
    assert_checker_finds_nothing_in_group(0);
}

#[test]
fn ipopt_derivative_checker_finds_nothing_under_the_exact_speed_mode() {
    assert_checker_finds_nothing_in_group(1);
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_scaled_entries_and_motor_dynamics() {
    assert_checker_finds_nothing_in_group(2);
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_the_envelope_and_the_hold() {
    assert_checker_finds_nothing_in_group(3);
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_losses() {
    assert_checker_finds_nothing_in_group(4);
}

#[test]
fn ipopt_derivative_checker_finds_nothing_with_the_energy_criterion() {
    assert_checker_finds_nothing_in_group(5);
}

/// IPOPT's derivative checker on `f`'s problem at design `ratios`: at the initial guess and
/// (hard kind) at a random interior point, with forward differences of step 1e-7.
pub(super) fn assert_checker_finds_nothing(f: &Formulation, ratios: &[f64]) {
    assert_checker_finds_nothing_at_step(f, ratios, 1e-7);
}

/// [`assert_checker_finds_nothing`] with the checker's relative step `perturbation`.
pub(super) fn assert_checker_finds_nothing_at_step(
    f: &Formulation,
    ratios: &[f64],
    perturbation: f64,
) {
    // IPOPT's random point moves the slacks too (see `random_point`): the elastic kind is
    // checked at the initial guess, where they are 0.
    let points = match f.kind() {
        ProblemKind::Hard => &[("initial guess", 0.0), ("random interior point", 0.05)][..],
        ProblemKind::Elastic => &[("initial guess", 0.0)][..],
    };
    for &(point, radius) in points {
        let mut problem = f.problem(ratios).unwrap();
        let options = Options::new()
            .num("point_perturbation_radius", radius)
            .num("derivative_test_perturbation", perturbation)
            .num("derivative_test_tol", 1e-4);
        let report = check_derivatives(&mut problem, &options, DerivativeOrder::Second).unwrap();
        assert_eq!(
            report.errors,
            0,
            "{:?} {} space, modes {:?}, motors {:?} {:?} {:?}, {:?}, {point}: {:?}",
            f.kind(),
            f.space(),
            f.modes(),
            f.motor_dynamics(),
            f.envelope(),
            f.transmission_loss(),
            f.criterion(),
            &report.flagged[..report.flagged.len().min(10)]
        );
    }
}

#[test]
fn pattern_is_lower_triangular_and_unique() {
    for f in all_formulations() {
        let mut seen = std::collections::HashSet::new();
        for &(r, c) in f.hessian() {
            assert!(r >= c);
            assert!(seen.insert((r, c)), "duplicate Hessian entry ({r}, {c})");
        }
        let mut seen = std::collections::HashSet::new();
        for &entry in f.jacobian() {
            assert!(seen.insert(entry), "duplicate Jacobian entry {entry:?}");
        }
    }
}

/// The elastic problem is the hard one plus its slacks: with the slacks at zero it has the
/// hard objective and rows (the rows replacing box speed bounds hold v itself), slacks enter
/// their rows as -s+ + s- and the objective with the weights, and the bounds are the hard
/// ones with the slacks at >= 0 and (box modes) the inner speeds free.
#[test]
fn elastic_problem_is_the_hard_one_plus_slacks() {
    for hard in all_formulations()
        .iter()
        .filter(|f| f.kind() == ProblemKind::Hard)
    {
        let elastic = hard.elastic();
        let ratios = [7.0, 4.0, 2.0, 1.5];
        let (mut p, mut q) = (
            hard.problem(&ratios).unwrap(),
            elastic.problem(&ratios).unwrap(),
        );
        let (layout, n) = (elastic.layout(), p.num_variables());
        let mut x = random_point(&q, 3);
        x[layout.slacks()].fill(0.0);
        assert_eq!(x[..n], random_point(&p, 3)[..n]);
        let (mut g_hard, mut g) = (
            vec![0.0; p.num_constraints()],
            vec![0.0; q.num_constraints()],
        );
        p.constraints(&x[..n], true, &mut g_hard).unwrap();
        q.constraints(&x, true, &mut g).unwrap();
        let objective = p.objective(&x[..n], true).unwrap();
        assert_eq!(q.objective(&x, true).unwrap(), objective);
        let weights = penalty_weights(hard.space());
        let [plus, minus] = layout.slack(FamilyId::Dynamics, 2, 1).unwrap();
        (x[plus], x[minus]) = (0.25, 0.5);
        let mut shifted = vec![0.0; g.len()];
        q.constraints(&x, true, &mut shifted).unwrap();
        let row = layout.row(FamilyId::Dynamics, 2, 1).unwrap();
        assert!((shifted[row] - g[row] - 0.25).abs() < 1e-12);
        let penalty = q.objective(&x, true).unwrap() - objective;
        assert!((penalty - 0.75 * weights.torque).abs() < 1e-9 * weights.torque);
        let (mut lower, mut upper) = (vec![0.0; q.num_variables()], vec![0.0; q.num_variables()]);
        q.variable_bounds(&mut lower, &mut upper);
        let (mut hard_lower, mut hard_upper) = (vec![0.0; n], vec![0.0; n]);
        p.variable_bounds(&mut hard_lower, &mut hard_upper);
        assert!(layout
            .slacks()
            .all(|c| lower[c] == 0.0 && upper[c] == f64::INFINITY));
        for c in 0..n {
            let free_speed = lower[c] == f64::NEG_INFINITY && upper[c] == f64::INFINITY;
            let same = (lower[c], upper[c]) == (hard_lower[c], hard_upper[c]);
            assert!(same || (free_speed && hard.modes().speed != LimitMode::Exact));
        }
        let (mut row_lower, mut row_upper) = (vec![0.0; g.len()], vec![0.0; g.len()]);
        q.constraint_bounds(&mut row_lower, &mut row_upper);
        for (k, i) in (1..layout.steps).flat_map(|k| (0..layout.dof).map(move |i| (k, i))) {
            let row = layout.row(FamilyId::MotorSpeed, k, i).unwrap();
            if hard.modes().speed == LimitMode::Exact {
                assert_eq!(
                    g[row],
                    g_hard[hard.layout().row(FamilyId::MotorSpeed, k, i).unwrap()]
                );
            } else {
                let v = layout.v(k, i);
                assert_eq!(g[row], x[v]);
                assert_eq!(
                    (row_lower[row], row_upper[row]),
                    (hard_lower[v], hard_upper[v])
                );
            }
        }
    }
}

/// The envelope rows: the hard kind's rows hold tau_u +- c G v within the torque limit at
/// the nodes 0 < k < N; the elastic kind's are the same at zero slack, and a speed slack
/// moves them as it moves the motor speeds, by c B d (B = G A^-1: the identity in mode
/// `exact`, G in the box modes).
#[test]
fn envelope_rows_hold_motor_torque_and_relaxed_motor_speed() {
    let formulations = all_formulations();
    let hard = formulations
        .iter()
        .filter(|f| f.kind() == ProblemKind::Hard && f.envelope().is_some());
    for hard in hard {
        let elastic = hard.elastic();
        let ratios = [7.0, 4.0, 2.0, 1.5];
        let (mut p, mut q) = (
            hard.problem(&ratios).unwrap(),
            elastic.problem(&ratios).unwrap(),
        );
        let envelope = hard.envelope().unwrap();
        let (layout, n) = (elastic.layout(), p.num_variables());
        let mut x = random_point(&q, 5);
        let constraints = |problem: &mut TrajectoryProblem<'_>, x: &[f64]| {
            let mut g = vec![0.0; problem.num_constraints()];
            problem.constraints(x, true, &mut g).unwrap();
            g
        };
        let (g_hard, g) = (constraints(&mut p, &x[..n]), constraints(&mut q, &x));
        let [_, _, row_lower, row_upper] = all_bounds(hard, &ratios);
        let g_matrix = p.coupling().matrix().clone();
        for k in 0..hard.layout().steps {
            let (_, v, _) = hard.layout().node_state(&x, k);
            let u = &x[hard.layout().u(k, 0)..hard.layout().u(k, 0) + 4];
            let (torques, speeds) = (p.motor_torques(u), p.coupling().motor_speeds(v));
            for (i, side) in (0..4).flat_map(|i| Side::BOTH.map(|side| (i, side))) {
                let Some(row) = envelope_row(hard.layout(), k, i, side) else {
                    assert_eq!(k, 0);
                    continue;
                };
                let expected = torques[i] + side.sign() * envelope.slope(i) * speeds[i];
                assert!((g_hard[row] - expected).abs() < 1e-12);
                let limit = hard.motor_torque_limits()[i];
                assert_eq!((row_lower[row], row_upper[row]), (-limit, limit));
                assert_eq!(g[envelope_row(layout, k, i, side).unwrap()], g_hard[row]);
            }
        }
        let [plus, _] = layout.slack(FamilyId::MotorSpeed, 2, 1).unwrap();
        x[plus] = 0.25;
        let shifted = constraints(&mut q, &x);
        for (i, side) in (0..4).flat_map(|i| Side::BOTH.map(|side| (i, side))) {
            let row = envelope_row(layout, 2, i, side).unwrap();
            let b = match hard.modes().speed {
                LimitMode::Exact => f64::from(u8::from(i == 1)),
                LimitMode::Paper | LimitMode::Interval => g_matrix[(i, 1)],
            };
            let expected = -0.25 * side.sign() * envelope.slope(i) * b;
            assert!(
                (shifted[row] - g[row] - expected).abs() < 1e-12,
                "{i} {side:?}"
            );
        }
    }
}

#[test]
fn original_design_has_the_papers_joint_torque_bounds() {
    let f = formulation(Space::Joint, LimitMode::Paper, LimitMode::Exact, 0.0);
    let problem = f.problem(&[6.0, 3.0, 1.0, 1.0]).unwrap();
    assert_eq!(f.layout().steps, 5);
    let (mut lower, mut upper) = (
        vec![0.0; problem.num_variables()],
        vec![0.0; problem.num_variables()],
    );
    problem.variable_bounds(&mut lower, &mut upper);
    let layout = f.layout();
    let expected = [18.7, 8.5, 3.4, 0.0];
    for (i, bound) in expected.iter().enumerate() {
        let u = layout.u(3, i);
        assert!(
            (upper[u] - bound).abs() < 1e-12 && (lower[u] + bound).abs() < 1e-12,
            "joint {i}: [{}, {}]",
            lower[u],
            upper[u]
        );
    }
}

/// Variable and row bounds of `f` at `ratios`.
fn all_bounds(f: &Formulation, ratios: &[f64]) -> [Vec<f64>; 4] {
    let problem = f.problem(ratios).unwrap();
    let (n, m) = (problem.num_variables(), problem.num_constraints());
    let (mut lower, mut upper) = (vec![0.0; n], vec![0.0; n]);
    problem.variable_bounds(&mut lower, &mut upper);
    let (mut row_lower, mut row_upper) = (vec![0.0; m], vec![0.0; m]);
    problem.constraint_bounds(&mut row_lower, &mut row_upper);
    [lower, upper, row_lower, row_upper]
}

/// [`all_formulations`]' hard kinds with the task's motor limits replaced by those of
/// `motors` (ideal motors), the motor model's keys kept.
fn with_motors(motors: &crate::model::task::Motors) -> Vec<Formulation> {
    all_formulations()
        .into_iter()
        .filter(|f| f.kind() == ProblemKind::Hard)
        .map(|f| {
            let mut task = f.task().clone();
            task.motors.torque_limit_nm = motors.torque_limit_nm.clone();
            task.motors.speed_limit_rad_s = motors.speed_limit_rad_s.clone();
            Formulation::new(&task, f.dynamics().robot().clone(), f.space(), *f.modes()).unwrap()
        })
        .collect()
}

/// A list of equal limits bounds every variable and row to the bit as the one number does,
/// in both spaces and every mode.
#[test]
fn equal_limits_per_motor_bound_as_one_limit() {
    use crate::model::task::{Motors, PerMotor};
    let listed = Motors::ideal(PerMotor::Each(vec![1.7; 4]), PerMotor::Each(vec![100.0; 4]));
    let one = all_formulations()
        .into_iter()
        .filter(|f| f.kind() == ProblemKind::Hard);
    for (one, listed) in one.zip(with_motors(&listed)) {
        assert_eq!(one.task().motors.torque_limit_nm, PerMotor::All(1.7));
        for ratios in [[6.0, 3.0, 1.0, 1.0], [7.3, 4.1, 2.2, 1.6]] {
            assert_eq!(all_bounds(&one, &ratios), all_bounds(&listed, &ratios));
        }
    }
}

/// Each motor's own limit bounds its control (actuation space) and its exact rows, and the
/// box modes' joint bounds are the coupling's for the motors' limits.
#[test]
fn each_motor_is_bounded_by_its_own_limit() {
    use crate::model::task::{Motors, PerMotor};
    let (torques, speeds) = ([1.7, 1.0, 2.5, 0.5], [100.0, 60.0, 120.0, 40.0]);
    let motors = Motors::ideal(
        PerMotor::Each(torques.to_vec()),
        PerMotor::Each(speeds.to_vec()),
    );
    let ratios = [7.3, 4.1, 2.2, 1.6];
    for f in with_motors(&motors) {
        assert_eq!(f.motor_torque_limits(), torques);
        assert_eq!(f.motor_speed_limits(), speeds);
        let [lower, upper, row_lower, row_upper] = all_bounds(&f, &ratios);
        let coupling = f.transmission().coupling(&ratios).unwrap();
        let layout = f.layout();
        let torque = match f.space() {
            Space::Actuation => JointLimits::Box {
                lower: torques.iter().map(|t| -t).collect(),
                upper: torques.to_vec(),
            },
            Space::Joint => coupling.torque_limits(f.modes().torque, &torques),
        };
        let speed = coupling.speed_limits(f.modes().speed, &speeds);
        for (k, i) in (1..layout.steps).flat_map(|k| (0..layout.dof).map(move |i| (k, i))) {
            let (u, v) = (layout.u(k, i), layout.v(k, i));
            match &torque {
                JointLimits::Box {
                    lower: lo,
                    upper: hi,
                } => {
                    assert_eq!((lower[u], upper[u]), (lo[i], hi[i]));
                }
                JointLimits::Linear { .. } => {
                    let row = layout.row(FamilyId::MotorTorque, k, i).unwrap();
                    assert_eq!((row_lower[row], row_upper[row]), (-torques[i], torques[i]));
                }
            }
            match &speed {
                JointLimits::Box {
                    lower: lo,
                    upper: hi,
                } => {
                    assert_eq!((lower[v], upper[v]), (lo[i], hi[i]));
                }
                JointLimits::Linear { .. } => {
                    let row = layout.row(FamilyId::MotorSpeed, k, i).unwrap();
                    assert_eq!((row_lower[row], row_upper[row]), (-speeds[i], speeds[i]));
                }
            }
            for row in Side::BOTH.map(|side| envelope_row(layout, k, i, side)) {
                assert_eq!(row.is_some(), f.envelope().is_some());
                if let Some(row) = row {
                    assert_eq!((row_lower[row], row_upper[row]), (-torques[i], torques[i]));
                }
            }
        }
    }
    let mut task = task();
    task.motors.torque_limit_nm = PerMotor::Each(vec![1.7; 3]);
    let robot = Robot::load(&task).unwrap();
    let error = Formulation::new(&task, robot, Space::Actuation, task.limit_modes).unwrap_err();
    assert!(
        error
            .0
            .starts_with("task: motors.torque_limit_nm has 3 values"),
        "{error}"
    );
}

/// The copper losses' cost weighs control i by h R_i / k_t,i^2 and nothing else but the box;
/// it is refused in the joint space, without the motors' constants and with a resistance of 0,
/// each error naming what to give.
#[test]
fn the_copper_losses_weigh_each_motor_by_its_constants() {
    use crate::model::task::PerMotor;
    let f = copper_loss_formulations().remove(0);
    let (k_t, r) = electrical();
    let h = f.task().step_s().unwrap();
    let expected: Vec<f64> = (0..4).map(|i| h * r[i] / (k_t[i] * k_t[i])).collect();
    assert_eq!(
        f.criterion(),
        &super::Criterion::CopperLoss(expected.clone())
    );
    let mut problem = f.problem(&[7.0, 4.0, 2.0, 1.5]).unwrap();
    let mut x = vec![0.0; problem.num_variables()];
    problem.initial_point(&mut x);
    let layout = f.layout();
    for k in 0..layout.steps {
        for i in 0..4 {
            x[layout.u(k, i)] = 0.1 * (i + 1) as f64;
        }
    }
    let box_only = {
        let mut rest = x.clone();
        (0..layout.steps).for_each(|k| (0..4).for_each(|i| rest[layout.u(k, i)] = 0.0));
        problem.objective(&rest, true).unwrap()
    };
    let copper: f64 = (0..4)
        .map(|i| expected[i] * (0.1 * (i + 1) as f64).powi(2))
        .sum();
    let value = problem.objective(&x, true).unwrap() - box_only;
    assert!((value - layout.steps as f64 * copper).abs() < 1e-12 * value);
    let joint = formulation(Space::Joint, LimitMode::Paper, LimitMode::Exact, 1.0);
    let mut task = joint.task().clone();
    let refused = |f: Formulation| f.minimising_copper_loss().unwrap_err().0;
    assert!(refused(joint.clone()).contains("--space actuation"));
    let actuation = formulation(Space::Actuation, LimitMode::Paper, LimitMode::Exact, 1.0);
    let error = refused(actuation.clone());
    assert!(error.contains("motors.torque_constant_nm_per_a and motors.resistance_ohm"));
    task.motors.torque_constant_nm_per_a = Some(PerMotor::All(0.05));
    task.motors.resistance_ohm = Some(PerMotor::Each(vec![1.0, 0.0, 1.0, 1.0]));
    let robot = actuation.dynamics().robot().clone();
    let zero = Formulation::new(&task, robot, Space::Actuation, *actuation.modes()).unwrap();
    assert!(refused(zero).contains("motors.resistance_ohm of motor 2 is 0"));
}

#[test]
fn invalid_designs_are_rejected() {
    let f = formulation(Space::Actuation, LimitMode::Paper, LimitMode::Exact, 0.0);
    for ratios in [
        [10.0, 3.0, 1.0, 1.0],
        [6.0, 6.0, 1.0, 1.0],
        [6.0, 2.0, 3.0, 1.0],
        [f64::NAN, 3.0, 1.0, 1.0],
    ] {
        assert!(f.problem(&ratios).is_err(), "{ratios:?} accepted");
    }
}

/// IPOPT's derivative checker finds nothing in the problem of the planar example carrying a
/// pulley whose mass follows r2 and a motor (`carried_pulley.json`), in both spaces, lossless
/// and lossy, at two designs: the rows and their Hessian use the inertia at the design.
#[test]
fn derivative_checker_finds_nothing_with_carried_parts() {
    let mut task = crate::testing::carried_task();
    task.motion.steps = 5;
    let mut lossy = task.clone();
    lossy.motors.efficiency = Some(crate::model::task::PerMotor::Each(vec![0.9, 0.8]));
    for task in [task, lossy] {
        for space in [Space::Actuation, Space::Joint] {
            let robot = Robot::load(&task).unwrap();
            let f = Formulation::new(&task, robot, space, task.limit_modes).unwrap();
            for ratios in [[50.0, 12.0], [30.0, 30.0]] {
                assert_checker_finds_nothing(&f, &ratios);
            }
        }
    }
}

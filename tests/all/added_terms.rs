//! A constraint and two cost terms composed onto the trajectory problem from outside the core,
//! through its public traits alone: the TCP kept above a floor at every node, the squared
//! accelerations, and a term that couples the controls with the speeds. Their derivatives pass
//! IPOPT's checker, the solve honours the floor, and the result reports the floor's violation
//! and the terms' values under their names.

use codesign_core::ipopt::{check_derivatives, DerivativeOrder, Options};
use codesign_core::model::{task::Task, Robot};
use codesign_core::problem::{Formulation, NodeConstraint, NodeContext, NodeCost, Space};
use codesign_core::solve::{solve_design, SolveSettings};
use nalgebra::DMatrix;
use std::sync::Arc;

/// The TCP's world z at or above `z_min` (m) at every node: one row, z(q_k) - z_min >= 0.
#[derive(Debug)]
struct TcpFloor {
    z_min: f64,
}

impl NodeConstraint for TcpFloor {
    fn name(&self) -> &str {
        "tcp_floor"
    }

    fn rows(&self) -> usize {
        1
    }

    fn bounds(&self, _k: usize, _steps: usize, lower: &mut [f64], upper: &mut [f64]) {
        (lower[0], upper[0]) = (0.0, f64::INFINITY);
    }

    fn values(&self, node: &mut NodeContext<'_>, values: &mut [f64]) {
        values[0] = node.dynamics.tcp_position(node.workspace, node.q)[2] - self.z_min;
    }

    fn jacobian(&self, node: &mut NodeContext<'_>, jacobian: &mut DMatrix<f64>) {
        let n = node.q.len();
        let mut tcp = DMatrix::zeros(3, n);
        node.dynamics.tcp_jacobian(node.workspace, node.q, &mut tcp);
        for j in 0..n {
            jacobian[(0, j)] = tcp[(2, j)];
        }
    }

    fn hessian(&self, node: &mut NodeContext<'_>, multipliers: &[f64], hessian: &mut DMatrix<f64>) {
        let n = node.q.len();
        let mut tcp = [
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
        ];
        node.dynamics.tcp_hessians(node.workspace, node.q, &mut tcp);
        for i in 0..n {
            for j in 0..n {
                hessian[(i, j)] += multipliers[0] * tcp[2][(i, j)];
            }
        }
    }
}

/// w h sum_i a_i^2 at each node.
#[derive(Debug)]
struct Accelerations {
    weight: f64,
}

impl NodeCost for Accelerations {
    fn name(&self) -> &str {
        "accelerations"
    }

    fn value(&self, node: &mut NodeContext<'_>) -> f64 {
        self.weight * node.step_s * node.a.iter().map(|a| a * a).sum::<f64>()
    }

    fn gradient(&self, node: &mut NodeContext<'_>, gradient: &mut [f64]) {
        let n = node.a.len();
        for (i, a) in node.a.iter().enumerate() {
            gradient[2 * n + i] += 2.0 * self.weight * node.step_s * a;
        }
    }

    fn hessian(&self, node: &mut NodeContext<'_>, hessian: &mut DMatrix<f64>) {
        let n = node.a.len();
        for i in 0..n {
            hessian[(2 * n + i, 2 * n + i)] += 2.0 * self.weight * node.step_s;
        }
    }
}

/// w h sum_i (u_i v_i)^2 at each node: second derivatives in u-u, u-v and v-v.
#[derive(Debug)]
struct SquaredPower {
    weight: f64,
}

impl NodeCost for SquaredPower {
    fn name(&self) -> &str {
        "squared_power"
    }

    fn value(&self, node: &mut NodeContext<'_>) -> f64 {
        let power = node.u.iter().zip(node.v).map(|(u, v)| (u * v).powi(2));
        self.weight * node.step_s * power.sum::<f64>()
    }

    fn gradient(&self, node: &mut NodeContext<'_>, gradient: &mut [f64]) {
        let (n, c) = (node.u.len(), 2.0 * self.weight * node.step_s);
        for i in 0..n {
            let (u, v) = (node.u[i], node.v[i]);
            gradient[n + i] += c * u * u * v;
            gradient[3 * n + i] += c * u * v * v;
        }
    }

    fn hessian(&self, node: &mut NodeContext<'_>, hessian: &mut DMatrix<f64>) {
        let (n, c) = (node.u.len(), 2.0 * self.weight * node.step_s);
        for i in 0..n {
            let (u, v) = (node.u[i], node.v[i]);
            hessian[(n + i, n + i)] += c * u * u;
            hessian[(3 * n + i, 3 * n + i)] += c * v * v;
            hessian[(3 * n + i, n + i)] += 2.0 * c * u * v;
        }
    }
}

/// The built-in task at 1 kg on 10 intervals, in the actuation space.
fn formulation() -> Formulation {
    let mut task = Task::built_in().expect("the built-in task loads");
    task.motion.steps = 10;
    task.payload.mass_kg = 1.0;
    let robot = Robot::load(&task).expect("its robot loads");
    Formulation::new(&task, robot, Space::Actuation, task.limit_modes).expect("it formulates")
}

const ORIGINAL: [f64; 4] = [6.0, 3.0, 1.0, 1.0];

#[test]
fn terms_added_from_outside_the_core_solve_check_and_report() {
    let plain = solve_design(&formulation(), &ORIGINAL, &SolveSettings::default()).unwrap();
    assert!(plain.feasible);
    let lowest = plain
        .trajectory
        .tcp_z
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    // A floor 5 cm above the plain motion's lowest point: it must bind.
    let floor = lowest + 0.05;
    let added = formulation()
        .with_constraint(Arc::new(TcpFloor { z_min: floor }))
        .with_cost(Arc::new(Accelerations { weight: 1e-4 }))
        .with_cost(Arc::new(SquaredPower { weight: 1e-3 }));

    for radius in [0.0, 0.05] {
        let mut problem = added.problem(&ORIGINAL).unwrap();
        let options = Options::new()
            .num("point_perturbation_radius", radius)
            .num("derivative_test_tol", 1e-4);
        let report = check_derivatives(&mut problem, &options, DerivativeOrder::Second).unwrap();
        assert_eq!(report.errors, 0, "radius {radius}: {:?}", report.flagged);
    }

    let result = solve_design(&added, &ORIGINAL, &SolveSettings::default()).unwrap();
    assert!(result.feasible, "{:?}", result.reason);
    let violation = result
        .violations
        .get("tcp_floor")
        .expect("the floor's violation");
    assert!(violation <= 1e-7, "{violation}");
    let below = result.trajectory.tcp_z[..10]
        .iter()
        .fold(f64::INFINITY, |m, &z| m.min(z));
    assert!(below >= floor - 1e-7, "{below} under {floor}");
    assert!(plain.violations.get("tcp_floor").is_none());
    let terms = result.cost_terms.expect("the cost by term");
    let (accelerations, power) = (
        terms.added.get("accelerations"),
        terms.added.get("squared_power"),
    );
    assert!(accelerations.unwrap() > 0.0 && power.unwrap() > 0.0);
    let sum = terms.position + terms.velocity + terms.control + terms.cartesian_box;
    let total = sum + accelerations.unwrap() + power.unwrap();
    assert!(
        (total - result.cost).abs() <= 1e-9 * result.cost.abs(),
        "{total} != {}",
        result.cost
    );
}

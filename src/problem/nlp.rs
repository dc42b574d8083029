//! The trajectory problem of one design: bounds, initial guess, cost, constraints and their exact
//! sparse derivatives.
//!
//! Sparse matrices are produced by one routine per matrix that visits every structural non-zero in
//! a fixed order; run on zero data it yields the pattern (once per [`Formulation`]), run on the
//! evaluated nodes it yields the values, so the two can never disagree.

use super::{Formulation, Layout, Space};
use crate::dynamics::Workspace;
use crate::ipopt::{EvalError, Nlp};
use crate::transmission::{Coupling, DesignError, JointLimits};
use nalgebra::{DMatrix, Vector3};

/// What the derivatives need at one node k < N, evaluated once per primal point.
#[derive(Clone, Debug)]
struct NodeEval {
    /// RNEA(q_k, v_k, a_k), N m.
    tau: Vec<f64>,
    dtau_dq: DMatrix<f64>,
    dtau_dv: DMatrix<f64>,
    mass: DMatrix<f64>,
    /// TCP position in the world, m.
    tcp: Vector3<f64>,
    /// d tcp / dq, 3 x n.
    tcp_jacobian: DMatrix<f64>,
}

impl NodeEval {
    fn zeros(n: usize) -> NodeEval {
        NodeEval {
            tau: vec![0.0; n],
            dtau_dq: DMatrix::zeros(n, n),
            dtau_dv: DMatrix::zeros(n, n),
            mass: DMatrix::zeros(n, n),
            tcp: Vector3::zeros(),
            tcp_jacobian: DMatrix::zeros(3, n),
        }
    }
}

/// How far the primal point's node data are evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Level {
    Nothing,
    Values,
    Derivatives,
}

/// The trajectory NLP of one design (see [`Formulation`]).
#[derive(Clone, Debug)]
pub struct TrajectoryProblem<'a> {
    formulation: &'a Formulation,
    ratios: Vec<f64>,
    coupling: Coupling,
    /// G^T in actuation space (tau = G^T u), the identity in joint space.
    control_map: DMatrix<f64>,
    /// G^-T, the motor torque of a joint torque.
    motor_of_joint: DMatrix<f64>,
    /// One dynamics workspace per node k < N (all of the formulation's one model), so that each
    /// keeps its node's kinematics cached from one callback to the next (the Hessian reuses what
    /// the Jacobian computed at the same point).
    workspaces: Vec<Workspace>,
    nodes: Vec<NodeEval>,
    level: Level,
    rnea_hessian: DMatrix<f64>,
    tcp_hessians: [DMatrix<f64>; 3],
    cost_qq: DMatrix<f64>,
}

impl<'a> TrajectoryProblem<'a> {
    pub(super) fn new(formulation: &'a Formulation, ratios: &[f64]) -> Result<Self, DesignError> {
        formulation.transmission.check_design(ratios)?;
        let coupling = formulation.transmission.coupling(ratios)?;
        let n = formulation.layout.dof;
        let control_map = match formulation.space {
            Space::Actuation => coupling.matrix().transpose(),
            Space::Joint => DMatrix::identity(n, n),
        };
        let motor_of_joint = coupling.inverse().transpose();
        Ok(TrajectoryProblem {
            formulation,
            ratios: ratios.to_vec(),
            coupling,
            control_map,
            motor_of_joint,
            workspaces: (0..formulation.layout.steps)
                .map(|_| formulation.dynamics.workspace())
                .collect(),
            nodes: vec![NodeEval::zeros(n); formulation.layout.steps],
            level: Level::Nothing,
            rnea_hessian: DMatrix::zeros(3 * n, 3 * n),
            tcp_hessians: [
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, n),
            ],
            cost_qq: DMatrix::zeros(n, n),
        })
    }

    /// The formulation this problem belongs to.
    pub fn formulation(&self) -> &'a Formulation {
        self.formulation
    }

    /// The design r.
    pub fn ratios(&self) -> &[f64] {
        &self.ratios
    }

    /// G(r) and its inverse at this design.
    pub fn coupling(&self) -> &Coupling {
        &self.coupling
    }

    /// Joint torques of control u at a node: G^T u (actuation space) or u (joint space), N m.
    pub fn joint_torques(&self, u: &[f64]) -> Vec<f64> {
        (&self.control_map * nalgebra::DVector::from_column_slice(u))
            .iter()
            .copied()
            .collect()
    }

    /// Motor torques of control u at a node: u (actuation space) or G^-T u (joint space), N m.
    pub fn motor_torques(&self, u: &[f64]) -> Vec<f64> {
        match self.formulation.space {
            Space::Actuation => u.to_vec(),
            Space::Joint => (&self.motor_of_joint * nalgebra::DVector::from_column_slice(u))
                .iter()
                .copied()
                .collect(),
        }
    }

    /// Evaluates the node data at x up to `level` (cached until x changes).
    fn evaluate(&mut self, x: &[f64], new_x: bool, level: Level) -> Result<(), EvalError> {
        if new_x {
            self.level = Level::Nothing;
        }
        if self.level >= level {
            return Ok(());
        }
        if let Some(i) = x.iter().position(|value| !value.is_finite()) {
            return Err(EvalError(format!(
                "variable {i} is {} at the evaluation point",
                x[i]
            )));
        }
        let dynamics = &self.formulation.dynamics;
        let layout = &self.formulation.layout;
        let n = layout.dof;
        let nodes = self.nodes.iter_mut().zip(&mut self.workspaces);
        for (k, (node, data)) in nodes.enumerate() {
            let q = &x[layout.q(k, 0)..layout.q(k, 0) + n];
            let v = &x[layout.v(k, 0)..layout.v(k, 0) + n];
            let a = &x[layout.a(k, 0)..layout.a(k, 0) + n];
            if level == Level::Derivatives {
                dynamics.rnea_derivatives(
                    data,
                    q,
                    v,
                    a,
                    &mut node.tau,
                    &mut node.dtau_dq,
                    &mut node.dtau_dv,
                    &mut node.mass,
                );
                dynamics.tcp_jacobian(data, q, &mut node.tcp_jacobian);
            } else {
                dynamics.rnea(data, q, v, a, &mut node.tau);
            }
            node.tcp = dynamics.tcp_position(data, q);
        }
        self.level = level;
        Ok(())
    }
}

/// Box penalty of one TCP coordinate p, m: (c, dc/dp) with c = max(0, lo - p) + max(0, p - hi).
fn box_violation(range: [f64; 2], p: f64) -> (f64, f64) {
    if p < range[0] {
        (range[0] - p, -1.0)
    } else if p > range[1] {
        (p - range[1], 1.0)
    } else {
        (0.0, 0.0)
    }
}

/// The constrained world axes of the Cartesian box: (axis 0..3, range, weight).
fn box_axes(f: &Formulation) -> impl Iterator<Item = (usize, [f64; 2], f64)> + '_ {
    let b = &f.task.cartesian_box;
    [&b.x, &b.y, &b.z]
        .into_iter()
        .enumerate()
        .filter_map(|(axis, interval)| interval.as_ref().map(|s| (axis, s.range, s.weight)))
}

/// The design-dependent matrices the Jacobian's values come from.
struct JacobianData<'m> {
    /// d(tau)/d(u): G^T or the identity.
    control_map: &'m DMatrix<f64>,
    /// Structural non-zeros of `control_map`.
    control_pattern: &'m DMatrix<f64>,
    /// G and its pattern, when motor speeds are linear rows.
    speed: Option<(&'m DMatrix<f64>, &'m DMatrix<f64>)>,
    /// G^-T, when motor torques are linear rows.
    torque: Option<&'m DMatrix<f64>>,
    /// Time step h, s.
    h: f64,
}

/// Visits the Jacobian's structural non-zeros in their fixed order.
fn visit_jacobian(
    layout: &Layout,
    data: &JacobianData<'_>,
    nodes: &[NodeEval],
    mut emit: impl FnMut(usize, usize, f64),
) {
    let JacobianData {
        control_map,
        control_pattern,
        speed,
        torque,
        h,
    } = *data;
    let n = layout.dof;
    for (k, node) in nodes.iter().enumerate() {
        for i in 0..n {
            let row = layout.dynamics_row(k, i);
            for j in 0..n {
                emit(row, layout.q(k, j), node.dtau_dq[(i, j)]);
            }
            for j in 0..n {
                emit(row, layout.v(k, j), node.dtau_dv[(i, j)]);
            }
            for j in 0..n {
                emit(row, layout.a(k, j), node.mass[(i, j)]);
            }
            for j in 0..n {
                if control_pattern[(i, j)] != 0.0 {
                    emit(row, layout.u(k, j), -control_map[(i, j)]);
                }
            }
        }
        for i in 0..n {
            let row = layout.velocity_row(k, i);
            emit(row, layout.v(k, i), -1.0);
            emit(row, layout.a(k, i), -h);
            emit(row, layout.v(k + 1, i), 1.0);
        }
        for i in 0..n {
            let row = layout.position_row(k, i);
            emit(row, layout.q(k, i), -1.0);
            emit(row, layout.q(k + 1, i), 1.0);
            emit(row, layout.v(k + 1, i), -h);
        }
        if let Some((g, g_pattern)) = speed {
            for i in 0..n {
                if let Some(row) = layout.speed_row(k, i) {
                    for j in 0..n {
                        if g_pattern[(i, j)] != 0.0 {
                            emit(row, layout.v(k, j), g[(i, j)]);
                        }
                    }
                }
            }
        }
        if let Some(motor_of_joint) = torque {
            for i in 0..n {
                if let Some(row) = layout.torque_row(k, i) {
                    for j in 0..n {
                        emit(row, layout.u(k, j), motor_of_joint[(i, j)]);
                    }
                }
            }
        }
    }
}

/// The pattern of the control block of the dynamics rows: d(tau_i)/d(u_j).
fn control_pattern(formulation: &Formulation) -> DMatrix<f64> {
    match formulation.space {
        Space::Actuation => formulation.g_pattern.transpose(),
        Space::Joint => DMatrix::identity(formulation.layout.dof, formulation.layout.dof),
    }
}

pub(super) fn jacobian_pattern(formulation: &Formulation) -> Vec<(usize, usize)> {
    let layout = &formulation.layout;
    let n = layout.dof;
    let nodes = vec![NodeEval::zeros(n); layout.steps];
    let pattern = control_pattern(formulation);
    let dense = DMatrix::from_element(n, n, 1.0);
    let mut entries = Vec::new();
    let data = JacobianData {
        control_map: &pattern,
        control_pattern: &pattern,
        speed: layout
            .speed_rows
            .then_some((&formulation.g_pattern, &formulation.g_pattern)),
        torque: layout.torque_rows.then_some(&dense),
        h: 0.0,
    };
    visit_jacobian(layout, &data, &nodes, |row, col, _| {
        entries.push((row, col))
    });
    entries
}

/// The lower triangle of one node's block of the Lagrangian Hessian, as (i, j) within the node's
/// 4n variables (q, v, a, u): the dynamics give q-q (lower), v-q, v-v (lower) and a-q (a-v and
/// a-a vanish since RNEA is linear in a); the cost adds to q-q, the v-v diagonal and the u-u
/// diagonal. Node k's block starts at column 4nk, so its global entries are offset by that.
pub(super) fn node_hessian_entries(n: usize) -> Vec<(usize, usize)> {
    let mut entries = Vec::new();
    for i in 0..n {
        entries.extend((0..=i).map(|j| (i, j)));
    }
    for i in n..2 * n {
        entries.extend((0..=i).map(|j| (i, j)));
    }
    for i in 2 * n..3 * n {
        entries.extend((0..n).map(|j| (i, j)));
    }
    entries.extend((3 * n..4 * n).map(|i| (i, i)));
    entries
}

pub(super) fn hessian_pattern(formulation: &Formulation) -> Vec<(usize, usize)> {
    let layout = &formulation.layout;
    (0..layout.steps)
        .flat_map(|k| {
            let base = layout.q(k, 0);
            formulation
                .node_hessian
                .iter()
                .map(move |&(i, j)| (base + i, base + j))
        })
        .collect()
}

impl Nlp for TrajectoryProblem<'_> {
    fn num_variables(&self) -> usize {
        self.formulation.layout.num_variables()
    }

    fn num_constraints(&self) -> usize {
        self.formulation.layout.num_constraints()
    }

    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        let f = self.formulation;
        let (layout, task) = (&f.layout, &f.task);
        let n = layout.dof;
        lower.fill(f64::NEG_INFINITY);
        upper.fill(f64::INFINITY);
        let limits = f.dynamics.robot().position_limits();
        let speed = self
            .coupling
            .speed_limits(f.modes.speed, task.motors.speed_limit_rad_s);
        let torque = match f.space {
            Space::Actuation => {
                let t = task.motors.torque_limit_nm;
                JointLimits::Box {
                    lower: vec![-t; n],
                    upper: vec![t; n],
                }
            }
            Space::Joint => self
                .coupling
                .torque_limits(f.modes.torque, task.motors.torque_limit_nm),
        };
        for k in 0..=layout.steps {
            for i in 0..n {
                let (q, v) = (layout.q(k, i), layout.v(k, i));
                (lower[q], upper[q]) = limits[i];
                if let JointLimits::Box {
                    lower: lo,
                    upper: hi,
                } = &speed
                {
                    (lower[v], upper[v]) = (lo[i], hi[i]);
                }
                if k < layout.steps {
                    if let JointLimits::Box {
                        lower: lo,
                        upper: hi,
                    } = &torque
                    {
                        let u = layout.u(k, i);
                        (lower[u], upper[u]) = (lo[i], hi[i]);
                    }
                }
            }
        }
        for i in 0..n {
            for (k, pose) in [(0, &task.motion.start), (layout.steps, &task.motion.goal)] {
                let (q, v) = (layout.q(k, i), layout.v(k, i));
                (lower[q], upper[q]) = (pose[i], pose[i]);
                (lower[v], upper[v]) = (0.0, 0.0);
            }
        }
    }

    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        let f = self.formulation;
        let layout = &f.layout;
        lower.fill(0.0);
        upper.fill(0.0);
        let (w, t) = (
            f.task.motors.speed_limit_rad_s,
            f.task.motors.torque_limit_nm,
        );
        for k in 0..layout.steps {
            for i in 0..layout.dof {
                if let Some(row) = layout.speed_row(k, i) {
                    (lower[row], upper[row]) = (-w, w);
                }
                if let Some(row) = layout.torque_row(k, i) {
                    (lower[row], upper[row]) = (-t, t);
                }
            }
        }
    }

    /// The standard initial guess (docs/model.md, section 6): q linear from start to goal; v the
    /// mean speed at inner nodes, 0 at the ends; u = 0; a = 0.
    fn initial_point(&self, x: &mut [f64]) {
        let f = self.formulation;
        let (layout, motion) = (&f.layout, &f.task.motion);
        x.fill(0.0);
        for k in 0..=layout.steps {
            let s = k as f64 / layout.steps as f64;
            for i in 0..layout.dof {
                let (start, goal) = (motion.start[i], motion.goal[i]);
                x[layout.q(k, i)] = start + s * (goal - start);
                if k > 0 && k < layout.steps {
                    x[layout.v(k, i)] = (goal - start) / motion.horizon_s;
                }
            }
        }
    }

    fn objective(&mut self, x: &[f64], new_x: bool) -> Result<f64, EvalError> {
        self.evaluate(x, new_x, Level::Values)?;
        let f = self.formulation;
        let (layout, w) = (&f.layout, &f.task.weights);
        let n = layout.dof;
        let mut cost = 0.0;
        for (k, node) in self.nodes.iter().enumerate() {
            for i in 0..n {
                let (q, v, u) = (x[layout.q(k, i)], x[layout.v(k, i)], x[layout.u(k, i)]);
                cost += w.position * q * q + w.velocity * v * v + w.control * u * u;
            }
            for (axis, range, weight) in box_axes(f) {
                let (c, _) = box_violation(range, node.tcp[axis]);
                cost += weight * c * c;
            }
        }
        Ok(cost)
    }

    fn gradient(&mut self, x: &[f64], new_x: bool, gradient: &mut [f64]) -> Result<(), EvalError> {
        self.evaluate(x, new_x, Level::Derivatives)?;
        let f = self.formulation;
        let (layout, w) = (&f.layout, &f.task.weights);
        let n = layout.dof;
        gradient.fill(0.0);
        for (k, node) in self.nodes.iter().enumerate() {
            for i in 0..n {
                let (q, v, u) = (layout.q(k, i), layout.v(k, i), layout.u(k, i));
                gradient[q] = 2.0 * w.position * x[q];
                gradient[v] = 2.0 * w.velocity * x[v];
                gradient[u] = 2.0 * w.control * x[u];
            }
            for (axis, range, weight) in box_axes(f) {
                let (c, sign) = box_violation(range, node.tcp[axis]);
                if c > 0.0 {
                    for j in 0..n {
                        gradient[layout.q(k, j)] +=
                            2.0 * weight * c * sign * node.tcp_jacobian[(axis, j)];
                    }
                }
            }
        }
        Ok(())
    }

    fn constraints(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) -> Result<(), EvalError> {
        self.evaluate(x, new_x, Level::Values)?;
        let f = self.formulation;
        let layout = &f.layout;
        let (n, h) = (layout.dof, f.step_s());
        let g_matrix = self.coupling.matrix();
        for (k, node) in self.nodes.iter().enumerate() {
            let u = &x[layout.u(k, 0)..layout.u(k, 0) + n];
            for i in 0..n {
                let applied: f64 = (0..n).map(|j| self.control_map[(i, j)] * u[j]).sum();
                g[layout.dynamics_row(k, i)] = node.tau[i] - applied;
                g[layout.velocity_row(k, i)] =
                    x[layout.v(k + 1, i)] - x[layout.v(k, i)] - h * x[layout.a(k, i)];
                g[layout.position_row(k, i)] =
                    x[layout.q(k + 1, i)] - x[layout.q(k, i)] - h * x[layout.v(k + 1, i)];
                if let Some(row) = layout.speed_row(k, i) {
                    g[row] = (0..n).map(|j| g_matrix[(i, j)] * x[layout.v(k, j)]).sum();
                }
                if let Some(row) = layout.torque_row(k, i) {
                    g[row] = (0..n).map(|j| self.motor_of_joint[(i, j)] * u[j]).sum();
                }
            }
        }
        Ok(())
    }

    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        self.formulation.jacobian.clone()
    }

    fn jacobian_values(
        &mut self,
        x: &[f64],
        new_x: bool,
        values: &mut [f64],
    ) -> Result<(), EvalError> {
        self.evaluate(x, new_x, Level::Derivatives)?;
        let f = self.formulation;
        let layout = &f.layout;
        let pattern = control_pattern(f);
        let mut next = 0;
        let data = JacobianData {
            control_map: &self.control_map,
            control_pattern: &pattern,
            speed: layout
                .speed_rows
                .then_some((self.coupling.matrix(), &f.g_pattern)),
            torque: layout.torque_rows.then_some(&self.motor_of_joint),
            h: f.step_s(),
        };
        visit_jacobian(layout, &data, &self.nodes, |_, _, value| {
            values[next] = value;
            next += 1;
        });
        Ok(())
    }

    fn hessian_structure(&self) -> Vec<(usize, usize)> {
        self.formulation.hessian.clone()
    }

    fn hessian_values(
        &mut self,
        x: &[f64],
        new_x: bool,
        obj_factor: f64,
        lambda: &[f64],
        values: &mut [f64],
    ) -> Result<(), EvalError> {
        self.evaluate(x, new_x, Level::Derivatives)?;
        let f = self.formulation;
        let (layout, w) = (&f.layout, &f.task.weights);
        let n = layout.dof;
        let mut next = 0;
        for k in 0..layout.steps {
            let q = &x[layout.q(k, 0)..layout.q(k, 0) + n];
            let v = &x[layout.v(k, 0)..layout.v(k, 0) + n];
            let a = &x[layout.a(k, 0)..layout.a(k, 0) + n];
            let multipliers = &lambda[layout.dynamics_row(k, 0)..layout.dynamics_row(k, 0) + n];
            let data = &mut self.workspaces[k];
            f.dynamics
                .rnea_hessian(data, q, v, a, multipliers, &mut self.rnea_hessian);
            // The cost's Hessian in q: 2 wq I, plus 2 rho (J^T J + c sign H) per violated axis.
            self.cost_qq.fill_with_identity();
            self.cost_qq *= 2.0 * w.position;
            let node = &self.nodes[k];
            let mut tcp_hessians_ready = false;
            for (axis, range, weight) in box_axes(f) {
                let (c, sign) = box_violation(range, node.tcp[axis]);
                if c > 0.0 {
                    if !tcp_hessians_ready {
                        f.dynamics.tcp_hessians(data, q, &mut self.tcp_hessians);
                        tcp_hessians_ready = true;
                    }
                    for i in 0..n {
                        for j in 0..n {
                            let jj = node.tcp_jacobian[(axis, i)] * node.tcp_jacobian[(axis, j)];
                            self.cost_qq[(i, j)] +=
                                2.0 * weight * (jj + c * sign * self.tcp_hessians[axis][(i, j)]);
                        }
                    }
                }
            }
            for &(i, j) in &f.node_hessian {
                let (cost, dynamics) = if i < n {
                    (self.cost_qq[(i, j)], self.rnea_hessian[(i, j)])
                } else if i < 3 * n {
                    let cost = if i < 2 * n && i == j {
                        2.0 * w.velocity
                    } else {
                        0.0
                    };
                    (cost, self.rnea_hessian[(i, j)])
                } else {
                    (2.0 * w.control, 0.0)
                };
                values[next] = obj_factor * cost + dynamics;
                next += 1;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipopt::{check_derivatives, DerivativeOrder, Options};
    use crate::model::task::{LimitMode, LimitModes, Task};
    use crate::model::Robot;
    use std::path::Path;

    fn task() -> Task {
        Task::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/tasks/pick_place.json"))
            .unwrap()
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

    /// Every combination of space and modes (torque modes only matter in joint space).
    fn all_formulations() -> Vec<Formulation> {
        let modes = [LimitMode::Paper, LimitMode::Interval, LimitMode::Exact];
        let mut list = Vec::new();
        for speed in modes {
            list.push(formulation(Space::Actuation, LimitMode::Paper, speed, 1.0));
            for torque in modes {
                list.push(formulation(Space::Joint, torque, speed, 1.0));
            }
        }
        list
    }

    /// A small deterministic generator for test points.
    struct Lcg(u64);
    impl Lcg {
        fn uniform(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A point near the initial guess with every variable moved: the TCP leaves the box at some
    /// nodes, so the penalty's derivatives are exercised too.
    fn random_point(problem: &TrajectoryProblem<'_>, seed: u64) -> Vec<f64> {
        let mut x = vec![0.0; problem.num_variables()];
        problem.initial_point(&mut x);
        let mut rng = Lcg(seed);
        for value in &mut x {
            *value += 0.6 * (rng.uniform() - 0.5);
        }
        x
    }

    #[test]
    fn sparse_derivatives_match_finite_differences() {
        for f in all_formulations() {
            let mut problem = f.problem(&[7.0, 4.0, 2.0, 1.5]).unwrap();
            let (n, m) = (problem.num_variables(), problem.num_constraints());
            let x = random_point(&problem, 7);
            let lambda: Vec<f64> = {
                let mut rng = Lcg(11);
                (0..m).map(|_| rng.uniform() - 0.5).collect()
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
            for (&(r, c), &value) in f.jacobian.iter().zip(&jacobian) {
                dense_jacobian[(r, c)] += value;
            }
            let mut dense_hessian = DMatrix::<f64>::zeros(n, n);
            for (&(r, c), &value) in f.hessian.iter().zip(&hessian) {
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
                for (&(r, c), &value) in f.jacobian.iter().zip(&values) {
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
    }

    #[test]
    fn ipopt_derivative_checker_finds_nothing() {
        for f in all_formulations() {
            for (point, radius) in [("initial guess", 0.0), ("random interior point", 0.05)] {
                let mut problem = f.problem(&[6.0, 3.0, 1.0, 1.0]).unwrap();
                let options = Options::new()
                    .num("point_perturbation_radius", radius)
                    .num("derivative_test_perturbation", 1e-7)
                    .num("derivative_test_tol", 1e-4);
                let report =
                    check_derivatives(&mut problem, &options, DerivativeOrder::Second).unwrap();
                assert_eq!(
                    report.errors,
                    0,
                    "{} space, modes {:?}, {point}: {:?}",
                    f.space(),
                    f.modes(),
                    &report.flagged[..report.flagged.len().min(10)]
                );
            }
        }
    }

    #[test]
    fn pattern_is_lower_triangular_and_unique() {
        for f in all_formulations() {
            let mut seen = std::collections::HashSet::new();
            for &(r, c) in &f.hessian {
                assert!(r >= c);
                assert!(seen.insert((r, c)), "duplicate Hessian entry ({r}, {c})");
            }
            let mut seen = std::collections::HashSet::new();
            for &entry in &f.jacobian {
                assert!(seen.insert(entry), "duplicate Jacobian entry {entry:?}");
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
}

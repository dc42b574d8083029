//! Inverse dynamics (RNEA), the joint-space mass matrix (CRBA), nonlinear effects, gravity
//! torques and forward dynamics (Cholesky of the mass matrix), all in the world frame.
//!
//! RNEA with gravity as a base acceleration a_base = -g: v_i = v_(i-1) + S_i qd_i,
//! a_i = a_(i-1) + S_i qdd_i + (v_i x S_i) qd_i, f_i = I_i a_i + v_i x* I_i v_i,
//! tau_i = S_i . sum_(k >= i) f_k. CRBA: M_ij = S_i . IC_max(i,j) S_j with IC_i = sum_(k >= i) I_k.

use super::spatial::{Force, Inertia, Motion};
use super::{shape, BodyFrame, Dynamics, Workspace};
use crate::model::chain::MassProperties;
use nalgebra::DMatrix;

impl Dynamics {
    /// Inverse dynamics tau = M(q) a + b(q, v), N m, at q (rad), v (rad/s), a (rad/s^2).
    ///
    /// ```
    /// use codesign_core::dynamics::Dynamics;
    /// use codesign_core::model::{task::Task, Robot};
    ///
    /// let task = Task::built_in()?;
    /// let dynamics = Dynamics::new(Robot::load(&task)?);
    /// let mut data = dynamics.workspace();
    /// let (q, v, a) = ([0.1, 0.5, -0.3, 0.2], [0.4, -0.2, 0.1, 0.3], [1.0, 0.5, -1.0, 0.0]);
    /// let mut tau = [0.0; 4];
    /// dynamics.rnea(&mut data, &q, &v, &a, &mut tau);
    ///
    /// // tau = M(q) a + b(q, v)
    /// let mut mass = nalgebra::DMatrix::zeros(4, 4);
    /// let mut b = [0.0; 4];
    /// dynamics.mass_matrix(&mut data, &q, &mut mass);
    /// dynamics.nonlinear_effects(&mut data, &q, &v, &mut b);
    /// let m_a = &mass * nalgebra::DVector::from_column_slice(&a);
    /// for j in 0..4 {
    ///     assert!((tau[j] - m_a[j] - b[j]).abs() < 1e-12);
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn rnea(&self, data: &mut Workspace, q: &[f64], v: &[f64], a: &[f64], tau: &mut [f64]) {
        self.expect_joints("v", v);
        self.expect_joints("a", a);
        self.inverse_dynamics(data, q, Some(v), Some(a), tau);
    }

    /// b(q, v) = RNEA(q, v, 0): Coriolis, centrifugal and gravity torques, N m.
    pub fn nonlinear_effects(&self, data: &mut Workspace, q: &[f64], v: &[f64], b: &mut [f64]) {
        self.expect_joints("v", v);
        self.inverse_dynamics(data, q, Some(v), None, b);
    }

    /// Gravity torques g(q) = RNEA(q, 0, 0), N m.
    pub fn gravity_torques(&self, data: &mut Workspace, q: &[f64], g: &mut [f64]) {
        self.inverse_dynamics(data, q, None, None, g);
    }

    /// The joint-space mass matrix M(q) (n x n, kg m^2); `mass` is resized if it has another shape.
    pub fn mass_matrix(&self, data: &mut Workspace, q: &[f64], mass: &mut DMatrix<f64>) {
        self.update_frames(data, q);
        let n = self.dof();
        shape(mass, n, n);
        let mut composite = Inertia::default();
        for i in (0..n).rev() {
            composite += data.frames[i].inertia;
            let column = composite.apply(&data.frames[i].s);
            for j in 0..=i {
                let entry = data.frames[j].s.dot(&column);
                mass[(i, j)] = entry;
                mass[(j, i)] = entry;
            }
        }
    }

    /// Forward dynamics: the a (rad/s^2) solving M(q) a + b(q, v) = tau (N m). Should M not be
    /// numerically positive definite (only possible for a degenerate model), `a` is all NaN.
    pub fn forward_dynamics(
        &self,
        data: &mut Workspace,
        q: &[f64],
        v: &[f64],
        tau: &[f64],
        a: &mut [f64],
    ) {
        self.expect_joints("tau", tau);
        self.nonlinear_effects(data, q, v, a);
        for (rhs, torque) in a.iter_mut().zip(tau) {
            *rhs = torque - *rhs;
        }
        let mut factor = std::mem::take(&mut data.factor);
        self.mass_matrix(data, q, &mut factor);
        if cholesky_in_place(&mut factor) {
            cholesky_solve(&factor, a);
        } else {
            a.fill(f64::NAN);
        }
        data.factor = factor;
    }

    /// The derivative of RNEA(q, v, a) (N m) along a change of the bodies' inertial
    /// parameters, `parts` giving each changed body's change (mass, first moment and rotational
    /// inertia, in the body's frame; bodies not named do not change, a body named twice takes
    /// the sum): RNEA is linear in the inertial parameters, so this is RNEA with the same
    /// kinematics and gravity and the changes as the only inertias (docs/model.md, section 18).
    pub fn rnea_inertia_derivative(
        &self,
        data: &mut Workspace,
        (q, v, a): (&[f64], &[f64], &[f64]),
        parts: &[(usize, MassProperties)],
        tau: &mut [f64],
    ) {
        self.expect_joints("v", v);
        self.expect_joints("a", a);
        let mut change = vec![Inertia::default(); self.dof()];
        for (body, part) in parts {
            change[*body] += Inertia::of_body(part);
        }
        self.update_frames(data, q);
        let world: Vec<Inertia> = (change.iter().zip(&data.frames))
            .map(|(change, frame)| change.transformed(&frame.pose))
            .collect();
        self.recursion(data, (Some(v), Some(a)), |i, _| world[i], tau);
    }

    /// RNEA at q with v and a, each 0 when None.
    fn inverse_dynamics(
        &self,
        data: &mut Workspace,
        q: &[f64],
        v: Option<&[f64]>,
        a: Option<&[f64]>,
        tau: &mut [f64],
    ) {
        self.update_frames(data, q);
        self.recursion(data, (v, a), |_, frame| frame.inertia, tau);
    }

    /// RNEA's passes at the workspace's frames with v and a (0 when None), body i's world
    /// inertia `inertia(i, frame)`.
    fn recursion(
        &self,
        data: &mut Workspace,
        (v, a): (Option<&[f64]>, Option<&[f64]>),
        inertia: impl Fn(usize, &BodyFrame) -> Inertia,
        tau: &mut [f64],
    ) {
        self.expect_joints("the torque output", tau);
        let mut v_parent = Motion::default();
        let mut a_parent = self.base_acceleration;
        for (i, (frame, force)) in data.frames.iter().zip(&mut data.forces).enumerate() {
            let speed = v.map_or(0.0, |v| v[i]);
            let velocity = v_parent + frame.s * speed;
            let acceleration =
                a_parent + frame.s * a.map_or(0.0, |a| a[i]) + velocity.cross(&frame.s) * speed;
            let inertia = inertia(i, frame);
            let momentum = inertia.apply(&velocity);
            *force = inertia.apply(&acceleration) + velocity.cross_force(&momentum);
            v_parent = velocity;
            a_parent = acceleration;
        }
        let mut total = Force::default();
        for ((frame, force), torque) in data.frames.iter().zip(&data.forces).zip(tau).rev() {
            total = total + *force;
            *torque = frame.s.dot(&total);
        }
    }
}

/// Overwrites the lower triangle of the symmetric `matrix` with its Cholesky factor L
/// (matrix = L L^T); false if it is not numerically positive definite.
fn cholesky_in_place(matrix: &mut DMatrix<f64>) -> bool {
    let n = matrix.nrows();
    for j in 0..n {
        let mut diagonal = matrix[(j, j)];
        for k in 0..j {
            diagonal -= matrix[(j, k)] * matrix[(j, k)];
        }
        if !(diagonal.is_finite() && diagonal > 0.0) {
            return false;
        }
        let root = diagonal.sqrt();
        matrix[(j, j)] = root;
        for i in j + 1..n {
            let mut entry = matrix[(i, j)];
            for k in 0..j {
                entry -= matrix[(i, k)] * matrix[(j, k)];
            }
            matrix[(i, j)] = entry / root;
        }
    }
    true
}

/// Solves L L^T x = rhs in place, L in the lower triangle of `factor`.
fn cholesky_solve(factor: &DMatrix<f64>, x: &mut [f64]) {
    let n = x.len();
    for i in 0..n {
        let mut value = x[i];
        for k in 0..i {
            value -= factor[(i, k)] * x[k];
        }
        x[i] = value / factor[(i, i)];
    }
    for i in (0..n).rev() {
        let mut value = x[i];
        for k in i + 1..n {
            value -= factor[(k, i)] * x[k];
        }
        x[i] = value / factor[(i, i)];
    }
}

//! Forward kinematics (world poses, joint motion vectors, world inertias) and the tool centre
//! point: its world position, its Jacobian and the Hessians of its coordinates.
//!
//! With S_j = (u_j, p_j x u_j) the world motion vector of joint j (unit axis u_j through p_j), the
//! TCP's velocity due to joint j <= b (b its body) is J_j = u_j x P + p_j x u_j = u_j x (P - p_j);
//! a prismatic joint's S_j = (0, u_j) gives J_j = u_j. As du_i/dq_j = u_j x u_i for j <= i (zero
//! for a prismatic j), the second derivatives are d^2 P / dq_i dq_j = w_min(i,j) x J_max(i,j), w
//! the angular part of S (zero beyond the TCP's body).
//!
//! A direction d fixed to body b, w = R_b(q) d in the world, turns with each revolute joint
//! j <= b: dw/dq_j = u_j x w, and d^2 w / dq_i dq_j = u_min(i,j) x (u_max(i,j) x w) (zero where
//! either joint lies beyond b or is prismatic, whose w is 0).

use super::spatial::Motion;
use super::{remember, same_state, shape, Dynamics, Workspace};
use crate::model::chain::{JointKind, Placement};
use nalgebra::{DMatrix, Matrix3, Vector3};

impl Dynamics {
    /// Brings the poses, joint motion vectors and inertias in the world frame to `q`.
    pub(super) fn update_frames(&self, data: &mut Workspace, q: &[f64]) {
        self.expect_own(data);
        self.expect_joints("q", q);
        if same_state(&data.frames_at, &[q]) {
            return;
        }
        let mut parent = Placement::identity();
        for ((frame, model), &angle) in data.frames.iter_mut().zip(&self.bodies).zip(q) {
            let joint = parent.then(&model.joint_placement);
            let axis = joint.rotation * model.axis;
            match model.kind {
                JointKind::Revolute => {
                    let (sin, cos) = angle.sin_cos();
                    let turn = Matrix3::identity()
                        + model.axis_cross * sin
                        + model.axis_cross_squared * (1.0 - cos);
                    frame.pose = Placement {
                        rotation: joint.rotation * turn,
                        translation: joint.translation,
                    };
                    frame.s = Motion::new(axis, joint.translation.cross(&axis));
                }
                JointKind::Prismatic => {
                    frame.pose = Placement {
                        rotation: joint.rotation,
                        translation: joint.translation + axis * angle,
                    };
                    frame.s = Motion::new(Vector3::zeros(), axis);
                }
            }
            frame.inertia = model.inertia.transformed(&frame.pose);
            parent = frame.pose;
        }
        remember(&mut data.frames_at, &[q]);
    }

    /// The TCP's world position at the workspace's current frames.
    fn tcp_world(&self, data: &Workspace) -> Vector3<f64> {
        match self.tcp.body {
            Some(b) => data.frames[b].pose.apply(&self.tcp.point),
            None => self.tcp.point,
        }
    }

    /// Joints that move the TCP: those up to its body.
    fn tcp_joints(&self) -> usize {
        self.tcp.body.map_or(0, |b| b + 1)
    }

    /// The TCP's position in the world frame at `q`, m.
    ///
    /// ```
    /// use codesign_core::dynamics::Dynamics;
    /// use codesign_core::model::{task::Task, Robot};
    ///
    /// let dynamics = Dynamics::new(Robot::load(&Task::built_in()?)?);
    /// let mut data = dynamics.workspace();
    /// let q = [0.3, 0.2, -0.4, 0.1];
    /// let p = dynamics.tcp_position(&mut data, &q);
    /// let mut jacobian = nalgebra::DMatrix::zeros(3, 4);
    /// dynamics.tcp_jacobian(&mut data, &q, &mut jacobian);
    /// // d p / d q_0 against a forward difference
    /// let mut q1 = q;
    /// q1[0] += 1e-7;
    /// let p1 = dynamics.tcp_position(&mut data, &q1);
    /// assert!(((p1 - p) / 1e-7 - jacobian.column(0)).norm() < 1e-5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn tcp_position(&self, data: &mut Workspace, q: &[f64]) -> Vector3<f64> {
        self.update_frames(data, q);
        self.tcp_world(data)
    }

    /// The world positions at `q`, m, of the joints' origins from the base outward, then of the
    /// TCP: the arm drawn as segments between them (the base at the world origin before them).
    pub fn skeleton(&self, data: &mut Workspace, q: &[f64]) -> Vec<Vector3<f64>> {
        self.update_frames(data, q);
        let mut points: Vec<Vector3<f64>> =
            data.frames.iter().map(|f| f.pose.translation).collect();
        points.push(self.tcp_world(data));
        points
    }

    /// The pose at `q` of `body`'s frame in the world frame (the identity for the base).
    pub fn body_pose(&self, data: &mut Workspace, q: &[f64], body: Option<usize>) -> Placement {
        self.update_frames(data, q);
        body.map_or_else(Placement::identity, |b| data.frames[b].pose)
    }

    /// The world position at `q` of `point`, fixed to a body of the chain (or to the base), m.
    pub fn point_position(
        &self,
        data: &mut Workspace,
        q: &[f64],
        point: &crate::model::chain::PointOnBody,
    ) -> Vector3<f64> {
        self.update_frames(data, q);
        match point.body {
            Some(b) => data.frames[b].pose.apply(&point.point),
            None => point.point,
        }
    }

    /// The Jacobian dp/dq (3 x n, m/rad) of the TCP's world position; `jacobian` is resized if
    /// it has another shape.
    pub fn tcp_jacobian(&self, data: &mut Workspace, q: &[f64], jacobian: &mut DMatrix<f64>) {
        self.update_frames(data, q);
        let n = self.dof();
        shape(jacobian, 3, n);
        let tcp = self.tcp_world(data);
        jacobian.fill(0.0);
        for j in 0..self.tcp_joints() {
            let s = &data.frames[j].s;
            jacobian.set_column(j, &(s.ang.cross(&tcp) + s.lin));
        }
    }

    /// The Hessians d^2 p_k / dq dq (n x n each, m/rad^2) of the TCP's world x, y and z; each
    /// matrix is resized if it has another shape.
    pub fn tcp_hessians(&self, data: &mut Workspace, q: &[f64], hessians: &mut [DMatrix<f64>; 3]) {
        self.update_frames(data, q);
        let n = self.dof();
        for hessian in hessians.iter_mut() {
            shape(hessian, n, n);
            hessian.fill(0.0);
        }
        let tcp = self.tcp_world(data);
        for j in 0..self.tcp_joints() {
            let s = &data.frames[j].s;
            let column = s.ang.cross(&tcp) + s.lin;
            for i in 0..=j {
                let entry = data.frames[i].s.ang.cross(&column);
                for (hessian, value) in hessians.iter_mut().zip(entry.iter()) {
                    hessian[(i, j)] = *value;
                    hessian[(j, i)] = *value;
                }
            }
        }
    }

    /// The world coordinates at `q` of `direction`, given in `body`'s frame (None: the base).
    pub fn direction_world(
        &self,
        data: &mut Workspace,
        q: &[f64],
        body: Option<usize>,
        direction: &Vector3<f64>,
    ) -> Vector3<f64> {
        self.update_frames(data, q);
        body.map_or(*direction, |b| data.frames[b].pose.rotation * direction)
    }

    /// The Jacobian dw/dq (3 x n, per rad) of [`Dynamics::direction_world`]: column j is
    /// u_j x w for a joint j <= `body`; `jacobian` is resized if it has another shape.
    pub fn direction_jacobian(
        &self,
        data: &mut Workspace,
        q: &[f64],
        (body, direction): (Option<usize>, &Vector3<f64>),
        jacobian: &mut DMatrix<f64>,
    ) {
        let w = self.direction_world(data, q, body, direction);
        shape(jacobian, 3, self.dof());
        jacobian.fill(0.0);
        for j in 0..body.map_or(0, |b| b + 1) {
            jacobian.set_column(j, &data.frames[j].s.ang.cross(&w));
        }
    }

    /// The Hessians d^2 w_c / dq dq (n x n each, per rad^2) of the world x, y and z of
    /// [`Dynamics::direction_world`]: entry (i, j) is u_min(i,j) x (u_max(i,j) x w); each matrix
    /// is resized if it has another shape.
    pub fn direction_hessians(
        &self,
        data: &mut Workspace,
        q: &[f64],
        (body, direction): (Option<usize>, &Vector3<f64>),
        hessians: &mut [DMatrix<f64>; 3],
    ) {
        let w = self.direction_world(data, q, body, direction);
        let n = self.dof();
        for hessian in hessians.iter_mut() {
            shape(hessian, n, n);
            hessian.fill(0.0);
        }
        for j in 0..body.map_or(0, |b| b + 1) {
            let column = data.frames[j].s.ang.cross(&w);
            for i in 0..=j {
                let entry = data.frames[i].s.ang.cross(&column);
                for (hessian, value) in hessians.iter_mut().zip(entry.iter()) {
                    hessian[(i, j)] = *value;
                    hessian[(j, i)] = *value;
                }
            }
        }
    }
}

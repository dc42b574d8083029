//! First derivatives of inverse dynamics: dtau/dq, dtau/dv and M = dtau/da.
//!
//! Derivation (world frame, index k >= i means "carried by joint i"). A quantity X fixed to a body
//! carried by joint j moves with it: dX/dq_j = S_j (x) X, the spatial cross product fitting X's kind.
//! What does not move with joint j are the parent's velocity and acceleration, so for every k >= j
//! the part of d/dq_j that is not such a rotation is the same (with dS/dt = v_(j-1) x S_j,
//! d^2S/dt^2 = a_(j-1) x S_j + v_(j-1) x dS/dt):
//!   dv_k/dq_j - S_j x v_k = dS_j/dt,   da_k/dq_j - S_j x a_k = d^2S_j/dt^2 + dS_j/dt x v_k,
//! and for the joint rates, dv_k/dqd_j = S_j, da_k/dqd_j = 2 dS_j/dt + S_j x v_k (k >= j).
//! Feeding these through f_k = I_k a_k + v_k x* I_k v_k and summing over k >= i gives, with the
//! composites IC_i = sum I_k, dIC_i = sum (v_k x* I_k - I_k v_k x), H_i = sum I_k v_k and
//! F_i = sum f_k over k >= i, and since S_i . (S_j x* F) + (S_j x S_i) . F = 0:
//!   j <= i: dtau_i/dq_j  = S_i . (IC_i d^2S_j + dIC_i dS_j + dS_j x* H_i)
//!           dtau_i/dqd_j = S_i . (2 IC_i dS_j + dIC_i S_j + S_j x* H_i)
//!   j > i:  dtau_i/dq_j  = S_i . (S_j x* F_j + IC_j d^2S_j + dIC_j dS_j + dS_j x* H_j)
//!           dtau_i/dqd_j = S_i . (2 IC_j dS_j + dIC_j S_j + S_j x* H_j)
//! and M_ij = S_i . IC_max(i,j) S_j. These are the world-frame expressions of Carpentier and Mansard
//! (RSS 2018), written here with composites so that every entry is a few dot products.

use super::spatial::{Force, Inertia, Motion};
use super::{remember, same_state, shape, Dynamics, Workspace};
use nalgebra::DMatrix;

impl Dynamics {
    /// Brings the velocity-level quantities and composites to (q, v, a).
    pub(super) fn update_motion(&self, data: &mut Workspace, q: &[f64], v: &[f64], a: &[f64]) {
        self.expect_joints("v", v);
        self.expect_joints("a", a);
        self.update_frames(data, q);
        if same_state(&data.motion_at, &[q, v, a]) {
            return;
        }
        let mut v_parent = Motion::default();
        let mut a_parent = self.base_acceleration;
        for (i, (frame, body)) in data.frames.iter().zip(&mut data.motion).enumerate() {
            let s = frame.s;
            body.sd = v_parent.cross(&s);
            body.sdd = a_parent.cross(&s) + v_parent.cross(&body.sd);
            body.v = v_parent + s * v[i];
            body.a = a_parent + s * a[i] + body.sd * v[i];
            body.h = frame.inertia.apply(&body.v);
            v_parent = body.v;
            a_parent = body.a;
        }
        let mut ic = Inertia::default();
        let mut ic_rate = Inertia::default();
        let mut momentum = Force::default();
        let mut f = Force::default();
        for (frame, body) in data.frames.iter().zip(&mut data.motion).rev() {
            let inertia = &frame.inertia;
            ic += *inertia;
            ic_rate += inertia.rate(&body.v);
            momentum = momentum + body.h;
            f = f + inertia.apply(&body.a) + body.v.cross_force(&body.h);
            body.ic = ic;
            body.ic_rate = ic_rate;
            body.momentum = momentum;
            body.f = f;
            body.ic_s = ic.apply(&frame.s);
            body.ic_sd = ic.apply(&body.sd);
            body.ic_sdd = ic.apply(&body.sdd);
            body.ic_rate_s = ic_rate.apply(&frame.s);
            body.ic_rate_sd = ic_rate.apply(&body.sd);
        }
        remember(&mut data.motion_at, &[q, v, a]);
    }

    /// tau (N m) with dtau/dq (N m/rad), dtau/dv (N m s/rad) and M = dtau/da (kg m^2) at once,
    /// n x n each with row = torque index; matrices are resized if they have another shape.
    ///
    /// ```
    /// use codesign_core::dynamics::Dynamics;
    /// use codesign_core::model::{task::Task, Robot};
    /// use nalgebra::DMatrix;
    ///
    /// let dynamics = Dynamics::new(Robot::load(&Task::built_in()?)?);
    /// let mut data = dynamics.workspace();
    /// let (q, v, a) = ([0.1, 0.5, -0.3, 0.2], [0.4, -0.2, 0.1, 0.3], [1.0, 0.5, -1.0, 0.0]);
    /// let mut tau = [0.0; 4];
    /// let (mut dq, mut dv, mut mass) = (DMatrix::zeros(4, 4), DMatrix::zeros(4, 4), DMatrix::zeros(4, 4));
    /// dynamics.rnea_derivatives(&mut data, &q, &v, &a, &mut tau, &mut dq, &mut dv, &mut mass);
    ///
    /// // dtau/dq_1 against a central difference
    /// let h = 1e-6;
    /// let (mut plus, mut minus) = ([0.0; 4], [0.0; 4]);
    /// let (mut qp, mut qm) = (q, q);
    /// qp[1] += h;
    /// qm[1] -= h;
    /// dynamics.rnea(&mut data, &qp, &v, &a, &mut plus);
    /// dynamics.rnea(&mut data, &qm, &v, &a, &mut minus);
    /// for i in 0..4 {
    ///     assert!((dq[(i, 1)] - (plus[i] - minus[i]) / (2.0 * h)).abs() < 1e-6);
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn rnea_derivatives(
        &self,
        data: &mut Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        tau: &mut [f64],
        dtau_dq: &mut DMatrix<f64>,
        dtau_dv: &mut DMatrix<f64>,
        mass: &mut DMatrix<f64>,
    ) {
        self.expect_joints("tau", tau);
        self.update_motion(data, q, v, a);
        let n = self.dof();
        shape(dtau_dq, n, n);
        shape(dtau_dv, n, n);
        shape(mass, n, n);
        let frames = &data.frames;
        let motion = &data.motion;
        for j in 0..n {
            let s_j = &frames[j].s;
            let m_j = &motion[j];
            tau[j] = s_j.dot(&m_j.f);
            // Column j above the diagonal: S_i . (force of joint j's carried bodies).
            let by_q = s_j.cross_force(&m_j.f)
                + m_j.ic_sdd
                + m_j.ic_rate_sd
                + m_j.sd.cross_force(&m_j.momentum);
            let by_v = m_j.ic_sd * 2.0 + m_j.ic_rate_s + s_j.cross_force(&m_j.momentum);
            for i in 0..j {
                let s_i = &frames[i].s;
                dtau_dq[(i, j)] = s_i.dot(&by_q);
                dtau_dv[(i, j)] = s_i.dot(&by_v);
            }
            // Column j on and below the diagonal.
            for i in j..n {
                let s_i = &frames[i].s;
                let m_i = &motion[i];
                dtau_dq[(i, j)] = m_j.sdd.dot(&m_i.ic_s)
                    + m_j.sd.dot(&m_i.ic_rate_s)
                    + s_i.cross(&m_j.sd).dot(&m_i.momentum);
                dtau_dv[(i, j)] = (m_j.sd * 2.0).dot(&m_i.ic_s)
                    + s_j.dot(&m_i.ic_rate_s)
                    + s_i.cross(s_j).dot(&m_i.momentum);
                let entry = s_j.dot(&m_i.ic_s);
                mass[(i, j)] = entry;
                mass[(j, i)] = entry;
            }
        }
    }
}

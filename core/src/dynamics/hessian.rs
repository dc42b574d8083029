//! The Hessian of phi(q, v, a) = lambda . RNEA(q, v, a) with respect to (q, v, a).
//!
//! Derivation, by hand, with the notation and rules of `derivatives.rs` (dS_j = dS_j/dt,
//! ddS_j = d^2S_j/dt^2). With Lambda_k = sum_(i <= k) lambda_i S_i (the body velocities the
//! joint rates lambda would give), phi = sum_k Lambda_k . f_k. Its gradient, with the composites
//! over k >= i
//!   P_i = sum I_k Lambda_k,   H_i = sum I_k v_k,   F_i = sum f_k,
//!   psi_i = sum [v_k x* I_k Lambda_k - Lambda_k x* I_k v_k + I_k (Lambda_k x v_k)],
//! and sigma_i = Lambda_(i-1) x S_i (the "dS/dt" of the rates lambda), is
//!   dphi/da_i = S_i . P_i,   dphi/dv_i = S_i . psi_i + 2 dS_i . P_i,
//!   dphi/dq_i = sigma_i . F_i + ddS_i . P_i + dS_i . psi_i.
//! Differentiating once more uses, besides the rules for v, a, dS, ddS, that Lambda_k moves like
//! v_k (the non-rotation part of dLambda_k/dq_j is sigma_j, k >= j - 1), and the composites
//! IC_i = sum I_k, dIC_i = sum rate(I_k, v_k), J_i = sum rate(I_k, Lambda_k), where
//! rate(I, m) = m x* I - I m x. For j <= i (each term a scalar, so only the non-rotation parts
//! count):
//!   d2phi/dq_j dq_i = (sigma_j x S_i) . F_i + sigma_i . (IC_i ddS_j + dIC_i dS_j + dS_j x* H_i)
//!       + (IC_i sigma_j) . ddS_i + P_i . ddS'_ij + dS_i . psi'_ij + psi_i . (dS_j x S_i),
//!     ddS'_ij = (ddS_j + dS_j x v_(i-1)) x S_i + dS_j x dS_i + v_(i-1) x (dS_j x S_i),
//!     psi'_ij = dS_j x* P_i + dIC_i sigma_j - sigma_j x* H_i - J_i dS_j;
//!   d2phi/dq_i dv_j = (dS_i x S_j) . P_j + sigma_i . dIC_j S_j + (sigma_i x S_j) . H_j
//!       - dS_i . J_j S_j + 2 sigma_i . IC_j dS_j                           (i <= j),
//!                   = S_j . dpsi_i + 2 dS_j . dP_i                         (i > j),
//!     dP_i = S_i x* P_i + IC_i sigma_i,  dpsi_i = S_i x* psi_i + psi'_ii;
//!   d2phi/dq_i da_j = sigma_i . IC_j S_j (i <= j),  S_j . dP_i (i > j);
//!   d2phi/dv_i dv_j = P_m . (S_i x S_j) - S_i . J_m S_j  (i <= j, m = max(i, j));
//! and phi is linear in a with a coefficient free of v: the (v, a) and (a, a) blocks are zero.

use super::spatial::{Force, Inertia, Motion};
use super::{shape, Dynamics, Workspace};
use nalgebra::DMatrix;

impl Dynamics {
    /// The full symmetric 3n x 3n Hessian of lambda . RNEA(q, v, a), variables ordered (q, v, a);
    /// lambda weighs the joint torques (1/(N m) for a dimensionless result). `hessian` is resized
    /// if it has another shape.
    pub fn rnea_hessian(
        &self,
        data: &mut Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        lambda: &[f64],
        hessian: &mut DMatrix<f64>,
    ) {
        self.expect_joints("lambda", lambda);
        self.update_motion(data, q, v, a);
        update_adjoint(data, lambda);
        let n = self.dof();
        shape(hessian, 3 * n, 3 * n);
        let frames = &data.frames;
        let motion = &data.motion;
        let adjoint = &data.adjoint;
        for i in 0..n {
            let s_i = &frames[i].s;
            let (m_i, l_i) = (&motion[i], &adjoint[i]);
            let v_before = if i == 0 {
                Motion::default()
            } else {
                motion[i - 1].v
            };
            for j in 0..n {
                let s_j = &frames[j].s;
                let (m_j, l_j) = (&motion[j], &adjoint[j]);
                if j <= i {
                    let sd_j_s_i = m_j.sd.cross(s_i);
                    let sdd_prime = (m_j.sdd + m_j.sd.cross(&v_before)).cross(s_i)
                        + m_j.sd.cross(&m_i.sd)
                        + v_before.cross(&sd_j_s_i);
                    let qq = l_j.sigma.cross(s_i).dot(&m_i.f)
                        + m_j.sdd.dot(&l_i.ic_sigma)
                        + m_j.sd.dot(&l_i.ic_rate_sigma)
                        + l_i.sigma.cross(&m_j.sd).dot(&m_i.momentum)
                        + l_j.sigma.dot(&m_i.ic_sdd)
                        + sdd_prime.dot(&l_i.p)
                        + m_i.sd.cross(&m_j.sd).dot(&l_i.p)
                        + l_j.sigma.dot(&m_i.ic_rate_sd)
                        + l_j.sigma.cross(&m_i.sd).dot(&m_i.momentum)
                        - m_j.sd.dot(&l_i.j_sd)
                        + sd_j_s_i.dot(&l_i.psi);
                    hessian[(i, j)] = qq;
                    hessian[(j, i)] = qq;
                    let vv = s_j.cross(s_i).dot(&l_i.p) - s_j.dot(&l_i.j_s);
                    hessian[(n + i, n + j)] = vv;
                    hessian[(n + j, n + i)] = vv;
                }
                let (qv, qa) = if i <= j {
                    (
                        m_i.sd.cross(s_j).dot(&l_j.p)
                            + l_i.sigma.dot(&m_j.ic_rate_s)
                            + l_i.sigma.cross(s_j).dot(&m_j.momentum)
                            - m_i.sd.dot(&l_j.j_s)
                            + 2.0 * l_i.sigma.dot(&m_j.ic_sd),
                        l_i.sigma.dot(&m_j.ic_s),
                    )
                } else {
                    (
                        s_j.dot(&l_i.dpsi) + 2.0 * m_j.sd.dot(&l_i.dp),
                        s_j.dot(&l_i.dp),
                    )
                };
                hessian[(i, n + j)] = qv;
                hessian[(n + j, i)] = qv;
                hessian[(i, 2 * n + j)] = qa;
                hessian[(2 * n + j, i)] = qa;
                hessian[(n + i, 2 * n + j)] = 0.0;
                hessian[(2 * n + j, n + i)] = 0.0;
                hessian[(2 * n + i, 2 * n + j)] = 0.0;
            }
        }
    }
}

/// Computes the lambda-dependent quantities at the workspace's current motion.
fn update_adjoint(data: &mut Workspace, lambda: &[f64]) {
    let mut lambda_parent = Motion::default();
    for ((frame, body), &weight) in data.frames.iter().zip(&mut data.adjoint).zip(lambda) {
        body.sigma = lambda_parent.cross(&frame.s);
        body.lambda = lambda_parent + frame.s * weight;
        lambda_parent = body.lambda;
    }
    let mut p = Force::default();
    let mut psi = Force::default();
    let mut j = Inertia::default();
    let bodies = data.frames.iter().zip(&data.motion).zip(&mut data.adjoint);
    for ((frame, m), body) in bodies.rev() {
        let inertia = &frame.inertia;
        let lambda = &body.lambda;
        let i_lambda = inertia.apply(lambda);
        p = p + i_lambda;
        psi = psi + m.v.cross_force(&i_lambda) - lambda.cross_force(&m.h)
            + inertia.apply(&lambda.cross(&m.v));
        j += inertia.rate(lambda);
        body.p = p;
        body.psi = psi;
        body.ic_sigma = m.ic.apply(&body.sigma);
        body.ic_rate_sigma = m.ic_rate.apply(&body.sigma);
        body.j_s = j.apply(&frame.s);
        body.j_sd = j.apply(&m.sd);
        body.dp = frame.s.cross_force(&p) + body.ic_sigma;
        body.dpsi = frame.s.cross_force(&psi) + m.sd.cross_force(&p) + body.ic_rate_sigma
            - body.sigma.cross_force(&m.momentum)
            - body.j_sd;
    }
}

//! Reading a primal point back as a trajectory: states, torques and motor speeds through G at
//! each node (G(q_k) where the transmission depends on the pose, with the rotor inertia's speed
//! term dG/dt v), the TCP's path.

use super::trajectory::Trajectory;
use crate::problem::TrajectoryProblem;
use crate::transmission::PoseError;

/// The trajectory of `problem`'s primal point x, or the first node k <= N where a linkage of
/// the transmission does not close.
pub(super) fn read_trajectory(
    problem: &TrajectoryProblem<'_>,
    x: &[f64],
) -> Result<Trajectory, (usize, PoseError)> {
    let f = problem.formulation();
    let layout = f.layout();
    let (n, steps) = (layout.dof, layout.steps);
    let slice = |start: usize| x[start..start + n].to_vec();
    let dynamics = problem.dynamics();
    let posed = f.transmission().is_pose_dependent();
    let mut data = dynamics.workspace();
    let mut trajectory = Trajectory::default();
    for (k, time) in f.setting().times_at(x).into_iter().enumerate() {
        let (q, v) = (slice(layout.q(k, 0)), slice(layout.v(k, 0)));
        let actuation = problem.actuation_at(&q).map_err(|error| (k, error))?;
        let tcp = dynamics.tcp_position(&mut data, &q);
        trajectory.time.push(time);
        trajectory.tcp_x.push(tcp[0]);
        trajectory.tcp_y.push(tcp[1]);
        trajectory.tcp_z.push(tcp[2]);
        trajectory
            .motor_speed
            .push(actuation.coupling().motor_speeds(&v));
        if posed {
            let angles = problem.motor_angles(&q).map_err(|error| (k, error))?;
            trajectory.motor_position.push(angles);
            let g = actuation.coupling().matrix();
            let rows = g.row_iter().map(|row| row.iter().copied().collect());
            trajectory.ratio.push(rows.collect());
        }
        if k < steps {
            let (u, a) = (slice(layout.u(k, 0)), slice(layout.a(k, 0)));
            let loss = actuation.loss().map(|_| {
                let mut tau = vec![0.0; n];
                dynamics.rnea(&mut data, &q, &v, &a, &mut tau);
                let loss = actuation.node_loss(&tau, &v);
                loss.expect("the actuation has losses")
            });
            let mut links = actuation.link_torques((&v, &a), &u, loss.as_ref());
            if posed {
                let speed_term = problem.speed_term_torques(&q, &v);
                let speed_term = speed_term.map_err(|error| (k, error))?;
                links.iter_mut().zip(speed_term).for_each(|(t, s)| *t -= s);
            }
            trajectory.joint_torque.push(links);
            if let Some(loss) = &loss {
                trajectory.transmission_loss.push(loss.motor_torques());
            }
            trajectory.a.push(a);
            trajectory.motor_torque.push(actuation.motor_torques(&u));
        }
        trajectory.q.push(q);
        trajectory.v.push(v);
    }
    Ok(trajectory)
}

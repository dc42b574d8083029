//! What a result can stand for: whether it judges its design ([`TrajectoryResult::unjudged`])
//! and whether every number in it is finite ([`TrajectoryResult::non_finite`]), so that no
//! command reports a solver failure as a verdict or writes a number JSON cannot hold.

use super::result::TrajectoryResult;
use crate::ipopt::Status;

impl TrajectoryResult {
    /// Why the result is no verdict, where it is none: an infeasible elastic result that IPOPT
    /// did not bring to an optimum (its iterations spent, a number it could not evaluate) and
    /// that shows no shortfall at all (no torque deficit, no speed excess: an infeasible verdict
    /// with nothing lacking says nothing), unless the motors cannot hold the load at rest at a
    /// judged end (which no trajectory changes) or its trajectory passes a linkage's dead point
    /// (which makes it infeasible, whatever it lacks). An elastic solve stopped short of an optimum
    /// with a positive shortfall still judges the design infeasible, by the shortfall where it
    /// stopped, as every verdict of the committed results was made. None where the result
    /// judges the design.
    pub fn unjudged(&self) -> Option<String> {
        let optimum = [Status::SolveSucceeded, Status::SolvedToAcceptableLevel]
            .iter()
            .any(|status| status.name() == self.status);
        let unheld = self.static_hold.as_ref().and_then(|h| h.failure());
        let shortfall = self.elastic.as_ref().is_some_and(|e| {
            let positive = |value: f64| value.is_finite() && value > 0.0;
            positive(e.torque_deficit) || positive(e.speed_excess)
        });
        let crossed = !self.dead_points.is_empty();
        let judged = self.feasible
            || self.elastic.is_none()
            || optimum
            || shortfall
            || unheld.is_some()
            || crossed;
        (!judged).then(|| {
            format!(
                "the elastic solve ended with {} short of an optimum (in {} iterations in all) \
                 and shows no shortfall, so it shows neither a feasible trajectory nor a \
                 deficit: the design was not judged",
                self.status, self.iterations
            )
        })
    }

    /// Whether the design is infeasible by the judged static hold alone: the motion's own
    /// verdict (the trajectory problem's, or the relaxed problem's slacks) found nothing
    /// lacking, so the reason is the hold's failure and nothing after it.
    pub fn infeasible_by_hold_alone(&self) -> bool {
        let unheld = self.static_hold.as_ref().and_then(|h| h.failure());
        !self.feasible && unheld.is_some() && self.reason == unheld
    }

    /// The first part of the result holding a number that is not finite (JSON would write it
    /// as null, and no reader of results takes that), e.g. `cost`; None where every number is.
    pub fn non_finite(&self) -> Option<&'static str> {
        let finite = |values: &[f64]| values.iter().all(|v| v.is_finite());
        let rows = |rows: &[Vec<f64>]| rows.iter().all(|row| finite(row));
        let some = |values: &Option<Vec<f64>>| values.as_deref().is_none_or(finite);
        let (v, t) = (&self.violations, &self.trajectory);
        let elastic = self.elastic.as_ref().is_none_or(|e| {
            let measures = [
                e.torque_deficit,
                e.speed_excess,
                e.largest_slack,
                e.objective,
            ];
            finite(&measures) && some(&e.objective_gradient)
        });
        let terms = self.cost_terms.as_ref().is_none_or(|c| {
            finite(&[c.position, c.velocity, c.control, c.cartesian_box, c.time])
                && c.added.iter().all(|(_, value)| value.is_finite())
        });
        let execute = self
            .motors_execute
            .as_ref()
            .is_none_or(|m| finite(&m.torque_excess_nm) && finite(&m.speed_excess_rad_s));
        let hold = self.static_hold.as_ref().is_none_or(|h| {
            [&h.start, &h.goal].iter().all(|end| {
                finite(&end.joint_torques_nm)
                    && finite(&end.motor_torques_nm)
                    && finite(&end.margins_nm)
            })
        });
        let violations: Vec<f64> = v.iter().map(|(_, value)| value).collect();
        let trajectory = finite(&t.time)
            && [
                &t.q,
                &t.v,
                &t.a,
                &t.joint_torque,
                &t.motor_torque,
                &t.motor_speed,
            ]
            .iter()
            .all(|r| rows(r))
            && [&t.tcp_x, &t.tcp_y, &t.tcp_z].iter().all(|r| finite(r));
        let parts = [
            ("cost", finite(&[self.cost])),
            ("ratios", finite(&self.ratios)),
            ("max_motor_torque", finite(&[self.max_motor_torque])),
            ("max_motor_speed", finite(&[self.max_motor_speed])),
            ("violations", finite(&violations)),
            ("cost_gradient", some(&self.cost_gradient)),
            ("elastic", elastic),
            ("cost_terms", terms),
            ("motors_execute", execute),
            ("static_hold", hold),
            ("goal_pose", some(&self.goal_pose)),
            ("trajectory", trajectory),
        ];
        parts.iter().find(|(_, fine)| !fine).map(|(name, _)| *name)
    }
}

//! What the motion asks at its ends (`motion.ends`, docs/model.md, section 6), as bounds that
//! override the joint limits there: q_0 and q_N at the task's start and goal poses and v_0 =
//! v_N = 0 under every choice; under `rest` also a_0 = a_(N-1) = 0, the last node with an
//! acceleration (its interval ends at q_N, v_N). A TCP goal leaves q_N free within the joint
//! limits and asks a_(N-1) = 0 under every choice: the motion rests at the goal. The static hold of `hold` and `rest` is no
//! bound of the NLP but a check before it (`../hold.rs`).

use super::family::{Family, Shape};
use crate::problem::design_data::DesignData;
use std::sync::Arc;

/// The end conditions.
#[derive(Debug)]
struct Ends;

/// Every formulation has them.
pub(super) fn of(_shape: &Shape<'_>) -> Option<Arc<dyn Family>> {
    Some(Arc::new(Ends))
}

impl Family for Ends {
    fn variable_bounds(&self, p: &DesignData<'_>, lower: &mut [f64], upper: &mut [f64]) {
        let f = p.setting();
        let (layout, motion) = (f.layout(), &f.task().motion);
        // A TCP goal leaves q_N free (its row holds the TCP) and the motion rests at the goal
        // whatever `ends` says, so that the hold there is the NLP's own rows at q_N.
        let goal = motion.goal.joints();
        let poses = [(0, Some(&motion.start[..])), (layout.steps, goal)];
        let mut rests = Vec::new();
        if motion.ends.rests() {
            rests.push(0);
        }
        if motion.ends.rests() || goal.is_none() {
            rests.push(layout.steps - 1);
        }
        for i in 0..layout.dof {
            for (k, pose) in poses {
                let (q, v) = (layout.q(k, i), layout.v(k, i));
                if let Some(pose) = pose {
                    (lower[q], upper[q]) = (pose[i], pose[i]);
                }
                (lower[v], upper[v]) = (0.0, 0.0);
            }
            for &k in &rests {
                let a = layout.a(k, i);
                (lower[a], upper[a]) = (0.0, 0.0);
            }
        }
    }
}

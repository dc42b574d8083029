//! The nodes of a motion's via points and the phases they split its grid into (docs/model.md,
//! section 6).
//!
//! A via point at a time t_s on a fixed horizon T, with no window in the motion, holds at the
//! node k = round(t_s N / T) nearest it, on the uniform grid t_k = k T/N. Once a via point has a
//! window [t_a, t_b], or the horizon is free, the motion is *phased*: every via point is a phase
//! boundary at a node chosen once, k = round(t_mid N / T_ref) with t_mid the middle of its
//! window (its time for a given one) and T_ref the duration the standard guess takes (T, or a
//! free horizon's T_max), and its time is the given t_s or a variable in [t_a, t_b]. Between two
//! boundaries the nodes are evenly spaced. Every node is inner (0 < k < N: the task's start and
//! goal fix nodes 0 and N), and a phased motion's via points are listed in time order, each
//! beginning after the one before it ends, strictly within (0, T_end), T_end the fixed T or a
//! free horizon's T_min, so that every phase has a duration > 0.

use super::ranges::FieldError;
use super::task::{Horizon, Motion, ViaTime};
use crate::text::number;

impl Motion {
    /// Whether the via points split the grid into phases: one has a window, or the horizon is
    /// free and there is a via point.
    pub fn phased(&self) -> bool {
        let windowed = (self.via.iter()).any(|via| matches!(via.time(), ViaTime::Within(_)));
        windowed || (self.horizon.is_free() && !self.via.is_empty())
    }

    /// Each via point's node, or an error naming its field (`motion.via[1].window_s`): a time
    /// outside the motion, a node 0 or N, and for a phased motion a via point that does not
    /// begin after the one before it ends or that falls on its node.
    pub fn via_nodes(&self) -> Vec<Result<usize, FieldError>> {
        let mut nodes: Vec<_> = (0..self.via.len()).map(|i| self.via_node(i)).collect();
        if !self.phased() {
            return nodes;
        }
        for i in 1..self.via.len() {
            let (earlier, time) = (self.via[i - 1].time(), self.via[i].time());
            let field = format!("motion.via[{i}].{}", time.key());
            let (end, begin) = (earlier.span().1, time.span().0);
            let problem = if begin <= end {
                format!(
                    " = {} must begin after motion.via[{}] ends at {} s: the via points of a \
                     phased motion are listed in time order, their windows apart",
                    time.text(),
                    i - 1,
                    number(end)
                )
            } else if let (Ok(before), Ok(k)) = (&nodes[i - 1], &nodes[i]) {
                if k > before {
                    continue;
                }
                format!(
                    " = {} falls on node {k} as motion.via[{}] does (each via point of a phased \
                     motion has a node of its own): give more motion.steps",
                    time.text(),
                    i - 1
                )
            } else {
                continue;
            };
            if nodes[i].is_ok() {
                nodes[i] = Err(FieldError::new(field, problem));
            }
        }
        nodes
    }

    /// The node of via point `i` (module documentation), or an error naming its field where its
    /// time lies outside the motion or its node is node 0 or N.
    fn via_node(&self, i: usize) -> Result<usize, FieldError> {
        let time = self.via[i].time();
        let field = format!("motion.via[{i}].{}", time.key());
        let ((a, b), reference) = (time.span(), self.horizon.initial_s());
        let end = match self.horizon {
            Horizon::Fixed(t) => t,
            Horizon::Free { min_s, .. } => min_s,
        };
        let phased = self.phased();
        let inside = match phased {
            true => a > 0.0 && b < end,
            false => a >= 0.0 && b <= end,
        };
        if !inside {
            let (open, close) = if phased { ("(", ")") } else { ("[", "]") };
            let why = match self.horizon.is_free() {
                true => ", T_min of the free horizon, so that T ends after it",
                false => "",
            };
            return Err(FieldError::new(
                field,
                format!(
                    " = {} lies outside the motion's {open}0, {}{close} s{why}",
                    time.text(),
                    number(end)
                ),
            ));
        }
        let steps = self.steps;
        let k = ((a + b) / 2.0 * steps as f64 / reference).round() as usize;
        if k == 0 || k >= steps {
            let (end, pose) = if k == 0 {
                ("node 0", "motion.start")
            } else {
                ("the last node", "motion.goal")
            };
            let h = reference / steps as f64;
            return Err(FieldError::new(
                field,
                format!(
                    " = {} falls on {end}, which {pose} fixes: a via point lies at an inner node, \
                     its time (a window's middle) from {} to {} s (h = {} s)",
                    time.text(),
                    number(h / 2.0),
                    number(reference - h / 2.0),
                    number(h)
                ),
            ));
        }
        Ok(k)
    }
}

#[cfg(test)]
mod tests {
    use crate::model::task::{Horizon, Task, TcpVia, Via, ViaTime};

    fn via(time: ViaTime) -> Via {
        Via::Tcp(TcpVia {
            time,
            tcp: [0.0; 3],
            tol_m: 0.01,
        })
    }

    fn errors(motion: &crate::model::task::Motion) -> Vec<String> {
        let nodes = motion.via_nodes().into_iter();
        nodes
            .filter_map(|node| node.err().map(|e| e.to_string()))
            .collect()
    }

    #[test]
    fn a_via_time_falls_on_the_nearest_inner_node_of_a_fixed_horizon() {
        let mut motion = Task::built_in().unwrap().motion;
        motion.steps = 5;
        let at = |t| via(ViaTime::At(t));
        motion.via = vec![at(0.4), at(0.25), at(0.05), at(0.75), at(0.9), at(-0.1)];
        assert!(!motion.phased());
        let nodes = motion.via_nodes();
        assert_eq!(*nodes[0].as_ref().unwrap(), 3);
        assert_eq!(*nodes[1].as_ref().unwrap(), 2);
        for (i, words) in [
            (2, "falls on node 0"),
            (3, "falls on the last node"),
            (4, "outside the motion's [0, 0.8] s"),
            (5, "outside"),
        ] {
            let error = nodes[i].as_ref().unwrap_err().to_string();
            assert!(
                error.starts_with(&format!("motion.via[{i}].t_s")),
                "{error}"
            );
            assert!(error.contains(words), "{error}");
        }
    }

    /// A window makes the motion phased: its node is its middle's, its times lie strictly
    /// within the motion, the via points in time order apart, each on a node of its own.
    #[test]
    fn a_window_falls_on_its_middles_node_and_the_windows_are_checked_in_order() {
        let mut motion = Task::built_in().unwrap().motion;
        motion.steps = 10;
        let within = |a, b| via(ViaTime::Within([a, b]));
        motion.via = vec![within(0.1, 0.3), via(ViaTime::At(0.4)), within(0.5, 0.7)];
        assert!(motion.phased());
        let nodes: Vec<usize> = motion.via_nodes().into_iter().map(Result::unwrap).collect();
        assert_eq!(nodes, [3, 5, 8]);
        for (vias, field, words) in [
            (
                vec![within(0.3, 0.5), within(0.45, 0.7)],
                "[1].window_s",
                "must begin after",
            ),
            (
                vec![within(0.3, 0.5), via(ViaTime::At(0.5))],
                "[1].t_s",
                "ends at 0.5 s",
            ),
            (
                vec![within(0.3, 0.33), within(0.34, 0.36)],
                "[1].window_s",
                "falls on node 4",
            ),
            (
                vec![within(0.0, 0.3)],
                "[0].window_s",
                "outside the motion's (0, 0.8) s",
            ),
            (vec![within(0.5, 0.8)], "[0].window_s", "outside"),
            (vec![within(0.001, 0.03)], "[0].window_s", "falls on node 0"),
        ] {
            motion.via = vias;
            let found = errors(&motion);
            assert_eq!(found.len(), 1, "{found:?}");
            assert!(
                found[0].starts_with(&format!("motion.via{field}")),
                "{found:?}"
            );
            assert!(found[0].contains(words), "{found:?}");
        }
    }

    /// Under a free horizon a via point (a time or a window) ends before T_min, and its node is
    /// that of T_max.
    #[test]
    fn a_free_horizon_phases_its_via_points_within_its_shortest_duration() {
        let mut motion = Task::built_in().unwrap().motion;
        motion.steps = 10;
        motion.horizon = Horizon::Free {
            min_s: 0.5,
            max_s: 1.0,
        };
        motion.via = vec![via(ViaTime::At(0.3)), via(ViaTime::Within([0.35, 0.45]))];
        assert!(motion.phased());
        let nodes: Vec<usize> = motion.via_nodes().into_iter().map(Result::unwrap).collect();
        assert_eq!(nodes, [3, 4]);
        motion.via = vec![via(ViaTime::At(0.6))];
        let found = errors(&motion);
        assert!(
            found[0].contains("(0, 0.5) s, T_min of the free horizon"),
            "{found:?}"
        );
    }
}

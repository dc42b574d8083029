//! Dead points crossed between two nodes (docs/model.md, section 17). A linkage's ratio may fall
//! to zero between two nodes, where the problem does not look: the trajectory then passes a pose
//! where G(q) is singular (a screw in line with its elbow), at which its motor cannot drive its
//! joints, and beyond which it turns the other way. Such a trajectory is not executable, and its
//! result is infeasible, whatever its nodes satisfy.

use crate::text::{numbers, rounded};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

/// A step of a trajectory across which det G(q) changes sign, so that G(q) is singular at some
/// pose between its two nodes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DeadPoint {
    /// The node k before the crossing: it lies between nodes k and k + 1.
    pub node: usize,
    /// The motors (0-based rows of G) whose row of G turns by more than a right angle across
    /// the step (a one-joint linkage's ratio changes sign); every row that changes, where none
    /// turns that far.
    pub motors: Vec<usize>,
    /// det G(q) at nodes k and k + 1.
    pub determinant: [f64; 2],
}

impl DeadPoint {
    /// The crossing in words, with the joint positions `q` of the trajectory's nodes (rad).
    pub fn text(&self, q: &[Vec<f64>]) -> String {
        let motors: Vec<String> = self.motors.iter().map(|m| (m + 1).to_string()).collect();
        let [before, after] = self.determinant;
        format!(
            "G(q) turns singular between nodes {} and {} (q from [{}] to [{}] rad, det G from {} \
             to {}): the linkage of motor {} passes a dead point there, where it cannot drive its \
             joints, so the trajectory is not executable",
            self.node,
            self.node + 1,
            numbers(&q[self.node]),
            numbers(&q[self.node + 1]),
            rounded(before),
            rounded(after),
            motors.join(", ")
        )
    }
}

/// The steps across which det G(q) changes sign, from G(q) at each node (`ratio`, row = motor,
/// column = joint, as the trajectory records it; empty for a constant G).
pub fn dead_points(ratio: &[Vec<Vec<f64>>]) -> Vec<DeadPoint> {
    let matrix = |g: &Vec<Vec<f64>>| DMatrix::from_fn(g.len(), g.len(), |i, j| g[i][j]);
    let determinants: Vec<f64> = ratio.iter().map(|g| matrix(g).determinant()).collect();
    let mut found = Vec::new();
    for node in 0..determinants.len().saturating_sub(1) {
        let determinant = [determinants[node], determinants[node + 1]];
        if determinant[0] * determinant[1] >= 0.0 {
            continue;
        }
        let (before, after) = (&ratio[node], &ratio[node + 1]);
        let dot = |i: usize| {
            before[i]
                .iter()
                .zip(&after[i])
                .map(|(a, b)| a * b)
                .sum::<f64>()
        };
        let mut motors: Vec<usize> = (0..before.len()).filter(|&i| dot(i) < 0.0).collect();
        if motors.is_empty() {
            motors = (0..before.len())
                .filter(|&i| before[i] != after[i])
                .collect();
        }
        found.push(DeadPoint {
            node,
            motors,
            determinant,
        });
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The elbow screw of the planar example: its ratio -> 6.1 at node 3 and -17.3 at node 4.
    #[test]
    fn a_ratio_that_changes_sign_between_two_nodes_is_a_dead_point() {
        let g = |elbow: f64| vec![vec![50.0, 0.0], vec![0.0, elbow]];
        let ratio = vec![g(43.6), g(34.0), g(6.1), g(-17.3), g(-34.5)];
        let found = dead_points(&ratio);
        assert_eq!(
            found,
            [DeadPoint {
                node: 2,
                motors: vec![1],
                determinant: [305.0, -865.0]
            }]
        );
        let q = vec![vec![0.0, -1.0]; 5];
        let text = found[0].text(&q);
        assert!(
            text.starts_with("G(q) turns singular between nodes 2 and 3 (q from [0, -1] to"),
            "{text}"
        );
        assert!(
            text.contains("the linkage of motor 2 passes a dead point"),
            "{text}"
        );
        assert!(dead_points(&ratio[..3]).is_empty());
        assert!(dead_points(&[]).is_empty());
    }
}

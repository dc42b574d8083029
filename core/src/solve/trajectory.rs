//! The trajectory of a solution, node by node: the data that the result, its figures and the
//! read-back of a primal point share.

use serde::{Deserialize, Serialize};

/// The trajectory at the nodes k = 0..=N (controls at k = 0..N-1).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Trajectory {
    /// Node times, s.
    pub time: Vec<f64>,
    /// Joint positions per node, rad.
    pub q: Vec<Vec<f64>>,
    /// Joint speeds per node, rad/s.
    pub v: Vec<Vec<f64>>,
    /// Joint accelerations per interval, rad/s^2.
    pub a: Vec<Vec<f64>>,
    /// Joint torques the links take per interval, N m: the controls' (G^T u or u) less the
    /// motors' rotor inertia and friction reflected into the joints and the transmissions'
    /// losses, where the task sets them.
    pub joint_torque: Vec<Vec<f64>>,
    /// Motor torques per interval, N m (G^-T u for a joint-space solution), the rotors' and
    /// the friction's share included.
    pub motor_torque: Vec<Vec<f64>>,
    /// Motor speeds per node, rad/s (G v).
    pub motor_speed: Vec<Vec<f64>>,
    /// Each motor's angle per node, rad: gamma_i(q) for a linkage row, G_i q for a constant one
    /// (docs/model.md, section 17); written only for a transmission whose ratio changes with the
    /// pose.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub motor_position: Vec<Vec<f64>>,
    /// G(q) per node (row = motor, column = joint), the ratios dq_u/dq; written only for a
    /// transmission whose ratio changes with the pose.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ratio: Vec<Vec<Vec<f64>>>,
    /// Each motor's transmission loss torque per interval, N m, its share of `motor_torque`
    /// (docs/model.md, section 3); empty where the transmissions are lossless, and then not
    /// written.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub transmission_loss: Vec<Vec<f64>>,
    /// TCP world x per node, m.
    pub tcp_x: Vec<f64>,
    /// TCP world y per node, m.
    pub tcp_y: Vec<f64>,
    /// TCP world z per node, m.
    pub tcp_z: Vec<f64>,
}

impl Trajectory {
    /// Each motor's largest |torque| over the intervals, N m (motor i at index i).
    pub fn motor_torque_peaks(&self) -> Vec<f64> {
        peaks(&self.motor_torque)
    }

    /// Each motor's largest |speed| over the nodes, rad/s (motor i at index i).
    pub fn motor_speed_peaks(&self) -> Vec<f64> {
        peaks(&self.motor_speed)
    }
}

/// The largest |value| of each column of `rows`.
fn peaks(rows: &[Vec<f64>]) -> Vec<f64> {
    let mut largest: Vec<f64> = Vec::new();
    for row in rows {
        largest.resize(largest.len().max(row.len()), 0.0);
        for (peak, value) in largest.iter_mut().zip(row) {
            *peak = peak.max(value.abs());
        }
    }
    largest
}

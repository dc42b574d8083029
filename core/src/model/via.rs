//! Where the motion must pass and how a link must stay (docs/model.md, section 6): the task's
//! `motion.via`, points the motion passes at given times, each as joint angles or as a position
//! of the TCP in the world, and `motion.upright`, a link's axis kept within a tolerance of the
//! world's vertical at every node.
//!
//! A via point is passed at a time t_s or within a window [t_a, t_b] ([`ViaTime`]); the nodes
//! and the phases of the grid they make are `via_nodes.rs`'s.

use super::ranges::{FieldError, MAX_POINT_M};
use super::task::Motion;
use crate::text::number;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A point the motion passes: joint angles or a TCP position, at a time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged, try_from = "ViaFields")]
pub enum Via {
    /// Joint angles.
    Joints(JointVia),
    /// A TCP position in the world.
    Tcp(TcpVia),
}

/// When a via point is passed: at a given time or within a window of time.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum ViaTime {
    /// At t_s, s from the start (`"t_s"`).
    #[serde(rename = "t_s")]
    At(f64),
    /// At a time the solve chooses within [t_a, t_b], s from the start (`"window_s"`).
    #[serde(rename = "window_s")]
    Within([f64; 2]),
}

impl ViaTime {
    /// The earliest and the latest time, s (equal for a given time).
    pub fn span(self) -> (f64, f64) {
        match self {
            ViaTime::At(t) => (t, t),
            ViaTime::Within([a, b]) => (a, b),
        }
    }

    /// The name of its field: `t_s` or `window_s`.
    pub fn key(self) -> &'static str {
        match self {
            ViaTime::At(_) => "t_s",
            ViaTime::Within(_) => "window_s",
        }
    }

    /// As written: `0.4` or `[0.3, 0.5]`.
    pub fn text(self) -> String {
        match self {
            ViaTime::At(t) => number(t).to_string(),
            ViaTime::Within([a, b]) => format!("[{}, {}]", number(a), number(b)),
        }
    }
}

/// Joint angles the motion passes: |q_k,i - q_i| <= tol_rad for every joint at the via's node
/// (bounds on the node's variables).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JointVia {
    /// When, s from the start.
    #[serde(flatten)]
    pub time: ViaTime,
    /// The joint angles, rad (m for a prismatic joint), one per moving joint.
    pub q: Vec<f64>,
    /// The tolerance on each joint, rad (m), >= 0 (0: exactly).
    pub tol_rad: f64,
}

/// A TCP position the motion passes: |p(q_k) - tcp| <= tol_m at the via's node k, p the
/// TCP's world position.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TcpVia {
    /// When, s from the start.
    #[serde(flatten)]
    pub time: ViaTime,
    /// The point in the world frame, m.
    pub tcp: [f64; 3],
    /// The radius of the ball around it, m, > 0.
    pub tol_m: f64,
}

/// A link held upright: the angle between its `axis` (in the link's frame) and the world's +z
/// stays within tol_rad at every node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Upright {
    /// The link's name in the URDF.
    pub link: String,
    /// The axis in the link's frame (any length > 0; its direction counts).
    pub axis: [f64; 3],
    /// The largest angle from the vertical, rad, in (0, pi).
    pub tol_rad: f64,
}

/// A via point as written, before it is known which kind it is.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ViaFields {
    t_s: Option<f64>,
    window_s: Option<[f64; 2]>,
    q: Option<Vec<f64>>,
    tol_rad: Option<f64>,
    tcp: Option<[f64; 3]>,
    tol_m: Option<f64>,
}

impl TryFrom<ViaFields> for Via {
    type Error = String;

    fn try_from(fields: ViaFields) -> Result<Via, String> {
        let time = match (fields.t_s, fields.window_s) {
            (Some(t_s), None) => ViaTime::At(t_s),
            (None, Some(window)) => ViaTime::Within(window),
            _ => {
                return Err("a via point has exactly one of \"t_s\" (a time, s) and \
                            \"window_s\" ([t_a, t_b], a window of time, s)"
                    .to_owned())
            }
        };
        match (fields.q, fields.tol_rad, fields.tcp, fields.tol_m) {
            (Some(q), Some(tol_rad), None, None) => Ok(Via::Joints(JointVia { time, q, tol_rad })),
            (None, None, Some(tcp), Some(tol_m)) => Ok(Via::Tcp(TcpVia { time, tcp, tol_m })),
            _ => Err(
                "a via point is {\"t_s\", \"q\", \"tol_rad\"} (joint angles, rad) or \
                      {\"t_s\", \"tcp\", \"tol_m\"} (a TCP position in the world, m), with \
                      \"window_s\": [t_a, t_b] in place of \"t_s\" for a window of time"
                    .to_owned(),
            ),
        }
    }
}

impl Via {
    /// When it is passed.
    pub fn time(&self) -> ViaTime {
        match self {
            Via::Joints(via) => via.time,
            Via::Tcp(via) => via.time,
        }
    }

    /// Checks its numbers, `field` naming it (`motion.via[2]`).
    fn validate(&self, field: &str) -> Result<(), FieldError> {
        let (time, (a, b)) = (self.time(), self.time().span());
        if !(a.is_finite() && b.is_finite()) {
            return Err(FieldError::new(
                format!("{field}.{}", time.key()),
                " is not a finite time",
            ));
        }
        if a >= b && matches!(time, ViaTime::Within(_)) {
            return Err(FieldError::new(
                format!("{field}.window_s"),
                format!(" = {} must give t_a < t_b", time.text()),
            ));
        }
        match self {
            Via::Joints(via) => {
                finite(&format!("{field}.q"), &via.q)?;
                if !(via.tol_rad.is_finite() && (0.0..=PI).contains(&via.tol_rad)) {
                    return Err(FieldError::new(
                        format!("{field}.tol_rad"),
                        format!(" = {} must be from 0 to pi rad", number(via.tol_rad)),
                    ));
                }
            }
            Via::Tcp(via) => {
                finite(&format!("{field}.tcp"), &via.tcp)?;
                if via.tcp.iter().map(|p| p * p).sum::<f64>().sqrt() > MAX_POINT_M {
                    return Err(FieldError::new(
                        format!("{field}.tcp"),
                        format!(" lies farther than {MAX_POINT_M} m from the world's origin"),
                    ));
                }
                if !(via.tol_m.is_finite() && via.tol_m >= MIN_TOL_M && via.tol_m <= MAX_POINT_M) {
                    return Err(FieldError::new(
                        format!("{field}.tol_m"),
                        format!(
                            " = {} must be from {MIN_TOL_M} to {MAX_POINT_M} m (a ball of radius \
                             0 has no interior, and its row's gradient vanishes at its centre)",
                            number(via.tol_m)
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The smallest radius of a TCP via point, m: a micrometre, below any arm's repeatability.
pub const MIN_TOL_M: f64 = 1e-6;

/// The smallest tolerance of `motion.upright`, rad: its row is scaled by 1/sin(tol).
pub const MIN_UPRIGHT_TOL_RAD: f64 = 1e-6;

/// Ok if every value is finite; else an error naming `name[i]` of the first that is not.
fn finite(name: &str, values: &[f64]) -> Result<(), FieldError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(FieldError::new(
            format!("{name}[{i}]"),
            " is not a finite number",
        )),
        None => Ok(()),
    }
}

impl Upright {
    /// Checks its numbers: a finite axis of length > 0, a tolerance in (0, pi); `field` names
    /// it (`motion.upright`).
    fn validate(&self, field: &str) -> Result<(), FieldError> {
        finite(&format!("{field}.axis"), &self.axis)?;
        if self.axis.iter().all(|&a| a == 0.0) {
            return Err(FieldError::new(
                format!("{field}.axis"),
                " is the zero vector, which has no direction",
            ));
        }
        let tol = self.tol_rad;
        if !(MIN_UPRIGHT_TOL_RAD..PI).contains(&tol) {
            return Err(FieldError::new(
                format!("{field}.tol_rad"),
                format!(
                    " = {} must be from {MIN_UPRIGHT_TOL_RAD} rad to below pi (an axis held \
                     exactly vertical leaves its row without a gradient)",
                    number(tol)
                ),
            ));
        }
        Ok(())
    }

    /// The unit axis, in the link's frame.
    pub fn unit_axis(&self) -> [f64; 3] {
        let norm = self.axis.iter().map(|a| a * a).sum::<f64>().sqrt();
        self.axis.map(|a| a / norm)
    }
}

impl Motion {
    /// Checks the via points' and the upright link's numbers (what needs no robot and no
    /// duration: the nodes are found by [`Motion::via_node`]); `name` names the motion in errors
    /// (`motion`, `motions[1]`).
    pub(super) fn validate_targets(&self, name: &str) -> Result<(), FieldError> {
        for (i, via) in self.via.iter().enumerate() {
            via.validate(&format!("{name}.via[{i}]"))?;
        }
        (self.upright.as_ref()).map_or(Ok(()), |up| up.validate(&format!("{name}.upright")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::task::Task;

    #[test]
    fn a_via_point_reads_as_joints_or_tcp_and_writes_back() {
        for text in [
            r#"{"t_s":0.4,"q":[0.0,1.0],"tol_rad":0.05}"#,
            r#"{"t_s":0.4,"tcp":[0.1,0.2,0.3],"tol_m":0.01}"#,
            r#"{"window_s":[0.3,0.5],"tcp":[0.1,0.2,0.3],"tol_m":0.01}"#,
            r#"{"window_s":[0.3,0.5],"q":[0.0,1.0],"tol_rad":0.05}"#,
        ] {
            let via: Via = serde_json::from_str(text).unwrap();
            assert_eq!(serde_json::to_string(&via).unwrap(), text);
        }
        for bad in [
            r#"{"t_s":0.4,"q":[0.0],"tol_m":0.01}"#,
            r#"{"t_s":0.4,"tcp":[0.0,0.0,0.0]}"#,
            r#"{"t_s":0.4,"q":[0.0],"tol_rad":0.1,"tcp":[0.0,0.0,0.0],"tol_m":0.1}"#,
        ] {
            let error = serde_json::from_str::<Via>(bad).unwrap_err().to_string();
            assert!(error.contains("a via point is"), "{bad}: {error}");
        }
        for bad in [
            r#"{"t_s":0.4,"window_s":[0.3,0.5],"q":[0.0],"tol_rad":0.1}"#,
            r#"{"q":[0.0],"tol_rad":0.1}"#,
        ] {
            let error = serde_json::from_str::<Via>(bad).unwrap_err().to_string();
            assert!(error.contains("exactly one of"), "{bad}: {error}");
        }
        assert!(
            serde_json::from_str::<Via>(r#"{"t_s":0.4,"q":[0.0],"tol_rad":0.1,"x":1}"#)
                .unwrap_err()
                .to_string()
                .contains("unknown field")
        );
    }

    #[test]
    fn the_targets_numbers_are_checked_naming_their_fields() {
        let mut motion = Task::built_in().unwrap().motion;
        motion.via = vec![Via::Tcp(TcpVia {
            time: ViaTime::At(0.4),
            tcp: [0.0; 3],
            tol_m: 0.0,
        })];
        let error = motion.validate_targets("motion").unwrap_err().to_string();
        assert!(error.starts_with("motion.via[0].tol_m = 0"), "{error}");
        motion.via = vec![Via::Tcp(TcpVia {
            time: ViaTime::Within([0.5, 0.3]),
            tcp: [0.0; 3],
            tol_m: 0.01,
        })];
        let error = motion.validate_targets("motion").unwrap_err().to_string();
        assert!(
            error.starts_with("motion.via[0].window_s = [0.5, 0.3] must give t_a < t_b"),
            "{error}"
        );
        motion.via.clear();
        motion.upright = Some(Upright {
            link: "link_4".into(),
            axis: [0.0; 3],
            tol_rad: 0.1,
        });
        let error = motion.validate_targets("motion").unwrap_err().to_string();
        assert!(error.starts_with("motion.upright.axis"), "{error}");
    }
}

//! A row of the task's `transmission.matrix`: constant entries, or a linkage whose ratio changes
//! with the pose (a linear actuator, a crank and rod; docs/model.md, section 17).

use super::task::MatrixEntry;
use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
use serde::de::{MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::fmt;

/// One motor's row of G: one entry per joint, or a linkage object.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum MatrixRow {
    /// Constant entries: numbers, `r<i>`, `-r<i>` or `k*r<i>`, one per joint.
    Entries(Vec<MatrixEntry>),
    /// A linkage between two links (boxed: it is much larger than a row of entries).
    Linkage(Box<LinkageSpec>),
}

impl MatrixRow {
    /// The constant entries, or None for a linkage.
    pub fn entries(&self) -> Option<&[MatrixEntry]> {
        match self {
            MatrixRow::Entries(entries) => Some(entries),
            MatrixRow::Linkage(_) => None,
        }
    }
}

impl MatrixRow {
    /// The constant entry of column `column` to change, or None for a linkage or a column past
    /// the row's end.
    pub fn entry_mut(&mut self, column: usize) -> Option<&mut MatrixEntry> {
        match self {
            MatrixRow::Entries(entries) => entries.get_mut(column),
            MatrixRow::Linkage(_) => None,
        }
    }
}

impl<'de> Deserialize<'de> for MatrixRow {
    /// A list reads as entries, an object as a linkage, each with its own errors (a derived
    /// untagged enum would only say that nothing matched).
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<MatrixRow, D::Error> {
        struct RowVisitor;
        impl<'de> Visitor<'de> for RowVisitor {
            type Value = MatrixRow;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(
                    "a list of entries (numbers or \"r<i>\"), or a linkage {\"linear\": {...}} or \
                     {\"crank_rod\": {...}}",
                )
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<MatrixRow, A::Error> {
                Vec::deserialize(SeqAccessDeserializer::new(seq)).map(MatrixRow::Entries)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<MatrixRow, A::Error> {
                LinkageSpec::deserialize(MapAccessDeserializer::new(map))
                    .map(|linkage| MatrixRow::Linkage(Box::new(linkage)))
            }
        }
        deserializer.deserialize_any(RowVisitor)
    }
}

/// A linkage row as written in the task.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum LinkageSpec {
    /// A screw between two points: q_u = 2 pi |p_to - p_from| / lead.
    Linear(LinearSpec),
    /// A crank turned by the motor and a rod to a point of another link.
    CrankRod(CrankRodSpec),
}

impl LinkageSpec {
    /// The key the linkage is written under: `linear` or `crank_rod`.
    pub fn kind(&self) -> &'static str {
        match self {
            LinkageSpec::Linear(_) => "linear",
            LinkageSpec::CrankRod(_) => "crank_rod",
        }
    }
}

/// A point fixed to a link.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSpec {
    /// The link's name in the URDF.
    pub link: String,
    /// The point in the link's frame, m; each coordinate a number or a design parameter.
    pub point: [MatrixEntry; 3],
}

/// A linear actuator (ball screw, cylinder).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearSpec {
    /// One end.
    pub from: PointSpec,
    /// The other end.
    pub to: PointSpec,
    /// The lead, m per motor turn.
    pub lead_m: MatrixEntry,
    /// The length between the ends to keep, [min, max], m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stroke_m: Option<[f64; 2]>,
}

/// A crank on the link that carries its motor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrankSpec {
    /// The link's name in the URDF.
    pub link: String,
    /// The crank's centre on its axis, in the link's frame, m.
    pub point: [MatrixEntry; 3],
    /// The crank's axis in the link's frame (any length but zero).
    pub axis: [f64; 3],
    /// The crank's radius, m.
    pub radius_m: MatrixEntry,
    /// The reduction k from motor to crank: q_u = k theta.
    pub ratio: MatrixEntry,
}

/// A crank-rod linkage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrankRodSpec {
    /// The crank.
    pub crank: CrankSpec,
    /// The rod's length, m.
    pub rod_m: MatrixEntry,
    /// The rod's end on the driven link.
    pub to: PointSpec,
    /// The assembly: the side of the line from the crank's axis to the rod's end on which the
    /// crank pin lies.
    #[serde(default, skip_serializing_if = "Branch::is_positive")]
    pub branch: Branch,
}

/// Which of the two assemblies of a crank and rod: the side of the line from the crank's axis to
/// the rod's end on which the crank pin lies, turning about the crank's axis (right-hand rule).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Branch {
    /// The pin a positive turn (0 to pi) from that line.
    #[default]
    Positive,
    /// The pin a negative turn (0 to -pi) from that line.
    Negative,
}

impl Branch {
    /// +1 or -1.
    pub fn sign(self) -> f64 {
        match self {
            Branch::Positive => 1.0,
            Branch::Negative => -1.0,
        }
    }

    fn is_positive(&self) -> bool {
        *self == Branch::Positive
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_read_as_entries_or_linkages_and_write_back_the_same() {
        let text = r#"[[1, "r1"], {"linear": {"from": {"link": "a", "point": [0, 0.1, "r2"]},
            "to": {"link": "b", "point": [0.2, 0, 0]}, "lead_m": 0.01}}]"#;
        let rows: Vec<MatrixRow> = serde_json::from_str(text).unwrap();
        assert_eq!(rows[0].entries().unwrap().len(), 2);
        let MatrixRow::Linkage(linkage) = &rows[1] else {
            panic!("{rows:?}")
        };
        let LinkageSpec::Linear(screw) = linkage.as_ref() else {
            panic!("{linkage:?}")
        };
        assert_eq!(screw.from.point[2], MatrixEntry::Ratio("r2".into()));
        let again: Vec<MatrixRow> =
            serde_json::from_str(&serde_json::to_string(&rows).unwrap()).unwrap();
        assert_eq!(again, rows);
        assert_eq!(serde_json::to_string(&rows[0]).unwrap(), r#"[1.0,"r1"]"#);
    }

    #[test]
    fn a_misspelt_field_of_a_linkage_is_named() {
        let text = r#"{"crank_rod": {"crank": {"link": "a", "point": [0, 0, 0], "axis": [0, 0, 1],
            "radius_m": 0.02, "ratio": 10}, "rod": 0.1, "to": {"link": "b", "point": [0, 0, 0]}}}"#;
        let error = serde_json::from_str::<MatrixRow>(text)
            .unwrap_err()
            .to_string();
        assert!(error.contains("unknown field `rod`"), "{error}");
        let error = serde_json::from_str::<MatrixRow>(r#"{"screw": {}}"#)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("linear") && error.contains("crank_rod"),
            "{error}"
        );
        let error = serde_json::from_str::<MatrixRow>("3")
            .unwrap_err()
            .to_string();
        assert!(error.contains("a list of entries"), "{error}");
    }
}

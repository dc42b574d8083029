//! Reading the task's `transmission` section: the entries of G (numbers, `[-]r<i>` names and
//! scaled names `k*r<i>`) and the order strings `r<i> <= r<j>` / `r<i> < r<j>`, with errors
//! naming the field at fault.

use super::design_space::{DesignSpace, OrderConstraint};
use super::entry::{parse_number, parse_ratio_name, Entry, MAX_MAGNITUDE};
use super::linkage::{Linkage, ResolveError};
use super::{PoseRow, Transmission};
use crate::dynamics::Dynamics;
use crate::model::matrix_row::LinkageSpec;
use crate::model::task::{MatrixEntry, MatrixRow, TransmissionSpec};
use crate::text::number;
use std::fmt;

/// Why a task's `transmission` section is not usable; each variant names its field (indices
/// 0-based), and the message starts with that field, e.g. `transmission.matrix[2][1] = ...`.
#[derive(Clone, Debug, PartialEq)]
pub enum SpecError {
    /// `transmission.original` does not have one value per bound.
    OriginalLength {
        /// Values in `transmission.original`.
        original: usize,
        /// Entries of `transmission.bounds` (the number of ratios).
        bounds: usize,
    },
    /// `transmission.bounds[index]` is not finite or has lower > upper.
    Bound {
        /// Which ratio.
        index: usize,
        /// Its lower bound as written.
        lower: f64,
        /// Its upper bound as written.
        upper: f64,
    },
    /// `transmission.original[index]` is not finite.
    Original {
        /// Which ratio.
        index: usize,
    },
    /// `transmission.matrix` has no rows.
    EmptyMatrix,
    /// `transmission.matrix[row]` does not have as many entries as the matrix has rows.
    RowLength {
        /// Which row.
        row: usize,
        /// Its entries.
        entries: usize,
        /// The matrix's rows.
        rows: usize,
    },
    /// `transmission.matrix[row][column]` is neither a finite number nor `[-]r<i>` or `k*r<i>`
    /// (k finite and non-zero) of a ratio.
    Entry {
        /// Row of G (motor).
        row: usize,
        /// Column of G (joint).
        column: usize,
        /// The entry as written.
        entry: MatrixEntry,
        /// The number of ratios.
        ratios: usize,
    },
    /// `transmission.order[index]` is not `r<i> <= r<j>` or `r<i> < r<j>` of two ratios.
    Order {
        /// Which constraint.
        index: usize,
        /// The constraint as written.
        text: String,
        /// The number of ratios.
        ratios: usize,
    },
    /// `transmission.matrix[row]` is a linkage, whose ratio changes with the pose, read where
    /// the robot is unknown ([`Transmission::from_spec`]; [`Transmission::on_chain`] reads it).
    PoseDependent {
        /// Row of G (motor).
        row: usize,
        /// The linkage's key: `linear` or `crank_rod`.
        kind: &'static str,
    },
    /// A linkage row that cannot be resolved on the robot.
    Linkage(ResolveError),
    /// `transmission.order[index]` compares a ratio with itself.
    OrderWithItself {
        /// Which constraint.
        index: usize,
        /// The constraint as written.
        text: String,
    },
}

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SpecError::OriginalLength { original, bounds } => write!(
                f,
                "transmission.original has {original} values but transmission.bounds has {bounds}"
            ),
            SpecError::Bound {
                index,
                lower,
                upper,
            } => write!(
                f,
                "transmission.bounds[{index}] = [{}, {}] must be finite with lower <= upper, each of \
                 magnitude at most {MAX_MAGNITUDE}",
                number(*lower),
                number(*upper)
            ),
            SpecError::Original { index } => {
                write!(f, "transmission.original[{index}] is not a finite number")
            }
            SpecError::EmptyMatrix => f.write_str("transmission.matrix is empty"),
            SpecError::RowLength { row, entries, rows } => write!(
                f,
                "transmission.matrix[{row}] has {entries} entries but the matrix has {rows} rows (it must be square)"
            ),
            SpecError::Entry {
                row,
                column,
                entry,
                ratios,
            } => {
                let shown = match entry {
                    MatrixEntry::Constant(value) => value.to_string(),
                    MatrixEntry::Ratio(text) => format!("{text:?}"),
                };
                write!(
                    f,
                    "transmission.matrix[{row}][{column}] = {shown} must be a number, \
                     \"r<i>\", \"-r<i>\" or \"k*r<i>\" (k a non-zero number, e.g. \
                     \"0.5*r2\") with 1 <= i <= {ratios} (the number of bounds), each number of \
                     magnitude at most {MAX_MAGNITUDE}"
                )
            }
            SpecError::Order {
                index,
                text,
                ratios,
            } => write!(
                f,
                "transmission.order[{index}] = {text:?} must read \"r<i> <= r<j>\" or \"r<i> < r<j>\" \
                 with 1 <= i, j <= {ratios}"
            ),
            SpecError::PoseDependent { row, kind } => write!(
                f,
                "transmission.matrix[{row}] is a {kind} linkage, whose ratio changes with the \
                 pose: it needs the robot's geometry, which this reading of the task lacks"
            ),
            SpecError::Linkage(error) => error.fmt(f),
            SpecError::OrderWithItself { index, text } => write!(
                f,
                "transmission.order[{index}] = {text:?} compares a ratio with itself"
            ),
        }
    }
}

impl std::error::Error for SpecError {}

/// Parses `r<i> <= r<j>` or `r<i> < r<j>`.
fn parse_order(text: &str, count: usize) -> Option<OrderConstraint> {
    let (left, right, strict) = match text.split_once("<=") {
        Some((left, right)) => (left, right, false),
        None => {
            let (left, right) = text.split_once('<')?;
            (left, right, true)
        }
    };
    Some(OrderConstraint {
        lower: parse_ratio_name(left, count)?,
        upper: parse_ratio_name(right, count)?,
        strict,
    })
}

/// Checks that `original` has one finite value per bound and every bound is finite with
/// lower <= upper.
fn check_bounds(spec: &TransmissionSpec) -> Result<(), SpecError> {
    let count = spec.bounds.len();
    if spec.original.len() != count {
        return Err(SpecError::OriginalLength {
            original: spec.original.len(),
            bounds: count,
        });
    }
    for (index, &[lower, upper]) in spec.bounds.iter().enumerate() {
        let within = |v: f64| v.abs() <= MAX_MAGNITUDE;
        if !(within(lower) && within(upper) && lower <= upper) {
            return Err(SpecError::Bound {
                index,
                lower,
                upper,
            });
        }
    }
    match spec.original.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(SpecError::Original { index }),
        None => Ok(()),
    }
}

/// The row-major entries of the square matrix, with the matrix's size; a linkage row is given
/// to `linkage` with its index and has zero entries.
fn parse_matrix(
    matrix: &[MatrixRow],
    count: usize,
    linkage: &mut dyn FnMut(usize, &LinkageSpec) -> Result<(), SpecError>,
) -> Result<(usize, Vec<Entry>), SpecError> {
    let dof = matrix.len();
    if dof == 0 {
        return Err(SpecError::EmptyMatrix);
    }
    let mut entries = Vec::with_capacity(dof * dof);
    for (row, values) in matrix.iter().enumerate() {
        let values = match values {
            MatrixRow::Entries(values) => values,
            MatrixRow::Linkage(spec) => {
                linkage(row, spec)?;
                entries.extend((0..dof).map(|_| Entry::Constant(0.0)));
                continue;
            }
        };
        if values.len() != dof {
            return Err(SpecError::RowLength {
                row,
                entries: values.len(),
                rows: dof,
            });
        }
        for (column, entry) in values.iter().enumerate() {
            entries.push(parse_number(entry, count).ok_or_else(|| SpecError::Entry {
                row,
                column,
                entry: entry.clone(),
                ratios: count,
            })?);
        }
    }
    Ok((dof, entries))
}

/// The order constraints, each between two different ratios.
fn parse_orders(order: &[String], count: usize) -> Result<Vec<OrderConstraint>, SpecError> {
    let mut constraints = Vec::with_capacity(order.len());
    for (index, text) in order.iter().enumerate() {
        let constraint = parse_order(text, count).ok_or_else(|| SpecError::Order {
            index,
            text: text.clone(),
            ratios: count,
        })?;
        if constraint.lower == constraint.upper {
            return Err(SpecError::OrderWithItself {
                index,
                text: text.clone(),
            });
        }
        constraints.push(constraint);
    }
    Ok(constraints)
}

impl Transmission {
    /// Parses and checks the spec: a square matrix whose entries are finite numbers, `[-]r<i>`
    /// or `k*r<i>` (k finite and non-zero) with 1 <= i <= number of ratios (= number of bounds), as many original values as bounds,
    /// finite bounds with lower <= upper, finite original values, and order strings
    /// `r<i> <= r<j>` or `r<i> < r<j>` with i != j. Errors name the field, e.g.
    /// `transmission.matrix[2][1]` (0-based indices). The original design is not held to the
    /// design space here: [`Transmission::check_design`] does that.
    /// A linkage row is refused ([`SpecError::PoseDependent`]): it needs the robot
    /// ([`Transmission::on_chain`]).
    ///
    /// ```
    /// use codesign_core::model::task::{MatrixEntry, MatrixRow, TransmissionSpec};
    /// use codesign_core::transmission::Transmission;
    ///
    /// // Two joints: a belt of ratio r1 on the shoulder, and an elbow belt of ratio r2 whose
    /// // motor also turns with the shoulder (a parallel transmission).
    /// let ratio = |name: &str| MatrixEntry::Ratio(name.to_owned());
    /// let spec = TransmissionSpec {
    ///     matrix: vec![
    ///         MatrixRow::Entries(vec![ratio("r1"), MatrixEntry::Constant(0.0)]),
    ///         MatrixRow::Entries(vec![MatrixEntry::Constant(1.0), ratio("r2")]),
    ///     ],
    ///     original: vec![10.0, 5.0],
    ///     bounds: vec![[1.0, 50.0], [1.0, 50.0]],
    ///     order: vec!["r2 <= r1".to_owned()],
    /// };
    /// let transmission = Transmission::from_spec(&spec)?;
    /// let coupling = transmission.coupling(&[20.0, 4.0])?;
    /// assert_eq!(coupling.matrix()[(1, 1)], 4.0);
    /// // tau = G^T tau_u: 1 N m on each motor
    /// assert_eq!(coupling.joint_torques(&[1.0, 1.0]), vec![21.0, 4.0]);
    /// // a design that breaks the order r2 <= r1 is refused
    /// assert!(transmission.coupling(&[2.0, 4.0]).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_spec(spec: &TransmissionSpec) -> Result<Transmission, SpecError> {
        Transmission::parse(spec, &mut |row, linkage| {
            Err(SpecError::PoseDependent {
                row,
                kind: linkage.kind(),
            })
        })
    }

    /// Parses and checks the spec as [`Transmission::from_spec`] does, and resolves its linkage
    /// rows on the chain of `dynamics` (docs/model.md, section 17).
    pub fn on_chain(
        spec: &TransmissionSpec,
        dynamics: &Dynamics,
    ) -> Result<Transmission, SpecError> {
        let mut linkages = Vec::new();
        let mut transmission = Transmission::parse(spec, &mut |row, linkage| {
            let resolved = Linkage::resolve(linkage, row, dynamics, &spec.original)
                .map_err(SpecError::Linkage)?;
            linkages.push(PoseRow::new(row, resolved));
            Ok(())
        })?;
        transmission.linkages = linkages;
        Ok(transmission)
    }

    /// The design space of `spec` alone (bounds, order constraints, the original design),
    /// checked as [`Transmission::from_spec`] checks them, whatever its rows are.
    pub fn design_space_of(spec: &TransmissionSpec) -> Result<DesignSpace, SpecError> {
        check_bounds(spec)?;
        let order = parse_orders(&spec.order, spec.bounds.len())?;
        Ok(DesignSpace::new(
            spec.original.clone(),
            spec.bounds.clone(),
            order,
        ))
    }

    /// The transmission of `spec`, each linkage row handed to `linkage`.
    fn parse(
        spec: &TransmissionSpec,
        linkage: &mut dyn FnMut(usize, &LinkageSpec) -> Result<(), SpecError>,
    ) -> Result<Transmission, SpecError> {
        check_bounds(spec)?;
        let count = spec.bounds.len();
        let (dof, entries) = parse_matrix(&spec.matrix, count, linkage)?;
        let order = parse_orders(&spec.order, count)?;
        Ok(Transmission {
            dof,
            entries,
            linkages: Vec::new(),
            space: DesignSpace::new(spec.original.clone(), spec.bounds.clone(), order),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transmission::fixtures::{belt_arm, pick_place};
    use nalgebra::DMatrix;

    #[test]
    fn structure_follows_the_task_file() {
        let t = belt_arm();
        assert_eq!((t.dof(), t.num_ratios()), (4, 4));
        assert_eq!(t.original(), &[6.0, 3.0, 1.0, 1.0]);
        assert_eq!(t.bounds()[2], [1.0, 3.0]);
        let order: Vec<String> = t
            .design_space()
            .order()
            .iter()
            .map(|c| c.to_string())
            .collect();
        assert_eq!(order, ["r3 <= r2", "r2 < r1"]);
        let g = t.matrix(&[6.0, 3.0, 1.5, 2.0]);
        let expected = DMatrix::from_row_slice(
            4,
            4,
            &[
                6.0, 0.0, 0.0, 0.0, //
                3.0, 3.0, 0.0, 0.0, //
                1.0, 1.5, 2.0, 2.0, //
                1.0, 1.5, 2.0, -2.0,
            ],
        );
        assert_eq!(g, expected);
    }

    /// `k*r<i>` entries scale their ratio in G and in dG/dr; `-r<i>` is `-1*r<i>`.
    #[test]
    fn scaled_entries_scale_g_and_its_derivative() {
        let mut spec = pick_place().transmission;
        *spec.matrix[1].entry_mut(0).unwrap() = MatrixEntry::Ratio("0.5*r2".into());
        *spec.matrix[2].entry_mut(1).unwrap() = MatrixEntry::Ratio(" -2 * r3 ".into());
        *spec.matrix[3].entry_mut(3).unwrap() = MatrixEntry::Ratio("-1*r4".into());
        let t = Transmission::from_spec(&spec).unwrap();
        let g = t.matrix(&[6.0, 3.0, 1.5, 2.0]);
        assert_eq!(g[(1, 0)], 1.5);
        assert_eq!(g[(2, 1)], -3.0);
        assert_eq!(g[(3, 3)], -2.0);
        assert_eq!(t.matrix_derivative(1)[(1, 0)], 0.5);
        assert_eq!(t.matrix_derivative(2)[(2, 1)], -2.0);
        assert_eq!(t.matrix_derivative(3), belt_arm().matrix_derivative(3));
    }

    #[test]
    fn a_linkage_row_is_refused_where_the_robot_is_unknown() {
        let mut spec = pick_place().transmission;
        spec.matrix[2] = serde_json::from_str(
            r#"{"linear": {"from": {"link": "link_1", "point": [0, 0, 0]},
                "to": {"link": "link_2", "point": [0.1, 0, 0]}, "lead_m": 0.01}}"#,
        )
        .unwrap();
        let error = Transmission::from_spec(&spec).unwrap_err();
        assert_eq!(
            error,
            SpecError::PoseDependent {
                row: 2,
                kind: "linear"
            }
        );
        assert!(error
            .to_string()
            .starts_with("transmission.matrix[2] is a linear linkage, whose ratio changes"));
    }

    #[test]
    fn spec_errors_name_the_field() {
        let good = pick_place().transmission;
        type Change = Box<dyn Fn(&mut TransmissionSpec)>;
        let cases: Vec<(Change, &str)> = vec![
            (
                Box::new(|s| *s.matrix[2].entry_mut(1).unwrap() = MatrixEntry::Ratio("r5".into())),
                "transmission.matrix[2][1]",
            ),
            (
                Box::new(|s| *s.matrix[0].entry_mut(0).unwrap() = MatrixEntry::Ratio("x1".into())),
                "transmission.matrix[0][0]",
            ),
            (
                Box::new(|s| *s.matrix[3].entry_mut(3).unwrap() = MatrixEntry::Ratio("-r0".into())),
                "transmission.matrix[3][3]",
            ),
            (
                Box::new(|s| {
                    *s.matrix[1].entry_mut(0).unwrap() = MatrixEntry::Ratio("0*r2".into())
                }),
                "transmission.matrix[1][0] = \"0*r2\" must be a number, \"r<i>\"",
            ),
            // Products of the task's numbers would overflow: refused, naming the field.
            (
                Box::new(|s| {
                    *s.matrix[1].entry_mut(0).unwrap() = MatrixEntry::Ratio("1e308*r1".into())
                }),
                "transmission.matrix[1][0] = \"1e308*r1\" must be a number",
            ),
            (
                Box::new(|s| s.bounds[0] = [1.0, 1e308]),
                "transmission.bounds[0] = [1, 1e308] must be finite with lower <= upper, each of \
                 magnitude at most 1000000",
            ),
            (
                Box::new(|s| {
                    *s.matrix[1].entry_mut(0).unwrap() = MatrixEntry::Ratio("inf*r2".into())
                }),
                "transmission.matrix[1][0]",
            ),
            (
                Box::new(|s| {
                    *s.matrix[1].entry_mut(0).unwrap() = MatrixEntry::Ratio("2*r9".into())
                }),
                "transmission.matrix[1][0]",
            ),
            (
                Box::new(|s| {
                    *s.matrix[1].entry_mut(0).unwrap() = MatrixEntry::Ratio("r2*2".into())
                }),
                "transmission.matrix[1][0]",
            ),
            (
                Box::new(|s| *s.matrix[1].entry_mut(0).unwrap() = MatrixEntry::Constant(f64::NAN)),
                "transmission.matrix[1][0]",
            ),
            (
                Box::new(|s| {
                    if let MatrixRow::Entries(row) = &mut s.matrix[1] {
                        row.pop();
                    }
                }),
                "transmission.matrix[1]",
            ),
            (
                Box::new(|s| s.matrix.clear()),
                "transmission.matrix is empty",
            ),
            (Box::new(|s| s.original.push(1.0)), "transmission.original"),
            (
                Box::new(|s| s.original[2] = f64::NAN),
                "transmission.original[2]",
            ),
            (
                Box::new(|s| s.bounds[1] = [9.0, 1.0]),
                "transmission.bounds[1]",
            ),
            (
                Box::new(|s| s.order[1] = "r2 >= r1".into()),
                "transmission.order[1]",
            ),
            (
                Box::new(|s| s.order[0] = "r3 <= r5".into()),
                "transmission.order[0]",
            ),
            (
                Box::new(|s| s.order[0] = "r3 <= r2 <= r1".into()),
                "transmission.order[0]",
            ),
            (Box::new(|s| s.order[0] = "r3 < r3".into()), "itself"),
        ];
        for (change, field) in cases {
            let mut spec = good.clone();
            change(&mut spec);
            let error = Transmission::from_spec(&spec).unwrap_err().to_string();
            assert!(error.contains(field), "{error} should name {field}");
        }
        let mut spaced = good.clone();
        *spaced.matrix[3].entry_mut(3).unwrap() = MatrixEntry::Ratio(" -r4 ".into());
        spaced.order = vec![" r3<=r2".into(), "r2<r1 ".into()];
        let t = Transmission::from_spec(&spaced).unwrap();
        assert_eq!(
            t.matrix(&[6.0, 3.0, 1.0, 1.0]),
            belt_arm().matrix(&[6.0, 3.0, 1.0, 1.0])
        );
        assert_eq!(t.design_space().order(), belt_arm().design_space().order());
    }

    #[test]
    fn spec_errors_keep_their_messages() {
        let mut spec = pick_place().transmission;
        *spec.matrix[2].entry_mut(1).unwrap() = MatrixEntry::Ratio("r5".into());
        assert_eq!(
            Transmission::from_spec(&spec).unwrap_err().to_string(),
            "transmission.matrix[2][1] = \"r5\" must be a number, \"r<i>\", \"-r<i>\" or \
             \"k*r<i>\" (k a non-zero number, e.g. \"0.5*r2\") with 1 <= i <= 4 (the number of \
             bounds), each number of magnitude at most 1000000"
        );
        *spec.matrix[2].entry_mut(1).unwrap() = MatrixEntry::Constant(f64::INFINITY);
        assert_eq!(
            Transmission::from_spec(&spec).unwrap_err(),
            SpecError::Entry {
                row: 2,
                column: 1,
                entry: MatrixEntry::Constant(f64::INFINITY),
                ratios: 4
            }
        );
        let mut spec = pick_place().transmission;
        spec.order[0] = "r3 < r3".into();
        assert_eq!(
            Transmission::from_spec(&spec).unwrap_err().to_string(),
            "transmission.order[0] = \"r3 < r3\" compares a ratio with itself"
        );
    }
}

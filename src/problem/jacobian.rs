//! The constraint Jacobian's structure and values, from one routine that visits every structural
//! non-zero in a fixed order: run on zero data it yields the pattern (once per [`Formulation`]),
//! run on the evaluated nodes it yields the values, so the two can never disagree. The elastic
//! kind's slacks enter their rows linearly, with constant entries -1 (s+, e+) and +1 (s-, e-).
//! The torque-speed envelope's rows are linear too: tau_u(u) +- c (G v + B d), with entries
//! d(tau_u)/du in u, +-c_i G_ij in v and, in the elastic kind, -+c_i B_ij and +-c_i B_ij in the
//! node's speed slacks e+ and e- (d = e- - e+).

use super::node::NodeEval;
use super::{Formulation, Layout, Space};
use crate::model::task::LimitMode;
use crate::transmission::{Envelope, Side};
use nalgebra::DMatrix;

/// The design-dependent matrices the Jacobian's values come from.
pub(super) struct JacobianData<'m> {
    /// d(tau)/d(u): G^T or the identity ([`Actuation::control_map`](crate::transmission::Actuation::control_map)).
    pub(super) control_map: &'m DMatrix<f64>,
    /// Structural non-zeros of `control_map`.
    pub(super) control_pattern: &'m DMatrix<f64>,
    /// The motors' rotor inertia and friction reflected into the joints, G^T J_m G and
    /// G^T B_m G ([`Actuation::reflected`](crate::transmission::Actuation::reflected)): added
    /// to the dynamics rows' a and v blocks, which are dense already. None for ideal motors.
    pub(super) reflected: Option<(&'m DMatrix<f64>, &'m DMatrix<f64>)>,
    /// The speed rows' matrix (G, or the identity in the elastic kind's box modes) and its
    /// pattern, when speeds are limited by linear rows.
    pub(super) speed: Option<(&'m DMatrix<f64>, &'m DMatrix<f64>)>,
    /// G^-T, when motor torques are linear rows.
    pub(super) torque: Option<&'m DMatrix<f64>>,
    /// The torque-speed envelope's matrices, when the motors have one.
    pub(super) envelope: Option<EnvelopeData<'m>>,
    /// Time step h, s.
    pub(super) h: f64,
}

/// The design-dependent matrices of the envelope rows, each with its structural non-zeros.
#[derive(Clone, Copy)]
pub(super) struct EnvelopeData<'m> {
    /// The slopes c_i.
    pub(super) envelope: &'m Envelope,
    /// d(tau_u)/du ([`Actuation::motor_of_control`](crate::transmission::Actuation::motor_of_control)).
    pub(super) torque: (&'m DMatrix<f64>, &'m DMatrix<f64>),
    /// G, the motor speeds of v.
    pub(super) speed: (&'m DMatrix<f64>, &'m DMatrix<f64>),
    /// B, the motor speeds of the speed rows' relaxations (elastic kind).
    pub(super) slack: (&'m DMatrix<f64>, &'m DMatrix<f64>),
}

/// The structural non-zeros of the envelope rows' design-dependent blocks that are not G's.
pub(super) struct EnvelopePattern {
    /// d(tau_u)/du: diagonal in actuation space, dense (G^-T) in joint space.
    pub(super) torque: DMatrix<f64>,
    /// B: the identity in speed mode `exact`, G's pattern in the box modes.
    pub(super) slack: DMatrix<f64>,
}

impl EnvelopePattern {
    /// The pattern of `formulation`'s envelope rows.
    pub(super) fn of(formulation: &Formulation) -> EnvelopePattern {
        let n = formulation.layout.dof;
        EnvelopePattern {
            torque: match formulation.space {
                Space::Actuation => DMatrix::identity(n, n),
                Space::Joint => DMatrix::from_element(n, n, 1.0),
            },
            slack: match formulation.modes.speed {
                LimitMode::Exact => DMatrix::identity(n, n),
                LimitMode::Paper | LimitMode::Interval => formulation.g_pattern.clone(),
            },
        }
    }
}

/// Visits the Jacobian's structural non-zeros in their fixed order.
pub(super) fn visit(
    layout: &Layout,
    data: &JacobianData<'_>,
    nodes: &[NodeEval],
    mut emit: impl FnMut(usize, usize, f64),
) {
    let n = layout.dof;
    let h = data.h;
    for (k, node) in nodes.iter().enumerate() {
        visit_dynamics(layout, data, k, node, &mut emit);
        for i in 0..n {
            let row = layout.velocity_row(k, i);
            emit(row, layout.v(k, i), -1.0);
            emit(row, layout.a(k, i), -h);
            emit(row, layout.v(k + 1, i), 1.0);
        }
        for i in 0..n {
            let row = layout.position_row(k, i);
            emit(row, layout.q(k, i), -1.0);
            emit(row, layout.q(k + 1, i), 1.0);
            emit(row, layout.v(k + 1, i), -h);
        }
        if let Some((g, g_pattern)) = data.speed {
            for i in 0..n {
                if let Some(row) = layout.speed_row(k, i) {
                    for j in 0..n {
                        if g_pattern[(i, j)] != 0.0 {
                            emit(row, layout.v(k, j), g[(i, j)]);
                        }
                    }
                    emit_slacks(row, layout.excess_slack(k, i), &mut emit);
                }
            }
        }
        if let Some(motor_of_joint) = data.torque {
            for i in 0..n {
                if let Some(row) = layout.torque_row(k, i) {
                    for j in 0..n {
                        emit(row, layout.u(k, j), motor_of_joint[(i, j)]);
                    }
                }
            }
        }
        if let Some(envelope) = &data.envelope {
            visit_envelope(layout, k, envelope, &mut emit);
        }
    }
}

/// Visits node k's dynamics rows: d tau / d(q, v, a) (with the reflected rotor inertia and
/// damping), minus the control map on u, and in the elastic kind the deficit slacks.
fn visit_dynamics(
    layout: &Layout,
    data: &JacobianData<'_>,
    k: usize,
    node: &NodeEval,
    emit: &mut impl FnMut(usize, usize, f64),
) {
    let (control_map, control_pattern) = (data.control_map, data.control_pattern);
    let (inertia, damping) = (data.reflected.map(|r| r.0), data.reflected.map(|r| r.1));
    let n = layout.dof;
    for i in 0..n {
        let row = layout.dynamics_row(k, i);
        for j in 0..n {
            emit(row, layout.q(k, j), node.dtau_dq[(i, j)]);
        }
        for j in 0..n {
            emit(
                row,
                layout.v(k, j),
                plus(node.dtau_dv[(i, j)], damping, (i, j)),
            );
        }
        for j in 0..n {
            emit(
                row,
                layout.a(k, j),
                plus(node.mass[(i, j)], inertia, (i, j)),
            );
        }
        for j in 0..n {
            if control_pattern[(i, j)] != 0.0 {
                emit(row, layout.u(k, j), -control_map[(i, j)]);
            }
        }
        emit_slacks(row, layout.deficit_slack(k, i), emit);
    }
}

/// Visits node k's envelope rows: P_i = tau_u,i + c_i (G v + B d)_i, then M_i, the same with
/// -c_i; their u entries, v entries and, in the elastic kind, speed slack entries.
fn visit_envelope(
    layout: &Layout,
    k: usize,
    data: &EnvelopeData<'_>,
    emit: &mut impl FnMut(usize, usize, f64),
) {
    let n = layout.dof;
    let ((torque, torque_pattern), (g, g_pattern), (slack, slack_pattern)) =
        (data.torque, data.speed, data.slack);
    for side in Side::BOTH {
        for i in 0..n {
            let Some(row) = layout.envelope_row(k, i, side) else {
                continue;
            };
            let slope = side.sign() * data.envelope.slope(i);
            for j in (0..n).filter(|&j| torque_pattern[(i, j)] != 0.0) {
                emit(row, layout.u(k, j), torque[(i, j)]);
            }
            for j in (0..n).filter(|&j| g_pattern[(i, j)] != 0.0) {
                emit(row, layout.v(k, j), slope * g[(i, j)]);
            }
            for j in (0..n).filter(|&j| slack_pattern[(i, j)] != 0.0) {
                if let Some([plus, minus]) = layout.excess_slack(k, j) {
                    let entry = slope * slack[(i, j)];
                    emit(row, plus, -entry);
                    emit(row, minus, entry);
                }
            }
        }
    }
}

/// value + m[(i, j)], or value itself without m (no rounding where there is nothing to add).
fn plus(value: f64, m: Option<&DMatrix<f64>>, (i, j): (usize, usize)) -> f64 {
    m.map_or(value, |m| value + m[(i, j)])
}

/// The entries of a row's slack pair [plus, minus], if it has one: -1 and +1.
fn emit_slacks(row: usize, slacks: Option<[usize; 2]>, emit: &mut impl FnMut(usize, usize, f64)) {
    if let Some([plus, minus]) = slacks {
        emit(row, plus, -1.0);
        emit(row, minus, 1.0);
    }
}

/// The pattern of the control block of the dynamics rows: d(tau_i)/d(u_j).
pub(super) fn control_pattern(formulation: &Formulation) -> DMatrix<f64> {
    match formulation.space {
        Space::Actuation => formulation.g_pattern.transpose(),
        Space::Joint => DMatrix::identity(formulation.layout.dof, formulation.layout.dof),
    }
}

/// The Jacobian's structure, from a visit of zero nodes with every design-dependent entry set.
pub(super) fn pattern(formulation: &Formulation) -> Vec<(usize, usize)> {
    let layout = &formulation.layout;
    let n = layout.dof;
    let nodes = vec![NodeEval::zeros(n); layout.steps];
    let pattern = control_pattern(formulation);
    let dense = DMatrix::from_element(n, n, 1.0);
    let envelope_pattern = EnvelopePattern::of(formulation);
    let mut entries = Vec::new();
    let data = JacobianData {
        control_map: &pattern,
        control_pattern: &pattern,
        reflected: None,
        speed: layout
            .speed_rows
            .then_some((&formulation.speed_pattern, &formulation.speed_pattern)),
        torque: layout.torque_rows.then_some(&dense),
        envelope: formulation.envelope.as_ref().map(|envelope| EnvelopeData {
            envelope,
            torque: (&envelope_pattern.torque, &envelope_pattern.torque),
            speed: (&formulation.g_pattern, &formulation.g_pattern),
            slack: (&envelope_pattern.slack, &envelope_pattern.slack),
        }),
        h: 0.0,
    };
    visit(layout, &data, &nodes, |row, col, _| {
        entries.push((row, col))
    });
    entries
}

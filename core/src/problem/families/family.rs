//! What every constraint family shares: the [`Family`] trait the NLP adapter and the
//! sensitivity walk, the [`Shape`] that decides which families a formulation has, where a
//! family's rows sit ([`Place`]) and what its visits read ([`At`], [`NodeSecondOrder`]).

use crate::dynamics::{Dynamics, Workspace};
use crate::ipopt::Solution;
use crate::model::task::LimitModes;
use crate::problem::design_data::DesignData;
use crate::problem::kind::ProblemKind;
use crate::problem::layout::{BlockId, RowBlock};
use crate::problem::node::NodeEval;
use crate::problem::setting::Setting;
use crate::problem::targets::Targets;
use crate::transmission::{Actuation, Coupling, Envelope, MotorDynamics, PoseRow, Space};
use nalgebra::{DMatrix, DVector};
use std::fmt;
use std::sync::Arc;

/// The constraint families, in the order their rows sit within a node and their terms are
/// visited.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FamilyId {
    /// The equations of motion: inverse dynamics against the controls' joint torques.
    Dynamics,
    /// The integration of speeds and positions from node to node.
    Integration,
    /// The motor speed rows G v of speed mode `exact` (and the elastic kind's speed rows).
    MotorSpeed,
    /// The motors' torque limits: a box on u in actuation space, rows G^-T u in joint space
    /// under torque mode `exact`.
    MotorTorque,
    /// The motors' torque-speed envelope.
    Envelope,
    /// The joints' limits as boxes: positions (URDF), and speeds and joint-space torques under
    /// the box modes `paper` and `interval`.
    JointLimits,
    /// What the motion asks at its ends (`motion.ends`).
    Ends,
    /// The strokes of the linear actuators that give one.
    Strokes,
    /// The via points of the motion: joint bounds and TCP rows at their nodes.
    Via,
    /// A TCP goal: its row on the last node's positions.
    Goal,
    /// A link held upright.
    Upright,
    /// The elastic kind's slacks, non-negative and penalised.
    Slacks,
}

impl FamilyId {
    /// Every family, in order.
    pub const ALL: [FamilyId; 12] = [
        FamilyId::Dynamics,
        FamilyId::Integration,
        FamilyId::MotorSpeed,
        FamilyId::MotorTorque,
        FamilyId::Envelope,
        FamilyId::JointLimits,
        FamilyId::Ends,
        FamilyId::Strokes,
        FamilyId::Via,
        FamilyId::Goal,
        FamilyId::Upright,
        FamilyId::Slacks,
    ];

    /// Number of families.
    pub const COUNT: usize = FamilyId::ALL.len();
}

impl From<FamilyId> for BlockId {
    fn from(id: FamilyId) -> BlockId {
        BlockId(id as usize)
    }
}

/// What decides which families a formulation has and their structure.
pub(in crate::problem) struct Shape<'a> {
    /// Degrees of freedom n.
    pub(in crate::problem) dof: usize,
    pub(in crate::problem) space: Space,
    pub(in crate::problem) modes: LimitModes,
    pub(in crate::problem) kind: ProblemKind,
    pub(in crate::problem) envelope: Option<&'a Envelope>,
    /// Structural non-zeros of G over the whole design space (and every pose).
    pub(in crate::problem) g_pattern: &'a DMatrix<f64>,
    /// The rows of G that depend on the pose; empty for a constant G(r).
    pub(in crate::problem) linkages: &'a [PoseRow],
    /// The motors' rotor inertia and friction, None for ideal motors.
    pub(in crate::problem) motors: Option<&'a MotorDynamics>,
    /// The task's via points and upright link.
    pub(in crate::problem) targets: &'a Targets,
}

/// Where a family's rows sit at one node.
#[derive(Clone, Copy, Debug)]
pub(in crate::problem) struct Place {
    /// The node k < N.
    pub(in crate::problem) k: usize,
    /// The family's first row at the node.
    pub(in crate::problem) row: usize,
}

/// What a Jacobian visit reads its values from.
pub(in crate::problem) enum At<'a> {
    /// The structure: every entry that some design of the space makes non-zero; the values
    /// given are not meaningful.
    Structure(&'a Setting),
    /// The values at one design and the nodes evaluated at the current point.
    Design(&'a DesignData<'a>),
}

impl At<'_> {
    /// The formulation's setting.
    pub(in crate::problem) fn setting(&self) -> &Setting {
        match self {
            At::Structure(setting) => setting,
            At::Design(design) => design.setting(),
        }
    }

    /// The actuation at `node` (its own G(q_k) where G depends on the pose), None for the
    /// structure.
    pub(in crate::problem) fn actuation<'n>(&'n self, node: &'n NodeEval) -> Option<&'n Actuation> {
        match self {
            At::Structure(_) => None,
            At::Design(problem) => Some(problem.actuation_of(node)),
        }
    }

    /// `value` at a design, `pattern` itself for the structure: the matrix whose entries at
    /// the pattern's non-zeros are emitted.
    pub(in crate::problem) fn pick<'m>(
        &'m self,
        value: impl FnOnce(&'m DesignData<'m>) -> &'m DMatrix<f64>,
        pattern: &'m DMatrix<f64>,
    ) -> &'m DMatrix<f64> {
        match self {
            At::Structure(_) => pattern,
            At::Design(problem) => value(problem),
        }
    }
}

/// Receives the Jacobian's entries (row, column, value) in their fixed order.
pub(in crate::problem) type Emit<'e> = dyn FnMut(usize, usize, f64) + 'e;

/// The derivatives of G with respect to one design parameter r_l.
pub(in crate::problem) struct DesignDerivative {
    /// dG/dr_l.
    pub(in crate::problem) dg: DMatrix<f64>,
    /// d(G^-1)/dr_l = -G^-1 dG_l G^-1.
    pub(in crate::problem) dg_inv: DMatrix<f64>,
    /// The design parameter l (0-based).
    pub(in crate::problem) parameter: usize,
    /// d gamma_i/dr_l of each linkage row at the node (zero for constant rows and a constant
    /// transmission), rad per unit of r_l.
    pub(in crate::problem) angle: DVector<f64>,
    /// G(q_k) and its inverse where G depends on the pose, None for a constant G(r).
    pub(in crate::problem) coupling: Option<Coupling>,
    /// The motors' own torques at the node where G depends on the pose, None otherwise.
    pub(in crate::problem) load: Option<LoadDerivative>,
}

/// The motors' own torques m = J_m (G a + h) + B_m G v at a node where G depends on the pose
/// (`motor_load.rs`), and their derivative in one design parameter.
pub(in crate::problem) struct LoadDerivative {
    /// m, N m per motor.
    pub(in crate::problem) own: DVector<f64>,
    /// dm/dr_l = J_m (dG_l a + dh_l) + B_m dG_l v, per motor.
    pub(in crate::problem) own_derivative: DVector<f64>,
}

/// The evaluation of one node's second-order terms.
pub(in crate::problem) struct NodeSecondOrder<'a> {
    /// The node k < N.
    pub(in crate::problem) k: usize,
    pub(in crate::problem) dynamics: &'a Dynamics,
    /// The node's evaluation (RNEA's derivatives, the transmissions' losses).
    pub(in crate::problem) node: &'a NodeEval,
    /// The design's actuation.
    pub(in crate::problem) actuation: &'a Actuation,
    pub(in crate::problem) data: &'a mut Workspace,
    /// (q_k, v_k, a_k).
    pub(in crate::problem) state: (&'a [f64], &'a [f64], &'a [f64]),
    /// The multipliers of the family's rows at the node.
    pub(in crate::problem) multipliers: &'a [f64],
    /// Scratch of 3n x 3n.
    pub(in crate::problem) scratch: &'a mut DMatrix<f64>,
}

/// A node's Hessian blocks a family adds to: (q, v, a) x (q, v, a), 3n x 3n, and u x q, n x n.
pub(in crate::problem) type Blocks<'b> = (&'b mut DMatrix<f64>, &'b mut DMatrix<f64>);

/// One family of constraints (see the module's documentation). Every method has a default
/// that adds nothing, for the families that have no such part.
pub(in crate::problem) trait Family: fmt::Debug + Send + Sync {
    /// Its rows at a node, None for a family of variable bounds alone.
    fn rows(&self) -> Option<RowBlock> {
        None
    }

    /// Sets the bounds it puts on variables (after the earlier families', which it may
    /// override).
    fn variable_bounds(&self, _p: &DesignData<'_>, _lower: &mut [f64], _upper: &mut [f64]) {}

    /// Sets its rows' bounds at `place`.
    fn row_bounds(
        &self,
        _p: &DesignData<'_>,
        _place: Place,
        _lower: &mut [f64],
        _upper: &mut [f64],
    ) {
    }

    /// Writes its rows' values at `place` for the primal point x, with the node's evaluation.
    fn values(
        &self,
        _p: &DesignData<'_>,
        _x: &[f64],
        _node: &NodeEval,
        _place: Place,
        _g: &mut [f64],
    ) {
    }

    /// Visits its rows' Jacobian entries at `place` in their fixed order.
    fn jacobian(&self, _at: &At<'_>, _node: &NodeEval, _place: Place, _emit: &mut Emit<'_>) {}

    /// Adds lambda . its rows' second derivatives at a node: in (q, v, a) into `block` (3n x
    /// 3n, lower triangle used), in u and q into `mixed` (n x n, row = control, column =
    /// joint); linear families add nothing.
    fn hessian(&self, _node: NodeSecondOrder<'_>, _blocks: Blocks<'_>) {}

    /// Visits the entries of lambda . its rows' second derivatives at `place` outside node k's
    /// blocks: those that couple a node's variable with a problem-wide one (the free horizon T),
    /// or the last node's positions among themselves (a TCP goal), (row, column, value) in the
    /// Hessian's lower triangle, in a fixed order; `multipliers` are its rows' at the node (all
    /// 0 for the structure), `at` gives the point evaluated last at a design.
    fn wide_hessian(
        &self,
        _at: &At<'_>,
        _place: Place,
        _multipliers: &[f64],
        _emit: &mut Emit<'_>,
    ) {
    }

    /// Adds lambda . d(rows)/dr_l at `place` to `total`, at `solution`.
    fn sensitivity(
        &self,
        _p: &DesignData<'_>,
        _solution: &Solution,
        _derivative: &DesignDerivative,
        _place: Place,
        _total: &mut f64,
    ) {
    }

    /// Adds the terms of its design-dependent variable bounds to `total`, after every node's
    /// row terms: -(z_L + z_U) . d(bound)/dr_l.
    fn bound_sensitivity(
        &self,
        _p: &DesignData<'_>,
        _solution: &Solution,
        _derivative: &DesignDerivative,
        _total: &mut f64,
    ) {
    }
}

/// The entries of a row's slack pair [plus, minus], if it has one: -1 and +1 (the row's value
/// is shifted by minus - plus).
pub(in crate::problem) fn emit_slacks(row: usize, slacks: Option<[usize; 2]>, emit: &mut Emit<'_>) {
    if let Some([plus, minus]) = slacks {
        emit(row, plus, -1.0);
        emit(row, minus, 1.0);
    }
}

/// The shift minus - plus of a row's slack pair at x, if it has one.
pub(in crate::problem) fn slack_shift(x: &[f64], slacks: Option<[usize; 2]>) -> Option<f64> {
    slacks.map(|[plus, minus]| x[minus] - x[plus])
}

/// The n values of x from column `start`, as a vector.
pub(in crate::problem) fn segment(x: &[f64], start: usize, n: usize) -> DVector<f64> {
    DVector::from_column_slice(&x[start..start + n])
}

/// The families of a formulation in order, keyed by their row blocks.
pub(in crate::problem) type Families = [(BlockId, Arc<dyn Family>)];

/// The structure of the Jacobian of `families` over `setting`: one visit of zero nodes.
pub(in crate::problem) fn jacobian_pattern(
    setting: &Setting,
    families: &Families,
) -> Vec<(usize, usize)> {
    let mut entries = Vec::new();
    let zeros = NodeEval::zeros(setting.layout().dof);
    let at = At::Structure(setting);
    visit_jacobian(&at, families, |_| &zeros, &mut |row, col, _| {
        entries.push((row, col))
    });
    entries
}

/// The number of entries of the same Jacobian, counted without storing them.
pub(in crate::problem) fn jacobian_count(setting: &Setting, families: &Families) -> usize {
    let mut count = 0;
    let zeros = NodeEval::zeros(setting.layout().dof);
    let at = At::Structure(setting);
    visit_jacobian(&at, families, |_| &zeros, &mut |_, _, _| count += 1);
    count
}

/// Visits the Jacobian's entries of `families` node by node, each node's families in order,
/// with node k's evaluation `node(k)`.
pub(in crate::problem) fn visit_jacobian<'n>(
    at: &At<'_>,
    families: &Families,
    node: impl Fn(usize) -> &'n NodeEval,
    emit: &mut Emit<'_>,
) {
    let layout = at.setting().layout();
    for k in 0..layout.steps {
        for (id, family) in families {
            if let Some(row) = layout.first_row(*id, k) {
                family.jacobian(at, node(k), Place { k, row }, emit);
            }
        }
    }
}

/// Visits the Hessian's entries that couple node variables with problem-wide ones, node by node
/// and each node's families in order, with the rows' multipliers `lambda` (None: zeros, for the
/// structure).
pub(in crate::problem) fn visit_wide_hessian(
    at: &At<'_>,
    families: &Families,
    lambda: Option<&[f64]>,
    emit: &mut Emit<'_>,
) {
    let layout = at.setting().layout();
    let mut zeros = Vec::new();
    for k in 0..layout.steps {
        for (id, family) in families {
            let Some(rows) = layout.rows_at(*id, k) else {
                continue;
            };
            let row = rows.start;
            let multipliers = match lambda {
                Some(lambda) => &lambda[rows],
                None => {
                    zeros.resize(rows.len(), 0.0);
                    &zeros[..]
                }
            };
            family.wide_hessian(at, Place { k, row }, multipliers, emit);
        }
    }
}

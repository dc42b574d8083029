//! [`Formulation`]: everything of a trajectory problem except the design, built once with its
//! constraint families, its layout and its sparsity patterns.

use super::cost::Criterion;
use super::error::FormulationError;
use super::families::{self, added, At, Families, Family, Shape};
use super::grid::Grid;
use super::hessian;
use super::kind::ProblemKind;
use super::layout::{BlockId, Layout, RowBlock, WideVariable};
use super::memory::{self, MemoryNeed};
use super::pose_rules;
use super::setting::g_pattern;
use super::setting::{Setting, DEFAULT_HOLD_TOLERANCE_NM};
use super::targets::{check_end_poses, Targets};
use super::terms::{AddedTerms, NodeConstraint, NodeCost};
use crate::dynamics::Dynamics;
use crate::model::carried::CarriedModel;
use crate::model::task::{CartesianBox, LimitModes, Task, Weights};
use crate::model::Robot;
use crate::transmission::{Envelope, MotorDynamics, Space, Transmission, TransmissionLoss};
use std::sync::Arc;

/// The weights and soft box of the fixed-horizon problems that shorten a free horizon: those of
/// the task a pure minimum-time problem was made from (whose own weights are 0 but w_T, and
/// which has no box).
#[derive(Clone, Debug, PartialEq)]
pub struct Shaping {
    /// The weights of J, per rad^2, (rad/s)^2, (N m)^2 and s.
    pub weights: Weights,
    /// The soft Cartesian box.
    pub cartesian_box: CartesianBox,
}

impl Shaping {
    /// The weights and box of `task`.
    pub fn of(task: &Task) -> Shaping {
        Shaping {
            weights: task.weights.clone(),
            cartesian_box: task.cartesian_box.clone(),
        }
    }
}

/// Everything of a trajectory problem except the design: built once, then
/// [`Formulation::problem`] for each design.
#[derive(Clone, Debug)]
pub struct Formulation {
    /// What is fixed for every design: task, robot, transmission, modes, motors, layout.
    setting: Setting,
    /// What the problem minimises: the task's J or the motors' copper losses.
    criterion: Criterion,
    /// The constraint families, in the order of [`FamilyId::ALL`], then the added constraints.
    families: Vec<(BlockId, Arc<dyn Family>)>,
    /// The constraints and cost terms added from outside the core, in the order added.
    added: AddedTerms,
    /// The weights and box of the fixed-horizon problems that shorten a free horizon, where
    /// they are not the task's own (`super::shortening`).
    pub(super) shaping: Option<Shaping>,
    /// The stored entries of one node's Hessian block, in their order.
    node_hessian: Vec<hessian::Entry>,
    jacobian: Vec<(usize, usize)>,
    hessian: Vec<(usize, usize)>,
}

impl Formulation {
    /// The hard formulation of `task` for `robot` (payload already set) in `space` with `modes`;
    /// refused, naming the estimate, when one solve of it would need more memory than the
    /// machine has available ([`MemoryNeed`]).
    pub fn new(
        task: &Task,
        robot: Robot,
        space: Space,
        modes: LimitModes,
    ) -> Result<Formulation, FormulationError> {
        let mut formulation = Formulation::laid_out(task, robot, space, modes)?;
        let need = formulation.memory_need();
        need.check(
            memory::available_bytes(),
            task.motion.steps,
            formulation.layout().dof,
        )?;
        formulation.jacobian =
            families::jacobian_pattern(&formulation.setting, &formulation.families);
        formulation.hessian = formulation.hessian_pattern();
        Ok(formulation)
    }

    /// The estimated memory of one solve of the formulation [`Formulation::new`] would build,
    /// without building its sparsity patterns; errs where `new` errs for another reason.
    pub fn memory_need_of(
        task: &Task,
        robot: Robot,
        space: Space,
        modes: LimitModes,
    ) -> Result<MemoryNeed, FormulationError> {
        Ok(Formulation::laid_out(task, robot, space, modes)?.memory_need())
    }

    /// The hard formulation's families and layout, without its sparsity patterns.
    fn laid_out(
        task: &Task,
        robot: Robot,
        space: Space,
        modes: LimitModes,
    ) -> Result<Formulation, FormulationError> {
        let dynamics = Dynamics::new(robot);
        let transmission = Transmission::on_chain(&task.transmission, &dynamics)
            .map_err(|message| FormulationError(format!("task: {message}")))?;
        let robot = dynamics.robot();
        let n = robot.dof();
        if transmission.dof() != n {
            return Err(FormulationError(format!(
                "task: transmission.matrix is {0} x {0} but the robot has {n} joints",
                transmission.dof()
            )));
        }
        task.motors
            .validate(n)
            .map_err(|error| FormulationError(format!("task: {error}")))?;
        check_end_poses(task, robot)?;
        pose_rules::check_modes(&transmission, space, &modes)?;
        let targets = Targets::resolve(task, &dynamics)
            .map_err(|problems| FormulationError(format!("task: {}", problems.join("; "))))?;
        let g_pattern = g_pattern(&transmission);
        let posed = transmission.is_pose_dependent();
        let envelope = Envelope::of(&task.motors, n);
        let loss = TransmissionLoss::of(&task.motors, n);
        let layout = Layout::new(n, task.motion.steps, &[], ProblemKind::Hard, &[]);
        let carried =
            CarriedModel::on_chain(&task.carried, robot.chain(), transmission.num_ratios())
                .map_err(|message| FormulationError(format!("task: {message}")))?;
        let setting = Setting {
            task: task.clone(),
            carried,
            transmission,
            dynamics,
            space,
            modes,
            torque_limits: task.motors.torque_limit_nm.values(n),
            speed_limits: task.motors.speed_limit_rad_s.values(n),
            motor_dynamics: MotorDynamics::of(&task.motors, n),
            envelope,
            loss,
            hold_tolerance_nm: DEFAULT_HOLD_TOLERANCE_NM,
            g_pattern,
            targets,
            grid: Grid::new(&layout, task.motion.horizon, &[]),
            layout,
        };
        let mut formulation = Formulation {
            node_hessian: hessian::node_entries(n, setting.loss.is_some(), posed, false),
            setting,
            criterion: Criterion::Weighted,
            families: Vec::new(),
            added: AddedTerms::default(),
            shaping: None,
            jacobian: Vec::new(),
            hessian: Vec::new(),
        };
        formulation.lay_out(ProblemKind::Hard);
        Ok(formulation)
    }

    /// The estimated memory of one solve of this formulation; [`Formulation::new`] refuses a
    /// formulation whose need exceeds the memory the machine has available.
    /// The Jacobian's entries are counted, the Hessian's are steps times one node's: the
    /// patterns need not be built.
    pub fn memory_need(&self) -> MemoryNeed {
        let jacobian = families::jacobian_count(&self.setting, &self.families);
        let hessian = self.layout().steps * self.node_hessian.len();
        MemoryNeed::of((jacobian + hessian) as u64)
    }

    /// The same formulation in the elastic kind (docs/model.md, section 14): always feasible,
    /// with the torque deficit and the speed excess as penalised slacks.
    pub fn elastic(&self) -> Formulation {
        self.of_kind(ProblemKind::Elastic)
    }

    /// The same formulation in the hard kind: the formulation [`Formulation::elastic`] was made
    /// from.
    pub fn hard(&self) -> Formulation {
        self.of_kind(ProblemKind::Hard)
    }

    /// The same formulation in `kind`. The elastic kind has speed rows in every mode (the box
    /// modes' rows on the joint speeds, so that a slack can relax them); the hard kind only in
    /// mode `exact`, on the motor speeds G v.
    fn of_kind(&self, kind: ProblemKind) -> Formulation {
        let mut other = self.clone();
        other.build(kind);
        other
    }

    /// Builds the families of `kind`, their layout and the Jacobian's structure.
    fn build(&mut self, kind: ProblemKind) {
        self.lay_out(kind);
        self.jacobian = families::jacobian_pattern(&self.setting, &self.families);
    }

    /// Builds the families of `kind` and their layout.
    fn lay_out(&mut self, kind: ProblemKind) {
        let shape = Shape {
            dof: self.setting.layout.dof,
            space: self.setting.space,
            modes: self.setting.modes,
            kind,
            envelope: self.setting.envelope.as_ref(),
            g_pattern: &self.setting.g_pattern,
            linkages: self.setting.transmission.linkages(),
            motors: self.setting.motor_dynamics.as_ref(),
            targets: &self.setting.targets,
        };
        self.families = families::of(&shape);
        for (i, constraint) in self.added.constraints.iter().enumerate() {
            let family: Arc<dyn Family> = Arc::new(added::Added(constraint.clone()));
            self.families.push((added::block(i), family));
        }
        let blocks: Vec<(BlockId, RowBlock)> = (self.families.iter())
            .filter_map(|(id, family)| family.rows().map(|rows| (*id, rows)))
            .collect();
        self.setting.layout = Layout::new(
            self.setting.layout.dof,
            self.setting.layout.steps,
            &blocks,
            kind,
            &self.wide_variables(),
        );
        let (horizon, targets) = (self.task().motion.horizon, &self.setting.targets);
        self.setting.grid = Grid::new(&self.setting.layout, horizon, &targets.boundaries);
    }

    /// The problem-wide variables: the duration T where the task's horizon is free, then the
    /// time of each via point with a window.
    fn wide_variables(&self) -> Vec<WideVariable> {
        let free = self.task().motion.horizon.is_free();
        let horizon = free.then_some(WideVariable::Horizon).into_iter();
        let windows = (self.setting.targets.windows()).map(|(via, _)| WideVariable::ViaTime(via));
        horizon.chain(windows).collect()
    }

    /// The same formulation (space, modes, kind) for the robot carrying `payload_kg` kg at the
    /// task's payload point instead.
    pub fn with_payload(&self, payload_kg: f64) -> Result<Formulation, FormulationError> {
        let mut task = self.task().clone();
        task.payload.mass_kg = payload_kg;
        self.rebuilt(&task, self.dynamics().robot().with_payload(payload_kg))
    }

    /// The same formulation (space, modes, kind, criterion, added terms, hold tolerance,
    /// shaping) of `task` for `robot`, which differ from its own in their numbers only.
    pub(super) fn rebuilt(
        &self,
        task: &Task,
        robot: Robot,
    ) -> Result<Formulation, FormulationError> {
        let mut hard = Formulation::new(task, robot, self.space(), *self.modes())?
            .with_hold_tolerance(self.hold_tolerance_nm());
        hard.criterion = self.criterion.clone();
        hard.shaping = self.shaping.clone();
        if self.has_added_terms() {
            hard.added = self.added.clone();
            hard = hard.rebuild();
        }
        Ok(match self.kind() {
            ProblemKind::Hard => hard,
            ProblemKind::Elastic => hard.elastic(),
        })
    }

    /// The same formulation, a static-hold margin down to minus `tolerance_nm` N m holding
    /// (the solve settings' constraint tolerance, `SolveSettings::constraint_tolerance`).
    pub fn with_hold_tolerance(mut self, tolerance_nm: f64) -> Formulation {
        self.setting.hold_tolerance_nm = tolerance_nm;
        self
    }

    /// The same formulation minimising the motors' copper losses, J (docs/model.md, section 7):
    /// sum_k h sum_i (R_i / k_t,i^2) u_k,i^2 and the soft box, in the actuation space, whose
    /// controls are the motor torques. An error naming what is missing: the actuation space,
    /// the task's `motors.torque_constant_nm_per_a` and `motors.resistance_ohm`, a resistance > 0.
    pub fn minimising_copper_loss(mut self) -> Result<Formulation, FormulationError> {
        let refuse = |why: &str| Err(FormulationError(format!("the energy objective {why}")));
        if self.space() != Space::Actuation {
            return refuse(
                "weighs the motor torques, the controls of the actuation space: use the space \
                 actuation (--space actuation)",
            );
        }
        let Some(h) = self.task().step_s() else {
            return refuse(
                "weighs the losses by the step h, which a free horizon or a via point's window \
                 makes a variable: give motion.horizon_s a fixed duration and the via points \
                 their times (t_s)",
            );
        };
        let n = self.setting.layout.dof;
        let Some(constants) = self.task().motors.electrical(n) else {
            return refuse(
                "needs the motors' copper losses: give the task's motors.torque_constant_nm_per_a \
                 and motors.resistance_ohm",
            );
        };
        if let Some(i) = constants.iter().position(|&(_, r)| r <= 0.0) {
            return refuse(&format!(
                "needs a winding resistance > 0 for every motor: motors.resistance_ohm of motor \
                 {} is 0, so its torque would cost nothing",
                i + 1
            ));
        }
        let weights = constants.iter().map(|(k_t, r)| h * r / (k_t * k_t));
        self.criterion = Criterion::CopperLoss(weights.collect());
        Ok(self)
    }

    /// What the problem minimises.
    pub fn criterion(&self) -> &Criterion {
        &self.criterion
    }

    /// The tolerance of the static hold's margins, N m ([`Formulation::with_hold_tolerance`]).
    pub fn hold_tolerance_nm(&self) -> f64 {
        self.setting.hold_tolerance_nm()
    }

    /// Hard or elastic.
    pub fn kind(&self) -> ProblemKind {
        self.setting.layout.kind
    }

    /// The constraint families, in order.
    pub(super) fn families(&self) -> &Families {
        &self.families
    }

    /// What a node's Hessian sums at the primal point x of a design whose dynamics are
    /// `dynamics`: the setting, the families and the added terms.
    pub(super) fn hessian_parts<'p>(
        &'p self,
        x: &[f64],
        dynamics: &'p Dynamics,
    ) -> hessian::Parts<'p> {
        hessian::Parts {
            setting: &self.setting,
            steps_s: (0..self.layout().steps)
                .map(|k| self.step_at(x, k))
                .collect(),
            dynamics,
            families: &self.families,
            added: &self.added,
        }
    }

    /// The same formulation with `constraint`'s rows at every node k < N, after every family's
    /// (see [`NodeConstraint`]).
    pub fn with_constraint(mut self, constraint: Arc<dyn NodeConstraint>) -> Formulation {
        self.added.constraints.push(constraint);
        self.rebuild()
    }

    /// The same formulation with `term` added to its cost (see [`NodeCost`]).
    pub fn with_cost(mut self, term: Arc<dyn NodeCost>) -> Formulation {
        self.added.costs.push(term);
        self.rebuild()
    }

    /// The constraints added from outside the core, in order.
    pub fn added_constraints(&self) -> &[Arc<dyn NodeConstraint>] {
        &self.added.constraints
    }

    /// The cost terms added from outside the core, in order.
    pub fn added_costs(&self) -> &[Arc<dyn NodeCost>] {
        &self.added.costs
    }

    /// Whether terms were added from outside the core: their second derivatives then fill each
    /// node's whole Hessian block.
    pub(super) fn has_added_terms(&self) -> bool {
        !self.added.is_empty()
    }

    /// Whether a problem keeps the primal point it evaluated last, for the Jacobians that read
    /// it: those of terms added from outside the core, of the rows that read a problem-wide
    /// variable (a free T, a via time) and of a TCP goal.
    pub(super) fn keeps_point(&self) -> bool {
        self.has_added_terms() || self.layout().has_wide() || self.setting.targets().goal.is_some()
    }

    /// The families, layout and patterns built again after a term was added.
    fn rebuild(mut self) -> Formulation {
        let n = self.setting.layout.dof;
        let full = self.has_added_terms();
        let (losses, posed) = (
            self.setting.loss.is_some(),
            self.transmission().is_pose_dependent(),
        );
        self.node_hessian = hessian::node_entries(n, losses, posed, full);
        self.build(self.kind());
        self.hessian = self.hessian_pattern();
        self
    }

    /// The Hessian's structure: every node's entries, node by node, then those that couple
    /// node variables with problem-wide ones.
    fn hessian_pattern(&self) -> Vec<(usize, usize)> {
        let mut pattern = hessian::pattern(self.layout(), &self.node_hessian);
        let emit = &mut |row, column, _| pattern.push((row, column));
        families::visit_wide_hessian(&At::Structure(&self.setting), &self.families, None, emit);
        pattern
    }

    /// The per-node entries of the Lagrangian's Hessian, in their order.
    pub(super) fn node_hessian(&self) -> &[hessian::Entry] {
        &self.node_hessian
    }

    /// The Jacobian's structure.
    pub(super) fn jacobian(&self) -> &[(usize, usize)] {
        &self.jacobian
    }

    /// The Hessian's structure.
    pub(super) fn hessian(&self) -> &[(usize, usize)] {
        &self.hessian
    }

    /// What is fixed for every design of this formulation.
    pub fn setting(&self) -> &Setting {
        &self.setting
    }

    /// The task.
    pub fn task(&self) -> &Task {
        self.setting.task()
    }

    /// The transmission's structure and design space.
    pub fn transmission(&self) -> &Transmission {
        self.setting.transmission()
    }

    /// The robot's dynamics model (with the payload), shared by every problem of the formulation.
    pub fn dynamics(&self) -> &Dynamics {
        self.setting.dynamics()
    }

    /// Joint or actuation space.
    pub fn space(&self) -> Space {
        self.setting.space()
    }

    /// The limit modes.
    pub fn modes(&self) -> &LimitModes {
        self.setting.modes()
    }

    /// Each motor's torque limit |tau_u,i| <= limit_i, N m (motor i = row i of G).
    pub fn motor_torque_limits(&self) -> &[f64] {
        self.setting.motor_torque_limits()
    }

    /// Each motor's speed limit |qd_u,i| <= limit_i, rad/s (motor i = row i of G).
    pub fn motor_speed_limits(&self) -> &[f64] {
        self.setting.motor_speed_limits()
    }

    /// The motors' rotor inertia and viscous friction, None for ideal motors.
    pub fn motor_dynamics(&self) -> Option<&MotorDynamics> {
        self.setting.motor_dynamics()
    }

    /// The motors' torque-speed envelope, None without `motors.no_load_speed_rad_s`.
    pub fn envelope(&self) -> Option<&Envelope> {
        self.setting.envelope()
    }

    /// The transmissions' losses, None without `motors.efficiency`.
    pub fn transmission_loss(&self) -> Option<&TransmissionLoss> {
        self.setting.transmission_loss()
    }

    /// The index layout.
    pub fn layout(&self) -> &Layout {
        self.setting.layout()
    }

    /// The step h_k of interval k at the primal point x, s: T/N, of the task's T or of x's
    /// free one, unless the via points split the grid into phases (docs/model.md, section 6).
    pub fn step_at(&self, x: &[f64], k: usize) -> f64 {
        self.setting.step_at(x, k)
    }

    /// Number of structural non-zeros of the constraint Jacobian.
    pub fn jacobian_nonzeros(&self) -> usize {
        self.jacobian.len()
    }

    /// Number of structural non-zeros of the Lagrangian Hessian's lower triangle.
    pub fn hessian_nonzeros(&self) -> usize {
        self.hessian.len()
    }
}

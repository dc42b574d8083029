//! The trajectory problem of one design as an [`Nlp`]: a thin adapter that walks the
//! formulation's constraint families (`families/`) node by node for the bounds, the values and
//! the Jacobian, adds the cost (`cost.rs`) and the elastic kind's penalty, and assembles the
//! Hessian's node blocks (`hessian.rs`).

use super::cost::{Cost, CostTerms};
use super::design_data::DesignData;
use super::families::{self, elastic, At, Place};
use super::formulation::Formulation;
use super::hessian::NodeHessian;
use super::kind::ProblemKind;
use super::layout::WideVariable;
use super::node::{Level, NodeEval, NodePose};
use super::terms;
use crate::dynamics::{Dynamics, Workspace};
use crate::ipopt::{EvalError, Nlp};
use crate::solve::Keyed;
use crate::transmission::{
    Actuation, Coupling, Depth, DesignError, JointLimits, NodeLoss, PoseError,
};
use nalgebra::DVector;

/// The trajectory NLP of one design (see [`Formulation`]).
#[derive(Clone, Debug)]
pub struct TrajectoryProblem<'a> {
    formulation: &'a Formulation,
    /// What the families read of this design: r, its actuation and the point evaluated last.
    design: DesignData<'a>,
    /// G at the motion's start and goal: the static hold's.
    ends: [Coupling; 2],
    /// Each screw's motor and length per motor radian l / 2 pi at this design, m/rad.
    screws: Vec<(usize, f64)>,
    /// One dynamics workspace per node k < N (all of the design's one model), so that each
    /// keeps its node's kinematics cached from one callback to the next (the Hessian reuses what
    /// the Jacobian computed at the same point).
    workspaces: Vec<Workspace>,
    nodes: Vec<NodeEval>,
    level: Level,
    /// The Hessian's blocks at the node being assembled.
    node_hessian: NodeHessian,
    /// The trajectory IPOPT starts from instead of the standard guess (see
    /// [`TrajectoryProblem::start_at`]).
    start: Option<Vec<f64>>,
}

impl<'a> TrajectoryProblem<'a> {
    fn new(formulation: &'a Formulation, ratios: &[f64]) -> Result<Self, DesignError> {
        // The coupling checks the design (bounds, order, G invertible, the linkages closed at
        // both ends) before building G.
        let (transmission, motion) = (formulation.transmission(), &formulation.task().motion);
        let dynamics = formulation.dynamics();
        let start = transmission.coupling_at(ratios, (dynamics, &motion.start), "the start")?;
        let goal_pose = formulation.setting().goal_pose();
        let goal = transmission.coupling_at(ratios, (dynamics, goal_pose), "the goal");
        // A TCP goal's pose is the guess's, no condition of the design: where a linkage does not
        // close there, its (unjudged) hold is read through G at the start.
        let goal = match (goal, formulation.setting().targets().goal.is_some()) {
            (Err(_), true) => start.clone(),
            (goal, _) => goal?,
        };
        let (n, steps) = (formulation.layout().dof, formulation.layout().steps);
        let design = DesignData::new(
            formulation.setting(),
            ratios,
            formulation.setting().actuation(start.clone()),
        );
        Ok(TrajectoryProblem {
            formulation,
            workspaces: (0..steps).map(|_| design.dynamics().workspace()).collect(),
            design,
            ends: [start, goal],
            screws: (transmission.linkages().iter())
                .filter_map(|row| Some((row.motor, row.linkage.length_per_angle(ratios)?)))
                .collect(),
            nodes: vec![NodeEval::zeros(n); steps],
            level: Level::Nothing,
            node_hessian: NodeHessian::zeros(n),
            start: None,
        })
    }

    /// Starts IPOPT from the trajectory of `x`, a primal point of this design's problem in
    /// either kind (an elastic point's slacks are dropped, this problem's own start at 0),
    /// instead of the standard initial guess; the multipliers start as in a cold start. An
    /// error when `x` is shorter than the trajectory or not finite.
    pub fn start_at(&mut self, x: &[f64]) -> Result<(), crate::ipopt::Error> {
        let trajectory = self.formulation.layout().slacks().start;
        let Some(own) = x.get(..trajectory) else {
            return Err(crate::ipopt::Error::InvalidProblem(format!(
                "a start of {} values is shorter than the trajectory's {trajectory}",
                x.len()
            )));
        };
        if let Some(i) = own.iter().position(|value| !value.is_finite()) {
            return Err(crate::ipopt::Error::InvalidProblem(format!(
                "start x[{i}] = {} is not finite",
                own[i]
            )));
        }
        self.start = Some(own.to_vec());
        Ok(())
    }

    /// Each constraint added from outside the core's largest violation at x, by name.
    pub fn added_violations(&self, x: &[f64]) -> Keyed {
        let f = self.formulation;
        terms::violations(&self.design, f.added_constraints(), x)
    }

    /// J at x by term ([`CostTerms`]), with the TCP's world position `tcp(k)` at each node
    /// k < N.
    pub fn cost_terms(&self, x: &[f64], tcp: impl Fn(usize) -> [f64; 3]) -> CostTerms {
        let f = self.formulation;
        Cost::new(f.criterion(), f.setting()).terms(x, tcp, self.added_costs(x))
    }

    /// Each cost term added from outside the core at x, summed over the nodes, by name.
    pub fn added_costs(&self, x: &[f64]) -> Keyed {
        let f = self.formulation;
        terms::costs(&self.design, f.added_costs(), x)
    }

    /// The formulation this problem belongs to.
    pub fn formulation(&self) -> &'a Formulation {
        self.formulation
    }

    /// The design r.
    pub fn ratios(&self) -> &[f64] {
        self.design.ratios()
    }

    /// The robot's dynamics at this design: the formulation's, carrying the task's parts at
    /// r where it has any (docs/model.md, section 18).
    pub fn dynamics(&self) -> &Dynamics {
        self.design.dynamics()
    }

    /// What the families read of this design.
    pub(super) fn design(&self) -> &DesignData<'a> {
        &self.design
    }

    /// G(r) and its inverse at this design.
    pub fn coupling(&self) -> &Coupling {
        self.design.coupling()
    }

    /// The actuation at this design: the controls' map to joint and motor torques (at the
    /// motion's start for a pose-dependent transmission: see [`TrajectoryProblem::actuation_at`]).
    pub fn actuation(&self) -> &Actuation {
        self.design.actuation()
    }

    /// G at the motion's start and goal.
    pub fn end_couplings(&self) -> &[Coupling; 2] {
        &self.ends
    }

    /// The actuation at pose q (rad): this design's for a constant G, G(q) for a
    /// pose-dependent one, or why its linkages do not close there.
    pub fn actuation_at(&self, q: &[f64]) -> Result<Actuation, PoseError> {
        let f = self.formulation;
        if !f.transmission().is_pose_dependent() {
            return Ok(self.actuation().clone());
        }
        let mut data = f.dynamics().workspace();
        let at = (f.transmission()).at_pose(
            self.ratios(),
            (f.dynamics(), &mut data),
            q,
            Depth::First,
        )?;
        Ok(f.setting().actuation(at.coupling))
    }

    /// The joint torques G(q)^T J_m h the motors' rotor inertia takes through the speed term
    /// h_i = v^T (d^2 gamma_i/dq^2) v of each linkage row (rad/s^2) at pose q and joint speeds
    /// v, N m: zero for a constant G or ideal motors.
    pub fn speed_term_torques(&self, q: &[f64], v: &[f64]) -> Result<Vec<f64>, PoseError> {
        let f = self.formulation;
        let (Some(motors), true) = (f.motor_dynamics(), f.transmission().is_pose_dependent())
        else {
            return Ok(vec![0.0; q.len()]);
        };
        let mut data = f.dynamics().workspace();
        let at = (f.transmission()).at_pose(
            self.ratios(),
            (f.dynamics(), &mut data),
            q,
            Depth::Third,
        )?;
        let rows = at.rows.iter().map(|(motor, row)| (*motor, &row.hessian));
        let h = families::speed_terms(rows, &DVector::from_column_slice(v));
        let torques = families::speed_term_torques(at.coupling.matrix(), motors, &h);
        Ok(torques.iter().copied().collect())
    }

    /// Each motor's angle at pose q, rad: gamma_i(q) for a linkage row, G_i q for a constant one.
    pub fn motor_angles(&self, q: &[f64]) -> Result<Vec<f64>, PoseError> {
        self.design.motor_angles(q)
    }

    /// Joint torques the links take at a node of speeds v and accelerations a under control u,
    /// N m: G^T u (actuation space) or u (joint space), less the motors' rotor inertia and
    /// friction reflected into the joints and the transmissions' losses `loss` there.
    pub fn joint_torques(
        &self,
        (v, a): (&[f64], &[f64]),
        u: &[f64],
        loss: Option<&NodeLoss>,
    ) -> Vec<f64> {
        self.actuation().link_torques((v, a), u, loss)
    }

    /// Motor torques of control u at a node: u (actuation space) or G^-T u (joint space), N m.
    pub fn motor_torques(&self, u: &[f64]) -> Vec<f64> {
        self.actuation().motor_torques(u)
    }

    /// The box or linear rows that limit the joint speeds v in the formulation's speed mode, rad/s.
    pub fn speed_limits(&self) -> JointLimits {
        self.design.speed_limits()
    }

    /// The box or linear rows that limit the controls u: |u_i| <= motor i's torque limit in
    /// actuation space, the formulation's torque mode in joint space, N m.
    pub fn control_limits(&self) -> JointLimits {
        self.design.control_limits()
    }

    /// The same limits through `coupling`, G at some pose of a pose-dependent transmission.
    pub fn control_limits_with(&self, coupling: &Coupling) -> JointLimits {
        self.design.control_limits_with(coupling)
    }

    /// Evaluates the node data at x up to `level` (cached until x changes).
    fn evaluate(&mut self, x: &[f64], new_x: bool, level: Level) -> Result<(), EvalError> {
        if new_x {
            self.level = Level::Nothing;
        }
        if self.level == Level::Nothing && self.formulation.keeps_point() {
            self.design.point.clear();
            self.design.point.extend_from_slice(x);
        }
        if self.level >= level {
            return Ok(());
        }
        if let Some(i) = x.iter().position(|value| !value.is_finite()) {
            return Err(EvalError::from(format!(
                "variable {i} is {} at the evaluation point",
                x[i]
            )));
        }
        let (f, actuation) = (self.formulation, self.design.actuation());
        // The linkage rows are taken to the third order at once: IPOPT asks for the derivatives
        // at nearly every point whose values it asked for (each accepted step), and the jets
        // cost about as much to the third order as to the first. At the values' x they are
        // then current.
        let poses_current = self.level >= Level::Values;
        // The rotor inertia's speed term v^T (d^2 gamma/dq^2) v takes the Hessian to the fourth.
        let depth = match f.motor_dynamics() {
            Some(_) => Depth::Fourth,
            None => Depth::Third,
        };
        let nodes = self.nodes.iter_mut().zip(&mut self.workspaces);
        for (k, (node, data)) in nodes.enumerate() {
            let state = f.layout().node_state(x, k);
            let dynamics = self.design.dynamics();
            node.evaluate(dynamics, data, state, level);
            if let Some(upright) = &f.setting().targets().upright {
                node.upright = Some(upright.z_and_gradient(dynamics, data, state.0));
            }
            if f.transmission().is_pose_dependent() && !poses_current {
                let at = (f.transmission())
                    .at_pose(self.design.ratios(), (dynamics, data), state.0, depth)
                    .map_err(|error| EvalError::outside_domain(format!("node {k}: {error}")))?;
                node.pose = Some(NodePose {
                    actuation: f.setting().actuation(at.coupling),
                    rows: at.rows,
                    screws: self.screws.clone(),
                    speeds: state.1.to_vec(),
                    accelerations: state.2.to_vec(),
                    controls: f.layout().controls(x, k).to_vec(),
                });
            }
            let node_actuation = node.pose.as_ref().map_or(actuation, |pose| &pose.actuation);
            node.loss = node_actuation.node_loss(&node.tau, state.1);
        }
        self.level = level;
        Ok(())
    }
}

impl Formulation {
    /// The problem of design `ratios`, or why the design is not valid.
    pub fn problem(&self, ratios: &[f64]) -> Result<TrajectoryProblem<'_>, DesignError> {
        TrajectoryProblem::new(self, ratios)
    }
}

impl TrajectoryProblem<'_> {
    /// Each family's rows at each node, with where they sit.
    fn places(&self) -> impl Iterator<Item = (&dyn families::Family, Place)> + '_ {
        let f = self.formulation;
        let layout = f.layout();
        (0..layout.steps).flat_map(move |k| {
            f.families().iter().filter_map(move |(id, family)| {
                let row = layout.first_row(*id, k)?;
                Some((family.as_ref(), Place { k, row }))
            })
        })
    }
}

impl Nlp for TrajectoryProblem<'_> {
    fn num_variables(&self) -> usize {
        self.formulation.layout().num_variables()
    }

    fn num_constraints(&self) -> usize {
        self.formulation.layout().num_constraints()
    }

    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.fill(f64::NEG_INFINITY);
        upper.fill(f64::INFINITY);
        for (_, family) in self.formulation.families() {
            family.variable_bounds(&self.design, lower, upper);
        }
    }

    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.fill(0.0);
        upper.fill(0.0);
        for (family, place) in self.places() {
            family.row_bounds(&self.design, place, lower, upper);
        }
    }

    /// The standard initial guess (docs/model.md, section 6): q linear from start to goal (a TCP
    /// goal's pose of the inverse kinematics); v the mean speed at inner nodes, 0 at the ends;
    /// u = 0; a = 0. Or the trajectory given to [`TrajectoryProblem::start_at`], slacks at 0.
    fn initial_point(&self, x: &mut [f64]) {
        let f = self.formulation;
        let (layout, motion) = (f.layout(), &f.task().motion);
        let goal_pose = f.setting().goal_pose();
        x.fill(0.0);
        if let Some(start) = &self.start {
            x[..start.len()].copy_from_slice(start);
            return;
        }
        if let Some(column) = layout.horizon() {
            x[column] = motion.horizon.initial_s();
        }
        // A via time at its node's time on the uniform grid of the initial T, within its window.
        for boundary in &f.setting().targets().boundaries {
            if let Some(column) = layout.wide(WideVariable::ViaTime(boundary.via)) {
                let (t_a, t_b) = boundary.time.span();
                let uniform =
                    boundary.node as f64 * motion.horizon.initial_s() / layout.steps as f64;
                x[column] = uniform.clamp(t_a, t_b);
            }
        }
        for k in 0..=layout.steps {
            let s = k as f64 / layout.steps as f64;
            for i in 0..layout.dof {
                let (start, goal) = (motion.start[i], goal_pose[i]);
                x[layout.q(k, i)] = start + s * (goal - start);
                if k > 0 && k < layout.steps {
                    x[layout.v(k, i)] = (goal - start) / motion.horizon.initial_s();
                }
            }
        }
    }

    fn objective(&mut self, x: &[f64], new_x: bool) -> Result<f64, EvalError> {
        self.evaluate(x, new_x, Level::Values)?;
        let f = self.formulation;
        let mut cost = Cost::new(f.criterion(), f.setting()).value(x, &self.nodes);
        if f.has_added_terms() {
            cost += terms::cost(&self.design, f.added_costs(), x);
        }
        Ok(match f.layout().kind {
            ProblemKind::Hard => cost,
            ProblemKind::Elastic => cost + elastic::penalty(f.setting(), x),
        })
    }

    fn gradient(&mut self, x: &[f64], new_x: bool, gradient: &mut [f64]) -> Result<(), EvalError> {
        self.evaluate(x, new_x, Level::Derivatives)?;
        let f = self.formulation;
        Cost::new(f.criterion(), f.setting()).gradient(x, &self.nodes, gradient);
        terms::add_cost_gradient(&self.design, f.added_costs(), x, gradient);
        elastic::penalty_gradient(f.setting(), gradient);
        Ok(())
    }

    fn constraints(&mut self, x: &[f64], new_x: bool, g: &mut [f64]) -> Result<(), EvalError> {
        self.evaluate(x, new_x, Level::Values)?;
        for (family, place) in self.places() {
            family.values(&self.design, x, &self.nodes[place.k], place, g);
        }
        Ok(())
    }

    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        self.formulation.jacobian().to_vec()
    }

    fn jacobian_values(
        &mut self,
        x: &[f64],
        new_x: bool,
        values: &mut [f64],
    ) -> Result<(), EvalError> {
        self.evaluate(x, new_x, Level::Derivatives)?;
        let mut next = 0;
        let at = At::Design(&self.design);
        let f = self.formulation.families();
        families::visit_jacobian(&at, f, |k| &self.nodes[k], &mut |_, _, value| {
            values[next] = value;
            next += 1;
        });
        Ok(())
    }

    fn hessian_structure(&self) -> Vec<(usize, usize)> {
        self.formulation.hessian().to_vec()
    }

    fn hessian_values(
        &mut self,
        x: &[f64],
        new_x: bool,
        obj_factor: f64,
        lambda: &[f64],
        values: &mut [f64],
    ) -> Result<(), EvalError> {
        self.evaluate(x, new_x, Level::Derivatives)?;
        let f = self.formulation;
        let layout = f.layout();
        let cost = Cost::new(f.criterion(), f.setting());
        let per_node = f.node_hessian().len();
        let parts = f.hessian_parts(x, self.design.dynamics());
        let nodes = self.nodes.iter().zip(&mut self.workspaces);
        for (k, ((node, data), values)) in nodes.zip(values.chunks_mut(per_node)).enumerate() {
            let state = (layout.node_state(x, k), layout.controls(x, k));
            let actuation = self.design.actuation_of(node);
            self.node_hessian
                .evaluate((&parts, k, data), &cost, state, (node, actuation), lambda);
            self.node_hessian
                .write(f.node_hessian(), obj_factor, values);
        }
        let mut next = layout.steps * per_node;
        let emit = &mut |_, _, value| {
            values[next] = value;
            next += 1;
        };
        families::visit_wide_hessian(&At::Design(&self.design), f.families(), Some(lambda), emit);
        Ok(())
    }
}

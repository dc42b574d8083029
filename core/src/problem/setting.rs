//! [`Setting`]: what a formulation fixes for every design besides its families and patterns:
//! the task, the robot's dynamics, the transmission, the space and limit modes, the motors'
//! limits, dynamics, envelope and losses, and the index layout. The constraint families read it
//! (and, for one design, a [`DesignData`](super::DesignData) over it), never the whole
//! formulation.

use super::grid::Grid;
use super::layout::Layout;
use super::targets::Targets;
use crate::dynamics::Dynamics;
use crate::model::carried::{motor_parts_mass_kg, CarriedModel, CarriedPart};
use crate::model::task::{LimitModes, Task};
use crate::transmission::{
    Actuation, Coupling, Envelope, MotorDynamics, Space, Transmission, TransmissionLoss,
};
use nalgebra::DMatrix;

/// IPOPT's default `constr_viol_tol`, N m here: the violation of a constraint IPOPT accepts at
/// an optimum. A hold margin down to minus the solver's tolerance counts as held, as a
/// trajectory that close to its limit counts as feasible (a joint whose limit is 0 in mode
/// `paper` and whose gravity torque is 0 up to rounding holds).
pub const DEFAULT_HOLD_TOLERANCE_NM: f64 = 1e-4;

/// What a formulation fixes for every design (see the module's documentation).
#[derive(Clone, Debug)]
pub struct Setting {
    pub(super) task: Task,
    pub(super) transmission: Transmission,
    /// The robot's dynamics without the carried parts (with the payload).
    pub(super) dynamics: Dynamics,
    /// The parts the links carry, whose mass may follow the design (empty: none).
    pub(super) carried: CarriedModel,
    pub(super) space: Space,
    pub(super) modes: LimitModes,
    /// Each motor's torque limit (the task's `motors.torque_limit_nm`), N m, one per row of G.
    pub(super) torque_limits: Vec<f64>,
    /// Each motor's speed limit (the task's `motors.speed_limit_rad_s`), rad/s, one per row of G.
    pub(super) speed_limits: Vec<f64>,
    /// The motors' rotor inertia and friction, None for ideal motors (neither key given).
    pub(super) motor_dynamics: Option<MotorDynamics>,
    /// The motors' torque-speed envelope, None without `motors.no_load_speed_rad_s`.
    pub(super) envelope: Option<Envelope>,
    /// The transmissions' losses, None without `motors.efficiency`.
    pub(super) loss: Option<TransmissionLoss>,
    /// A static-hold margin down to minus this holds, N m: the solver's constraint tolerance
    /// ([`DEFAULT_HOLD_TOLERANCE_NM`] unless set).
    pub(super) hold_tolerance_nm: f64,
    /// Structural non-zeros of G (row = motor, column = joint) over the whole design space.
    pub(super) g_pattern: DMatrix<f64>,
    /// The task's via points and upright link, on their nodes and bodies.
    pub(super) targets: Targets,
    pub(super) layout: Layout,
    /// The node times over the layout's problem-wide variables.
    pub(super) grid: Grid,
}

impl Setting {
    /// The actuation of `coupling` (G at one design and, for a pose-dependent transmission, one
    /// pose) in this setting's space, with its motors and losses.
    pub(super) fn actuation(&self, coupling: Coupling) -> Actuation {
        Actuation::new(coupling, self.space, self.motor_dynamics()).with_loss(self.loss.as_ref())
    }

    /// The task.
    pub fn task(&self) -> &Task {
        &self.task
    }

    /// The transmission's structure and design space.
    pub fn transmission(&self) -> &Transmission {
        &self.transmission
    }

    /// The robot's dynamics model (with the payload), shared by every problem of the
    /// formulation; without the parts the links carry, which a design's dynamics add
    /// ([`DesignData::dynamics`](super::DesignData::dynamics)).
    pub fn dynamics(&self) -> &Dynamics {
        &self.dynamics
    }

    /// The parts the links carry (docs/model.md, section 18); empty for none.
    pub fn carried(&self) -> &CarriedModel {
        &self.carried
    }

    /// The actuators' mass at design r, kg: the motors of `motors.parts` and the parts the
    /// links carry. None where the task has neither, or a motor part's mass is unknown.
    pub fn actuator_mass_kg(&self, r: &[f64]) -> Option<f64> {
        let parts = self.task.motors.parts.as_deref();
        // A carried motor of `motors.parts` (`of_motor`) is counted there.
        let own = |part: &CarriedPart| part.motor.as_ref().is_some_and(|m| m.of_motor.is_some());
        let carried: f64 = (self.task.carried.iter().zip(self.carried.masses(r)))
            .filter(|(part, _)| !own(part))
            .map(|(_, mass)| mass)
            .sum();
        match (parts, motor_parts_mass_kg(parts)) {
            (Some(_), Some(motors)) => Some(motors + carried),
            (Some(_), None) => None,
            (None, _) => (!self.carried.is_empty()).then_some(carried),
        }
    }

    /// Joint or actuation space.
    pub fn space(&self) -> Space {
        self.space
    }

    /// The limit modes.
    pub fn modes(&self) -> &LimitModes {
        &self.modes
    }

    /// Each motor's torque limit |tau_u,i| <= limit_i, N m (motor i = row i of G).
    pub fn motor_torque_limits(&self) -> &[f64] {
        &self.torque_limits
    }

    /// Each motor's speed limit |qd_u,i| <= limit_i, rad/s (motor i = row i of G).
    pub fn motor_speed_limits(&self) -> &[f64] {
        &self.speed_limits
    }

    /// The motors' rotor inertia and viscous friction, None for ideal motors.
    pub fn motor_dynamics(&self) -> Option<&MotorDynamics> {
        self.motor_dynamics.as_ref()
    }

    /// The motors' torque-speed envelope, None without `motors.no_load_speed_rad_s`.
    pub fn envelope(&self) -> Option<&Envelope> {
        self.envelope.as_ref()
    }

    /// The transmissions' losses, None without `motors.efficiency`.
    pub fn transmission_loss(&self) -> Option<&TransmissionLoss> {
        self.loss.as_ref()
    }

    /// The tolerance of the static hold's margins, N m.
    pub fn hold_tolerance_nm(&self) -> f64 {
        self.hold_tolerance_nm
    }

    /// Structural non-zeros of G (row = motor, column = joint) over the whole design space and
    /// every pose.
    pub fn g_pattern(&self) -> &DMatrix<f64> {
        &self.g_pattern
    }

    /// The task's via points and upright link, resolved (`motion.via`, `motion.upright`).
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// The pose the motion's standard initial guess ends at, rad: the goal's angles, or a TCP
    /// goal's pose of the inverse kinematics ([`Targets::goal_pose`]).
    pub fn goal_pose(&self) -> &[f64] {
        self.targets.goal_pose(self.task())
    }

    /// The index layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The node times, the steps and their derivatives in the problem-wide variables.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The duration T at the primal point x, s: the task's fixed T, or x's T where the horizon
    /// is free (a column of the layout).
    pub fn horizon_at(&self, x: &[f64]) -> f64 {
        self.grid.horizon(x)
    }

    /// The step h_k of interval k at the primal point x, s: T/N unless the via points split the
    /// grid into phases ([`Grid`]).
    pub fn step_at(&self, x: &[f64], k: usize) -> f64 {
        self.grid.step(x, k)
    }

    /// Each node's time t_k at the primal point x, k = 0..=N, s.
    pub fn times_at(&self, x: &[f64]) -> Vec<f64> {
        self.grid.times(x)
    }
}

/// The structural non-zeros of G (row = motor, column = joint) over the whole design space and
/// every pose: the entries of G(r) at the original design, those some ratio moves, and a linkage
/// row's joints.
pub(super) fn g_pattern(transmission: &Transmission) -> DMatrix<f64> {
    let mut pattern = transmission
        .matrix(transmission.original())
        .map(|g| f64::from(u8::from(g != 0.0)));
    for i in 0..transmission.num_ratios() {
        let derivative = transmission.matrix_derivative(i);
        pattern.zip_apply(&derivative, |p, d| {
            if d != 0.0 {
                *p = 1.0;
            }
        });
    }
    for row in transmission.linkages() {
        row.joints().for_each(|j| pattern[(row.motor, j)] = 1.0);
    }
    pattern
}

//! [`DesignData`]: what the constraint families read of one design, over the formulation's
//! [`Setting`]: the design r, its actuation (G(r) and the controls' map to torques), the
//! robot's dynamics carrying the task's parts at r, and the primal point evaluated last.

use super::node::NodeEval;
use super::setting::Setting;
use crate::dynamics::Dynamics;
use crate::transmission::{Actuation, Coupling, JointLimits, PoseError, Space};

/// One design of a formulation, as its families read it.
#[derive(Clone, Debug)]
pub struct DesignData<'a> {
    setting: &'a Setting,
    ratios: Vec<f64>,
    /// The robot carrying the task's parts at this design; None without carried parts (the
    /// setting's dynamics then serve).
    carrying: Option<Dynamics>,
    /// G(r), its inverse, and the controls' map to joint and motor torques; G at the motion's
    /// start for a pose-dependent transmission, whose nodes hold their own.
    actuation: Actuation,
    /// The primal point evaluated last, kept where terms were added from outside the core
    /// (whose Jacobians read it); else empty.
    pub(super) point: Vec<f64>,
}

impl<'a> DesignData<'a> {
    /// The data of design `ratios`, whose actuation (at the motion's start) is `actuation`.
    pub(super) fn new(setting: &'a Setting, ratios: &[f64], actuation: Actuation) -> Self {
        let carried = setting.carried();
        DesignData {
            setting,
            ratios: ratios.to_vec(),
            carrying: (!carried.is_empty()).then(|| {
                setting
                    .dynamics()
                    .with_carried(&carried.mass_properties(ratios))
            }),
            actuation,
            point: Vec::new(),
        }
    }

    /// The formulation's setting.
    pub fn setting(&self) -> &'a Setting {
        self.setting
    }

    /// The design r.
    pub fn ratios(&self) -> &[f64] {
        &self.ratios
    }

    /// The robot's dynamics at this design: the setting's, carrying the task's parts at r
    /// where it has any (docs/model.md, section 18).
    pub fn dynamics(&self) -> &Dynamics {
        self.carrying.as_ref().unwrap_or(self.setting.dynamics())
    }

    /// d(RNEA(q, v, a))/dr_l through the carried parts' mass and inertia, N m; None where no
    /// part depends on r_l.
    pub fn rnea_design_derivative(
        &self,
        state: (&[f64], &[f64], &[f64]),
        l: usize,
    ) -> Option<Vec<f64>> {
        let parts = self.setting.carried().derivative(&self.ratios, l);
        if parts.is_empty() {
            return None;
        }
        let dynamics = self.setting.dynamics();
        let mut tau = vec![0.0; dynamics.dof()];
        dynamics.rnea_inertia_derivative(&mut dynamics.workspace(), state, &parts, &mut tau);
        Some(tau)
    }

    /// The primal point evaluated last, where terms were added from outside the core (else
    /// empty).
    pub(super) fn point(&self) -> &[f64] {
        &self.point
    }

    /// G(r) and its inverse at this design.
    pub fn coupling(&self) -> &Coupling {
        self.actuation.coupling()
    }

    /// The actuation at this design: the controls' map to joint and motor torques (at the
    /// motion's start for a pose-dependent transmission).
    pub fn actuation(&self) -> &Actuation {
        &self.actuation
    }

    /// The actuation at `node`: its own G(q_k) where the transmission depends on the pose,
    /// this design's otherwise.
    pub(super) fn actuation_of<'n>(&'n self, node: &'n NodeEval) -> &'n Actuation {
        node.pose
            .as_ref()
            .map_or(&self.actuation, |pose| &pose.actuation)
    }

    /// Each motor's angle at pose q, rad: gamma_i(q) for a linkage row, G_i q for a constant one.
    pub fn motor_angles(&self, q: &[f64]) -> Result<Vec<f64>, PoseError> {
        let s = self.setting;
        let mut data = s.dynamics().workspace();
        (s.transmission()).motor_angles(&self.ratios, (s.dynamics(), &mut data), q)
    }

    /// The box or linear rows that limit the joint speeds v in the formulation's speed mode, rad/s.
    pub fn speed_limits(&self) -> JointLimits {
        let s = self.setting;
        self.coupling()
            .speed_limits(s.modes().speed, s.motor_speed_limits())
    }

    /// The box or linear rows that limit the controls u: |u_i| <= motor i's torque limit in
    /// actuation space, the formulation's torque mode in joint space, N m.
    pub fn control_limits(&self) -> JointLimits {
        self.control_limits_with(self.coupling())
    }

    /// The same limits through `coupling`, G at some pose of a pose-dependent transmission.
    pub fn control_limits_with(&self, coupling: &Coupling) -> JointLimits {
        let s = self.setting;
        let limits = s.motor_torque_limits();
        match s.space() {
            Space::Actuation => JointLimits::Box {
                lower: limits.iter().map(|limit| -limit).collect(),
                upper: limits.to_vec(),
            },
            Space::Joint => coupling.torque_limits(s.modes().torque, limits),
        }
    }
}

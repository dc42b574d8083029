//! The formulations that shorten a free horizon (docs/model.md, section 6, "Shortening a free
//! horizon"): the fixed-horizon problem at a duration T, whose weights and Cartesian box shape
//! the trajectory the rule finds, and the free problem bounded above by T, started from it.

use super::error::FormulationError;
use super::formulation::{Formulation, Shaping};
use crate::model::task::{Horizon, LimitModes, Task};
use crate::model::Robot;
use crate::transmission::Space;

impl Formulation {
    /// The hard formulation of `task`'s pure minimum-time problem ([`Task::minimum_time`]) for
    /// `robot` in `space` with `modes`, its free horizon shortened through fixed-horizon
    /// problems with `task`'s own weights and box.
    pub fn minimum_time_of(
        task: &Task,
        robot: Robot,
        space: Space,
        modes: LimitModes,
    ) -> Result<Formulation, FormulationError> {
        Ok(Formulation::new(&task.minimum_time(), robot, space, modes)?.shaped_by(task))
    }

    /// The same formulation, its free horizon shortened through fixed-horizon problems shaped by
    /// `source`'s weights and box instead of its own (the pure minimum-time problem of
    /// `source`, `Task::minimum_time`).
    pub fn shaped_by(mut self, source: &Task) -> Formulation {
        self.shaping = Some(Shaping::of(source));
        self
    }

    /// The weights and box that shape the fixed-horizon problems shortening its free horizon:
    /// those it was [`Formulation::shaped_by`], else its task's own.
    pub fn shaping(&self) -> Shaping {
        (self.shaping.clone()).unwrap_or_else(|| Shaping::of(self.task()))
    }

    /// The fixed-horizon problem at `horizon_s`, s, with [`Formulation::shaping`]'s weights and
    /// box, in the hard kind: its trajectories start the free problem bounded above by
    /// `horizon_s` ([`Formulation::free_up_to`]).
    pub fn fixed_at(&self, horizon_s: f64) -> Result<Formulation, FormulationError> {
        let shaping = self.shaping();
        let mut task = self.task().clone();
        task.motion.horizon = Horizon::Fixed(horizon_s);
        task.weights = shaping.weights;
        task.cartesian_box = shaping.cartesian_box;
        let mut fixed = self.rebuilt(&task, self.dynamics().robot().clone())?;
        fixed.shaping = None;
        Ok(fixed.hard())
    }

    /// The same free-horizon formulation with T's range cut to [T_min, `max_s`]; None where the
    /// horizon is fixed or `max_s` is not above T_min.
    pub fn free_up_to(&self, max_s: f64) -> Result<Option<Formulation>, FormulationError> {
        let Horizon::Free { min_s, .. } = self.task().motion.horizon else {
            return Ok(None);
        };
        if max_s <= min_s {
            return Ok(None);
        }
        let mut task = self.task().clone();
        task.motion.horizon = Horizon::Free { min_s, max_s };
        self.rebuilt(&task, self.dynamics().robot().clone())
            .map(Some)
    }
}

//! The pure minimum-time problem of a task: its motion with a free horizon, J = T (docs/model.md,
//! section 6), what the cycle-time co-design solves for each design.

use super::ranges::{MAX_HORIZON_S, MIN_HORIZON_S};
use super::task::{CartesianBox, Horizon, Task, Weights};

/// The range of the free horizon of a task whose horizon is fixed at T, as multiples of T:
/// [0.3 T, 1.5 T] (the one place of this default). Its upper end starts the solve (the slowest
/// motion allowed, the one most likely within the limits): 1.2 s for the built-in task's 0.8 s.
pub const MINIMUM_TIME_RANGE: [f64; 2] = [0.3, 1.5];

impl Horizon {
    /// The free horizon of a minimum-time problem: a free horizon as it is, a fixed T freed to
    /// [`MINIMUM_TIME_RANGE`] times T, each end within the durations a task accepts.
    ///
    /// ```
    /// use codesign_core::model::task::Horizon;
    /// let free = Horizon::Fixed(0.8).minimum_time();
    /// assert_eq!(free, Horizon::Free { min_s: 0.3 * 0.8, max_s: 1.5 * 0.8 });
    /// assert_eq!(free.minimum_time(), free);
    /// ```
    pub fn minimum_time(self) -> Horizon {
        match self {
            Horizon::Fixed(seconds) => {
                let [low, high] = MINIMUM_TIME_RANGE
                    .map(|factor| (factor * seconds).clamp(MIN_HORIZON_S, MAX_HORIZON_S));
                // For any T a task accepts, low < high: 0.3 T < 1.5 T, 0.01 < 0.015, 1080 < 3600.
                Horizon::Free {
                    min_s: low,
                    max_s: high,
                }
            }
            free @ Horizon::Free { .. } => free,
        }
    }
}

impl Task {
    /// The task's pure minimum-time problem: its motion with the free horizon of
    /// [`Horizon::minimum_time`], w_T = 1 per s and every other weight 0, and no Cartesian box,
    /// so that J* = T*, s. Everything else (robot, payload, ends, motors, transmission, limit
    /// modes) is the task's own; applied twice it gives the same task.
    pub fn minimum_time(&self) -> Task {
        let mut task = self.clone();
        task.motion.horizon = task.motion.horizon.minimum_time();
        task.weights = Weights {
            position: 0.0,
            velocity: 0.0,
            control: 0.0,
            time: 1.0,
        };
        task.cartesian_box = CartesianBox::default();
        task
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_minimum_time_task_frees_the_horizon_and_weighs_time_alone() {
        let task = Task::built_in().unwrap();
        let pure = task.minimum_time();
        assert_eq!(
            pure.motion.horizon,
            Horizon::Free {
                min_s: 0.3 * 0.8,
                max_s: 1.5 * 0.8
            }
        );
        assert_eq!(pure.weights.time, 1.0);
        assert_eq!(pure.cartesian_box, CartesianBox::default());
        assert_eq!(pure.transmission, task.transmission);
        assert_eq!(pure.minimum_time(), pure);
        pure.validate().unwrap();
        let own = Horizon::Free {
            min_s: 0.4,
            max_s: 0.9,
        };
        assert_eq!(own.minimum_time(), own);
        for seconds in [MIN_HORIZON_S, MAX_HORIZON_S] {
            let Horizon::Free { min_s, max_s } = Horizon::Fixed(seconds).minimum_time() else {
                panic!("not free");
            };
            assert!(MIN_HORIZON_S <= min_s && min_s < max_s && max_s <= MAX_HORIZON_S);
        }
    }
}

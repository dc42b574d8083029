//! The memory one IPOPT solve of a formulation needs, estimated from its structural non-zeros
//! before its sparsity patterns are built, and the check that the machine has that memory.
//!
//! IPOPT with MUMPS keeps the KKT matrix, its factor (whose fill-in follows the banded
//! structure node after node) and several copies of the Jacobian and Hessian values; all scale
//! with the problem's non-zeros. Measured on the built-in arm (4 joints) and the UR5 example (6
//! joints) at 250 and 1000 steps (peak resident memory of `solve`, Debian's IPOPT 3.14 with
//! MUMPS): 396 to 411 bytes per non-zero of the hard problem, and 479 to 489 bytes per non-zero
//! of the hard problem for the elastic one (which adds slacks), above about 15 MiB.

use super::error::FormulationError;
use std::fmt;

/// Bytes one solve needs per structural non-zero of the hard problem's Jacobian and Hessian:
/// the elastic problem's measured 489, rounded up.
pub const BYTES_PER_NONZERO: u64 = 500;

/// Bytes a solve needs whatever its size: the process, IPOPT and MUMPS at a few steps.
pub const BASE_BYTES: u64 = 16 << 20;

/// The estimated memory of one solve of a formulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryNeed {
    /// Structural non-zeros of the Jacobian and the Hessian's lower triangle.
    pub nonzeros: u64,
    /// The estimate, bytes: [`BASE_BYTES`] + [`BYTES_PER_NONZERO`] per non-zero.
    pub bytes: u64,
}

impl MemoryNeed {
    /// The need of a solve whose Jacobian and Hessian have `nonzeros` structural non-zeros.
    pub(super) fn of(nonzeros: u64) -> MemoryNeed {
        MemoryNeed {
            nonzeros,
            bytes: BASE_BYTES.saturating_add(nonzeros.saturating_mul(BYTES_PER_NONZERO)),
        }
    }

    /// Refuses a need above `available` bytes (none: not known, nothing refused), naming the
    /// estimate, the task's steps and the robot's joints.
    pub fn check(
        &self,
        available: Option<u64>,
        steps: usize,
        joints: usize,
    ) -> Result<(), FormulationError> {
        match self.refusal(available, steps, joints) {
            Some(why) => Err(FormulationError(format!("task: {why}"))),
            None => Ok(()),
        }
    }

    /// Why a need above `available` bytes is refused, in the words of [`MemoryNeed::check`];
    /// none when it fits or `available` is not known.
    pub fn refusal(&self, available: Option<u64>, steps: usize, joints: usize) -> Option<String> {
        let available = available.filter(|&available| self.bytes > available)?;
        Some(format!(
            "motion.steps = {steps} with {joints} joints needs about {} for one solve \
             (estimated: {} structural non-zeros at {BYTES_PER_NONZERO} bytes each), but this \
             machine has {} available: use fewer steps (--steps) or a machine with more memory",
            Bytes(self.bytes),
            self.nonzeros,
            Bytes(available)
        ))
    }
}

/// The memory available to a new process, bytes: `MemAvailable` of /proc/meminfo (Linux),
/// none where that cannot be read.
pub fn available_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    mem_available(&text)
}

/// `MemAvailable` in the text of /proc/meminfo, bytes.
fn mem_available(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut words = line["MemAvailable:".len()..].split_whitespace();
    let kib: u64 = words.next()?.parse().ok()?;
    (words.next() == Some("kB")).then(|| kib.saturating_mul(1024))
}

/// A number of bytes in MiB or GiB, for messages.
struct Bytes(u64);

impl fmt::Display for Bytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const MIB: f64 = (1u64 << 20) as f64;
        let mib = self.0 as f64 / MIB;
        if mib < 1024.0 {
            write!(f, "{mib:.0} MiB")
        } else {
            write!(f, "{:.1} GiB", mib / 1024.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{mem_available, Bytes, MemoryNeed, BASE_BYTES, BYTES_PER_NONZERO};
    use crate::ipopt::Nlp;
    use crate::problem::Space;
    use crate::testing::formulation;

    #[test]
    fn the_need_counts_every_structural_nonzero() {
        let f = formulation(1.0, Space::Actuation);
        let need = f.memory_need();
        let problem = f.problem(&[6.0, 3.0, 1.0, 1.0]).unwrap();
        let jacobian = problem.jacobian_structure().len();
        let hessian = problem.hessian_structure().len();
        assert_eq!(need.nonzeros, (jacobian + hessian) as u64);
        assert_eq!(need.bytes, BASE_BYTES + need.nonzeros * BYTES_PER_NONZERO);
    }

    #[test]
    fn the_need_at_4000_steps_covers_what_a_solve_was_measured_to_take() {
        // Measured: `solve --space actuation --payload 1 --steps 4000` peaked at about 290 MB.
        let mut f = formulation(1.0, Space::Actuation);
        let mut task = f.task().clone();
        task.motion.steps = 4000;
        let robot = crate::model::Robot::load(&task).unwrap().with_payload(1.0);
        f = crate::problem::Formulation::new(&task, robot, Space::Actuation, *f.modes()).unwrap();
        let mib = f.memory_need().bytes as f64 / (1u64 << 20) as f64;
        assert!((280.0..400.0).contains(&mib), "{mib} MiB");
    }

    #[test]
    fn a_need_above_what_is_available_is_refused_naming_it() {
        let need = MemoryNeed {
            nonzeros: 82_000_000,
            bytes: 41 << 30,
        };
        assert!(need.check(None, 5000, 64).is_ok());
        assert!(need.check(Some(42 << 30), 5000, 64).is_ok());
        let message = need.check(Some(20 << 30), 5000, 64).unwrap_err().0;
        for part in [
            "motion.steps = 5000",
            "64 joints",
            "41.0 GiB",
            "82000000",
            "20.0 GiB available",
        ] {
            assert!(message.contains(part), "{part}: {message}");
        }
    }

    #[test]
    fn mem_available_is_read_in_bytes() {
        let text = "MemTotal:       24603856 kB\nMemFree:  1 kB\nMemAvailable:   20000000 kB\n";
        assert_eq!(mem_available(text), Some(20_000_000 * 1024));
        assert_eq!(mem_available("MemTotal: 5 kB\n"), None);
        assert_eq!(mem_available("MemAvailable: lots\n"), None);
        assert_eq!(Bytes(300 << 20).to_string(), "300 MiB");
        assert!(super::available_bytes().is_some_and(|b| b > 0));
    }
}

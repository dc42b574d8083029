//! A search over parts (`codesign parts`): every combination of a task's candidate motors
//! ([`PartsFamily`]) co-designed in its ratios by the gradient method, in order of increasing
//! motor mass, each run's document written to a file of its own in the output folder, and the
//! front of actuator mass against the objective ([`ParetoDocument`], `pareto.json`; its plot
//! is `report::pareto`'s). Enumeration instead of a mixed-integer search: a catalogue offers a
//! few motors per slot, and within a combination the exact dJ*/dr drives the ratios.

mod document;
mod pareto;
mod search;

pub use document::{
    check_front, check_front_file, Axes, Axis, ParetoDocument, ParetoInputs, PartsObjective,
    PartsPoint,
};
pub use pareto::{dominates, front, Better};
pub use search::{combination_files, run_parts, PartsError, PartsEvent, PartsSearch};

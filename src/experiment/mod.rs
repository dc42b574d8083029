//! The experiment of a task (docs/model.md, section 13) as library code: its [`Plan`] of
//! cases from a [`PlanRequest`], and the [`Layout`] of its results folder, which owns every
//! path and file name in it. `codesign reproduce` (`cli/reproduce/`) parses the request from
//! its flags, runs the plan's stages and merges their results through this layout.

mod layout;
mod plan;

pub use layout::{CapacityOf, Layout, RunName, FOLDERS, HOLD_FOLDER};
pub use plan::{Plan, PlanError, PlanRequest, PlannedRun, SPACES};

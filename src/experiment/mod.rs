//! The experiment of a task (docs/model.md, section 13) as library code: its [`Plan`] of
//! cases from a [`PlanRequest`], the [`Layout`] of its results folder, which owns every path
//! and file name in it, its task ([`ExperimentTask`]), its stages run here and told to an
//! [`Observer`] (`stages`), the merge of the results its printed commands wrote elsewhere
//! (`merge`), the table of a section (`finish`, [`run_experiment`]) and the folder's front page
//! (`index`, [`write_index`]). `codesign reproduce`
//! (`cli/reproduce/`) only parses the request from its flags, prints what it is told, and
//! words the errors with its flags.

mod error;
mod finish;
mod index;
mod layout;
mod merge;
mod plan;
mod stages;
mod summary;
mod task;

pub use error::{ExperimentError, MergeError};
pub use finish::{run_experiment, Section};
pub use index::{index_page, write_index};
pub use layout::{CapacityOf, Layout, RunName, FOLDERS, HOLD_FOLDER};
pub use plan::{Plan, PlanError, PlanRequest, PlannedRun, SPACES};
pub use stages::{Event, Observer, Outcomes};
pub use task::ExperimentTask;

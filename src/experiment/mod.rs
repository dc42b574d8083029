//! The experiment of a task (docs/model.md, section 13) as library code: today the [`Layout`]
//! of its results folder, which owns every path and file name in it. Its plan, stages and merge
//! are run by `codesign reproduce` (`cli/reproduce/`) through this layout.

mod layout;

pub use layout::{CapacityOf, Layout, RunName, FOLDERS, HOLD_FOLDER};

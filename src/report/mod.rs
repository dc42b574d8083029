//! Reports: result files written atomically, SVG plots, and the documents of each command.

pub mod files;
pub mod plots;
pub mod trajectory;

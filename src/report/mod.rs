//! Reports: result files written atomically, SVG plots, and the documents of each command.

pub mod codesign;
pub mod files;
pub mod plots;
pub mod table;
pub mod trajectory;

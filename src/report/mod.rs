//! Reports: SVG plots, the paper table, and the documents of each command (written through
//! [`crate::store`]).

pub mod codesign;
pub mod plots;
pub mod table;
pub mod trajectory;

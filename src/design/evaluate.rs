//! The objective and the evaluation record at their former path; they live in [`super::score`].
//! Kept until `design::log`, `cli::case` and `report::codesign`, being moved elsewhere, import
//! them from there.

pub use super::score::{Evaluation, Objective, PayloadRange};

//! Solving the trajectory problem of one design and reading the result.
//!
//! [`solve_design`] runs IPOPT on a [`TrajectoryProblem`](crate::problem::TrajectoryProblem)
//! with the [`SolveSettings`] the command or worker was given, under the one rule of
//! feasibility (`certify`: no design is infeasible while some start finds a feasible
//! trajectory), and returns a
//! [`TrajectoryResult`]: status, feasibility, cost, timing, the trajectory with joint and motor
//! torques and the TCP path, and the largest violation of each constraint family. [`solve_elastic`]
//! solves the elastic kind of the same problem (docs/model.md, section 14), which always has a
//! solution, and reports how much torque and speed the design lacks.
//!
//! The modules: `settings` (IPOPT's settings, read from a task file's `solver` section), `run`
//! (one IPOPT solve), `certify` (the rule, over several solves), `continuation` (its payload
//! continuation), `shorten` (a free horizon shortened by the fixed-horizon rule), `result` (the result and its file schema), `trajectory` (the solution node by
//! node), `figures` (its physical figures), `readback` (a primal point read back as a
//! trajectory), `result_checks` (whether it judges its design and holds finite numbers only),
//! `verify` (the constraint residuals evaluated again on the trajectory), `keyed` (their
//! largest values, keyed by family), `dead_points` (a linkage's dead point crossed between two
//! nodes), `execute` (whether the motors can execute it), `start` (a solve's raw solution kept
//! to warm-start another solve from,
//! [`StartPoint`], with the checks that it fits), `error`.

mod certify;
mod continuation;
mod dead_points;
mod error;
mod execute;
mod figures;
mod keyed;
mod readback;
mod result;
mod result_checks;
mod run;
mod settings;
mod shorten;
mod start;
mod trajectory;
mod verify;

pub use crate::problem::CostTerms;
pub use certify::{solve_design, solve_design_along, solve_design_from, solve_elastic};
pub use continuation::{PayloadChain, CONTINUATION_STEP_KG};
pub use dead_points::{dead_points, DeadPoint};
pub use error::SolveError;
pub use execute::MotorsExecute;
pub use figures::{MotorFigures, PhysicalFigures};
pub use keyed::{Keyed, Violations};
pub use result::{ElasticMeasures, SolveSeconds, ToolInfo, TrajectoryResult, VerdictBy};
pub use run::WARM_MAX_ITER;
pub use settings::{
    FreeHorizonSearch, SettingsError, SolveSettings, TaskRecord, DEFAULT_MAX_ITER, DEFAULT_TOL,
};
pub use shorten::MAX_SHORTENING_ROUNDS;
pub use start::{StartError, StartPart, StartPoint};
pub use trajectory::Trajectory;
pub use verify::{envelope_margins, least_envelope_margin, EnvelopeMargin};

#[cfg(test)]
mod carried_tests;
#[cfg(test)]
mod certify_tests;
#[cfg(test)]
mod envelope_tests;
#[cfg(test)]
mod linkage_tests;
#[cfg(test)]
mod loss_tests;
#[cfg(test)]
mod minimum_time_tests;
#[cfg(test)]
mod parts_tests;
#[cfg(test)]
mod prismatic_tests;
#[cfg(test)]
mod tests;

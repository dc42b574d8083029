//! IPOPT's return codes as a Rust enum.

use ipopt_sys::ApplicationReturnStatus as raw;
use std::fmt;

/// The outcome IPOPT reports for a solve: one variant per `ApplicationReturnStatus` code of the
/// C interface. [`Status::name`] gives IPOPT's own spelling, used in every result file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// Optimal to the requested tolerance (`tol`).
    SolveSucceeded,
    /// Optimal to the looser "acceptable" tolerances.
    SolvedToAcceptableLevel,
    /// The restoration phase converged to a point of locally minimal infeasibility.
    InfeasibleProblemDetected,
    /// The search direction fell below machine precision relative to the iterate.
    SearchDirectionBecomesTooSmall,
    /// The iterates grew without bound.
    DivergingIterates,
    /// A callback asked IPOPT to stop.
    UserRequestedStop,
    /// A feasible point was found (only with `start_with_resto`-style feasibility problems).
    FeasiblePointFound,
    /// `max_iter` was reached.
    MaximumIterationsExceeded,
    /// The restoration phase failed to find a less infeasible point.
    RestorationFailed,
    /// The linear system of the step could not be solved.
    ErrorInStepComputation,
    /// `max_cpu_time` was reached.
    MaximumCpuTimeExceeded,
    /// Fewer variables than equality constraints.
    NotEnoughDegreesOfFreedom,
    /// Inconsistent bounds or sizes.
    InvalidProblemDefinition,
    /// An option value was rejected when the solve started.
    InvalidOption,
    /// A callback returned NaN or infinity.
    InvalidNumberDetected,
    /// IPOPT caught one of its own exceptions it could not recover from.
    UnrecoverableException,
    /// IPOPT caught an exception of foreign origin.
    NonIpoptExceptionThrown,
    /// Memory ran out.
    InsufficientMemory,
    /// An internal error of IPOPT.
    InternalError,
    /// A code this binding does not know (a newer IPOPT); carries the raw value.
    Unknown(i32),
}

impl Status {
    /// IPOPT's own name for the status, e.g. `Solve_Succeeded`.
    pub fn name(self) -> String {
        let name = match self {
            Status::SolveSucceeded => "Solve_Succeeded",
            Status::SolvedToAcceptableLevel => "Solved_To_Acceptable_Level",
            Status::InfeasibleProblemDetected => "Infeasible_Problem_Detected",
            Status::SearchDirectionBecomesTooSmall => "Search_Direction_Becomes_Too_Small",
            Status::DivergingIterates => "Diverging_Iterates",
            Status::UserRequestedStop => "User_Requested_Stop",
            Status::FeasiblePointFound => "Feasible_Point_Found",
            Status::MaximumIterationsExceeded => "Maximum_Iterations_Exceeded",
            Status::RestorationFailed => "Restoration_Failed",
            Status::ErrorInStepComputation => "Error_In_Step_Computation",
            Status::MaximumCpuTimeExceeded => "Maximum_CpuTime_Exceeded",
            Status::NotEnoughDegreesOfFreedom => "Not_Enough_Degrees_Of_Freedom",
            Status::InvalidProblemDefinition => "Invalid_Problem_Definition",
            Status::InvalidOption => "Invalid_Option",
            Status::InvalidNumberDetected => "Invalid_Number_Detected",
            Status::UnrecoverableException => "Unrecoverable_Exception",
            Status::NonIpoptExceptionThrown => "NonIpopt_Exception_Thrown",
            Status::InsufficientMemory => "Insufficient_Memory",
            Status::InternalError => "Internal_Error",
            Status::Unknown(code) => return format!("Unknown_Status_{code}"),
        };
        name.to_owned()
    }

    /// Every status but [`Status::Unknown`].
    const KNOWN: [Status; 19] = [
        Status::SolveSucceeded,
        Status::SolvedToAcceptableLevel,
        Status::InfeasibleProblemDetected,
        Status::SearchDirectionBecomesTooSmall,
        Status::DivergingIterates,
        Status::UserRequestedStop,
        Status::FeasiblePointFound,
        Status::MaximumIterationsExceeded,
        Status::RestorationFailed,
        Status::ErrorInStepComputation,
        Status::MaximumCpuTimeExceeded,
        Status::NotEnoughDegreesOfFreedom,
        Status::InvalidProblemDefinition,
        Status::InvalidOption,
        Status::InvalidNumberDetected,
        Status::UnrecoverableException,
        Status::NonIpoptExceptionThrown,
        Status::InsufficientMemory,
        Status::InternalError,
    ];

    /// The status named `text` ([`Status::name`], an unknown code's `Unknown_Status_N`
    /// included), if any: the inverse of [`Status::name`].
    pub fn from_name(text: &str) -> Option<Status> {
        let unknown = text
            .strip_prefix("Unknown_Status_")
            .and_then(|code| code.parse::<i32>().ok())
            .map(Status::Unknown)
            .filter(|status| status.name() == text);
        unknown.or_else(|| Status::KNOWN.into_iter().find(|s| s.name() == text))
    }

    /// Whether `text` is the name of a status IPOPT returns ([`Status::name`], an unknown code's
    /// `Unknown_Status_N` included).
    pub fn is_name(text: &str) -> bool {
        Status::from_name(text).is_some()
    }

    /// Whether the point returned is a local optimum (to the strict or the acceptable tolerance).
    pub fn is_success(self) -> bool {
        matches!(
            self,
            Status::SolveSucceeded | Status::SolvedToAcceptableLevel
        )
    }

    /// Maps the integer code `IpoptSolve` returned (a C enum, so any value is possible).
    pub(crate) fn from_code(code: raw::Type) -> Status {
        match code {
            raw::Solve_Succeeded => Status::SolveSucceeded,
            raw::Solved_To_Acceptable_Level => Status::SolvedToAcceptableLevel,
            raw::Infeasible_Problem_Detected => Status::InfeasibleProblemDetected,
            raw::Search_Direction_Becomes_Too_Small => Status::SearchDirectionBecomesTooSmall,
            raw::Diverging_Iterates => Status::DivergingIterates,
            raw::User_Requested_Stop => Status::UserRequestedStop,
            raw::Feasible_Point_Found => Status::FeasiblePointFound,
            raw::Maximum_Iterations_Exceeded => Status::MaximumIterationsExceeded,
            raw::Restoration_Failed => Status::RestorationFailed,
            raw::Error_In_Step_Computation => Status::ErrorInStepComputation,
            raw::Maximum_CpuTime_Exceeded => Status::MaximumCpuTimeExceeded,
            raw::Not_Enough_Degrees_Of_Freedom => Status::NotEnoughDegreesOfFreedom,
            raw::Invalid_Problem_Definition => Status::InvalidProblemDefinition,
            raw::Invalid_Option => Status::InvalidOption,
            raw::Invalid_Number_Detected => Status::InvalidNumberDetected,
            raw::Unrecoverable_Exception => Status::UnrecoverableException,
            raw::NonIpopt_Exception_Thrown => Status::NonIpoptExceptionThrown,
            raw::Insufficient_Memory => Status::InsufficientMemory,
            raw::Internal_Error => Status::InternalError,
            other => Status::Unknown(other),
        }
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_ipopt_spelling() {
        assert_eq!(
            Status::from_code(raw::Solve_Succeeded).name(),
            "Solve_Succeeded"
        );
        assert_eq!(
            Status::from_code(raw::Infeasible_Problem_Detected).name(),
            "Infeasible_Problem_Detected"
        );
        assert_eq!(
            Status::from_code(raw::Internal_Error).to_string(),
            "Internal_Error"
        );
        assert!(Status::SolvedToAcceptableLevel.is_success());
        for status in Status::KNOWN.into_iter().chain([Status::Unknown(-7)]) {
            assert_eq!(Status::from_name(&status.name()), Some(status));
        }
        assert_eq!(Status::from_name("Unknown_Status_+7"), None);
        assert_eq!(Status::from_name("solve_succeeded"), None);
        assert!(!Status::RestorationFailed.is_success());
    }
}

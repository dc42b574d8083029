//! The record of one evaluation, as the evaluation log and the worker protocol write it: where a
//! [`Score`] becomes JSON. Its status texts are IPOPT's return status names or the fixed texts
//! below; committed logs hold them, so they never change.

use super::Score;
use crate::design::penalty::Penalty;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// The outcome of evaluating one design, as logged and as the optimiser sees it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// The design r.
    pub ratios: Vec<f64>,
    /// The fitness: the objective's value when the design is valid and feasible, else the
    /// penalty.
    pub cost: f64,
    /// Whether the design is valid and its trajectory problem was solved.
    pub feasible: bool,
    /// What decided it.
    pub status: Status,
    /// IPOPT iterations (0 when no solve ran).
    pub iterations: usize,
    /// Wall time of the solves, s.
    pub seconds: f64,
    /// Why the design was penalised.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

impl Evaluation {
    /// The record of `score`, the score of design `ratios`, its fitness under `penalty`.
    pub fn new(ratios: &[f64], score: &Score, penalty: &Penalty) -> Evaluation {
        let verdict = &score.verdict;
        Evaluation {
            ratios: ratios.to_vec(),
            cost: verdict.fitness(penalty),
            feasible: verdict.is_feasible(),
            status: verdict.status(),
            iterations: score.iterations,
            seconds: score.seconds,
            reason: verdict.reason().map(str::to_owned),
        }
    }
}

/// What decided an evaluation; written as a status text (`Solve_Succeeded`, `Invalid_Design`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Status {
    /// The design was valid and solved.
    Solved(SolveStatus),
    /// `Invalid_Design`: the design is outside the design space.
    InvalidDesign,
    /// `Solver_Error`: IPOPT could not run.
    SolverError,
    /// `Worker_Failed`: the worker evaluating it failed twice.
    WorkerFailed,
}

impl Status {
    /// Whether the design was judged: false for a solver error or a failed worker, whose
    /// penalty says nothing about the design.
    pub fn is_judged(&self) -> bool {
        !matches!(self, Status::SolverError | Status::WorkerFailed)
    }
}

/// What the solves of a valid design said.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SolveStatus {
    /// IPOPT's name for the return status of the deciding solve, e.g. `Solve_Succeeded`.
    Ipopt(String),
    /// `Elastic_Deficit`: an elastic solve found the design short of torque or speed.
    ElasticDeficit,
    /// `Capacity_N_Probes`: a capacity search of `probes` solves found a capacity.
    Capacity {
        /// The solves of the search.
        probes: usize,
    },
    /// `Infeasible_Unloaded`: the capacity search found the design infeasible at 0 kg.
    InfeasibleUnloaded,
    /// `Static_Hold_Failed`: the motors cannot hold the load at rest at an end (at some payload),
    /// so the design is infeasible whatever a solve would say, and nothing was solved.
    StaticHoldFailed,
}

const INVALID_DESIGN: &str = "Invalid_Design";
const SOLVER_ERROR: &str = "Solver_Error";
const WORKER_FAILED: &str = "Worker_Failed";
const ELASTIC_DEFICIT: &str = "Elastic_Deficit";
const INFEASIBLE_UNLOADED: &str = "Infeasible_Unloaded";
const STATIC_HOLD_FAILED: &str = "Static_Hold_Failed";

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Status::Solved(SolveStatus::Ipopt(name)) => f.write_str(name),
            Status::Solved(SolveStatus::ElasticDeficit) => f.write_str(ELASTIC_DEFICIT),
            Status::Solved(SolveStatus::Capacity { probes }) => {
                write!(f, "Capacity_{probes}_Probes")
            }
            Status::Solved(SolveStatus::InfeasibleUnloaded) => f.write_str(INFEASIBLE_UNLOADED),
            Status::Solved(SolveStatus::StaticHoldFailed) => f.write_str(STATIC_HOLD_FAILED),
            Status::InvalidDesign => f.write_str(INVALID_DESIGN),
            Status::SolverError => f.write_str(SOLVER_ERROR),
            Status::WorkerFailed => f.write_str(WORKER_FAILED),
        }
    }
}

impl From<&str> for Status {
    /// Reads a status text; every text is one (those not named here are IPOPT's), and writing it
    /// again gives the same text.
    fn from(text: &str) -> Status {
        let probes = text
            .strip_prefix("Capacity_")
            .and_then(|rest| rest.strip_suffix("_Probes"))
            .and_then(|digits| {
                digits
                    .parse::<usize>()
                    .ok()
                    .filter(|n| n.to_string() == digits)
            });
        match (text, probes) {
            (_, Some(probes)) => Status::Solved(SolveStatus::Capacity { probes }),
            (INVALID_DESIGN, _) => Status::InvalidDesign,
            (SOLVER_ERROR, _) => Status::SolverError,
            (WORKER_FAILED, _) => Status::WorkerFailed,
            (ELASTIC_DEFICIT, _) => Status::Solved(SolveStatus::ElasticDeficit),
            (INFEASIBLE_UNLOADED, _) => Status::Solved(SolveStatus::InfeasibleUnloaded),
            (STATIC_HOLD_FAILED, _) => Status::Solved(SolveStatus::StaticHoldFailed),
            (name, None) => Status::Solved(SolveStatus::Ipopt(name.to_owned())),
        }
    }
}

impl Serialize for Status {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.to_string())
    }
}

impl<'de> Deserialize<'de> for Status {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Status, D::Error> {
        String::deserialize(deserializer).map(|text| Status::from(text.as_str()))
    }
}

//! The worker protocol, one JSON object a line: the parent sends a [`WorkerSetup`], the worker
//! answers with its [`Hello`], then each [`Request`] gets one [`Response`].

use super::WorkerError;
use crate::design::penalty::Penalty;
use crate::design::score::{Evaluation, Fitness, Objective, ScoreError};
use crate::ipopt::{LinearSolver, IPOPT_VERSION};
use crate::model::task::{LimitModes, Task};
use crate::problem::Space;
use crate::solve::SolveSettings;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::io::{BufRead, Write};

/// Everything a worker needs to build its [`Formulation`], sent as its first line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorkerSetup {
    /// The task with every override applied (its robot path absolute or relative to the
    /// worker's working directory, which is the parent's; none for the built-in robot).
    pub task: Task,
    /// IPOPT's settings of the solves (the worker's IPOPT log stays silent).
    pub solve: SolveSettings,
    /// Joint or actuation space.
    pub space: Space,
    /// Limit modes.
    pub modes: LimitModes,
    /// How invalid or infeasible designs are scored.
    pub penalty: Penalty,
    /// What the fitness is.
    #[serde(default)]
    pub objective: Objective,
}

impl WorkerSetup {
    /// Builds the fitness this setup describes.
    pub fn fitness(&self) -> Result<Fitness, ScoreError> {
        Fitness::new(
            &self.task,
            &self.solve,
            self.space,
            self.modes,
            &self.objective,
            self.penalty,
        )
    }
}

/// What a worker says first: its build and the setup it understood. A worker whose hello differs
/// from its parent's is refused, since results of mixed builds must never be merged.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Hello {
    /// The worker's codesign version.
    pub codesign: String,
    /// The IPOPT version it is linked with.
    pub ipopt: String,
    /// The linear solver its solves use.
    pub linear_solver: LinearSolver,
    /// FNV-1a (64 bit, hex) of the setup as the worker re-serialises it: equal exactly when
    /// both sides read the same task, space, limit modes, penalty and objective.
    pub setup_hash: String,
}

impl Hello {
    /// The hello of this build for `setup`.
    pub fn new(setup: &WorkerSetup) -> Result<Hello, WorkerError> {
        let text = serde_json::to_string(setup).map_err(WorkerError::EncodeSetup)?;
        let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |hash, byte| {
            (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3)
        });
        Ok(Hello {
            codesign: env!("CARGO_PKG_VERSION").to_owned(),
            ipopt: IPOPT_VERSION.to_owned(),
            linear_solver: setup.solve.linear_solver(),
            setup_hash: format!("{hash:016x}"),
        })
    }
}

impl fmt::Display for Hello {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "codesign {} with IPOPT {}, linear solver {}, setup {}",
            self.codesign,
            self.ipopt,
            self.linear_solver.name(),
            self.setup_hash
        )
    }
}

/// One design to evaluate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Request {
    /// The caller's identifier, echoed back.
    pub id: usize,
    /// The design r.
    pub ratios: Vec<f64>,
}

/// The evaluation of one request.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Response {
    /// The request's identifier.
    pub id: usize,
    /// Its evaluation.
    pub evaluation: Evaluation,
}

/// The worker's side: reads the setup and requests from `input`, writes responses to `output`,
/// until `input` ends or the parent stops reading (a closed pipe ends it quietly). Errors (a
/// malformed line, an unbuildable formulation) end the worker.
pub fn serve(input: impl BufRead, mut output: impl Write) -> Result<(), WorkerError> {
    let mut lines = input.lines();
    let setup_line = match lines.next() {
        Some(line) => line.map_err(WorkerError::ReadSetup)?,
        None => return Ok(()),
    };
    let setup: WorkerSetup =
        serde_json::from_str(&setup_line).map_err(WorkerError::MalformedSetup)?;
    let fitness = setup.fitness()?;
    let hello = serde_json::to_string(&Hello::new(&setup)?).map_err(WorkerError::EncodeAnswer)?;
    if !answer(&mut output, &hello)? {
        return Ok(());
    }
    for line in lines {
        let line = line.map_err(WorkerError::ReadRequest)?;
        let request: Request =
            serde_json::from_str(&line).map_err(WorkerError::MalformedRequest)?;
        let response = Response {
            id: request.id,
            evaluation: fitness.evaluate(&request.ratios),
        };
        let text = serde_json::to_string(&response).map_err(WorkerError::EncodeAnswer)?;
        if !answer(&mut output, &text)? {
            return Ok(());
        }
    }
    Ok(())
}

/// Writes one line to the parent; false when the parent is gone (it finished, failed or was
/// stopped: nobody to answer).
fn answer(output: &mut impl Write, line: &str) -> Result<bool, WorkerError> {
    match writeln!(output, "{line}").and_then(|()| output.flush()) {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(false),
        Err(e) => Err(WorkerError::Answer(e)),
    }
}

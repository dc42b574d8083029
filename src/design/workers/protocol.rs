//! The worker protocol, one JSON object a line: the parent sends a [`WorkerSetup`], the worker
//! answers with its [`Hello`], then each [`Request`] gets one [`Response`].

use super::WorkerError;
use crate::design::penalty::Penalty;
use crate::design::score::{Evaluation, Fitness, Merit, Objective, ScoreError};
use codesign_core::hash::fnv1a;
use codesign_core::ipopt::{LinearSolver, Solution, IPOPT_VERSION};
use codesign_core::model::task::{LimitModes, Task};
use codesign_core::model::Robot;
use codesign_core::problem::Space;
use codesign_core::solve::{SolveSettings, StartPoint};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::io::{self, BufRead, Read, Write};

/// The longest line of the protocol, bytes: a setup is a few kB, an answer a few hundred bytes,
/// a descent's start and merit a few hundred kB (x, lambda and z of one solve).
pub const MAX_LINE_BYTES: usize = 16 << 20;

/// Reads one line of the protocol, without its end, at most [`MAX_LINE_BYTES`] long (a longer
/// one is an error, not a reason to fill the memory); None at the end of the input.
pub fn read_line(input: &mut impl BufRead) -> io::Result<Option<String>> {
    let mut line = Vec::new();
    let limit = MAX_LINE_BYTES as u64 + 1;
    if input.by_ref().take(limit).read_until(b'\n', &mut line)? == 0 {
        return Ok(None);
    }
    if line.last() == Some(&b'\n') {
        line.pop();
    } else if line.len() > MAX_LINE_BYTES {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "a line longer than {} MiB: not the worker protocol",
                MAX_LINE_BYTES >> 20
            ),
        ));
    }
    String::from_utf8(line)
        .map(Some)
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidData, "a line that is not UTF-8"))
}

/// Everything a worker needs to build its [`Formulation`](codesign_core::problem::Formulation), sent as
/// its first line.
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
    /// FNV-1a of the robot's URDF text as the parent read it (`Robot::urdf_hash`).
    pub robot_hash: String,
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
    /// FNV-1a of the robot's URDF text as the worker read it: equal to the setup's
    /// `robot_hash` exactly when both sides read the same robot file.
    pub robot_hash: String,
}

impl Hello {
    /// The hello of this build for `setup`, having read a robot of `robot_hash` (the parent
    /// expects the setup's own).
    pub fn new(setup: &WorkerSetup, robot_hash: &str) -> Result<Hello, WorkerError> {
        let text = serde_json::to_string(setup).map_err(WorkerError::EncodeSetup)?;
        Ok(Hello {
            codesign: env!("CARGO_PKG_VERSION").to_owned(),
            ipopt: IPOPT_VERSION.to_owned(),
            linear_solver: setup.solve.linear_solver(),
            setup_hash: fnv1a(text.as_bytes()),
            robot_hash: robot_hash.to_owned(),
        })
    }

    /// The hello the parent expects of every worker for `setup`.
    pub fn expected(setup: &WorkerSetup) -> Result<Hello, WorkerError> {
        Hello::new(setup, &setup.robot_hash)
    }
}

impl fmt::Display for Hello {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "codesign {} with IPOPT {}, linear solver {}, setup {}, robot {}",
            self.codesign,
            self.ipopt,
            self.linear_solver.name(),
            self.setup_hash,
            self.robot_hash
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
    /// The design whose solution the solve starts from (the generation's CMA-ES mean in the
    /// design space): the worker solves it once, from the standard guess, and keeps its solution
    /// for every request with the same anchor. None: the standard guess.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub anchor: Option<Vec<f64>>,
    /// Set when the gradient method asks: the design is scored for a descent
    /// (`Fitness::descend_from`), from this start rather than the anchor's, and answered with
    /// its merit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub descent: Option<DescentRequest>,
}

/// What a request of the gradient method adds (see [`Request::descent`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DescentRequest {
    /// The solutions the design's solves start from (a nearby design's merit's, one per problem
    /// its merit is made of); none: the standard guess.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub starts: Vec<StartPoint>,
}

/// A worker's solution of the last anchor it was sent (see [`Request::anchor`]).
struct Anchored {
    anchor: Vec<f64>,
    /// None when the anchor is invalid or infeasible: its designs start from the standard guess.
    solution: Option<Solution>,
}

impl Anchored {
    /// The warm start of `request`: the solution of its anchor, solved by `fitness` when the
    /// anchor changed (each worker solves the same anchor to the same bits, so the evaluations do
    /// not depend on which worker took a design).
    fn warm_start<'a>(
        cached: &'a mut Option<Anchored>,
        fitness: &Fitness,
        request: &Request,
    ) -> Option<&'a Solution> {
        let anchor = request.anchor.as_ref()?;
        if cached.as_ref().is_none_or(|c| c.anchor != *anchor) {
            *cached = Some(Anchored {
                anchor: anchor.clone(),
                solution: fitness.anchor(anchor),
            });
        }
        cached.as_ref()?.solution.as_ref()
    }
}

/// The evaluation of one request.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Response {
    /// The request's identifier.
    pub id: usize,
    /// Its evaluation.
    pub evaluation: Evaluation,
    /// Its merit, for a request of the gradient method whose design has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub merit: Option<Box<Merit>>,
}

/// The worker's side: reads the setup and requests from `input`, writes responses to `output`,
/// until `input` ends or the parent stops reading (a closed pipe ends it quietly). Errors (a
/// malformed line, an unbuildable formulation) end the worker.
pub fn serve(mut input: impl BufRead, mut output: impl Write) -> Result<(), WorkerError> {
    let Some(setup_line) = read_line(&mut input).map_err(WorkerError::ReadSetup)? else {
        return Ok(());
    };
    let setup: WorkerSetup =
        serde_json::from_str(&setup_line).map_err(WorkerError::MalformedSetup)?;
    let fitness = setup.fitness()?;
    let robot = Robot::load(&setup.task).map_err(WorkerError::Robot)?;
    let hello = Hello::new(&setup, robot.urdf_hash())?;
    let hello = serde_json::to_string(&hello).map_err(WorkerError::EncodeAnswer)?;
    if !answer(&mut output, &hello)? {
        return Ok(());
    }
    let mut anchored = None;
    while let Some(line) = read_line(&mut input).map_err(WorkerError::ReadRequest)? {
        let request: Request =
            serde_json::from_str(&line).map_err(WorkerError::MalformedRequest)?;
        let response = match &request.descent {
            Some(descent) => {
                let scored = fitness.descend_from(&request.ratios, &descent.starts);
                Response {
                    id: request.id,
                    evaluation: scored.evaluation,
                    merit: scored.merit.map(Box::new),
                }
            }
            None => {
                let warm = Anchored::warm_start(&mut anchored, &fitness, &request);
                Response {
                    id: request.id,
                    evaluation: fitness.evaluate_from(&request.ratios, warm),
                    merit: None,
                }
            }
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

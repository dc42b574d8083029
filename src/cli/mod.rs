//! The command line: one subcommand per module, each a thin layer over the library.

/// Prints on stdout like `println!`, but a failed write (a closed pipe, a full disk) is not a
/// reason to panic: it is remembered, the command goes on to write its files, and it then
/// exits non-zero (see [`stdout_failure`]).
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::cli::print_out(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` with the same handling of a failed write as [`say!`].
macro_rules! say_raw {
    ($($arg:tt)*) => {
        $crate::cli::print_out(format_args!($($arg)*))
    };
}

/// The first error writing stdout, if any.
static STDOUT_ERROR: Mutex<Option<(ErrorKind, String)>> = Mutex::new(None);

/// Writes `text` on stdout, remembering the first failure.
pub(crate) fn print_out(text: std::fmt::Arguments<'_>) {
    if let Err(error) = write_stdout(text) {
        remember_stdout_error(&error);
    }
}

/// Whether the process started with stdout closed (`>&-`), as the binary saw it.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes `text` on stdout. Rust's runtime puts /dev/null where stdout was closed (`>&-`);
/// here writing there fails, so that output nobody can read is an error like output a full
/// disk refused.
fn write_stdout(text: std::fmt::Arguments<'_>) -> std::io::Result<()> {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return Err(std::io::Error::other("stdout is closed"));
    }
    std::io::stdout().lock().write_fmt(text)
}

fn remember_stdout_error(error: &std::io::Error) {
    let mut first = STDOUT_ERROR.lock().unwrap_or_else(|p| p.into_inner());
    first.get_or_insert_with(|| (error.kind(), error.to_string()));
}

/// Flushes stdout and returns the first failure to write it, if there was one. A closed pipe
/// (`codesign ... | head -1`) is none: the reader chose to stop, as with most Unix tools.
fn stdout_failure() -> Option<String> {
    if let Err(error) = std::io::stdout().lock().flush() {
        remember_stdout_error(&error);
    }
    let first = STDOUT_ERROR.lock().unwrap_or_else(|p| p.into_inner());
    match &*first {
        Some((ErrorKind::BrokenPipe, _)) | None => None,
        Some((_, message)) => Some(message.clone()),
    }
}

mod capacity;
mod check;
mod choice;
mod common;
mod doctor;
mod dynamics;
mod export;
mod failure;
mod migrate;
mod optimize;
mod parts;
mod progress;
mod reproduce;
mod run_flags;
mod solve;
mod solve_args;
mod solve_motions;
mod solve_summary;
mod store_hints;
mod table;
mod task;
mod time_curve;
mod tradeoff;
mod tradeoff_args;
mod worker;

use clap::{Parser, Subcommand};
use failure::Failure;
use std::io::{ErrorKind, Write};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// Co-design of gear ratios and motion for robots with parallel (belt) transmissions.
#[derive(Debug, Parser)]
#[command(name = "codesign", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Check the installation: IPOPT version, a solve of HS071, IPOPT's derivative checker.
    Doctor(doctor::Args),
    /// Inspect a robot and its task before solving: the chain, G, the static torques at the
    /// start and the goal, the design space, and a verdict per check (exit 1 on any problem).
    Check(check::Args),
    /// Evaluate the robot's dynamics and TCP kinematics, with derivatives, at one state (JSON).
    Dynamics(dynamics::Args),
    /// Solve the trajectory problem of one design and report cost, feasibility and trajectory.
    Solve(solve_args::Args),
    /// The largest payload a design can move through the task (bracketing and bisection).
    Capacity(capacity::Args),
    /// A design's payload capacity against the duration of its motion: the capacity within each
    /// of several durations, as JSON with its plot.
    Tradeoff(tradeoff_args::Args),
    /// Co-design: search the gear ratios with CMA-ES, solving each design in worker processes.
    Optimize(optimize::Args),
    /// Co-design every combination of a task's candidate parts (motors.parts[i].candidates) in
    /// its ratios with the gradient method, and write the front of actuator mass against the
    /// objective (pareto.json, pareto.svg).
    Parts(parts::Args),
    /// Run the task's experiment, by default the paper's (and more): original designs, co-design, capacities, table, plots.
    Reproduce(reproduce::Args),
    /// Rebuild the table from result files of `solve`, `optimize` and `capacity` of one task.
    Table(table::Args),
    /// Bring result files, tables and evaluation logs of older versions of codesign to this
    /// version, in place (the original kept as NAME.orig); a current file is left untouched.
    Migrate(migrate::Args),
    /// Print the built-in task (JSON), a starting point for one's own: `codesign task > my.json`.
    ///
    /// Every command uses the built-in task and robot unless given `--task FILE` (and
    /// `--robot URDF`). The `robot` path in a task file is relative to the file's folder: the
    /// printed task's `../belt_arm.urdf` names the repository's `robots/belt_arm.urdf` from
    /// `robots/tasks/`. In a task of one's own, set `robot` to the path of a URDF relative to the
    /// task file (e.g. `belt_arm.urdf` beside it, written by `codesign task --urdf >
    /// belt_arm.urdf`), or remove the line to use the built-in robot, or pass `--robot URDF`.
    Task(task::Args),
    /// Evaluate designs sent on stdin (the worker process of `optimize`; not for direct use).
    #[command(hide = true)]
    Worker,
}

/// Parses the command line, runs the subcommand, prints any error on stderr and returns the
/// process exit code (0 on success, 1 on any error, a failed write on stdout included, 2 on a
/// usage error: clap's, or a flag's value out of its range, [`Failure::Usage`], 3 for an
/// infeasible design under `solve --fail-if-infeasible`, [`Failure::Infeasible`]).
/// `stdout_closed`: the process started with its stdout closed.
pub fn main(stdout_closed: bool) -> ExitCode {
    STDOUT_CLOSED.store(stdout_closed, Ordering::Relaxed);
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => return parse_failure(&error),
    };
    // A worker answers on stdout itself and ends quietly when its parent stops reading.
    let answers_itself = matches!(cli.command, Command::Worker);
    let outcome = match cli.command {
        Command::Doctor(args) => doctor::run(&args).map_err(Failure::Work),
        Command::Check(args) => check::run(&args),
        Command::Dynamics(args) => dynamics::run(&args),
        Command::Solve(args) => solve::run(&args),
        Command::Optimize(args) => optimize::run(&args),
        Command::Parts(args) => parts::run(&args),
        Command::Capacity(args) => capacity::run(&args),
        Command::Tradeoff(args) => tradeoff::run(&args),
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Table(args) => table::run(&args).map_err(Failure::Work),
        Command::Migrate(args) => migrate::run(&args).map_err(Failure::Work),
        Command::Task(args) => task::run(&args).map_err(Failure::Work),
        Command::Worker => worker::run().map_err(Failure::Work),
    };
    // The work done (an infeasible verdict asked to fail on included), output that could not be
    // written on stdout is the failure to report.
    let outcome = match outcome {
        Ok(()) | Err(Failure::Infeasible(_)) => match stdout_failure() {
            Some(error) if !answers_itself => Err(Failure::Work(format!(
                "cannot write the output on stdout: {error}"
            ))),
            _ => outcome,
        },
        Err(failure) => Err(failure),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            note!("error: {failure}");
            failure.exit_code()
        }
    }
}

/// Prints what clap has to say (help and version on stdout, usage errors on stderr) and returns
/// its exit code: 0 for help and version, 2 for a usage error; 1 when help or version could not
/// be written (a full disk behind `>`, a closed stdout), unless the reader closed its pipe.
fn parse_failure(error: &clap::Error) -> ExitCode {
    let printed = match error.exit_code() {
        0 => write_stdout(format_args!("{}", error.render()))
            .and_then(|()| std::io::stdout().flush()),
        _ => error.print(),
    };
    match (error.exit_code(), printed) {
        (0, Err(failure)) if failure.kind() != ErrorKind::BrokenPipe => {
            note!("error: cannot write the output on stdout: {failure}");
            ExitCode::FAILURE
        }
        (code, _) => ExitCode::from(u8::try_from(code).unwrap_or(2)),
    }
}

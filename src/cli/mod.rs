//! The command line: one subcommand per module, each a thin layer over the library.

/// Prints on stdout like `println!`, but a closed stdout (`codesign solve | head -1`) is not a
/// reason to panic: the line is dropped and the command goes on to write its files.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// `print!` with the same tolerance of a closed stdout as [`say!`].
macro_rules! say_raw {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout(), $($arg)*);
    }};
}

mod capacity;
mod common;
mod doctor;
mod dynamics;
mod optimize;
mod reproduce;
mod solve;
mod table;
mod task;
mod worker;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

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
    /// Evaluate the robot's dynamics and TCP kinematics, with derivatives, at one state (JSON).
    Dynamics(dynamics::Args),
    /// Solve the trajectory problem of one design and report cost, feasibility and trajectory.
    Solve(solve::Args),
    /// The largest payload a design can move through the task (bracketing and bisection).
    Capacity(capacity::Args),
    /// Co-design: search the gear ratios with CMA-ES, solving each design in worker processes.
    Optimize(optimize::Args),
    /// Reproduce the paper's experiment (and more): original designs, co-design, capacities, table, plots.
    Reproduce(reproduce::Args),
    /// Rebuild the paper's table from result files of `solve`, `optimize` and `capacity`.
    Table(table::Args),
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
/// process exit code (0 on success, 1 on any error, 2 on a usage error).
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Doctor(args) => doctor::run(&args),
        Command::Dynamics(args) => dynamics::run(&args),
        Command::Solve(args) => solve::run(&args),
        Command::Optimize(args) => optimize::run(&args),
        Command::Capacity(args) => capacity::run(&args),
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Table(args) => table::run(&args),
        Command::Task(args) => task::run(&args),
        Command::Worker => worker::run(),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

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

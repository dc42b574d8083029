//! The command line: one subcommand per module, each a thin layer over the library.

mod doctor;
mod dynamics;

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
}

/// Parses the command line, runs the subcommand, prints any error on stderr and returns the
/// process exit code (0 on success, 1 on any error, 2 on a usage error).
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Doctor(args) => doctor::run(&args),
        Command::Dynamics(args) => dynamics::run(&args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

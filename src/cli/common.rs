//! Flags shared by the commands that load a task and a robot: parsed here into the design
//! layer's [`ModelChoice`] and [`ProblemChoice`], which do the work.

use super::failure::Failure;
use super::run_flags::{case_error, case_message};
use crate::cli::choice::choice;
use crate::design::run::{task_source, Loaded, ModelChoice, ProblemChoice};
use codesign_core::ipopt::LinearSolver;
use codesign_core::model::task::{Ends, LimitMode, LimitModes, Task, TaskSource};
use codesign_core::model::Robot;
use codesign_core::problem::Space;
use codesign_core::solve::SolveSettings;
use std::path::PathBuf;

/// Reads one gear ratio of `--ratios`: a finite number, so that NaN and inf are usage errors
/// as the other flags' values out of range are. Spaces around it are ignored, so that
/// `--ratios "40, 25, 12"` reads as `--ratios 40,25,12`.
pub fn finite_ratio(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(ratio) if ratio.is_finite() => Ok(ratio),
        Ok(_) => Err("a gear ratio must be a finite number".to_owned()),
        Err(error) => Err(error.to_string()),
    }
}

/// Reads one number of a comma-separated list (`--payloads`, `dynamics --q`), spaces around it
/// ignored as in [`finite_ratio`]; its range is the flag's own check.
pub fn listed_number(text: &str) -> Result<f64, String> {
    text.trim()
        .parse::<f64>()
        .map_err(|error| error.to_string())
}

/// Where the task and robot come from, and the payload.
#[derive(Debug, Clone, clap::Args)]
pub struct ModelArgs {
    /// Task file (JSON): motion, weights, box, motors, transmission, limit modes, solver
    /// [default: the built-in task, which `codesign task` prints].
    #[arg(long, value_name = "FILE")]
    pub task: Option<PathBuf>,
    /// URDF of the robot; overrides the task's `robot` [default: the task's, or the built-in
    /// robot for the built-in task].
    #[arg(long, value_name = "URDF")]
    pub robot: Option<PathBuf>,
    /// Payload at the task's payload point, kg; overrides the task's `payload.mass_kg`.
    #[arg(long, value_name = "KG", allow_negative_numbers = true)]
    pub payload: Option<f64>,
    /// What the motion asks at its ends beyond q and v fixed at the first and last node:
    /// `paper` nothing (the paper's formulation), `hold` the load held at rest there within the
    /// control limits, `rest` that and zero acceleration at the first and last interval;
    /// overrides the task's `motion.ends` [default: the task's; a task without it: hold].
    #[arg(long, value_parser = choice::<Ends>(), value_name = "ENDS")]
    pub ends: Option<Ends>,
}

impl ModelArgs {
    /// What these flags choose.
    pub fn choice(&self) -> ModelChoice {
        ModelChoice {
            task: task_source(self.task.as_ref()),
            robot: self.robot.clone(),
            payload: self.payload,
            ends: self.ends,
        }
    }

    /// Checks what needs no file ([`ModelChoice::validate`]): a usage error.
    pub fn validate(&self) -> Result<(), Failure> {
        self.choice().validate().map_err(case_error)
    }

    /// Where the task comes from.
    pub fn source(&self) -> TaskSource {
        self.choice().source()
    }

    /// Loads the task, the robot, the solve settings and the task hash ([`ModelChoice::load`]).
    pub fn load(&self) -> Result<Loaded, String> {
        self.choice().load()
    }

    /// For the commands that inspect a robot (`check`, `dynamics`): with `--robot` and no
    /// `--task`, the robot alone, its TCP (and payload point) at the origin of its chain's last
    /// link, the default solve settings, and true; else the task's robot and solve settings
    /// ([`ModelArgs::load`]) and false.
    pub fn load_robot(&self) -> Result<(Task, Robot, SolveSettings, bool), String> {
        let (Some(urdf), None) = (&self.robot, &self.task) else {
            return (self.load()).map(|loaded| (loaded.task, loaded.robot, loaded.settings, false));
        };
        let tip = Robot::tip_link(urdf).map_err(|e| e.to_string())?;
        let mut task = Task::built_in().map_err(|e| e.to_string())?;
        task.robot = Some(urdf.clone());
        task.tcp.link.clone_from(&tip);
        task.tcp.point = [0.0; 3];
        task.payload.at = task.tcp.clone();
        (self.choice().validate()).map_err(|e| case_message(&e))?;
        task.payload.mass_kg = self.payload.unwrap_or(0.0);
        if let Some(ends) = self.ends {
            task.motion.ends = ends;
        }
        let robot = Robot::load(&task).map_err(|e| e.to_string())?;
        Ok((task, robot, SolveSettings::default(), true))
    }
}

/// The space and limit modes of the trajectory problem.
#[derive(Debug, Clone, clap::Args)]
pub struct ProblemArgs {
    /// The controls: `joint` torques (the baseline, actuator limits mapped to joint space) or
    /// `actuation`, the motor torques, tau = G^T tau_u (the paper's method).
    #[arg(long, value_parser = choice::<Space>(), default_value = "actuation")]
    pub space: Space,
    /// Joint torque limit mode of the joint-space problem: `paper`, G^T applied elementwise to
    /// the bounds as the paper prints; `interval`, the tightest symmetric box holding the true
    /// polytope; `exact`, the true limits as linear constraints; default: the task's.
    #[arg(long, value_parser = choice::<LimitMode>(), value_name = "MODE")]
    pub torque_mode: Option<LimitMode>,
    /// Joint speed limit mode, as `--torque-mode` with G^-1 (`paper`, `interval`, `exact`);
    /// default: the task's.
    #[arg(long, value_parser = choice::<LimitMode>(), value_name = "MODE")]
    pub speed_mode: Option<LimitMode>,
    /// Linear solver inside IPOPT: codesign's sparse LDLᵀ or MUMPS; default: the task's
    /// `solver.linear_solver`, else ldl.
    #[arg(long, value_parser = choice::<LinearSolver>(), value_name = "SOLVER")]
    pub linear_solver: Option<LinearSolver>,
}

impl ProblemArgs {
    /// What these flags choose.
    pub fn choice(&self) -> ProblemChoice {
        ProblemChoice {
            space: self.space,
            torque_mode: self.torque_mode,
            speed_mode: self.speed_mode,
            linear_solver: self.linear_solver,
        }
    }

    /// Applies `--linear-solver` to the solve settings.
    pub fn configure(&self, settings: &mut SolveSettings) {
        self.choice().configure(settings);
    }

    /// The limit modes: the flags where given, else the task's.
    pub fn modes(&self, task: &Task) -> LimitModes {
        self.choice().modes(task)
    }
}

#[cfg(test)]
mod tests {
    use super::super::Cli;
    use super::*;
    use clap::Parser;

    #[test]
    fn numbers_are_read_with_spaces_around_them() {
        assert_eq!(finite_ratio(" 25 "), Ok(25.0));
        assert_eq!(finite_ratio("\t1.8"), Ok(1.8));
        assert!(finite_ratio(" inf").is_err());
        assert!(finite_ratio("2 5").is_err());
        assert!(finite_ratio(" ").is_err());
        assert_eq!(listed_number(" -0.5 "), Ok(-0.5));
        assert!(listed_number("1 kg").is_err());
    }

    /// Every flag that takes a list of numbers reads `"40, 25, 12"` as `40,25,12` (clap splits
    /// at the commas and hands each piece, spaces and all, to the flag's value parser).
    #[test]
    fn every_list_of_numbers_takes_spaces_around_its_commas() {
        let lists: [&[&str]; 6] = [
            &["solve", "--ratios", "9, 5.62 ,3,  1.8"],
            &["check", "--ratios", "9, 5.62 ,3,  1.8"],
            &["capacity", "--ratios", "9, 5.62 ,3,  1.8"],
            &["optimize", "--objective", "range", "--payloads", "1, 2, 3"],
            &[
                "dynamics",
                "--q",
                "0, -0.5, 1 ,2",
                "--v",
                " 1, 2",
                "--a",
                "1 ,2",
            ],
            &["dynamics", "--q", "0,0", "--lambda", "0.5, -1"],
        ];
        for args in lists {
            let line = [&["codesign"][..], args].concat();
            if let Err(error) = Cli::try_parse_from(&line) {
                panic!("{line:?}: {error}");
            }
        }
        let refused = Cli::try_parse_from(["codesign", "solve", "--ratios", "9, x"]);
        assert!(refused.is_err());
    }
}

//! What a constant ratio hides on a ball screw: the planar example's elbow screw
//! (`robots/examples/planar_2dof/ball_screw.json`) against its constant approximation, the
//! screw's ratio in the middle of the motion (the elbow at q = 0).
//!
//! `cargo run --release --example constant_approximation`: solves the task with the constant
//! row, then takes the trajectory it returns through the true screw, G(q_k) at every node, and
//! prints (Markdown) the elbow motor's peak torque and speed as the constant model reports them
//! and as the screw gives them, beside the limits; then the true model solved at the same design.

use codesign_core::model::task::{MatrixRow, Task};
use codesign_core::model::Robot;
use codesign_core::problem::{Formulation, Space};
use codesign_core::solve::{solve_design, SolveSettings, TrajectoryResult};
use codesign_core::transmission::{Depth, Transmission};
use std::error::Error;
use std::path::Path;

/// The elbow motor (row 1 of G).
const ELBOW: usize = 1;

/// Peak |torque| (N m) and |speed| (rad/s) of the elbow motor over a trajectory.
fn peaks(torques: &[Vec<f64>], speeds: &[Vec<f64>]) -> (f64, f64) {
    let peak = |rows: &[Vec<f64>]| rows.iter().fold(0.0_f64, |m, row| m.max(row[ELBOW].abs()));
    (peak(torques), peak(speeds))
}

/// The elbow motor's peak |torque| (N m) and |speed| (rad/s) along `result`'s trajectory
/// through the true G(q_k) of `screw`: tau_u = G^-T tau and qd_u = G v.
fn through_screw(
    screw: &Formulation,
    result: &TrajectoryResult,
) -> Result<(f64, f64), Box<dyn Error>> {
    let transmission = Transmission::on_chain(&screw.task().transmission, screw.dynamics())?;
    let mut data = screw.dynamics().workspace();
    let (mut torques, mut speeds) = (Vec::new(), Vec::new());
    let t = &result.trajectory;
    for (k, (q, v)) in t.q.iter().zip(&t.v).enumerate() {
        let at = (screw.dynamics(), &mut data);
        let pose = transmission.at_pose(&result.ratios, at, q, Depth::First)?;
        speeds.push(pose.coupling.motor_speeds(v));
        if let Some(tau) = t.joint_torque.get(k) {
            torques.push(pose.coupling.motor_torques(tau));
        }
    }
    Ok(peaks(&torques, &speeds))
}

fn main() -> Result<(), Box<dyn Error>> {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/examples/planar_2dof/ball_screw.json");
    let task = Task::load(&path)?;
    let settings = SolveSettings::from_section(None)?;
    let design = task.transmission.original.clone();
    let space = Space::Actuation;
    let screw = Formulation::new(&task, Robot::load(&task)?, space, task.limit_modes)?;
    // The screw's ratio at the elbow's q = 0, the middle of its motion from -1 to 1 rad.
    let transmission = Transmission::on_chain(&task.transmission, screw.dynamics())?;
    let middle = vec![0.0; 2];
    let mut data = screw.dynamics().workspace();
    let at = transmission.at_pose(
        &design,
        (screw.dynamics(), &mut data),
        &middle,
        Depth::First,
    )?;
    let ratio = at.coupling.matrix()[(ELBOW, ELBOW)];
    let mut constant = task.clone();
    constant.transmission.matrix[ELBOW] =
        serde_json::from_str::<MatrixRow>(&format!("[0, {ratio}]"))?;
    let approximation =
        Formulation::new(&constant, Robot::load(&constant)?, space, task.limit_modes)?;
    let approximate = solve_design(&approximation, &design, &settings)?;
    let reported = peaks(
        &approximate.trajectory.motor_torque,
        &approximate.trajectory.motor_speed,
    );
    let true_peaks = through_screw(&screw, &approximate)?;
    let exact = solve_design(&screw, &design, &settings)?;
    let exact_peaks = peaks(
        &exact.trajectory.motor_torque,
        &exact.trajectory.motor_speed,
    );
    let (torque_limit, speed_limit) = (
        screw.motor_torque_limits()[ELBOW],
        screw.motor_speed_limits()[ELBOW],
    );
    let g = |q: f64| {
        let mut data = screw.dynamics().workspace();
        let pose = [0.0, q];
        let at = transmission.at_pose(&design, (screw.dynamics(), &mut data), &pose, Depth::First);
        at.map(|at| at.coupling.matrix()[(ELBOW, ELBOW)])
            .unwrap_or(f64::NAN)
    };
    println!("Ball screw on the planar example's elbow, lead {} mm, design r = {design:?}, {space} space.", design[1]);
    println!("The screw's ratio d(motor angle)/dq runs {:.2} at q = -1, {:.2} at q = 0, {:.2} at q = 1 rad.", g(-1.0), g(0.0), g(1.0));
    println!();
    println!(
        "| model | J | verdict | elbow motor peak torque (N m) | elbow motor peak speed (rad/s) |"
    );
    println!("|---|---|---|---|---|");
    println!(
        "| constant ratio {ratio:.2}, as it reports | {:.4} | {} | {:.3} | {:.1} |",
        approximate.cost,
        if approximate.feasible {
            "feasible"
        } else {
            "infeasible"
        },
        reported.0,
        reported.1
    );
    println!(
        "| the same trajectory through the screw | - | {} | {:.3} | {:.1} |",
        if true_peaks.0 <= torque_limit * (1.0 + 1e-6) && true_peaks.1 <= speed_limit * (1.0 + 1e-6)
        {
            "within the limits"
        } else {
            "over a limit"
        },
        true_peaks.0,
        true_peaks.1
    );
    println!(
        "| the screw solved (G(q) at every node) | {:.4} | {} | {:.3} | {:.1} |",
        exact.cost,
        if exact.feasible {
            "feasible"
        } else {
            "infeasible"
        },
        exact_peaks.0,
        exact_peaks.1
    );
    println!("| limits | | | {torque_limit} | {speed_limit} |");
    let range = |r: &TrajectoryResult| {
        let elbow = r.trajectory.q.iter().map(|q| q[ELBOW]);
        let low = elbow.clone().fold(f64::INFINITY, f64::min);
        (low, elbow.fold(f64::NEG_INFINITY, f64::max))
    };
    let (low, high) = range(&approximate);
    let (exact_low, exact_high) = range(&exact);
    println!();
    println!(
        "The elbow moves over [{low:.3}, {high:.3}] rad in the constant model's trajectory, where \
         the screw's ratio falls to {:.2} at its end; over [{exact_low:.3}, {exact_high:.3}] rad \
         in the screw's own.",
        g(high)
    );
    Ok(())
}

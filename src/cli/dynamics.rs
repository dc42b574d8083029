//! `codesign dynamics`: every dynamics quantity of the robot at one state, as one JSON object with
//! the keys of a sample of `dynamics_vectors.json`.

use super::common::{listed_number, ModelArgs};
use super::failure::Failure;
use codesign_core::dynamics::Dynamics;
use nalgebra::DMatrix;
use serde::Serialize;

/// Flags of `codesign dynamics`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The task (URDF, gravity, tool point, payload point), the robot and the payload.
    #[command(flatten)]
    model: ModelArgs,
    /// Joint positions, rad (m for a prismatic joint), one per joint, comma-separated.
    #[arg(
        long,
        value_name = "Q1,Q2,..",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = listed_number,
        required = true
    )]
    q: Vec<f64>,
    /// Joint velocities, rad/s (m/s for a prismatic joint) [default: 0].
    #[arg(
        long,
        value_name = "V1,V2,..",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = listed_number
    )]
    v: Option<Vec<f64>>,
    /// Joint accelerations, rad/s^2 (m/s^2 for a prismatic joint) [default: 0].
    #[arg(
        long,
        value_name = "A1,A2,..",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = listed_number
    )]
    a: Option<Vec<f64>>,
    /// Weights of the joint torques in the Hessian of lambda . tau [default: 0].
    #[arg(
        long,
        value_name = "L1,L2,..",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = listed_number
    )]
    lambda: Option<Vec<f64>>,
}

/// The printed object: the inputs and everything computed from them (SI units, world frame).
#[derive(Serialize)]
struct Output {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    tau: Vec<f64>,
    mass_matrix: Vec<Vec<f64>>,
    nonlinear_effects: Vec<f64>,
    gravity: Vec<f64>,
    forward_dynamics_of_tau: Vec<f64>,
    dtau_dq: Vec<Vec<f64>>,
    dtau_dv: Vec<Vec<f64>>,
    tcp_position: Vec<f64>,
    tcp_jacobian: Vec<Vec<f64>>,
    tcp_hessian_y: Vec<Vec<f64>>,
    tcp_hessian_z: Vec<Vec<f64>>,
    #[serde(rename = "lambda_")]
    lambda: Vec<f64>,
    hessian_lambda_tau: Vec<Vec<f64>>,
}

/// Loads the robot, evaluates everything at the given state and prints it as JSON on stdout.
pub fn run(args: &Args) -> Result<(), Failure> {
    if let Some(ends) = args.model.ends {
        return Err(Failure::Usage(format!(
            "--ends {ends}: dynamics evaluates one state, which has no ends; leave --ends out"
        )));
    }
    args.model.validate()?;
    let (_, robot, _, _) = args.model.load_robot()?;
    let n = robot.dof();
    let joints = robot.joint_names().join(", ");
    let state = |flag: &str, values: Option<&Vec<f64>>| -> Result<Vec<f64>, String> {
        let Some(values) = values else {
            return Ok(vec![0.0; n]);
        };
        if values.len() != n {
            return Err(format!(
                "--{flag} has {} values but the robot has {n} joints ({joints})",
                values.len()
            ));
        }
        match values.iter().position(|x| !x.is_finite()) {
            Some(i) => Err(format!(
                "--{flag}: value {} ({}) is not a finite number",
                i + 1,
                values[i]
            )),
            None => Ok(values.clone()),
        }
    };
    let q = state("q", Some(&args.q))?;
    let v = state("v", args.v.as_ref())?;
    let a = state("a", args.a.as_ref())?;
    let lambda = state("lambda", args.lambda.as_ref())?;
    say!("{}", evaluate(Dynamics::new(robot), q, v, a, lambda)?);
    Ok(())
}

/// Everything at (q, v, a) with weights lambda, as pretty-printed JSON.
fn evaluate(
    dynamics: Dynamics,
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
) -> Result<String, String> {
    let n = dynamics.dof();
    let mut data = dynamics.workspace();
    let square = || DMatrix::zeros(n, n);
    let mut tau = vec![0.0; n];
    let (mut dtau_dq, mut dtau_dv, mut mass) = (square(), square(), square());
    dynamics.rnea_derivatives(
        &mut data,
        &q,
        &v,
        &a,
        &mut tau,
        &mut dtau_dq,
        &mut dtau_dv,
        &mut mass,
    );
    let mut nonlinear_effects = vec![0.0; n];
    dynamics.nonlinear_effects(&mut data, &q, &v, &mut nonlinear_effects);
    let mut gravity = vec![0.0; n];
    dynamics.gravity_torques(&mut data, &q, &mut gravity);
    let mut forward_dynamics_of_tau = vec![0.0; n];
    dynamics.forward_dynamics(&mut data, &q, &v, &tau, &mut forward_dynamics_of_tau);
    let mut tcp_jacobian = DMatrix::zeros(3, n);
    dynamics.tcp_jacobian(&mut data, &q, &mut tcp_jacobian);
    let mut tcp_hessians = [square(), square(), square()];
    dynamics.tcp_hessians(&mut data, &q, &mut tcp_hessians);
    let mut hessian = DMatrix::zeros(3 * n, 3 * n);
    dynamics.rnea_hessian(&mut data, &q, &v, &a, &lambda, &mut hessian);
    let output = Output {
        tcp_position: dynamics.tcp_position(&mut data, &q).as_slice().to_vec(),
        q,
        v,
        a,
        tau,
        mass_matrix: rows(&mass),
        nonlinear_effects,
        gravity,
        forward_dynamics_of_tau,
        dtau_dq: rows(&dtau_dq),
        dtau_dv: rows(&dtau_dv),
        tcp_jacobian: rows(&tcp_jacobian),
        tcp_hessian_y: rows(&tcp_hessians[1]),
        tcp_hessian_z: rows(&tcp_hessians[2]),
        lambda,
        hessian_lambda_tau: rows(&hessian),
    };
    let value = serde_json::to_value(&output).map_err(|e| e.to_string())?;
    // JSON has no infinity: a quantity that overflowed would print as null.
    if let Some(name) = first_not_finite(&value) {
        return Err(format!(
            "{name} is not finite at this state: the speeds or accelerations given (--v, --a, \
             --lambda) are too large for its terms to be represented"
        ));
    }
    serde_json::to_string_pretty(&value).map_err(|e| e.to_string())
}

/// The first field of `value` (an object of numbers and lists of them) that holds a number
/// JSON cannot write (serde_json writes infinities and NaN as null).
fn first_not_finite(value: &serde_json::Value) -> Option<String> {
    fn has_null(value: &serde_json::Value) -> bool {
        match value {
            serde_json::Value::Null => true,
            serde_json::Value::Array(items) => items.iter().any(has_null),
            _ => false,
        }
    }
    value
        .as_object()?
        .iter()
        .find(|(_, field)| has_null(field))
        .map(|(name, _)| name.clone())
}

fn rows(matrix: &DMatrix<f64>) -> Vec<Vec<f64>> {
    matrix
        .row_iter()
        .map(|row| row.iter().copied().collect())
        .collect()
}

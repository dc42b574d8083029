//! The trajectory problems of `tests/data/ocp_reference.json` (an independent CasADi +
//! IPOPT 3.14 implementation) reproduce their optimal cost to 1e-6 relative, with either linear
//! solver inside IPOPT.

use codesign::ipopt::LinearSolver;
use codesign::model::task::Task;
use codesign::model::Robot;
use codesign::problem::{Formulation, Space};
use codesign::solver::{solve_design, SolveSettings};

mod support;

#[test]
fn reference_costs_are_reproduced() {
    let text = std::fs::read_to_string(support::root().join("tests/data/ocp_reference.json"))
        .expect("tests/data/ocp_reference.json");
    let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut task = Task::load(&support::task_path()).unwrap();
    let cases = reference["cases"].as_array().unwrap();
    assert!(cases.len() >= 3);
    for (case, solver) in cases
        .iter()
        .flat_map(|case| [LinearSolver::Ldl, LinearSolver::Mumps].map(|solver| (case, solver)))
    {
        task.solver.linear_solver = Some(solver);
        let space = match case["space"].as_str().unwrap() {
            "joint" => Space::Joint,
            "actuation" => Space::Actuation,
            other => panic!("unknown space {other}"),
        };
        task.payload.mass_kg = case["payload_kg"].as_f64().unwrap();
        let ratios: Vec<f64> = case["ratios"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r.as_f64().unwrap())
            .collect();
        let robot = Robot::load(&task).unwrap();
        let formulation = Formulation::new(&task, robot, space, task.limit_modes).unwrap();
        let result = solve_design(&formulation, &ratios, &SolveSettings::default()).unwrap();
        let expected = case["cost"].as_f64().unwrap();
        let relative = (result.cost - expected).abs() / expected.abs();
        println!(
            "{solver} {space} payload {} r {ratios:?}: {} in {} iterations (reference {}), J = {} (reference {expected}), relative {relative:.1e}",
            task.payload.mass_kg, result.status, result.iterations, case["iterations"], result.cost
        );
        assert_eq!(result.status, case["status"].as_str().unwrap());
        assert!(
            relative < 1e-6,
            "J = {} against {expected}: relative error {relative:e}",
            result.cost
        );
        assert!(
            result.violations.dynamics < 1e-6 && result.violations.integration < 1e-6,
            "{:?}",
            result.violations
        );
    }
}

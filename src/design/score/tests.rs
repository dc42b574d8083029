//! Verdicts of feasible, infeasible, invalid and unsolvable designs, their fitness under flat and
//! graded penalties, and their records against the committed evaluation logs.

use super::*;
use crate::problem::Space;
use crate::testing;
use serde_json::Value;
use std::path::Path;

/// The fitness of the repository's task at `payload_kg` in `space`, costs scored with `penalty`.
fn fitness(payload_kg: f64, space: Space, penalty: &str) -> Fitness {
    fitness_with(payload_kg, space, penalty, &testing::settings())
}

fn fitness_with(payload_kg: f64, space: Space, penalty: &str, solve: &SolveSettings) -> Fitness {
    let mut task = testing::task();
    task.payload.mass_kg = payload_kg;
    let modes = task.limit_modes;
    let penalty = penalty.parse().unwrap();
    Fitness::new(&task, solve, space, modes, &Objective::Cost, penalty).unwrap()
}

/// The original design of the repository's task.
fn original() -> Vec<f64> {
    testing::task().transmission.original
}

/// The entry lines of the committed quick run `name`'s evaluation log.
fn log_lines(name: &str) -> Vec<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/quick/runs");
    let text = std::fs::read_to_string(path.join(format!("{name}.log.jsonl"))).unwrap();
    text.lines().skip(1).map(str::to_owned).collect()
}

/// The first logged evaluation of run `name` whose status is `status`, and its line.
fn logged(name: &str, status: &str) -> (Evaluation, String) {
    let tag = format!("\"status\":\"{status}\"");
    let line = log_lines(name)
        .into_iter()
        .find(|line| line.contains(&tag))
        .unwrap_or_else(|| panic!("{name} logs no {status}"));
    (serde_json::from_str(&line).unwrap(), line)
}

/// An evaluation's JSON without its braces: the text an entry line of the log holds.
fn fields(evaluation: &Evaluation) -> String {
    let text = serde_json::to_string(evaluation).unwrap();
    text[1..text.len() - 1].to_owned()
}

#[test]
fn a_feasible_design_scores_its_cost() {
    // Unloaded: the original design's motors hold 0.59 kg at rest, not 1 kg.
    let score = fitness(0.0, Space::Actuation, "flat").score(&original());
    let Verdict::Feasible { cost, ref status } = score.verdict else {
        panic!("{score:?}");
    };
    assert_eq!(status, &SolveStatus::Ipopt("Solve_Succeeded".to_owned()));
    assert!(score.iterations > 0 && score.seconds > 0.0, "{score:?}");
    let flat = Evaluation::new(&original(), &score, &Penalty::PAPER);
    let graded = Evaluation::new(&original(), &score, &"graded".parse().unwrap());
    assert_eq!((flat.cost, graded.cost), (cost, cost));
    assert!(flat.feasible && flat.reason.is_none());
}

#[test]
fn an_infeasible_design_scores_the_flat_or_the_graded_penalty() {
    // The original design cannot carry 3 kg in actuation space (results/original).
    let flat = fitness(3.0, Space::Actuation, "flat").score(&original());
    let Verdict::Infeasible { shortfall, .. } = flat.verdict else {
        panic!("{flat:?}");
    };
    // A hard solve measures only the static hold's part: its deficit over the horizon (0.8 s)
    // and the motors' limit (1.7 N m).
    let hold = testing::formulation(3.0, Space::Actuation)
        .static_hold(&original())
        .unwrap();
    assert!(
        (shortfall - hold.deficit_nm() * 0.8 / 1.7).abs() < 1e-12,
        "{shortfall}"
    );
    assert_eq!(flat.verdict.fitness(&Penalty::PAPER), 1e6);
    let reason = flat.verdict.reason().unwrap();
    assert!(
        reason.starts_with("cannot hold the load at rest at the start: motor 2"),
        "{reason}"
    );
    assert!(
        reason.ends_with("; IPOPT returned Infeasible_Problem_Detected"),
        "{reason}"
    );
    let hold_only = shortfall;
    let penalty: Penalty = "graded".parse().unwrap();
    let graded = fitness(3.0, Space::Actuation, "graded").score(&original());
    let Verdict::Infeasible { shortfall, .. } = graded.verdict else {
        panic!("{graded:?}");
    };
    assert!(shortfall > hold_only, "{graded:?}");
    assert_eq!(
        graded.verdict.fitness(&penalty),
        penalty.infeasible(shortfall)
    );
    assert!((1e6..2e6).contains(&graded.verdict.fitness(&penalty)));
    let record = Evaluation::new(&original(), &graded, &penalty);
    assert_eq!(record.status.to_string(), "Elastic_Deficit");
    let reason = record.reason.unwrap();
    assert!(
        reason.starts_with("cannot hold the load at rest"),
        "{reason}"
    );
    assert!(reason.contains("; torque deficit "), "{reason}");
}

#[test]
fn an_invalid_design_is_scored_without_a_solve_by_its_distance() {
    let penalty: Penalty = "graded".parse().unwrap();
    let score = fitness(1.0, Space::Joint, "graded").score(&[10.0, 3.0, 1.0, 1.0]);
    let expected = Verdict::Invalid {
        distance: 1.0,
        reason: "r1 = 10 is outside [1, 9]".to_owned(),
    };
    assert_eq!(score, Score::unsolved(expected));
    assert_eq!(score.verdict.fitness(&penalty), penalty.invalid(1.0));
    assert_eq!(score.verdict.fitness(&Penalty::PAPER), 1e6);
    // Logged invalid designs score again to the same text, flat and graded (whose fitness
    // carries the distance).
    for (run, payload_kg, penalty) in [
        ("joint-1kg-seed0", 1.0, "flat"),
        ("joint-3kg-graded-seed0", 3.0, "graded"),
    ] {
        let (record, line) = logged(run, "Invalid_Design");
        let again = fitness(payload_kg, Space::Joint, penalty).evaluate(&record.ratios);
        assert!(line.contains(&fields(&again)), "{line}\n{again:?}");
    }
}

#[test]
fn a_solver_error_leaves_the_design_unjudged() {
    let mut settings = testing::settings();
    settings
        .options
        .insert("no_such_option".to_owned(), 3.into());
    let penalty: Penalty = "graded".parse().unwrap();
    let graded = fitness_with(1.0, Space::Actuation, "graded", &settings);
    let score = graded.score(&original());
    let Verdict::SolverError { ref message } = score.verdict else {
        panic!("{score:?}");
    };
    assert!(
        message.contains("IPOPT rejected option `no_such_option`"),
        "{message}"
    );
    assert_eq!(score.verdict.fitness(&penalty), penalty.base);
    let record = graded.evaluate(&original());
    assert!(!record.status.is_judged());
    assert_eq!(record.status.to_string(), "Solver_Error");
}

#[test]
fn a_logged_design_that_cannot_hold_its_load_scores_worse_with_the_hold() {
    // The graded 3 kg run logged its elastic deficits before the hold was judged: the same
    // design now names the hold first, keeps the logged deficit, and scores worse by the hold's.
    let (record, _) = logged("actuation-3kg-graded-seed0", "Elastic_Deficit");
    let again = fitness(3.0, Space::Actuation, "graded").evaluate(&record.ratios);
    assert!(!again.feasible);
    assert_eq!(again.status.to_string(), "Elastic_Deficit");
    let (logged_reason, reason) = (record.reason.unwrap(), again.reason.unwrap());
    assert!(
        reason.starts_with("cannot hold the load at rest at the start"),
        "{reason}"
    );
    assert!(
        reason.contains("; torque deficit "),
        "{reason} / {logged_reason}"
    );
    assert!(
        again.cost > record.cost,
        "{} against {}",
        again.cost,
        record.cost
    );
    // Under the flat penalty an infeasible design keeps its verdict and score, the hold named
    // before IPOPT's reason.
    let (record, _) = logged("actuation-3kg-seed1", "Infeasible_Problem_Detected");
    let again = fitness(3.0, Space::Actuation, "flat").evaluate(&record.ratios);
    assert_eq!((again.feasible, again.cost), (false, record.cost));
    assert_eq!(again.status.to_string(), "Infeasible_Problem_Detected");
    let (logged_reason, reason) = (record.reason.unwrap(), again.reason.unwrap());
    assert!(
        reason.starts_with("cannot hold the load at rest at the start"),
        "{reason}"
    );
    assert!(reason.ends_with(&format!("; {logged_reason}")), "{reason}");
}

#[test]
fn logged_designs_score_again_as_logged() {
    // The committed logs were written before the static hold was judged: a design that holds
    // its load scores as logged (a joint-space design in torque mode `paper` never does, its
    // joint 4 having no torque at all, so the runs are the actuation space's).
    for (run, status, payload_kg, penalty) in [
        ("actuation-1kg-seed0", "Solve_Succeeded", 1.0, "flat"),
        ("actuation-1kg-seed1", "Solve_Succeeded", 1.0, "flat"),
    ] {
        let formulation = testing::formulation(payload_kg, Space::Actuation);
        let holds = |e: &Evaluation| formulation.static_hold(&e.ratios).unwrap().holds();
        let tag = format!("\"status\":\"{status}\"");
        let record = log_lines(run)
            .into_iter()
            .filter(|line| line.contains(&tag))
            .map(|line| serde_json::from_str::<Evaluation>(&line).unwrap())
            .find(holds)
            .unwrap_or_else(|| panic!("{run} logs no {status} that holds its load"));
        let again = fitness(payload_kg, Space::Actuation, penalty).evaluate(&record.ratios);
        let same = |e: &Evaluation| (e.feasible, e.status.to_string(), e.reason.clone());
        assert_eq!(same(&again), same(&record), "{run}");
        assert!(
            (again.cost - record.cost).abs() <= 1e-9 * record.cost,
            "{run}: {} against {}",
            again.cost,
            record.cost
        );
    }
}

#[test]
fn records_write_the_texts_of_the_committed_logs() {
    let runs = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/quick/runs");
    let mut kinds = std::collections::HashSet::new();
    for entry in std::fs::read_dir(runs).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        let Some(run) = name.strip_suffix(".log.jsonl") else {
            continue;
        };
        for line in log_lines(run) {
            let record: Evaluation = serde_json::from_str(&line).unwrap();
            assert!(line.contains(&fields(&record)), "{line}");
            let logged: Value = serde_json::from_str(&line).unwrap();
            assert_eq!(logged["status"], record.status.to_string());
            kinds.insert(match &record.status {
                Status::Solved(solved) => Err(std::mem::discriminant(solved)),
                unsolved => Ok(std::mem::discriminant(unsolved)),
            });
        }
    }
    // IPOPT's statuses, Elastic_Deficit, Capacity_N_Probes and Invalid_Design.
    assert_eq!(kinds.len(), 4);
    for (text, status) in [
        (
            "Solve_Succeeded",
            Status::Solved(SolveStatus::Ipopt("Solve_Succeeded".into())),
        ),
        (
            "Capacity_17_Probes",
            Status::Solved(SolveStatus::Capacity { probes: 17 }),
        ),
        (
            "Capacity_017_Probes",
            Status::Solved(SolveStatus::Ipopt("Capacity_017_Probes".into())),
        ),
        (
            "Elastic_Deficit",
            Status::Solved(SolveStatus::ElasticDeficit),
        ),
        (
            "Infeasible_Unloaded",
            Status::Solved(SolveStatus::InfeasibleUnloaded),
        ),
        ("Invalid_Design", Status::InvalidDesign),
        ("Solver_Error", Status::SolverError),
        ("Worker_Failed", Status::WorkerFailed),
    ] {
        assert_eq!(Status::from(text), status);
        assert_eq!(status.to_string(), text);
    }
}

#[test]
fn unsolved_verdicts_write_todays_records() {
    let ratios = [6.0, 3.0, 1.0, 1.0];
    let cases = [
        (
            Verdict::WorkerFailed {
                message: "worker process crashed, twice".to_owned(),
            },
            r#""cost":1000000.0,"feasible":false,"status":"Worker_Failed","iterations":0,"seconds":0.0,"reason":"worker process crashed, twice""#,
        ),
        (
            Verdict::SolverError {
                message: "IPOPT rejected option `x` = 3".to_owned(),
            },
            r#""cost":1000000.0,"feasible":false,"status":"Solver_Error","iterations":0,"seconds":0.0,"reason":"IPOPT rejected option `x` = 3""#,
        ),
        (
            Verdict::Feasible {
                cost: -2.5,
                status: SolveStatus::Capacity { probes: 12 },
            },
            r#""cost":-2.5,"feasible":true,"status":"Capacity_12_Probes","iterations":0,"seconds":0.0"#,
        ),
        (
            Verdict::Infeasible {
                shortfall: 0.0,
                reason: "infeasible even without payload".to_owned(),
                status: SolveStatus::InfeasibleUnloaded,
            },
            r#""cost":1000000.0,"feasible":false,"status":"Infeasible_Unloaded","iterations":0,"seconds":0.0,"reason":"infeasible even without payload""#,
        ),
    ];
    for (verdict, text) in cases {
        let record = Evaluation::new(&ratios, &Score::unsolved(verdict), &Penalty::PAPER);
        assert_eq!(
            fields(&record),
            format!(r#""ratios":[6.0,3.0,1.0,1.0],{text}"#)
        );
    }
}

#[test]
fn a_design_that_cannot_hold_its_load_is_infeasible_and_graded_by_the_deficit() {
    // The original design moves 1 and 1.5 kg through the task (its capacity is 1.9 kg without
    // the hold) but its motors hold at most 0.59 kg at rest: infeasible under either penalty,
    // and the heavier payload, whose hold deficit is larger, scores worse when graded.
    let graded: Penalty = "graded".parse().unwrap();
    let mut previous = 0.0;
    for payload in [1.0, 1.5] {
        let flat = fitness(payload, Space::Actuation, "flat").score(&original());
        let Verdict::Infeasible { ref reason, .. } = flat.verdict else {
            panic!("{flat:?}");
        };
        assert!(reason.starts_with("cannot hold the load at rest at the start: motor 2 needs "));
        let score = fitness(payload, Space::Actuation, "graded").score(&original());
        let Verdict::Infeasible {
            shortfall,
            ref reason,
            ..
        } = score.verdict
        else {
            panic!("{score:?}");
        };
        assert!(
            reason.starts_with("cannot hold the load at rest at the start"),
            "{reason}"
        );
        // The hold's deficit (N m) over the horizon (0.8 s) and the motors' limit (1.7 N m).
        let formulation = testing::formulation(payload, Space::Actuation);
        let deficit = formulation.static_hold(&original()).unwrap().deficit_nm();
        assert!(deficit > 0.0);
        assert!(
            shortfall >= deficit * 0.8 / 1.7 - 1e-12,
            "{shortfall} {deficit}"
        );
        assert!(
            shortfall > previous,
            "{payload} kg: {shortfall} <= {previous}"
        );
        assert!(score.verdict.fitness(&graded) > graded.infeasible(previous));
        previous = shortfall;
    }
}

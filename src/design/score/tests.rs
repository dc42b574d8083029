//! Verdicts of feasible, infeasible, invalid and unsolvable designs, their fitness under flat and
//! graded penalties, and their records against the committed evaluation logs.

use super::*;
use codesign_core::problem::Space;
use codesign_core::testing;
use serde_json::Value;
use std::path::Path;

/// The fitness of the repository's task at `payload_kg` in `space`, costs scored with `penalty`.
fn fitness(payload_kg: f64, space: Space, penalty: &str) -> Fitness {
    fitness_with(payload_kg, space, penalty, &testing::settings())
}

fn fitness_with(payload_kg: f64, space: Space, penalty: &str, solve: &SolveSettings) -> Fitness {
    let mut task = testing::held_task();
    task.payload.mass_kg = payload_kg;
    let modes = task.limit_modes;
    let penalty = penalty.parse().unwrap();
    Fitness::new(&task, solve, space, modes, &Objective::Cost, penalty).unwrap()
}

/// The original design of the repository's task.
fn original() -> Vec<f64> {
    testing::held_task().transmission.original
}

/// The entry lines of the committed quick run `name`'s evaluation log (`runs/NAME` of the
/// paper's ends, `hold/runs/NAME` of the hold section).
fn log_lines(name: &str) -> Vec<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/quick");
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
    // Unloaded, the original design holds the arm at rest, but not through the motion in 0.2 s
    // instead of 0.8 s: IPOPT judges it. On 20 intervals rather than 50: every start of the
    // rule fails on this design, and the smaller problem fails sooner.
    let mut task = testing::held_task();
    task.payload.mass_kg = 0.0;
    task.motion.horizon = codesign_core::model::task::Horizon::Fixed(0.2);
    task.motion.steps = 20;
    let modes = task.limit_modes;
    let fitness = |penalty: &Penalty| {
        let solve = testing::settings();
        Fitness::new(
            &task,
            &solve,
            Space::Actuation,
            modes,
            &Objective::Cost,
            *penalty,
        )
        .unwrap()
    };
    let flat = fitness(&Penalty::PAPER).score(&original());
    let Verdict::Infeasible {
        shortfall: flat_shortfall,
        ..
    } = flat.verdict
    else {
        panic!("{flat:?}");
    };
    // The hard problem fails from every start, and the elastic solve the rule tried measures
    // the shortfall; the flat penalty ignores it.
    assert!(flat_shortfall > 0.0, "{flat:?}");
    assert_eq!(flat.verdict.fitness(&Penalty::PAPER), 1e6);
    let reason = flat.verdict.reason().unwrap();
    assert!(reason.starts_with("torque deficit "), "{reason}");
    let penalty: Penalty = "graded".parse().unwrap();
    let graded = fitness(&penalty).score(&original());
    let Verdict::Infeasible { shortfall, .. } = graded.verdict else {
        panic!("{graded:?}");
    };
    // Both kinds tried the same elastic solve from the standard guess.
    assert_eq!(shortfall, flat_shortfall, "{graded:?}");
    assert_eq!(
        graded.verdict.fitness(&penalty),
        penalty.infeasible(shortfall)
    );
    assert!((1e6..2e6).contains(&graded.verdict.fitness(&penalty)));
    let record = Evaluation::new(&original(), &graded, &penalty);
    assert_eq!(record.status.to_string(), "Elastic_Deficit");
    let reason = record.reason.unwrap();
    assert!(reason.starts_with("torque deficit "), "{reason}");
}

#[test]
fn a_design_that_cannot_hold_its_load_is_not_solved_under_either_penalty() {
    // The original design cannot hold 3 kg at rest in actuation space (motor 2): infeasible
    // whatever IPOPT would say, so no solve runs, and the shortfall is the hold's alone: its
    // deficit over the horizon (0.8 s) and the motors' limit (1.7 N m).
    let deficit = testing::held_formulation(3.0, Space::Actuation)
        .static_hold(&original())
        .unwrap()
        .deficit_nm();
    assert!(deficit > 0.0);
    for penalty in ["flat", "graded"] {
        let fitness = fitness(3.0, Space::Actuation, penalty);
        let score = fitness.score(&original());
        let Verdict::Infeasible {
            shortfall,
            ref reason,
            ref status,
        } = score.verdict
        else {
            panic!("{score:?}");
        };
        assert_eq!((score.iterations, score.seconds), (0, 0.0), "{penalty}");
        assert_eq!(status, &SolveStatus::StaticHoldFailed);
        assert!(
            reason.starts_with("cannot hold the load at rest at the start: motor 2 needs "),
            "{reason}"
        );
        assert!(
            (shortfall - deficit * 0.8 / 1.7).abs() < 1e-12,
            "{shortfall}"
        );
        let record = fitness.evaluate(&original());
        assert_eq!(record.status.to_string(), "Static_Hold_Failed");
        assert!(!record.feasible && record.iterations == 0);
        let parsed: Penalty = penalty.parse().unwrap();
        assert_eq!(record.cost, parsed.infeasible(shortfall));
    }
    assert_eq!(
        fitness(3.0, Space::Actuation, "flat")
            .evaluate(&original())
            .cost,
        1e6
    );
}

/// The gradient method's scoring gives such a design CMA-ES's verdict: with the flat penalty
/// without a solve and without a merit, with the graded one after the elastic solve whose merit
/// leads the descent toward designs that hold the load.
#[test]
fn a_descent_judges_a_design_that_cannot_hold_as_an_evaluation_does() {
    for penalty in ["flat", "graded"] {
        let fitness = fitness(3.0, Space::Actuation, penalty);
        let evaluation = fitness.evaluate(&original());
        let descent = fitness.descend_from(&original(), &[]);
        let solved = descent.evaluation.iterations > 0;
        let work = Evaluation {
            iterations: 0,
            seconds: 0.0,
            ..descent.evaluation.clone()
        };
        assert_eq!(work, evaluation, "{penalty}");
        match penalty {
            "flat" => assert!(!solved && descent.merit.is_none(), "{descent:?}"),
            _ => {
                let merit = descent.merit.as_ref().expect("an elastic merit");
                assert!(solved && merit.feasible_cost.is_none(), "{descent:?}");
                assert_eq!(fitness.implausible_merit(&descent.evaluation, merit), None);
            }
        }
    }
}

#[test]
fn a_range_or_a_joint_space_design_that_cannot_hold_is_not_solved() {
    // A range names the payloads not held and sums their deficits; the 0 kg one is held.
    let mut task = testing::held_task();
    task.payload.mass_kg = 0.0;
    let modes = task.limit_modes;
    let range = Objective::Range(PayloadRange {
        payloads_kg: vec![0.0, 1.0, 3.0],
    });
    let penalty: Penalty = "graded".parse().unwrap();
    let solve = testing::settings();
    let fitness = Fitness::new(&task, &solve, Space::Actuation, modes, &range, penalty).unwrap();
    let score = fitness.score(&original());
    let Verdict::Infeasible {
        shortfall,
        ref reason,
        ..
    } = score.verdict
    else {
        panic!("{score:?}");
    };
    assert_eq!(score.iterations, 0);
    assert!(reason.starts_with("at 1 kg: cannot hold"), "{reason}");
    assert!(reason.contains("; at 3 kg: cannot hold"), "{reason}");
    let term = |kg: f64| {
        let f = testing::held_formulation(kg, Space::Actuation);
        f.static_hold(&original()).unwrap().deficit_nm() * 0.8 / 1.7
    };
    assert!(
        (shortfall - term(1.0) - term(3.0)).abs() < 1e-12,
        "{shortfall}"
    );
    // In joint space, torque mode `paper` gives joint 4 no torque at all: nothing is solved,
    // not even the capacity search's unloaded probe.
    let capacity = Objective::Capacity(Default::default());
    let joint = Fitness::new(&task, &solve, Space::Joint, modes, &capacity, penalty).unwrap();
    for fitness in [fitness_with(1.0, Space::Joint, "flat", &solve), joint] {
        let record = fitness.evaluate(&original());
        assert_eq!(record.status.to_string(), "Static_Hold_Failed");
        assert_eq!(record.iterations, 0);
        let reason = record.reason.unwrap();
        assert!(
            reason.contains("cannot hold the load at rest at the "),
            "{reason}"
        );
        assert!(reason.contains("joint 4 needs "), "{reason}");
    }
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
        ("runs/joint-1kg-seed0", 1.0, "flat"),
        ("runs/joint-3kg-graded-seed0", 3.0, "graded"),
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
    // Unloaded: the original design holds the arm at rest, so the solve is tried.
    let graded = fitness_with(0.0, Space::Actuation, "graded", &settings);
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

/// An elastic solve that IPOPT stops short of an optimum (`max_iter` 0: at the guess) judges
/// nothing, under either penalty: a solver error, not an infeasible design with no deficit.
#[test]
fn an_elastic_solve_short_of_an_optimum_leaves_the_design_unjudged() {
    let mut settings = testing::settings();
    settings.max_iter = 0;
    for penalty in ["flat", "graded"] {
        let score = fitness_with(0.0, Space::Actuation, penalty, &settings).score(&original());
        let Verdict::SolverError { ref message } = score.verdict else {
            panic!("{penalty}: {score:?}");
        };
        assert!(
            message.contains("the elastic solve ended with Maximum_Iterations_Exceeded"),
            "{message}"
        );
    }
}

#[test]
fn logged_designs_score_again_as_logged() {
    // A design that holds its load scores as logged under `hold` (a joint-space design in
    // torque mode `paper` never does, its joint 4 having no torque at all, so the runs are the
    // actuation space's, of the hold section).
    for (run, status, payload_kg, penalty) in [
        (
            "hold/runs/actuation-1kg-seed0",
            "Solve_Succeeded",
            1.0,
            "flat",
        ),
        (
            "hold/runs/actuation-1kg-seed1",
            "Solve_Succeeded",
            1.0,
            "flat",
        ),
    ] {
        let formulation = testing::held_formulation(payload_kg, Space::Actuation);
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
    let quick = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/quick");
    let mut kinds = std::collections::HashSet::new();
    let folders = ["runs", "hold/runs"];
    let entries = folders.iter().flat_map(|folder| {
        std::fs::read_dir(quick.join(folder))
            .unwrap()
            .map(move |e| (folder, e))
    });
    for (folder, entry) in entries {
        let name = entry.unwrap().file_name().into_string().unwrap();
        let Some(run) = name.strip_suffix(".log.jsonl") else {
            continue;
        };
        for line in log_lines(&format!("{folder}/{run}")) {
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
    // IPOPT's statuses, Elastic_Deficit, Capacity_N_Probes, Static_Hold_Failed and
    // Invalid_Design.
    assert_eq!(kinds.len(), 5);
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
        (
            "Static_Hold_Failed",
            Status::Solved(SolveStatus::StaticHoldFailed),
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
        (
            Verdict::Infeasible {
                shortfall: 0.5,
                reason: "cannot hold the load at rest at the goal: motor 2 needs 2 N m (limit 1.7)"
                    .to_owned(),
                status: SolveStatus::StaticHoldFailed,
            },
            r#""cost":1000000.0,"feasible":false,"status":"Static_Hold_Failed","iterations":0,"seconds":0.0,"reason":"cannot hold the load at rest at the goal: motor 2 needs 2 N m (limit 1.7)""#,
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
    // the hold) but its motors hold at most 0.59 kg at rest: infeasible under either penalty
    // without a solve, and graded by the hold's deficit alone, so the heavier payload, whose
    // deficit is larger, scores worse.
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
        let formulation = testing::held_formulation(payload, Space::Actuation);
        let deficit = formulation.static_hold(&original()).unwrap().deficit_nm();
        assert!(deficit > 0.0);
        assert!(
            (shortfall - deficit * 0.8 / 1.7).abs() < 1e-12,
            "{shortfall} {deficit}"
        );
        assert_eq!(score.iterations, 0);
        assert!(
            shortfall > previous,
            "{payload} kg: {shortfall} <= {previous}"
        );
        assert!(score.verdict.fitness(&graded) > graded.infeasible(previous));
        previous = shortfall;
    }
}

/// The designs of the solve layer's tests of the one rule of feasibility (solve::certify): a
/// graded evaluation (elastic problem first) and a flat one (hard problem first) give the
/// verdicts `solve` gives, at 3 kg (the motors cannot hold the load: infeasible without a
/// solve) and at 2 kg (feasible only from the elastic trajectory).
#[test]
fn graded_and_flat_evaluations_give_the_verdicts_solve_gives() {
    for ratios in [
        [8.8516, 3.9278, 1.5982, 2.8179],
        [7.2907, 4.5583, 1.7140, 2.8587],
    ] {
        for penalty in ["graded", "flat"] {
            let verdict = fitness(3.0, Space::Actuation, penalty)
                .score(&ratios)
                .verdict;
            let Verdict::Infeasible { status, .. } = &verdict else {
                panic!("{ratios:?} {penalty}: {verdict:?}");
            };
            assert_eq!(*status, SolveStatus::StaticHoldFailed);
        }
    }
    for (ratios, cost) in [
        ([8.294, 8.1354, 2.7474, 2.6466], 240.2977),
        ([8.336, 7.9244, 2.8483, 2.6475], 216.6044),
    ] {
        for penalty in ["graded", "flat"] {
            let verdict = fitness(2.0, Space::Actuation, penalty)
                .score(&ratios)
                .verdict;
            let Verdict::Feasible { cost: found, .. } = verdict else {
                panic!("{ratios:?} {penalty}: {verdict:?}");
            };
            assert!(
                (found - cost).abs() < 1e-3,
                "{ratios:?} {penalty}: J = {found}"
            );
        }
    }
}

#[test]
fn under_the_papers_ends_a_design_that_cannot_hold_is_solved() {
    // The original design cannot hold 1 kg at rest (motor 2), but the paper's formulation asks
    // nothing of the ends: it is solved, and its cost is IPOPT's optimum (171.26).
    let mut task = testing::task();
    task.payload.mass_kg = 1.0;
    let penalty: Penalty = "flat".parse().unwrap();
    let fitness = Fitness::new(
        &task,
        &testing::settings(),
        Space::Actuation,
        task.limit_modes,
        &Objective::Cost,
        penalty,
    )
    .unwrap();
    let score = fitness.score(&original());
    let Verdict::Feasible { cost, .. } = score.verdict else {
        panic!("{score:?}");
    };
    assert!((cost - 171.26).abs() < 0.01, "{cost}");
    assert!(score.iterations > 0);
}

//! The search over parts (issue 53, item 3), end to end: `codesign parts` on the planar arm
//! with three candidate motors for its shoulder, its `pareto.json` checked point by point
//! against every feasible combination, its plot, its resumption, and the refusals of a task
//! with candidates.

use crate::support;

use codesign::design::parts::check_front_file;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use support::{codesign, fails_saying, read_json, root, scratch};

const SMALL: &str = "Allied Motion HT02501-A00";
const LARGE: &str = "Allied Motion HT02502-A00";
const FAST: &str = "Allied Motion HT02003-A00";

/// The planar arm carrying its elbow pulley and a motor (the example
/// `planar_2dof/carried_pulley.json`), its paths made absolute, 16 intervals, a small design
/// box, its shoulder motor chosen among `candidates` and its elbow's a small one; written to
/// `dir/family.json`.
fn family(dir: &Path, candidates: &[&str]) -> PathBuf {
    let examples = root().join("robots/examples/planar_2dof");
    let text = std::fs::read_to_string(examples.join("carried_pulley.json")).unwrap();
    let mut task: Value = serde_json::from_str(&text).unwrap();
    let catalogue = root().join("robots/catalogue/parts.json");
    let catalogue = catalogue.to_str().unwrap();
    task["robot"] = json!(examples.join("robot.urdf"));
    task["carried"][0]["pulley"]["catalogue"] = json!(catalogue);
    task["carried"][1]["motor"]["catalogue"] = json!(catalogue);
    task["motion"]["steps"] = json!(16);
    task["transmission"]["bounds"] = json!([[10, 40], [4, 16]]);
    task["transmission"]["original"] = json!([30, 10]);
    task["motors"] = json!({"speed_limit_rad_s": 120, "parts": [
        {"catalogue": catalogue, "candidates": candidates},
        {"catalogue": catalogue, "name": SMALL},
    ]});
    let file = dir.join("family.json");
    std::fs::write(&file, task.to_string()).unwrap();
    file
}

/// (actuator mass, value) of a point of `pareto.json`.
fn placed(point: &Value) -> (f64, f64) {
    let number = |key: &str| point[key].as_f64().unwrap();
    (number("actuator_mass_kg"), number("value"))
}

/// The least duration T* against the actuator mass over three shoulder motors: every point of
/// the front is dominated by no feasible combination, every combination has its result file,
/// the plot is beside it; a second search on the folder is refused, and `--resume` reads every
/// combination back to the same front.
#[test]
fn every_point_of_the_front_is_non_dominated() {
    let dir = scratch("parts");
    let task = family(&dir, &[LARGE, SMALL, FAST]);
    let out = dir.join("search");
    let args = [
        "parts",
        "--task",
        task.to_str().unwrap(),
        "--payload",
        "0.5",
        "--objective",
        "time",
        "--gradient-iterations",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    let text = support::succeed_in(root(), &args);
    assert!(text.contains("[1/3] Allied Motion HT02501-A00, Allied Motion HT02501-A00"));
    let document = read_json(&out.join("pareto.json"));
    assert_eq!(document["schema"], "codesign/pareto");
    assert_eq!(document["axes"]["x"]["better"], "lower");
    assert_eq!(document["axes"]["y"]["better"], "lower");
    let list = |key: &str| document[key].as_array().unwrap().clone();
    let (front, dominated) = (list("points"), list("dominated"));
    let feasible: Vec<(f64, f64)> = front.iter().chain(&dominated).map(placed).collect();
    assert_eq!(feasible.len() + list("infeasible").len(), 3);
    assert!(!front.is_empty());
    for point in &front {
        let (mass, time) = placed(point);
        let beaten =
            (feasible.iter()).any(|&(m, t)| m <= mass && t <= time && (m < mass || t < time));
        assert!(!beaten, "{point} is dominated");
        let file = out.join(point["file"].as_str().unwrap());
        let run = read_json(&file);
        assert_eq!(run["best_cost"], point["value"]);
        assert_eq!(run["inputs"]["task_hash"], point["task_hash"]);
    }
    for point in &dominated {
        let (mass, time) = placed(point);
        let beaten = (front.iter().map(placed))
            .any(|(m, t)| m <= mass && t <= time && (m < mass || t < time));
        assert!(beaten, "{point} is not dominated");
    }
    assert_eq!(check_front_file(&out.join("pareto.json")), Ok(front.len()));
    let svg = std::fs::read_to_string(out.join("pareto.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("actuator mass (kg)"));
    fails_saying(
        &codesign(&args),
        "holds allied-motion-ht02501-a00.json of an earlier search",
    );
    let resumed = support::succeed_in(root(), &[&args[..], &["--resume"]].concat());
    assert_eq!(
        resumed.matches("(read from the folder)").count(),
        3,
        "{resumed}"
    );
    let again = read_json(&out.join("pareto.json"));
    assert_eq!(again["points"], document["points"]);
}

/// A task with candidates is a family: `solve` refuses it naming the entry and `codesign
/// parts`; `parts` refuses an unknown candidate naming the catalogue and its motors.
#[test]
fn a_task_with_candidates_is_refused_elsewhere() {
    let dir = scratch("parts_refused");
    let task = family(&dir, &[SMALL, LARGE]);
    let solved = codesign(&["solve", "--task", task.to_str().unwrap()]);
    fails_saying(
        &solved,
        "motors.parts[0].candidates offers a choice of parts",
    );
    fails_saying(&solved, "`codesign parts`");
    let unknown = family(&dir, &[SMALL, "HT9"]);
    let out = dir.join("out");
    let args = [
        "parts",
        "--task",
        unknown.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let searched = codesign(&args);
    fails_saying(
        &searched,
        "motors.parts[0].candidates[1] = 'HT9' is no motor of catalogue",
    );
    fails_saying(&searched, "(its motors: Allied Motion HT02501-A00, ");
}

/// Every committed front (`results/catalogue/*/pareto.json`) holds only points that no other
/// feasible combination of its search dominates, and has its plot beside it (a search whose
/// every combination is infeasible has an empty front: at least two are not empty).
#[test]
fn every_committed_front_is_non_dominated() {
    let folder = root().join("results/catalogue");
    let mut fronts = 0;
    for entry in std::fs::read_dir(&folder).unwrap() {
        let search = entry.unwrap().path();
        let file = search.join("pareto.json");
        if !file.is_file() {
            continue;
        }
        let points = check_front_file(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        assert!(search.join("pareto.svg").is_file(), "{}", search.display());
        fronts += usize::from(points > 0);
    }
    assert!(
        fronts >= 2,
        "{fronts} fronts with points under {}",
        folder.display()
    );
}

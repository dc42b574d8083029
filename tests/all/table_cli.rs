//! `codesign table` rebuilds the paper's table from committed result files.

use crate::support;

use support::{codesign, codesign_in, root};

#[test]
fn rebuilds_the_table_from_result_files() {
    let root = root();
    let mut files: Vec<String> = Vec::new();
    for folder in [
        "results/quick/original",
        "results/quick/runs",
        "results/quick/capacity",
    ] {
        for entry in std::fs::read_dir(root.join(folder)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "json") {
                files.push(path.display().to_string());
            }
        }
    }
    let args: Vec<&str> = ["table"]
        .into_iter()
        .chain(files.iter().map(String::as_str))
        .collect();
    let output = codesign(&args);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let table = String::from_utf8(output.stdout).unwrap();
    // Written before results recorded their task's hash, they say they are of the built-in
    // task, the paper's.
    assert!(
        table.starts_with("# Table II reproduced: gear ratios and cost per payload\n"),
        "{table}"
    );
    let main_table = table.split("## Beyond the paper").next().unwrap();
    let rows: Vec<&str> = main_table
        .lines()
        .filter(|l| l.starts_with("| ") && l.contains(" kg |"))
        .collect();
    assert_eq!(rows.len(), 6, "{table}");
    for (row, (payload, space)) in rows.iter().zip([
        ("0 kg", "joint"),
        ("0 kg", "actuation"),
        ("1 kg", "joint"),
        ("1 kg", "actuation"),
        ("3 kg", "joint"),
        ("3 kg", "actuation"),
    ]) {
        assert!(
            row.starts_with(&format!("| {payload} | {space} |")),
            "{row}"
        );
    }
    // The paper's values stand beside ours; under the paper's formulation the joint-space
    // original is feasible, its motors unable to execute it, and the table says where a cell
    // differs in kind from the paper's, and why.
    assert!(rows[1].contains("(6, 3, 1, 1): 50.99"), "{}", rows[1]);
    assert!(
        rows[0].contains("(6, 3, 1, 1): 68.74, motors cannot execute it"),
        "{}",
        rows[0]
    );
    assert!(rows[1].contains("(6, 3, 1, 1): 43.67 |"), "{}", rows[1]);
    // A seed that found no feasible design shows no cost, in files written when its
    // `best_cost` held the penalty too (issue 57, item 8).
    assert!(
        rows[5].contains("| 0: none feasible, 1: 213.75 |"),
        "{}",
        rows[5]
    );
    assert!(
        table.contains("The paper's formulation (`--ends paper`)"),
        "{table}"
    );
    assert!(
        table.contains("- 1 kg, joint space, before: feasible here and not in the paper."),
        "{table}"
    );

    // Beyond the paper: capacities, the design of largest capacity, the gradient method.
    let beyond = table
        .split("## Beyond the paper")
        .nth(1)
        .expect("a section beyond the paper");
    // Its tables, each the rows under its header: capacities and gradient, the payload range,
    // the graded penalty.
    let tables: Vec<Vec<&str>> = beyond
        .split("\n\n")
        .filter(|block| block.starts_with("| payload"))
        .map(|block| block.lines().skip(2).collect())
        .collect();
    assert_eq!(tables.len(), 3, "{beyond}");
    let extra = &tables[0];
    assert_eq!(extra.len(), 6, "{beyond}");
    assert!(
        tables[1][0].starts_with("| 1, 2, 3 kg | actuation | 0 |"),
        "{beyond}"
    );
    assert_eq!(tables[2].len(), 2, "{beyond}");
    // The graded runs at 3 kg find a design in each space.
    assert!(
        tables[2][1].starts_with("| 3 kg | actuation | (4.84, 3.02, 1.06, 2.98): 207.16 |"),
        "{beyond}"
    );
    assert!(extra.iter().all(|row| row.contains(" kg | ")), "{beyond}");
    assert!(
        extra[1].starts_with("| 0 kg | actuation |") && extra[1].contains("kg ("),
        "{}",
        extra[1]
    );

    // A run that stopped before its last generation says so beside its seed (an earlier full
    // reproduction's actuation 3 kg seed 3 met pagmo's ftol rule after one generation).
    let seeds: Vec<String> = [3, 4]
        .iter()
        .map(|seed| format!("tests/data/table/actuation-3kg-seed{seed}.json"))
        .collect();
    let args: Vec<&str> = ["table"]
        .into_iter()
        .chain(seeds.iter().map(String::as_str))
        .collect();
    let output = codesign_in(root, &args);
    let table = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{table}");
    // Written before results recorded their task's hash, from a task file: an unknown task,
    // shown without the paper's numbers.
    assert!(
        table.starts_with("# Co-design of task robots/tasks/pick_place.json (task hash unknown): "),
        "{table}"
    );
    assert!(!table.contains("159.42"), "{table}");
    assert!(
        table.contains("3: 345.31 (stopped after generation 1: ftol"),
        "{table}"
    );
    assert!(
        table.contains("4: 296.36,") || table.contains("4: 296.36 |"),
        "{table}"
    );

    let missing = codesign(&["table", "results/absent.json"]);
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("results/absent.json"));
}

/// A solve of another design than the task's original has no cell in the table: `table` refuses
/// it, naming the file, instead of leaving it out silently (issue 38, item 6).
#[test]
fn a_solve_of_another_design_is_refused_naming_the_file() {
    let dir = support::scratch("other-design");
    let out = dir.join("other.json");
    let solve = codesign(&[
        "solve",
        "--space",
        "actuation",
        "--payload",
        "0",
        "--steps",
        "4",
        "--ratios",
        "9,5,3,3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        solve.status.success(),
        "{}",
        String::from_utf8_lossy(&solve.stderr)
    );
    let output = codesign(&["table", out.to_str().unwrap()]);
    support::fails_saying(
        &output,
        "other.json: a solve of r = [9.0, 5.0, 3.0, 3.0], not of",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every result names its kind and version first (`schema`, `version`), and `table` reads a
/// file by that tag: a solve tagged as a capacity search is read as one and refused, as are an
/// unknown tag, a newer version and a table given as a result, each naming the file; a file
/// without the envelope (written before it) is read by its fields.
#[test]
fn results_are_read_by_their_schema_tag() {
    let dir = support::scratch("schema");
    let out = dir.join("solve.json");
    let solve = codesign(&[
        "solve",
        "--space",
        "actuation",
        "--payload",
        "0",
        "--steps",
        "4",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        solve.status.success(),
        "{}",
        String::from_utf8_lossy(&solve.stderr)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.starts_with("{\n  \"schema\": \"codesign/solve\",\n  \"version\": 2,\n"),
        "{text}"
    );
    let table = dir.join("t.md");
    let made = codesign(&[
        "table",
        out.to_str().unwrap(),
        "--out",
        table.to_str().unwrap(),
    ]);
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    let table_json = std::fs::read_to_string(dir.join("t.json")).unwrap();
    assert!(table_json.starts_with("{\n  \"schema\": \"codesign/table\""));
    let variant = |name: &str, from: &str, to: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        codesign(&["table", path.to_str().unwrap()])
    };
    let tag = "\"schema\": \"codesign/solve\"";
    let as_capacity = variant("cap.json", tag, "\"schema\": \"codesign/capacity\"");
    support::fails_saying(&as_capacity, "cap.json: not a codesign capacity result");
    let unknown = variant("film.json", tag, "\"schema\": \"codesign/film\"");
    support::fails_saying(&unknown, "film.json: schema \"codesign/film\" is none of");
    let newer = variant("newer.json", "\"version\": 2,", "\"version\": 7,");
    support::fails_saying(&newer, "written by a newer codesign");
    let given_table = codesign(&["table", dir.join("t.json").to_str().unwrap()]);
    support::fails_saying(&given_table, "t.json: a table, made from results");
    let untagged = variant("old.json", &format!("{tag},\n  \"version\": 2,\n  "), "");
    assert!(!std::fs::read_to_string(dir.join("old.json"))
        .unwrap()
        .contains("schema"));
    // Written before the envelope (version 0): refused until migrated, then read.
    let old = dir.join("old.json");
    let migrate = format!("run `codesign migrate {}`", old.display());
    support::fails_saying(&untagged, &migrate);
    support::fails_saying(&untagged, "old.json: codesign/solve of version 0");
    let migrated = codesign(&["migrate", old.to_str().unwrap()]);
    assert!(migrated.status.success());
    let again = codesign(&["table", old.to_str().unwrap()]);
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Numbers no run writes are refused as edited or damaged, naming the file and the field: a
/// capacity above its search's range, a search's range above the largest payload, counts of a
/// co-design run that disagree with its costs (issue 38, probe D10).
#[test]
fn impossible_counts_and_capacities_are_refused() {
    let dir = support::scratch("impossible");
    let root = support::root();
    let quick = root.join("results/quick");
    let edit = |from: &str, name: &str, change: &dyn Fn(&mut serde_json::Value)| {
        let mut value = support::read_json(&quick.join(from));
        change(&mut value);
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_string(&value).unwrap()).unwrap();
        codesign(&["table", path.to_str().unwrap()])
    };
    let capacity = "capacity/actuation-original.json";
    let above = edit(capacity, "above.json", &|v| v["capacity_kg"] = 100.0.into());
    support::fails_saying(
        &above,
        "above.json: capacity_kg = 100 is above the search's max_kg",
    );
    let range = edit(capacity, "range.json", &|v| {
        v["inputs"]["settings"]["max_kg"] = 1e308.into();
    });
    support::fails_saying(&range, "range.json: settings.max_kg = ");
    let run = "runs/actuation-1kg-seed0.json";
    let none = edit(run, "none.json", &|v| v["evaluations"] = 0.into());
    support::fails_saying(&none, "none.json: evaluations = 0 but costs holds 144");
    let replayed = edit(run, "replayed.json", &|v| v["replayed"] = 145.into());
    support::fails_saying(
        &replayed,
        "replayed.json: replayed = 145 is more than evaluations",
    );
    let invalid = edit(run, "invalid.json", &|v| {
        v["verdicts"] = serde_json::json!({
            "feasible": {"designs": 0, "iterations": 0, "seconds": 0.0},
            "infeasible": {"designs": 0, "iterations": 0, "seconds": 0.0},
            "invalid": {"designs": 145, "iterations": 0, "seconds": 0.0},
            "unjudged": {"designs": 0, "iterations": 0, "seconds": 0.0}
        })
    });
    support::fails_saying(
        &invalid,
        "invalid.json: verdicts = 145 is more than evaluations",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The committed optima at their bounds are said so: the gradient method's 1 kg actuation-space
/// optimum sits on the upper bounds of r1, r3 and r4, each named with dJ*/dr_i.
#[test]
fn the_committed_optima_at_their_bounds_are_named() {
    let runs = support::root().join("results/runs");
    let files: Vec<String> = std::fs::read_dir(&runs)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "json"))
        .map(|path| path.to_str().unwrap().to_owned())
        .collect();
    let mut args = vec!["table"];
    args.extend(files.iter().map(String::as_str));
    let output = codesign(&args);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let table = String::from_utf8(output.stdout).unwrap();
    let line = table
        .lines()
        .find(|l| l.starts_with("- 1 kg, actuation space, gradient method"))
        .unwrap_or_else(|| panic!("no bound report of the gradient optimum:\n{table}"));
    for ratio in [1, 3, 4] {
        assert!(
            line.contains(&format!("r{ratio} at its upper bound")),
            "r{ratio}: {line}"
        );
        assert!(
            line.contains(&format!("dJ*/dr{ratio} = -")),
            "r{ratio}: {line}"
        );
    }
    assert!(!line.contains("r2 at its"), "{line}");
}

/// The committed reproduction folders' pages, from
/// `results/**/paper_table.json`.
const COMMITTED_PAGES: [&str; 11] = [
    "results",
    "results/hold",
    "results/quick",
    "results/quick/hold",
    "results/motors/rotor_inertia",
    "results/motors/rotor_inertia/hold",
    "results/motors/rotor_inertia_heavy",
    "results/motors/rotor_inertia_heavy/hold",
    "results/motors/envelope",
    "results/motors/envelope/hold",
    "results/linkage/ball_screw_quick",
];

/// Every committed page is the one this build writes from its folder's table and plots
/// (`codesign table --page` writes it again after the page changes), so none lags behind.
#[test]
fn every_committed_page_is_current() {
    use codesign::experiment::{index_page, Layout};
    use codesign::report::table::read_table_file;
    for folder in COMMITTED_PAGES {
        let layout = Layout::new(root().join(folder));
        let table = read_table_file(&layout.table_json()).unwrap();
        let committed = std::fs::read_to_string(layout.index()).unwrap();
        assert!(
            committed == index_page(&layout, &table),
            "{folder}/index.html is not the page of its table: \
             `codesign table --page {folder}` writes it again"
        );
    }
}

/// `table --page FOLDER` writes the folder's page from its table, leading with the summary
/// chart, and touches nothing else; a folder without a table, or a result where the table
/// should be, is refused naming the file.
#[test]
fn the_page_is_written_again_from_the_table() {
    let dir = support::scratch("page");
    let quick = root().join("results/quick");
    std::fs::copy(quick.join("paper_table.json"), dir.join("paper_table.json")).unwrap();
    let output = codesign(&["table", "--page", dir.to_str().unwrap()]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let page = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let summary = page.find("id=\"summary\"").expect("a summary chart");
    assert!(summary < page.find("<table").unwrap());
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["index.html", "paper_table.json"]);
    let empty = dir.join("empty");
    std::fs::create_dir(&empty).unwrap();
    let output = codesign(&["table", "--page", empty.to_str().unwrap()]);
    support::fails_saying(&output, "paper_table.json");
    std::fs::copy(
        quick.join("original/actuation-0kg.json"),
        empty.join("paper_table.json"),
    )
    .unwrap();
    let output = codesign(&["table", "--page", empty.to_str().unwrap()]);
    support::fails_saying(&output, "a codesign/solve document, not a table");
    let output = codesign(&["table", "--page", dir.join("none").to_str().unwrap()]);
    support::fails_saying(&output, "no such folder");
    std::fs::remove_dir_all(&dir).unwrap();
}

//! A co-design run side by side with the paper's stack, one worker each: CMA-ES over the gear
//! ratios at 1 kg (or `--payload KG`: 3 for the paper's edge of feasibility) in actuation space,
//! population 16 over 8 generations, sigma0 0.3, per seed.
//!
//! `cargo bench --bench codesign [-- --seeds 0,1,2,3,4] [--payload 1] [--python PYTHON]`: for
//! each seed, in turn, `codesign optimize --space actuation --payload 1 --population 16 --generations 8
//! --seed S --workers 1` (the crate's defaults otherwise: LDLᵀ, flat penalty, bounds by penalty)
//! and `benches/paper_stack/codesign.py --seed S` (pygmo's cmaes over CasADi + IPOPT + MUMPS,
//! the same outer problem, static hold and penalty), each timed as a whole command, process
//! start included. Printed: per seed and as medians over the seeds, the wall time, the
//! evaluations, the IPOPT solves, their iterations and time, the best cost and when the best
//! design was first evaluated (s from the run's start; the paper stack's includes building its
//! CasADi problem, the crate's the run's own `run_seconds`). Then the crate's
//! run of the first seed with `--linear-solver mumps` (the paper stack's linear solver), and,
//! untimed, the two stacks' verdicts compared design by design on that run (`codesign.py
//! --agree`). The machine's load average is printed before and
//! after. The paper's stack needs `casadi` and `pygmo` in PYTHON (default: `$PAPER_STACK_PYTHON`,
//! else `python3`); without them only the crate's side runs, and the bench says how to install
//! them.

mod common;

use codesign::stats::median;
use common::{load, timed};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The run's size and settings but the payload, as both stacks take them.
const RUN_ARGS: [&str; 8] = [
    "--space",
    "actuation",
    "--population",
    "16",
    "--generations",
    "8",
    "--sigma",
    "0.3",
];

/// One stack's run of one seed.
struct Row {
    /// Wall time of the whole command, s.
    wall: f64,
    evaluations: f64,
    solves: f64,
    /// IPOPT iterations over the run's solves.
    iterations: f64,
    /// Time inside the solves, s.
    solve_seconds: f64,
    /// Mean time of a solve, ms.
    ms_per_solve: f64,
    /// Mean time of an IPOPT iteration, ms.
    ms_per_iteration: f64,
    best_cost: f64,
    /// When the best design was first evaluated, s from the run's start (NaN: not known).
    best_seconds: f64,
}

impl Row {
    /// A run's row from its totals: wall time, evaluations, solves, iterations, solve time (s),
    /// and its best cost with the time it was found, s.
    fn new(totals: [f64; 5], (best_cost, best_seconds): (f64, f64)) -> Row {
        let [wall, evaluations, solves, iterations, solve_seconds] = totals;
        Row {
            wall,
            evaluations,
            solves,
            iterations,
            solve_seconds,
            ms_per_solve: 1e3 * solve_seconds / solves.max(1.0),
            ms_per_iteration: 1e3 * solve_seconds / iterations.max(1.0),
            best_cost,
            best_seconds,
        }
    }
}

/// The command line: seeds, payload (kg, as given) and the paper stack's Python.
struct Options {
    seeds: Vec<u64>,
    payload: String,
    python: String,
}

fn options() -> Options {
    let mut options = Options {
        seeds: (0..5).collect(),
        payload: "1".into(),
        python: std::env::var("PAPER_STACK_PYTHON").unwrap_or_else(|_| "python3".into()),
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--seeds" => {
                let list = args.next().expect("--seeds takes a list such as 0,1,2");
                options.seeds = list
                    .split(',')
                    .map(|s| {
                        s.trim()
                            .parse()
                            .expect("--seeds: whole numbers, e.g. 0,1,2")
                    })
                    .collect();
            }
            "--payload" => {
                let payload = args.next().expect("--payload takes a mass in kg, e.g. 3");
                payload.parse::<f64>().expect("--payload: a number of kg");
                options.payload = payload;
            }
            "--python" => options.python = args.next().expect("--python takes an interpreter"),
            // `cargo bench` passes --bench; other flags are the harness's, not ours.
            _ => {}
        }
    }
    options
}

/// The number at `key` of a JSON object (0 when absent or not a number).
fn number(value: &Value, key: &str) -> f64 {
    value[key].as_f64().unwrap_or(0.0)
}

/// The crate's `optimize` run of `seed` at `payload` kg written to `out` (extra flags in
/// `extra`), timed.
fn ours(seed: u64, payload: &str, out: &Path, extra: &[&str]) -> Row {
    let mut command = Command::new(env!("CARGO_BIN_EXE_codesign"));
    command
        .arg("optimize")
        .args(RUN_ARGS)
        .args(["--payload", payload])
        .args(["--seed", &seed.to_string(), "--workers", "1", "--overwrite"])
        .arg("--out")
        .arg(out)
        .args(extra);
    let (_, wall) = timed(&mut command);
    let result: Value =
        serde_json::from_str(&std::fs::read_to_string(out).expect("the result is written"))
            .expect("the result is JSON");
    let log = std::fs::read_to_string(log_of(out)).expect("the log is written");
    let records: Vec<Value> = (log.lines().skip(1))
        .map(|line| serde_json::from_str(line).expect("a log record is JSON"))
        .collect();
    let iterations = records.iter().map(|r| number(r, "iterations")).sum();
    // No feasible design: no best cost (null).
    let best_cost = result["best_cost"].as_f64().unwrap_or(f64::NAN);
    let best_seconds = (records.iter())
        .find(|r| r["feasible"] == true && number(r, "cost") == best_cost)
        .map_or(f64::NAN, |r| number(r, "run_seconds"));
    Row::new(
        [
            wall,
            number(&result, "evaluations"),
            number(&result, "solves"),
            iterations,
            number(&result, "solve_seconds_total"),
        ],
        (best_cost, best_seconds),
    )
}

/// The evaluation log beside the result `out`.
fn log_of(out: &Path) -> PathBuf {
    out.with_extension("log.jsonl")
}

/// The paper stack's script.
fn script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/paper_stack/codesign.py")
}

/// The paper stack's run of `seed`, timed.
fn paper_stack(python: &str, seed: u64, payload: &str) -> Row {
    let (stdout, wall) = timed(
        Command::new(python)
            .arg(script())
            .args(&RUN_ARGS[2..])
            .args(["--payload", payload])
            .args(["--seed", &seed.to_string(), "--json"]),
    );
    let row: Value = serde_json::from_str(stdout.trim()).expect("the script prints JSON");
    if let Some(generation) = row["pagmo_ftol_stop_generation"].as_u64() {
        println!(
            "(seed {seed}: with pagmo's default ftol 1e-6 the paper's stack would have ended \
             this run before generation {generation}, all of whose parents scored the penalty)"
        );
    }
    Row::new(
        [
            wall,
            number(&row, "evaluations"),
            number(&row, "solves"),
            number(&row, "iterations"),
            number(&row, "solve_seconds"),
        ],
        (
            number(&row, "best_cost"),
            row["best_seconds"].as_f64().unwrap_or(f64::NAN),
        ),
    )
}

/// Whether `python` imports casadi and pygmo.
fn has_paper_stack(python: &str) -> bool {
    Command::new(python)
        .args(["-c", "import casadi, pygmo"])
        .output()
        .is_ok_and(|output| output.status.success())
}

fn print_row(name: &str, seed: &str, row: &Row) {
    println!(
        "{name:<12} seed {seed:<7} wall {:7.2} s  {:5.0} evaluations  {:4.0} solves  {:6.0} \
         iterations  solves {:6.2} s ({:6.1} ms per solve, {:5.2} ms per iteration)  best J {:.6} \
         found at {:.2} s",
        row.wall,
        row.evaluations,
        row.solves,
        row.iterations,
        row.solve_seconds,
        row.ms_per_solve,
        row.ms_per_iteration,
        row.best_cost,
        row.best_seconds
    );
}

/// The medians over seeds of each field.
fn medians(rows: &[Row]) -> Row {
    let of = |field: fn(&Row) -> f64| median(&rows.iter().map(field).collect::<Vec<_>>());
    Row {
        wall: of(|r| r.wall),
        evaluations: of(|r| r.evaluations),
        solves: of(|r| r.solves),
        iterations: of(|r| r.iterations),
        solve_seconds: of(|r| r.solve_seconds),
        ms_per_solve: of(|r| r.ms_per_solve),
        ms_per_iteration: of(|r| r.ms_per_iteration),
        best_cost: of(|r| r.best_cost),
        best_seconds: of(|r| r.best_seconds),
    }
}

fn main() {
    let options = options();
    let dir = std::env::temp_dir().join(format!("codesign-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let paper = has_paper_stack(&options.python);
    println!("load average before: {}", load());
    if !paper {
        println!(
            "the paper's stack is not importable with {}: `pip install casadi pygmo` (or set \
             PAPER_STACK_PYTHON to a Python that has them, see benches/paper_stack/README.md); \
             running the crate's side only",
            options.python
        );
    }
    let (mut crate_rows, mut paper_rows) = (Vec::new(), Vec::new());
    for &seed in &options.seeds {
        let out = dir.join(format!("seed{seed}.json"));
        let row = ours(seed, &options.payload, &out, &[]);
        print_row("codesign", &seed.to_string(), &row);
        crate_rows.push(row);
        if paper {
            let row = paper_stack(&options.python, seed, &options.payload);
            print_row("paper stack", &seed.to_string(), &row);
            paper_rows.push(row);
        }
    }
    println!("medians over {} seeds:", options.seeds.len());
    let ours_median = medians(&crate_rows);
    print_row("codesign", "median", &ours_median);
    if paper {
        let paper_median = medians(&paper_rows);
        print_row("paper stack", "median", &paper_median);
        compare(&ours_median, &paper_median);
        agreement(&options, &dir);
    }
    println!("load average after: {}", load());
    std::fs::remove_dir_all(&dir).ok();
}

/// The ratios of the two stacks' median times, where the paper's stack solved any design.
fn compare(ours_median: &Row, paper_median: &Row) {
    if paper_median.solves == 0.0 {
        println!(
            "the paper's stack solved no design (every sample outside the design space or failing \
             the static hold): no ratio of times"
        );
        return;
    }
    println!(
        "co-design run: codesign {:.1}x faster than the paper's stack (median wall times); per \
         solve {:.1}x, per IPOPT iteration {:.1}x (medians)",
        paper_median.wall / ours_median.wall,
        paper_median.ms_per_solve / ours_median.ms_per_solve,
        paper_median.ms_per_iteration / ours_median.ms_per_iteration
    );
}

/// The crate's run of the first seed with MUMPS (printed: the linear solver's share of the
/// difference), whose every design the paper's stack then judges again, untimed (validity,
/// static hold, feasibility and J of every solved design).
fn agreement(options: &Options, dir: &Path) {
    let Some(&seed) = options.seeds.first() else {
        return;
    };
    let out = dir.join("agree.json");
    let row = ours(seed, &options.payload, &out, &["--linear-solver", "mumps"]);
    print_row("with MUMPS", &seed.to_string(), &row);
    let output = Command::new(&options.python)
        .arg(script())
        .arg("--agree")
        .arg(log_of(&out))
        .args(["--designs", "1000"])
        .output()
        .expect("the script starts");
    print!("{}", String::from_utf8_lossy(&output.stdout));
    if !output.status.success() {
        println!(
            "the two stacks disagree on the designs above: {}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

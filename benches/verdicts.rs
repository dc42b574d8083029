//! What verdicts at the edge of feasibility cost (issue 54): a fixed sample of designs from the
//! committed 3 kg actuation-space co-design logs, each solved again as the optimize evaluator
//! solves it, with the verdict compared to the committed one.
//!
//! `cargo bench --bench verdicts` reads the sample `benches/verdicts/designs.json` (200 designs:
//! 50 from each of the flat and the graded penalty's logs times the feasible and the infeasible
//! verdicts, invalid designs left out) and scores each design cold, from the standard guess,
//! through the optimize command's `Fitness` (flat: the hard formulation; graded: the elastic
//! one) with the built-in task at 3 kg. It prints, per stratum and in all, the IPOPT iterations
//! (deterministic), the total and median solve time, and every verdict that differs from the
//! committed one. Arguments after `--`:
//! - `--draw`: draw the sample again from `results/runs/actuation-3kg-*seed*.log.jsonl` and
//!   write it (fixed seed, so the same file unless the logs change);
//! - `--only STRATUM`: solve only one stratum (`flat-feasible`, `graded-infeasible`, ...);
//! - `--out FILE`: write each design's evaluation as a JSON line, to compare two runs.

use codesign::design::penalty::Penalty;
use codesign::design::score::{Evaluation, Fitness, Objective};
use codesign::stats::median;
use codesign_core::model::task::{Task, TaskFile};
use codesign_core::problem::Space;
use codesign_core::solve::SolveSettings;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Designs drawn per stratum.
const PER_STRATUM: usize = 50;
/// The seed of the draw.
const SEED: u64 = 54;
/// The penalties whose logs are sampled, as the logs' names spell them.
const PENALTIES: [&str; 2] = ["flat", "graded"];

/// One design of the sample, with what its committed log said.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Design {
    /// `flat` or `graded`: the penalty of its run.
    penalty: String,
    /// The log it comes from (a file of results/runs).
    log: String,
    generation: u64,
    index: u64,
    ratios: Vec<f64>,
    /// The committed verdict.
    feasible: bool,
    status: String,
    /// The committed IPOPT iterations (warm-started from the generation's mean).
    iterations: u64,
}

impl Design {
    fn stratum(&self) -> String {
        let verdict = if self.feasible {
            "feasible"
        } else {
            "infeasible"
        };
        format!("{}-{verdict}", self.penalty)
    }
}

/// The sample file.
#[derive(Serialize, Deserialize)]
struct Sample {
    about: String,
    seed: u64,
    designs: Vec<Design>,
}

/// A small linear congruential stream: the same draw on every machine.
struct Stream(u64);

impl Stream {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) % n as u64) as usize
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn sample_path() -> PathBuf {
    root().join("benches/verdicts/designs.json")
}

/// Every evaluation of the 3 kg actuation logs of `penalty`, invalid designs left out.
fn logged(penalty: &str) -> Vec<Design> {
    let infix = if penalty == "graded" { "graded-" } else { "" };
    let mut designs = Vec::new();
    for seed in 0..5 {
        let log = format!("actuation-3kg-{infix}seed{seed}.log.jsonl");
        let text = std::fs::read_to_string(root().join("results/runs").join(&log))
            .unwrap_or_else(|error| panic!("{log}: {error}"));
        for line in text.lines().skip(1) {
            let record: Value = serde_json::from_str(line).expect("a JSON line");
            let status = record["status"].as_str().unwrap_or_default();
            if record.get("ratios").is_none() || status == "Invalid_Design" {
                continue;
            }
            designs.push(Design {
                penalty: penalty.into(),
                log: log.clone(),
                generation: record["generation"].as_u64().expect("generation"),
                index: record["index"].as_u64().expect("index"),
                ratios: serde_json::from_value(record["ratios"].clone()).expect("ratios"),
                feasible: record["feasible"].as_bool().expect("feasible"),
                status: status.into(),
                iterations: record["iterations"].as_u64().expect("iterations"),
            });
        }
    }
    designs
}

/// Draws [`PER_STRATUM`] designs from each stratum (a partial Fisher-Yates shuffle).
fn draw() -> Sample {
    let mut stream = Stream(SEED);
    let mut designs = Vec::new();
    for penalty in PENALTIES {
        let all = logged(penalty);
        for feasible in [true, false] {
            let mut pool: Vec<Design> = all
                .iter()
                .filter(|d| d.feasible == feasible)
                .cloned()
                .collect();
            for k in 0..PER_STRATUM {
                let pick = k + stream.below(pool.len() - k);
                pool.swap(k, pick);
            }
            designs.extend(pool.into_iter().take(PER_STRATUM));
        }
    }
    Sample {
        about: "Designs of the committed 3 kg actuation-space logs (results/runs), 50 per penalty \
                and verdict, invalid designs left out; drawn by `cargo bench --bench verdicts -- \
                --draw`"
            .into(),
        seed: SEED,
        designs,
    }
}

/// The fitness the optimize command scores a design with under `penalty`.
fn fitness(penalty: &str) -> Fitness {
    let mut task = Task::built_in().expect("the built-in task loads");
    task.payload.mass_kg = 3.0;
    let section = TaskFile::built_in().expect("the built-in task").solver;
    let settings = SolveSettings::from_section(section.as_ref()).expect("valid settings");
    let penalty: Penalty = penalty.parse().expect("a penalty");
    Fitness::new(
        &task,
        &settings,
        Space::Actuation,
        task.limit_modes,
        &Objective::Cost,
        penalty,
    )
    .expect("the fitness builds")
}

struct Options {
    draw: bool,
    only: Option<String>,
    out: Option<PathBuf>,
}

fn options() -> Options {
    let mut options = Options {
        draw: false,
        only: None,
        out: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--draw" => options.draw = true,
            "--only" => options.only = args.next(),
            "--out" => options.out = args.next().map(PathBuf::from),
            _ => {} // cargo bench passes `--bench`
        }
    }
    options
}

fn read_sample(path: &Path) -> Sample {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|error| panic!("{}: {error} (draw it with -- --draw)", path.display()));
    serde_json::from_str(&text).expect("the sample parses")
}

/// Prints one line of totals over `rows`.
fn totals(label: &str, rows: &[(&Design, Evaluation)]) {
    let iterations: usize = rows.iter().map(|(_, e)| e.iterations).sum();
    let committed: u64 = rows.iter().map(|(d, _)| d.iterations).sum();
    let seconds: Vec<f64> = rows.iter().map(|(_, e)| e.seconds).collect();
    let differ = rows
        .iter()
        .filter(|(d, e)| d.feasible != e.feasible)
        .count();
    println!(
        "{label:>18}: {:3} designs, {iterations:7} iterations (committed, warm: {committed:7}), \
         solve {:8.1} s in all, median {:7.1} ms; {differ} verdicts differ",
        rows.len(),
        seconds.iter().sum::<f64>(),
        1e3 * median(&seconds),
    );
}

fn main() {
    let options = options();
    if options.draw {
        let sample = draw();
        let text = serde_json::to_string_pretty(&sample).expect("serialises");
        std::fs::write(sample_path(), text + "\n").expect("the sample is written");
        println!(
            "wrote {} designs to {}",
            sample.designs.len(),
            sample_path().display()
        );
        return;
    }
    let sample = read_sample(&sample_path());
    let fitnesses = PENALTIES.map(|p| (p, fitness(p)));
    let mut out = options
        .out
        .as_ref()
        .map(|path| std::fs::File::create(path).expect("the output file opens"));
    let mut rows = Vec::new();
    for design in &sample.designs {
        if options
            .only
            .as_ref()
            .is_some_and(|s| *s != design.stratum())
        {
            continue;
        }
        let (_, fitness) = fitnesses
            .iter()
            .find(|(p, _)| *p == design.penalty)
            .expect("a known penalty");
        let evaluation = fitness.evaluate(&design.ratios);
        if let Some(out) = out.as_mut() {
            let line = serde_json::to_string(&evaluation).expect("serialises");
            writeln!(out, "{line}").expect("the output file is written");
        }
        rows.push((design, evaluation));
    }
    println!("verdicts at 3 kg, actuation space, cold starts, IPOPT iterations and solve times:");
    let strata = [
        "flat-feasible",
        "flat-infeasible",
        "graded-feasible",
        "graded-infeasible",
    ];
    for stratum in strata {
        let part: Vec<_> = rows
            .iter()
            .filter(|(d, _)| d.stratum() == stratum)
            .map(|(d, e)| (*d, e.clone()))
            .collect();
        if !part.is_empty() {
            totals(stratum, &part);
        }
    }
    let all: Vec<_> = rows.iter().map(|(d, e)| (*d, e.clone())).collect();
    totals("all", &all);
    for (design, evaluation) in rows.iter().filter(|(d, e)| d.feasible != e.feasible) {
        println!(
            "  differs: {} {} gen {} #{} r = {:?}: committed {} ({}), now {} ({}, {} iterations){}",
            design.penalty,
            design.log,
            design.generation,
            design.index,
            design.ratios,
            design.feasible,
            design.status,
            evaluation.feasible,
            evaluation.status,
            evaluation.iterations,
            evaluation
                .reason
                .as_ref()
                .map(|r| format!(": {r}"))
                .unwrap_or_default(),
        );
    }
}

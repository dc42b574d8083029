//! The experiment's independent commands, as `reproduce --plan` prints them for GNU parallel or
//! a Slurm job array: each a command line of `codesign`, its flags derived from its case.

use crate::cli::run_flags::case_flags;
use crate::design::run::{shell_quote, Method};
use crate::experiment::{CapacityOf, Plan, SPACES};
use crate::store::log::Start;
use std::path::PathBuf;

/// The experiment's independent commands, one a line, with `program` as the binary: the
/// original designs' solves, every co-design run, and the original designs' capacity
/// searches. The capacities of the best designs wait for the runs: `--from-runs` does them.
pub fn commands(plan: &Plan, program_path: &str) -> Vec<String> {
    let program = shell_quote(program_path);
    let path = |path: PathBuf| shell_quote(&path.to_string_lossy());
    let mut common = Vec::new();
    if let Some(task) = &plan.task {
        common.push(format!("--task {}", path(task.clone())));
    }
    if let Some(solver) = plan.linear_solver {
        common.push(format!("--linear-solver {}", solver.name()));
    }
    common.push(format!("--ends {}", plan.ends));
    let common = common
        .iter()
        .map(|flag| format!(" {flag}"))
        .collect::<String>();
    let mut lines = Vec::new();
    for &payload in &plan.experiment.original_payloads_kg {
        for space in SPACES {
            lines.push(format!(
                "{program} solve --space {space} --payload {payload}{common} --out {} --plot {}",
                path(plan.layout.original(space, payload)),
                path(plan.layout.original_plots(space, payload))
            ));
        }
    }
    let runs = plan
        .cost_runs()
        .into_iter()
        .chain(plan.gradient_runs())
        .chain(plan.beyond_runs());
    for run in runs {
        let mut case = run.case.clone();
        // Commands run side by side: one worker each unless --workers says otherwise; a
        // CMA-ES run continues its log when the plan runs again.
        case.execution.workers.get_or_insert(1);
        if case.settings.method == Method::Cmaes && case.execution.start == Start::Fresh {
            case.execution.start = Start::Resume;
        }
        let flags = case_flags(&case).join(" ");
        lines.push(format!(
            "{program} optimize {flags} --out {}",
            path(plan.layout.run(&run.name))
        ));
    }
    for space in SPACES {
        let out = path(plan.layout.capacity(CapacityOf::Original(space)));
        lines.push(format!(
            "{program} capacity --space {space}{common} --out {out}"
        ));
    }
    if let Some(hold) = plan.hold_section() {
        lines.extend(commands(&hold, program_path));
    }
    lines
}

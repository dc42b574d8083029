//! The steps that bring a result document of an older version to the current one, on its JSON
//! (the envelope taken off): the one place that knows what older versions wrote. Each step says
//! in words what it changed, for `codesign migrate`'s report.
//!
//! The versions (docs/results.md, section 1):
//! - **0**, before the envelope: no `schema` and `version`; fields were added one by one
//!   without a new version, each read with a default where absent;
//! - **1**, the envelope `schema` and `version` (2026-12-04);
//! - **2** (2026-12-04): `reason` always written (null when feasible), each motor's peaks and
//!   margins in `motors_execute`, a capacity search's inputs under `inputs`; every field a
//!   reader of version 1 took a default for is written;
//! - **3** of a co-design result, **2** of a table (2026-12-06): no cost without a design.

use crate::store::document::Schema;
use serde_json::{json, Map, Value};

/// What the steps changed, one line each.
pub type Changes = Vec<String>;

/// The penalty of every committed run and the default one: a version 1 table held it as the cost
/// of a seed that found no feasible design.
const DEFAULT_PENALTY: f64 = 1e6;

/// The fields of a capacity search's inputs, which versions 0 and 1 wrote at the top level.
const CAPACITY_INPUTS: [&str; 7] = [
    "task_file",
    "task_hash",
    "space",
    "ratios",
    "limit_modes",
    "ends",
    "settings",
];

/// The kind of a document written before the envelope (version 0), by its fields: a co-design
/// run has `best_ratios`, a table `rows`, a capacity search `probes`, a solve none of them.
/// None for JSON that is no codesign document (its `tool.name` is not `codesign`, or
/// `codesign-core` as later builds name it).
pub fn untagged_kind(value: &Value) -> Option<Schema> {
    let name = value.pointer("/tool/name").and_then(Value::as_str);
    if !name.is_some_and(|name| name == "codesign" || name == "codesign-core") {
        return None;
    }
    let has = |key: &str| value.get(key).is_some();
    Some(if has("best_ratios") {
        Schema::Optimize
    } else if has("rows") {
        Schema::Table
    } else if has("probes") {
        Schema::Capacity
    } else {
        Schema::Solve
    })
}

/// Brings `value`, a document of `schema` at `version` (its envelope taken off), to the version
/// this build writes; returns what changed (empty for a current document). `built_in` is the
/// built-in task's hash: a version 0 result of the built-in task without a hash gets it, as a
/// reader of version 0 took it.
pub fn upgrade(schema: Schema, version: u32, value: &mut Value, built_in: Option<&str>) -> Changes {
    let mut changes = Changes::new();
    if version == 0 {
        changes.push(format!("envelope added ({})", schema.tag()));
    }
    let Some(object) = value.as_object_mut() else {
        return changes;
    };
    if version < 2 {
        match schema {
            Schema::Solve => {
                fill_tool(object, &mut changes);
                result_to_2(object, "", &mut changes);
            }
            Schema::Optimize => optimize_to_2(object, &mut changes),
            Schema::Capacity => capacity_to_2(object, &mut changes),
            Schema::Table => table_fill(object, &mut changes),
            // Its first version is current.
            Schema::Tradeoff | Schema::TimeCurve | Schema::Pareto => {}
        }
    }
    if let (0, Some(hash), Some(inputs)) = (version, built_in, object_at(object, "inputs")) {
        if inputs.get("task_file").and_then(Value::as_str) == Some("built-in") {
            fill(inputs, "inputs.", "task_hash", json!(hash), &mut changes);
        }
    }
    match schema {
        Schema::Optimize if version < 3 => optimize_to_3(object, &mut changes),
        Schema::Table if version < 2 => table_to_2(object, &mut changes),
        _ => {}
    }
    if version < schema.version() {
        changes.push(format!("version {version} -> {}", schema.version()));
    }
    changes
}

/// Inserts `key: value` into `object` where it is absent, noting it as `{at}{key}`.
fn fill(object: &mut Map<String, Value>, at: &str, key: &str, value: Value, changes: &mut Changes) {
    if !object.contains_key(key) {
        changes.push(format!("{at}{key} = {value} (absent)"));
        object.insert(key.to_owned(), value);
    }
}

/// The object at `key` of `object`, if it is one.
fn object_at<'v>(
    object: &'v mut Map<String, Value>,
    key: &str,
) -> Option<&'v mut Map<String, Value>> {
    object.get_mut(key).and_then(Value::as_object_mut)
}

/// `tool.linear_solver`: MUMPS, the only solver before the LDLᵀ (2026-11-23).
fn fill_tool(document: &mut Map<String, Value>, changes: &mut Changes) {
    if let Some(tool) = object_at(document, "tool") {
        fill(tool, "tool.", "linear_solver", json!("mumps"), changes);
    }
}

/// A trajectory result (a solve document's top level, `at` empty, or an optimize document's
/// `best_result` and `original_result`) to version 2: `reason` null where absent, the static
/// hold judged at 1e-9 N m as it was before the choice of ends, each motor's peaks and margins
/// empty where not recorded, and the TCP's x empty where not recorded, as a reader of version
/// 1 took them.
fn result_to_2(result: &mut Map<String, Value>, at: &str, changes: &mut Changes) {
    fill(result, at, "reason", Value::Null, changes);
    if let Some(hold) = object_at(result, "static_hold") {
        let at = format!("{at}static_hold.");
        fill(hold, &at, "judged", json!(true), changes);
        fill(hold, &at, "tolerance_nm", json!(1e-9), changes);
    }
    if let Some(execute) = object_at(result, "motors_execute") {
        let at = format!("{at}motors_execute.");
        for key in [
            "torque_peak_nm",
            "speed_peak_rad_s",
            "torque_margin_nm",
            "speed_margin_rad_s",
        ] {
            fill(execute, &at, key, json!([]), changes);
        }
    }
    if let Some(trajectory) = object_at(result, "trajectory") {
        fill(
            trajectory,
            &format!("{at}trajectory."),
            "tcp_x",
            json!([]),
            changes,
        );
    }
}

/// A co-design run's settings (an optimize document's `inputs`, an evaluation log's `run`) as
/// every run before the setting was recorded ran: MUMPS, the verdict of IPOPT alone, cold starts,
/// CMA-ES on the cost.
pub fn run_inputs_fill(inputs: &mut Map<String, Value>, at: &str, changes: &mut Changes) {
    fill(inputs, at, "linear_solver", json!("mumps"), changes);
    fill(inputs, at, "verdict_rule", json!("ipopt"), changes);
    fill(inputs, at, "warm_start", json!("off"), changes);
    fill(inputs, at, "method", json!("cmaes"), changes);
    fill(inputs, at, "objective", json!({"kind": "cost"}), changes);
}

/// An optimize document to version 2: its settings, its solves' count and time (0 where not
/// counted), and its two results.
fn optimize_to_2(document: &mut Map<String, Value>, changes: &mut Changes) {
    fill_tool(document, changes);
    if let Some(inputs) = object_at(document, "inputs") {
        run_inputs_fill(inputs, "inputs.", changes);
    }
    fill(document, "", "solves", json!(0), changes);
    fill(document, "", "solve_seconds_total", json!(0.0), changes);
    for key in ["best_result", "original_result"] {
        if let Some(result) = object_at(document, key) {
            result_to_2(result, &format!("{key}."), changes);
        }
    }
}

/// An optimize document to version 3: without a best design, `best_cost` (the penalty) null.
fn optimize_to_3(document: &mut Map<String, Value>, changes: &mut Changes) {
    let none = (document.get("best_ratios").and_then(Value::as_array)).is_some_and(Vec::is_empty);
    if none
        && document
            .get("best_cost")
            .is_some_and(|cost| !cost.is_null())
    {
        changes.push("best_cost = null (no best design; was the penalty)".to_owned());
        document.insert("best_cost".to_owned(), Value::Null);
    }
}

/// A capacity document to version 2: its inputs under `inputs`, its ends `hold` where the file
/// predates the choice.
fn capacity_to_2(document: &mut Map<String, Value>, changes: &mut Changes) {
    fill_tool(document, changes);
    if !document.contains_key("inputs") {
        let mut inputs = Map::new();
        for field in CAPACITY_INPUTS {
            if let Some(entry) = document.remove(field) {
                inputs.insert(field.to_owned(), entry);
            }
        }
        changes.push(format!(
            "inputs moved under inputs ({})",
            inputs.keys().cloned().collect::<Vec<_>>().join(", ")
        ));
        document.insert("inputs".to_owned(), Value::Object(inputs));
    }
    if let Some(inputs) = object_at(document, "inputs") {
        fill(inputs, "inputs.", "ends", json!("hold"), changes);
    }
}

/// A table of version 0 or 1: the fields a reader took defaults for.
fn table_fill(table: &mut Map<String, Value>, changes: &mut Changes) {
    fill_tool(table, changes);
    fill(table, "", "title", json!(""), changes);
    fill(table, "", "paper_task", json!(false), changes);
    fill(table, "", "linear_solvers", json!([]), changes);
    fill(table, "", "capacity_evaluations", json!(0), changes);
    fill(table, "", "capacity_seconds", json!(0.0), changes);
    let rows = table.get_mut("rows").and_then(Value::as_array_mut);
    for (index, row) in rows.into_iter().flatten().enumerate() {
        for cell in ["after", "graded"] {
            if let Some(after) = row.get_mut(cell).and_then(Value::as_object_mut) {
                let at = format!("rows[{index}].{cell}.");
                fill(after, &at, "early_stops", json!([]), changes);
                fill(after, &at, "solves", json!(0), changes);
            }
        }
    }
}

/// A table to version 2: no cost for a seed that found no feasible design (every seed of a row
/// without a best design; else a seed whose cost is at least the default penalty, 1e6, which no
/// committed run's J comes near), nor for a payload range's run without a design.
fn table_to_2(table: &mut Map<String, Value>, changes: &mut Changes) {
    let rows = table.get_mut("rows").and_then(Value::as_array_mut);
    for (index, row) in rows.into_iter().flatten().enumerate() {
        for cell in ["after", "graded"] {
            let Some(after) = row.get_mut(cell).and_then(Value::as_object_mut) else {
                continue;
            };
            let no_best = after.get("best").is_none_or(Value::is_null);
            let seeds = after.get_mut("per_seed").and_then(Value::as_array_mut);
            for pair in seeds.into_iter().flatten() {
                let Some([seed, cost]) = pair.as_array_mut().map(Vec::as_mut_slice) else {
                    continue;
                };
                let penalised = cost.as_f64().is_some_and(|c| c >= DEFAULT_PENALTY);
                if no_best || penalised {
                    changes.push(format!(
                        "rows[{index}].{cell}.per_seed seed {seed}: cost {cost} -> null (no design)"
                    ));
                    *cost = Value::Null;
                }
            }
        }
    }
    let ranges = table.get_mut("ranges").and_then(Value::as_array_mut);
    for (index, range) in ranges.into_iter().flatten().enumerate() {
        let Some(range) = range.as_object_mut() else {
            continue;
        };
        let none = (range.get("ratios").and_then(Value::as_array)).is_some_and(Vec::is_empty);
        if none && range.get("mean_cost").is_some_and(|cost| !cost.is_null()) {
            changes.push(format!("ranges[{index}].mean_cost -> null (no design)"));
            range.insert("mean_cost".to_owned(), Value::Null);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A version 0 capacity search gets its inputs under `inputs`, its ends and its linear
    /// solver; a current one is left as it is.
    #[test]
    fn a_capacity_search_of_version_0_moves_its_inputs() {
        let mut old = json!({
            "tool": {"name": "codesign"}, "task_file": "t.json", "space": "joint",
            "ratios": [1.0], "limit_modes": {}, "settings": {}, "probes": []
        });
        assert_eq!(untagged_kind(&old), Some(Schema::Capacity));
        let changes = upgrade(Schema::Capacity, 0, &mut old, None);
        assert_eq!(old["inputs"]["ratios"], json!([1.0]));
        assert_eq!(old["inputs"]["ends"], json!("hold"));
        assert_eq!(old["tool"]["linear_solver"], json!("mumps"));
        assert!(old.get("space").is_none());
        assert_eq!(changes.last().unwrap(), "version 0 -> 2");
        let mut current = old.clone();
        assert!(upgrade(Schema::Capacity, 2, &mut current, None).is_empty());
        assert_eq!(current, old);
    }

    /// A version 0 solve of the built-in task gets the built-in task's hash, one of a task file
    /// none (its task is unknown).
    #[test]
    fn a_version_0_result_of_the_built_in_task_gets_its_hash() {
        let solve =
            |file: &str| json!({"tool": {"name": "codesign"}, "inputs": {"task_file": file}});
        let mut built_in = solve("built-in");
        upgrade(Schema::Solve, 0, &mut built_in, Some("0123"));
        assert_eq!(built_in["inputs"]["task_hash"], "0123");
        let mut own = solve("task.json");
        upgrade(Schema::Solve, 0, &mut own, Some("0123"));
        assert!(own["inputs"].get("task_hash").is_none());
    }

    /// JSON of another program is no document; a co-design run and a table are told by fields.
    #[test]
    fn the_kind_of_an_untagged_document() {
        assert_eq!(untagged_kind(&json!({"rows": []})), None);
        let tool = json!({"name": "codesign"});
        let run = json!({"tool": tool, "best_ratios": []});
        assert_eq!(untagged_kind(&run), Some(Schema::Optimize));
        let table = json!({"tool": tool, "rows": []});
        assert_eq!(untagged_kind(&table), Some(Schema::Table));
        assert_eq!(untagged_kind(&json!({"tool": tool})), Some(Schema::Solve));
    }

    /// A table of version 1: the penalty of a seed without a design, and the mean cost of a
    /// range without one, become null; a seed's J stays.
    #[test]
    fn a_table_of_version_1_has_no_cost_without_a_design() {
        let mut table = json!({
            "rows": [{"after": {"best": {"cost": 5.0}, "per_seed": [[0, 5.0], [1, 1e6]]}}],
            "ranges": [{"ratios": [], "mean_cost": 1e6}]
        });
        upgrade(Schema::Table, 1, &mut table, None);
        assert_eq!(
            table["rows"][0]["after"]["per_seed"],
            json!([[0, 5.0], [1, null]])
        );
        assert_eq!(table["ranges"][0]["mean_cost"], Value::Null);
    }
}

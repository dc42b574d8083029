//! Reading a task file's optional `experiment` section into an [`Experiment`]: every field
//! left out takes the paper's value, every value is checked, and every error names its field
//! (`experiment.budget.seeds`). It lives apart from the types and defaults it fills in
//! (`experiment.rs`), which the task file holds, because it uses the task's checks.

use super::experiment::{Budget, Experiment, MAX_SEEDS};
use super::ranges::{check_payload, FieldError, OutOfRange};
use crate::text::number;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// The `experiment` section as written: every field may be left out.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct Section {
    original_payloads_kg: Option<Vec<f64>>,
    codesign_payloads_kg: Option<Vec<f64>>,
    graded_payloads_kg: Option<Vec<f64>>,
    range_payloads_kg: Option<Vec<f64>>,
    budget: Option<Value>,
    quick_budget: Option<Value>,
}

/// A budget as written: every field may be left out.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct BudgetSection {
    seeds: Option<u64>,
    population: Option<usize>,
    generations: Option<usize>,
    capacity_population: Option<usize>,
    capacity_generations: Option<usize>,
}

impl Experiment {
    /// The experiment of a task file's `experiment` section (None: the paper's), each field
    /// left out taking the paper's value, checked; errors name the field (`experiment.budget.seeds`).
    pub fn from_section(section: Option<&Value>) -> Result<Experiment, FieldError> {
        let mut experiment = Experiment::paper();
        let Some(section) = section else {
            return Ok(experiment);
        };
        let written: Section = parse("experiment", section)?;
        let lists = [
            (
                &mut experiment.original_payloads_kg,
                written.original_payloads_kg,
            ),
            (
                &mut experiment.codesign_payloads_kg,
                written.codesign_payloads_kg,
            ),
            (
                &mut experiment.graded_payloads_kg,
                written.graded_payloads_kg,
            ),
            (&mut experiment.range_payloads_kg, written.range_payloads_kg),
        ];
        for (list, given) in lists {
            if let Some(given) = given {
                *list = given;
            }
        }
        for (budget, given, name) in [
            (&mut experiment.budget, written.budget, "budget"),
            (
                &mut experiment.quick_budget,
                written.quick_budget,
                "quick_budget",
            ),
        ] {
            if let Some(given) = given {
                *budget = with(*budget, parse(&format!("experiment.{name}"), &given)?);
            }
        }
        experiment.validate()?;
        Ok(experiment)
    }

    /// Checks the payloads (each a valid payload, none twice in a list, at least one original
    /// and one co-designed) and the seeds of both budgets.
    fn validate(&self) -> Result<(), FieldError> {
        let lists = [
            ("original_payloads_kg", &self.original_payloads_kg, true),
            ("codesign_payloads_kg", &self.codesign_payloads_kg, true),
            ("graded_payloads_kg", &self.graded_payloads_kg, false),
            ("range_payloads_kg", &self.range_payloads_kg, false),
        ];
        for (name, payloads, needed) in lists {
            check_payloads(&format!("experiment.{name}"), payloads, needed)?;
        }
        for (name, budget) in [("budget", self.budget), ("quick_budget", self.quick_budget)] {
            if !(1..=MAX_SEEDS).contains(&budget.seeds) {
                return Err(FieldError {
                    field: format!("experiment.{name}.seeds"),
                    problem: format!(
                        " = {}: must be 1 to {MAX_SEEDS} (20 times the paper's 5)",
                        budget.seeds
                    ),
                });
            }
        }
        Ok(())
    }
}

/// `budget` with the fields `given` replaced.
fn with(budget: Budget, given: BudgetSection) -> Budget {
    Budget {
        seeds: given.seeds.unwrap_or(budget.seeds),
        population: given.population.unwrap_or(budget.population),
        generations: given.generations.unwrap_or(budget.generations),
        capacity_population: given
            .capacity_population
            .unwrap_or(budget.capacity_population),
        capacity_generations: given
            .capacity_generations
            .unwrap_or(budget.capacity_generations),
    }
}

/// Reads `value` as a `T`; the error names `field`.
fn parse<T: DeserializeOwned + Serialize>(field: &str, value: &Value) -> Result<T, FieldError> {
    crate::json_keys::read_value(value).map_err(|e| FieldError {
        field: e.field(field),
        problem: format!(": {}", e.message),
    })
}

/// Checks a list of payloads named `field`: each a valid payload, none twice, and (when
/// `needed`) at least one.
fn check_payloads(field: &str, payloads: &[f64], needed: bool) -> Result<(), FieldError> {
    let error = |field: String, problem: String| Err(FieldError { field, problem });
    if needed && payloads.is_empty() {
        return error(
            field.to_owned(),
            " = []: give at least one payload".to_owned(),
        );
    }
    for (i, &kg) in payloads.iter().enumerate() {
        if check_payload(kg).is_err() {
            return error(
                format!("{field}[{i}]"),
                format!(" = {}: {}", number(kg), OutOfRange::Payload),
            );
        }
        if payloads[..i].contains(&kg) {
            return error(
                format!("{field}[{i}]"),
                format!(
                    " = {}: given twice (each payload names the files of its runs)",
                    number(kg)
                ),
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{Budget, Experiment};
    use serde_json::json;

    fn read(section: serde_json::Value) -> Result<Experiment, String> {
        Experiment::from_section(Some(&section)).map_err(|e| e.to_string())
    }

    #[test]
    fn without_a_section_or_its_fields_the_paper_s_experiment_runs() {
        let paper = Experiment::from_section(None).unwrap();
        assert_eq!(paper, Experiment::paper());
        assert!(paper.is_paper());
        assert_eq!(paper.original_payloads_kg, [0.0, 1.0, 3.0]);
        assert_eq!(paper.codesign_payloads_kg, [1.0, 3.0]);
        assert_eq!(paper.budget.seeds, 5);
        assert_eq!(paper.quick_budget, Budget::QUICK);
        assert_eq!(read(json!({})).unwrap(), paper);
        assert_eq!(
            paper.describe(),
            "original design at 0, 1, 3 kg; co-design at 1, 3 kg; graded penalty at 3 kg; \
             one design for 1, 2, 3 kg"
        );
    }

    #[test]
    fn fields_given_replace_the_paper_s_one_by_one() {
        let experiment = read(json!({
            "original_payloads_kg": [0.5, 2],
            "codesign_payloads_kg": [2],
            "graded_payloads_kg": [],
            "budget": {"seeds": 3, "population": 12},
            "quick_budget": {"capacity_generations": 1}
        }))
        .unwrap();
        assert!(!experiment.is_paper());
        assert_eq!(experiment.original_payloads_kg, [0.5, 2.0]);
        assert_eq!(experiment.codesign_payloads_kg, [2.0]);
        assert!(experiment.graded_payloads_kg.is_empty());
        assert_eq!(experiment.range_payloads_kg, [1.0, 2.0, 3.0]);
        assert_eq!(
            experiment.budget,
            Budget {
                seeds: 3,
                population: 12,
                ..Budget::PAPER
            }
        );
        assert_eq!(
            experiment.quick_budget,
            Budget {
                capacity_generations: 1,
                ..Budget::QUICK
            }
        );
        assert_eq!(
            experiment.describe(),
            "original design at 0.5, 2 kg; co-design at 2 kg; one design for 1, 2, 3 kg"
        );
    }

    #[test]
    fn errors_name_the_field() {
        let cases = [
            // serde reads a struct from an array too: its first element is at fault.
            (json!([1, 2]), "experiment[0]: invalid type: integer `1`"),
            (
                json!({"payloads": [1]}),
                "experiment.payloads: unknown field `payloads`",
            ),
            (
                json!({"budget": {"popsize": 5}}),
                "experiment.budget.popsize: unknown field `popsize`",
            ),
            (
                json!({"quick_budget": {"seeds": -1}}),
                "experiment.quick_budget.seeds: invalid value",
            ),
            (
                json!({"original_payloads_kg": []}),
                "experiment.original_payloads_kg = []: give at least one payload",
            ),
            (
                json!({"codesign_payloads_kg": [1, -2]}),
                "experiment.codesign_payloads_kg[1] = -2: the payload must be",
            ),
            // A payload of 1e-320 kg named files of 341 bytes after the originals were solved.
            (
                json!({"codesign_payloads_kg": [1e-320]}),
                "experiment.codesign_payloads_kg[0] = 1e-320: the payload must be 0 or a mass from",
            ),
            (
                json!({"range_payloads_kg": [1, 2, 1]}),
                "experiment.range_payloads_kg[2] = 1: given twice",
            ),
            (
                json!({"budget": {"seeds": 0}}),
                "experiment.budget.seeds = 0: must be 1 to 100",
            ),
            (
                json!({"quick_budget": {"seeds": 101}}),
                "experiment.quick_budget.seeds = 101: must be 1 to 100",
            ),
        ];
        for (section, expected) in cases {
            let error = read(section.clone()).unwrap_err();
            assert!(error.starts_with(expected), "{section}: {error}");
        }
        // Empty lists where they are optional mean no such runs.
        read(json!({"graded_payloads_kg": [], "range_payloads_kg": []})).unwrap();
    }
}

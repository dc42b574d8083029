//! The cycle-time co-design (issue 52, item 2), end to end: `optimize --objective time` with both
//! methods.

use crate::support;

use serde_json::{json, Value};
use support::{read_json, scratch, task_with};

/// Runs codesign in the repository's root, failing the test on an error; its stdout.
fn succeed(args: &[&str]) -> String {
    support::succeed_in(support::root(), args)
}

/// `optimize --objective time` on the repository's task (20 intervals, 0 kg, its fixed 0.8 s
/// freed to [0.24, 1.2] s): recorded as the objective's kind, the best and original costs are the
/// durations T* of their re-solved results, the best no longer than the original's, and the
/// summary speaks of T*. The gradient method, then a small CMA-ES run.
#[test]
fn the_time_objective_minimises_the_duration_with_both_methods() {
    let dir = scratch("cycle_time_optimize");
    let task = task_with(&dir, |task| task["motion"]["steps"] = json!(20));
    let task = task.to_str().unwrap();
    let methods: [&[&str]; 2] = [
        &["--method", "gradient", "--gradient-iterations", "2"],
        &["--population", "5", "--generations", "1", "--workers", "2"],
    ];
    for (i, method) in methods.into_iter().enumerate() {
        let out = dir.join(format!("time-{i}.json"));
        let args = [
            "optimize",
            "--objective",
            "time",
            "--payload",
            "0",
            "--task",
            task,
            "--out",
            out.to_str().unwrap(),
        ];
        let text = succeed(&[&args[..], method].concat());
        assert!(text.contains("with T* = ") && text.contains(" s (original design: T* = "));
        let document = read_json(&out);
        assert_eq!(document["inputs"]["objective"], json!({"kind": "time"}));
        let number = |value: &Value| value.as_f64().unwrap();
        let (best, original) = (&document["best_result"], &document["original_result"]);
        for result in [best, original] {
            let t_star = number(&result["horizon_s"]);
            assert_eq!(number(&result["cost"]), t_star, "J* = T*");
            assert!((0.24..=1.2).contains(&t_star), "{t_star}");
        }
        assert_eq!(number(&document["original_cost"]), number(&original["cost"]));
        let best_cost = number(&document["best_cost"]);
        assert!(best_cost <= number(&document["original_cost"]), "{document}");
        assert!(
            (best_cost - number(&best["cost"])).abs() <= 1e-6 * best_cost,
            "{best_cost} vs {}",
            best["cost"]
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
